// The runout sensor of docs/model.md §5: a laser triangulator fixed in the frame looks along
// a ray from the nominal centre at a fixed angle and reads how far out the ring's bore is.
// Its signal contains the centre's motion and the bore's own form passing by. Its runout is
// read two ways: the total indicator reading, and a peak-to-valley swing at a stated
// resolution (SwingRule).
#pragma once

#include <span>
#include <vector>

#include "engine/contact.h"
#include "engine/profile.h"

namespace ringtol::engine {

struct SensorReading {
  double distance = 0.0;    // [m] from the origin along the sensor ray to the bore
  double ring_theta = 0.0;  // [rad] ring body angle seen (warm start for the next reading)
};

// Cosines and sines of the angles a reading needs, which move in small steps from one
// reading to the next along a trajectory: pass the same object to every reading of a
// trajectory and most sincos calls, the bulk of a reading's cost, are saved.
struct SensorTrack {
  NearbyAngle sensor;
  NearbyAngle aim;   // the sensor's direction in the ring's body frame
  NearbyAngle bore;  // the bore angle being iterated on
};

// Exact ray/bore intersection by bracketed Newton iteration in the ring body angle.
// Requires the origin to lie inside the bore (always true for a supported ring). The
// answer does not depend on theta_guess or track (to round-off).
SensorReading ReadSensor(const PolarProfile& ring, const BodyPose& ring_pose, double sensor_angle,
                         double theta_guess, SensorTrack* track = nullptr);

// How the signal's peak-to-valley swing is read (docs/model.md §5). The scene's [sensor]
// table sets it; the defaults are a good laser triangulation sensor read unfiltered.
struct SwingRule {
  // [m] >= 0: a counter-move of the signal up to this much is not an extreme; a larger
  // one counts only by its excess, so the swing stays continuous as a ripple grows.
  double resolution = 0.1e-6;
  // [undulations per revolution] >= 0: the cutoff of the ISO 16610-21 Gaussian low-pass
  // applied before the swing is read (ISO 12181-2 lists 15, 50, 150, 500); 0: unfiltered.
  double cutoff_upr = 0.0;

  bool operator==(const SwingRule&) const = default;
};

struct Runout {
  // [m] total indicator reading, max - min of the signal over the revolution (ISO 1101
  // circular runout as a dial indicator reads it): the primary runout, continuous in every
  // input and in the sampling.
  double total = 0.0;
  // [m] the largest rise or fall of the signal, each net of the largest counter-move
  // inside it beyond the rule's resolution (after its filter): "peak to nearest valley"
  // made well-posed. Equals `total` for a signal with one peak and one valley.
  double swing = 0.0;
};

// Runout of a signal sampled uniformly over one revolution, psi_k = 2 pi k / (size - 1):
// the last sample is the revolution's end, the start again up to roller lobes that do not
// close. The total and the unfiltered swing read every sample (the swing treats the
// signal as periodic); the filter, when the rule asks for one, takes all samples but the
// last as one period. Empty input gives zeros.
Runout MeasureRunout(std::span<const double> signal, const SwingRule& rule = {});

// The swing of `signal` (periodic) with counter-moves up to `resolution` [m] ignored and
// larger ones charged by their excess: max over arcs of at most one revolution of
// |rise| - max(0, counter-move - resolution), the counter-move being the largest fall
// within a rise (rise within a fall). Evaluated on the signal's extremes at that
// resolution: O(extremes^2), a few dozen for a real part.
double Swing(std::span<const double> signal, double resolution);

// The ISO 16610-21 Gaussian low-pass's transmission of a sinusoid of `undulations` per
// revolution (any real number, a roller's lobes pass at fractional ones):
// exp(-pi (alpha undulations / cutoff_upr)^2), alpha = sqrt(ln 2 / pi), so 50 % of an
// undulation at the cutoff passes. cutoff_upr > 0 [undulations per revolution].
double GaussianTransmission(double undulations, double cutoff_upr);

// That filter on a closed profile: harmonic k of the periodic signal kept by
// GaussianTransmission(k, cutoff_upr).
std::vector<double> GaussianFilterClosed(std::span<const double> period, double cutoff_upr);

}  // namespace ringtol::engine
