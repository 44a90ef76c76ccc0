// A measured outline as a Fourier series: from the (angle, value) pairs of a roundness
// tester to the mean and harmonics that engine::PolarProfile takes.
//
// The model is engine/profile.h's, with the order-0 term free:
//   value(theta) = a_0 + sum_{n=1..N} (a_n cos n theta - b_n sin n theta)
//                = a_0 + sum_{n=1..N} C_n cos(n theta + phi_n),
//   C_n = hypot(a_n, b_n),  phi_n = atan2(b_n, a_n),
// so a_n and b_n are PolarProfile::cos_coefficient(n) and sin_coefficient(n). When the
// values are radii, a_0 is radius + mean deviation; when they are deviations from a
// nominal radius, a_0 is the mean deviation.
//
// The fit is plain linear least squares (an SVD of the design matrix), so samples may be
// unevenly spaced, leave gaps and repeat angles. With M evenly spaced samples and
// independent noise of standard deviation sigma the coefficients come out uncorrelated
// with standard errors sigma / sqrt(M) (a_0) and sigma sqrt(2 / M) (a_n, b_n, C_n).
#pragma once

#include <span>
#include <vector>

#include "engine/profile.h"

namespace ringtol::sampling {

// One reading of a roundness tester.
struct ProfileSample {
  double angle = 0.0;  // [rad] from +x counter-clockwise; any finite number, wrapped to one turn
  double value = 0.0;  // [m] radius, or radial deviation from a nominal radius
};

struct FourierFit {
  double mean = 0.0;  // [m] order-0 coefficient a_0
  // Orders 1..max_order, in order: amplitude C_n >= 0 [m], phase phi_n in (-pi, pi] [rad]
  // as in C_n cos(n theta + phi_n); phase 0 where C_n = 0.
  std::vector<engine::Harmonic> harmonics;
  // [m] standard error of C_n, index n - 1, from the least-squares covariance
  // s^2 (A^T A)^-1 with s^2 = SS_res / (points - unknowns), propagated to C_n by the delta
  // method (where C_n = 0 and the amplitude has no gradient, the root mean square of the
  // standard errors of a_n and b_n). NaN when points == unknowns (2N + 1): an
  // interpolation leaves no residual to estimate the noise from.
  std::vector<double> amplitude_standard_errors;
  double r_squared = 1.0;     // [-] 1 - SS_res / SS_tot, SS_tot about the mean value; 1 when SS_tot = 0
  double residual_rms = 0.0;  // [m] sqrt(SS_res / points)
  double residual_max = 0.0;  // [m] largest |residual|
  // [rad] largest angle between neighbouring distinct sample angles, including the one
  // across the end of the turn: where the outline is not measured.
  double largest_gap = 0.0;
  double condition_number = 1.0;  // [-] largest / smallest singular value of the design matrix
  int points = 0;                 // samples used, repeats included
};

// Beyond this condition number the design matrix counts as rank-deficient. Coefficient
// errors grow like condition number x (rounding or noise in the values): at 1e10 the
// eps = 2.2e-16 rounding of the data already costs 6 of 16 digits. Fits below it can
// still be poor: the standard errors show how much noise they amplify.
inline constexpr double kMaxFitConditionNumber = 1e10;

// The largest least-squares matrix a fit builds, points x (2 max_order + 1) [-]: with its
// SVD factor about 1 GB. A tester's export of a few thousand points fits hundreds of
// orders within it; a larger one is refused before any allocation rather than left to
// fail for memory.
inline constexpr double kMaxFitMatrixEntries = 64e6;

// Least-squares fit of orders 0..max_order to the samples. Throws std::invalid_argument,
// with a message for the person who took the measurement, when
//   - max_order < 1;
//   - the matrix would exceed kMaxFitMatrixEntries (the message says how many orders, or
//     every how many points, fit);
//   - an angle or a value is not finite (the message gives the sample's index);
//   - fewer than 2 max_order + 1 distinct angles (after wrapping) remain: the unknowns
//     outnumber the equations;
//   - the condition number exceeds kMaxFitConditionNumber, which happens when the
//     samples leave a gap too wide for the orders asked for (no data across the gap to
//     tell high orders apart); the message gives the gap in degrees and the highest
//     order that can be fitted to these samples.
FourierFit FitFourierSeries(std::span<const ProfileSample> samples, int max_order);

}  // namespace ringtol::sampling
