// Random form errors: a profile r(theta) = R + sum_n C_n cos(n theta + phi_n) whose
// harmonics of orders min_order..max_order are drawn independently, with
//   C_n = c s_n sqrt(-2 ln u_n)   (Rayleigh, scale c s_n)    phi_n = 2 pi v_n - pi (uniform),
// for uniform u_n, v_n in (0, 1). That is the random-phase spectral model: the cosine and
// sine coefficients C_n cos phi_n and C_n sin phi_n are independent Gaussians of standard
// deviation c s_n (docs/tolerances.md §7.1-7.2). s_n is the spectrum's shape, n^-a or a table;
// c is the scale, calibrated so that a stated fraction p of parts meets a tolerance t on a
// form measure:  P(measure <= t) = p. Every measure here is linear in c, so
// c = t / Q_p(measure at c = 1), with Q_p found once by Monte Carlo.
//
// Measures, as the standards measure them:
//   - kRoundness: RONt, peak-to-valley of the radius about the least-squares reference
//     circle (LSCI, ISO 12181-1). To first order in deviation/radius the LS circle removes
//     exactly orders 0 and 1, so RONt = max - min of the orders >= 2. The minimum-zone
//     value (ISO 1101's default) is never larger: calibrating the LS value to t is
//     conservative by a few percent (docs/tolerances.md §7.4 table).
//   - kTwoPointVariation: VDsp, the range of two-point diameters r(theta) + r(theta + pi)
//     in one plane (ISO 492). Odd orders cancel in that sum: a 3-lobed roller has
//     VDsp = 0. A spectrum without even orders therefore cannot be calibrated to VDsp.
// Both are computed exactly: a grid of 8 points per wavelength of the highest order finds
// every basin that may hold an extreme (grid values within max|r''| h^2 / 8 of the best),
// Newton on r' = 0 polishes each.
//
// Most draws are far from their tolerance, so deciding "measure <= limit" or finding a
// calibration's quantile rarely needs that exact value: bounds on it settle most draws
// (BoundForm, FormWithin, the calibration's selection), and only draws whose bounds
// straddle the limit or the quantile are measured exactly. The bounds hold for the value
// MeasureForm computes in floating point, not only for the true peak-to-valley, so every
// decision and every calibrated scale is the exact measure's, bit for bit.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "engine/profile.h"

namespace ringtol::sampling {

enum class FormMeasure { kRoundness, kTwoPointVariation };

// "roundness (RONt, least-squares circle)", "two-point variation (VDsp)".
const char* FormMeasureName(FormMeasure measure);

struct SpectrumShape {
  int min_order = 2;   // [-] lowest order drawn, >= 1
  int max_order = 50;  // [-] cutoff in undulations per revolution, >= min_order
  // s_n = n^-exponent [-], >= 0. No published exponent exists for ring roundness
  // (docs/tolerances.md §7.1); 1 is the middle of the range §7.4 tabulates.
  double exponent = 1.0;
  // When non-empty, s_n = relative_scales[n - min_order] instead of the power law, one
  // value >= 0 per order, not all zero.
  std::vector<double> relative_scales;

  int order_count() const { return max_order - min_order + 1; }
  double RelativeScale(int order) const;  // s_n [-]
  bool operator==(const SpectrumShape&) const = default;
};

// The harmonics of one draw: orders min..max in order, from u (amplitude draws) and v
// (phase draws), each of size order_count(), at scale c [m].
std::vector<engine::Harmonic> DrawHarmonics(const SpectrumShape& shape, double scale, std::span<const double> u,
                                            std::span<const double> v);
// The same draw with s_n given, relative_scales = RelativeScales(shape): the same bits without
// a pow per order, for callers that draw one shape many times.
std::vector<engine::Harmonic> DrawHarmonics(const SpectrumShape& shape, std::span<const double> relative_scales,
                                            double scale, std::span<const double> u, std::span<const double> v);
std::vector<double> RelativeScales(const SpectrumShape& shape);  // s_n for n = min..max [-]

// The measure of a profile whose deviations from its mean radius are `harmonics` [m].
// kRoundness ignores orders <= 1 (the LS circle absorbs them).
double MeasureForm(FormMeasure measure, std::span<const engine::Harmonic> harmonics);

// lower <= MeasureForm(measure, harmonics) <= upper [m], for the value MeasureForm
// computes, round-off included (each bound carries a margin of 16 eps (grid points +
// 2 top + terms + 1) times the amplitudes it sums, at least twice any evaluation's error).
struct FormBounds {
  double lower = 0.0;
  double upper = 0.0;
};

enum class FormBoundLevel {
  // From the amplitudes a_t alone, O(orders): upper 2 sum|a_t| (|r| <= sum|a_t|); lower
  // (pi/2) max|a_t| less the dense grid's curvature margin (an order's coefficient is the
  // profile's projection on a cosine: |a_n| <= (1/pi) (PV/2) int|cos| = 2 PV / pi).
  kAmplitudes,
  // From r, r' and r'' on every fourth point of MeasureForm's grid (2 points per wavelength
  // of the highest order, at least 16), about a quarter of the exact measure's work: lower
  // the coarse grid's range (those points are grid points of the exact measure, whose
  // range it never undercuts); upper the range of r + r' t + r'' t^2 / 2 over each point's
  // half-spacing |t| <= h/2 plus the Taylor remainder sum n^3 |a_n| (h/2)^3 / 6.
  kCoarseGrid,
};

FormBounds BoundForm(FormMeasure measure, std::span<const engine::Harmonic> harmonics, FormBoundLevel level);

// MeasureForm(measure, harmonics) <= limit, the same decision for every profile, with the
// exact measure taken only where the amplitude and coarse-grid bounds straddle the limit
// (and, inside it, its dense grid's range already above the limit skips the polish).
bool FormWithin(FormMeasure measure, std::span<const engine::Harmonic> harmonics, double limit);

struct CalibrationOptions {
  // Monte Carlo draws at unit scale. At least this many, and more when p is close to 1:
  // enough for 40 draws beyond the quantile, up to max_draws.
  int min_draws = 16384;
  int max_draws = 1 << 20;
  // Fixed, so that a class means the same scale in every campaign and on every machine.
  std::uint64_t seed = 0x5eed'ca1b;
  // The quantile and its interval are order statistics of the draws' measures: by default
  // they are selected by bounds (FormBoundLevel), measuring exactly only the draws whose
  // bounds reach the ranks' window (453 of 16,384 for the default ring class, 690 for the
  // default rollers' VDsp, at Cp 1). true measures every draw exactly and
  // sorts them all: the same calibration bit for bit, several times slower; kept as the
  // reference the selection is tested against.
  bool exact_every_draw = false;
  // Take the calibration from TabulatedCalibrations() when its shape, measure, coverage
  // and these options (min_draws, max_draws, seed) are one of its rows, instead of
  // drawing. The rows are CalibrateSpectrum's own results with tabulated = false, bit for
  // bit (a test recomputes each): the spectra every campaign file draws unless it says
  // otherwise, so that a run starts without drawing 16,384 profiles a class. false: the
  // Monte Carlo always, the reference the rows are held to.
  bool tabulated = true;
};

struct SpectrumCalibration {
  double scale = 0.0;          // [m] c
  double unit_quantile = 0.0;  // [m per m of c] Q_p of the measure at c = 1
  // 95 % distribution-free confidence interval of Q_p from the order statistics
  // (binomial ranks k p -+ 1.96 sqrt(k p (1-p))), and so of the coverage actually reached.
  double unit_quantile_low = 0.0;
  double unit_quantile_high = 0.0;
  int draws = 0;
};

// Scale c with P(measure <= tolerance) = coverage at that scale. tolerance > 0 [m],
// coverage in (0, 1). Throws std::invalid_argument for a shape that cannot be drawn
// (orders < 1, max < min, negative exponent or scales, all scales zero), for a two-point
// measure on a spectrum without even orders, and when coverage is so close to 1 that
// max_draws cannot place 40 draws beyond the quantile.
SpectrumCalibration CalibrateSpectrum(const SpectrumShape& shape, FormMeasure measure, double tolerance,
                                      double coverage, const CalibrationOptions& options = {});

// A calibration at unit tolerance (scale = 1 / unit_quantile), which holds for every
// tolerance: the unit quantile does not depend on it.
struct TabulatedCalibration {
  SpectrumShape shape;
  FormMeasure measure;
  double coverage;  // [-]
  SpectrumCalibration calibration;
};

// The default spectra at the default capability (Cp 1, coverage erf(3 / sqrt 2)) and
// CalibrationOptions: the ring's orders 2..50, n^-1, on RONt; the rollers' 2..8, n^-1, on
// VDsp (jobs/inputs/sampling_file.cpp's defaults).
std::span<const TabulatedCalibration> TabulatedCalibrations();

// Validates a shape as CalibrateSpectrum does; throws std::invalid_argument.
void CheckSpectrumShape(const SpectrumShape& shape);

}  // namespace ringtol::sampling
