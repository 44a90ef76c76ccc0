// Radial error motion of the ring's axis in a fixed sensitive direction, as ISO 230-7
// (axes of rotation) and ANSI/ASME B89.3.4 define it (docs/model.md §9): the axis motion
// along the sensor's direction, read over several revolutions at the same angles. A
// revolution of a ring on rollers does not repeat (the rollers turn R/r times a turn), so
// the revolutions spread into a band around their average:
//   synchronous   the average over the revolutions at each angle, with its fundamental
//                 (the once-per-revolution component, which a fixed sensitive direction
//                 cannot tell from the artefact's centring) removed;
//   asynchronous  each revolution's departure from that average;
//   total         every revolution, the same fundamental removed.
// Each value is read on the polar plot about its least-squares centre, which for a
// signal this small against the plot's base circle is the plot less its fundamental:
// total and synchronous are max - min there, asynchronous the widest the band is along
// one radial line (max - min over the revolutions at one angle).
#pragma once

#include <span>
#include <vector>

namespace ringtol::engine {

// The low-pass filter the axis motion passes before its values are read. ISO 230-7 asks a
// measurement to state its filter and its revolutions, and a spindle analyser filters the
// motion it records as one signal over all of them: an unfiltered value and an analyser's
// are different quantities, the more so here, where a roller's lobes pass at R/r times
// their order a revolution (docs/model.md §9).
struct ErrorMotionFilter {
  // [undulations per revolution] >= 0: cutoff of the ISO 16610-21 Gaussian low-pass; 0:
  // unfiltered. 50, the roundness analysers' long-standing default (ISO 12181-2 lists 15,
  // 50, 150 and 500), passes a ring's form orders and takes most of a roller's lobes out.
  double cutoff_upr = 50.0;

  bool filtered() const { return cutoff_upr > 0.0; }
  // The share of a sinusoid of `undulations` per revolution that passes: 1 unfiltered.
  double Transmission(double undulations) const;
  // Whole revolutions of motion the filter reads on either side of those it returns: its
  // weighting function (of width 1 / cutoff_upr revolutions) weighs less than 1e-16 beyond
  // them. 0 unfiltered.
  int MarginRevolutions() const;

  bool operator==(const ErrorMotionFilter&) const = default;
};

struct ErrorMotion {
  double total = 0.0;         // [m] total error motion value
  double synchronous = 0.0;   // [m] synchronous error motion value, fundamental removed
  double asynchronous = 0.0;  // [m] asynchronous error motion value
  double fundamental = 0.0;   // [m] amplitude of the once-per-revolution part removed
};

// `motion` holds `revolutions` revolutions of `steps` samples each, revolution-major, at
// psi_j = 2 pi j / steps (the revolution's end, j = steps, is the next one's start and
// not repeated) [m]. Requires steps >= 3 and motion.size() a positive multiple of steps;
// throws std::invalid_argument otherwise. One revolution has no asynchronous part.
ErrorMotion MeasureErrorMotion(std::span<const double> motion, int steps);

// `motion` through `filter`, as an analyser filters the signal it records: `motion` holds
// filter.MarginRevolutions() revolutions, then those to read, then as many again, each of
// `steps` samples (laid out as MeasureErrorMotion's), and the revolutions to read come
// back filtered as if the record went on for ever either side. Unfiltered: a copy.
// Requires steps >= 3 and at least one revolution to read; throws std::invalid_argument
// otherwise.
std::vector<double> FilterErrorMotion(std::span<const double> motion, int steps, const ErrorMotionFilter& filter);

// The polar plot the values are read from, at psi_j [m]: each angle's least and greatest
// value over the revolutions (the band) and their average (the synchronous plot), all less
// the average's fundamental, whose amplitude is ErrorMotion::fundamental. Same requirements
// as MeasureErrorMotion, which reads its values from it.
struct ErrorMotionBand {
  std::vector<double> lowest, highest, average;
  double fundamental = 0.0;  // [m]
};
ErrorMotionBand ErrorMotionBandOf(std::span<const double> motion, int steps);

// The once-per-revolution component of a revolution sampled as above: a cos psi + b sin psi
// with a, b its least-squares (discrete Fourier) coefficients [m]. Requires steps >= 3.
struct Fundamental {
  double cosine = 0.0;  // [m] a
  double sine = 0.0;    // [m] b
  double At(double psi) const;
};
Fundamental FundamentalOf(std::span<const double> revolution);

}  // namespace ringtol::engine
