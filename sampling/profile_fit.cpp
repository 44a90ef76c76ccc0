#include "sampling/profile_fit.h"
#include "engine/units.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <iterator>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SVD>

namespace ringtol::sampling {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTurn = 2.0 * kPi;

// Numbers in messages. sampling/ prints nothing and uses no fmt, so std::to_chars: the
// shortest text that reads back as the same double, or a fixed number of digits.
std::string Show(double value) {
  char buffer[32];
  return {buffer, std::to_chars(std::begin(buffer), std::end(buffer), value).ptr};
}

std::string Show(double value, std::chars_format format, int digits) {
  char buffer[64];
  return {buffer, std::to_chars(std::begin(buffer), std::end(buffer), value, format, digits).ptr};
}

// Into [0, 2 pi): fmod is exact, and a tiny negative angle plus a turn rounds up to a
// whole turn, which is angle 0.
double WrapAngle(double angle) {
  double wrapped = std::fmod(angle, kTurn);
  if (wrapped < 0.0) wrapped += kTurn;
  return wrapped < kTurn ? wrapped : 0.0;
}

// Columns 1, cos theta, -sin theta, cos 2 theta, -sin 2 theta, ...: the unknowns are then
// a_0, a_1, b_1, a_2, b_2, ... of the header's model.
Eigen::MatrixXd DesignMatrix(const std::vector<double>& angles, int max_order) {
  Eigen::MatrixXd design(static_cast<Eigen::Index>(angles.size()), 2 * max_order + 1);
  for (Eigen::Index i = 0; i < design.rows(); ++i) {
    const double theta = angles[static_cast<std::size_t>(i)];
    design(i, 0) = 1.0;
    for (int n = 1; n <= max_order; ++n) {
      design(i, 2 * n - 1) = std::cos(n * theta);
      design(i, 2 * n) = -std::sin(n * theta);
    }
  }
  return design;
}

double ConditionNumber(const Eigen::VectorXd& singular_values) {
  const double smallest = singular_values(singular_values.size() - 1);
  return smallest > 0.0 ? singular_values(0) / smallest : std::numeric_limits<double>::infinity();
}

double LargestGap(std::vector<double> angles) {
  std::sort(angles.begin(), angles.end());
  double gap = kTurn - angles.back() + angles.front();
  for (std::size_t i = 1; i < angles.size(); ++i) gap = std::max(gap, angles[i] - angles[i - 1]);
  return gap;
}

// The highest order below max_order whose design is well-conditioned, 0 if none. The
// design of order k is the first 2k + 1 columns of the full one; dropping columns can
// only lower the largest singular value and raise the smallest (interlacing), so the
// condition number grows with the order and bisection finds the answer.
int HighestWellConditionedOrder(const Eigen::MatrixXd& design, int max_order) {
  int good = 0;  // order 0, the constant column alone, has condition number 1
  int bad = max_order;
  while (bad - good > 1) {
    const int order = good + (bad - good) / 2;
    const Eigen::BDCSVD<Eigen::MatrixXd> svd(design.leftCols(2 * order + 1));
    (ConditionNumber(svd.singularValues()) <= kMaxFitConditionNumber ? good : bad) = order;
  }
  return good;
}

[[noreturn]] void FailIllConditioned(const Eigen::MatrixXd& design, int max_order, double condition,
                                     double largest_gap) {
  const int feasible = HighestWellConditionedOrder(design, max_order);
  std::string message = "fitting orders up to " + std::to_string(max_order) +
                        " is numerically rank-deficient (condition number " +
                        Show(condition, std::chars_format::scientific, 2) + " > " + Show(kMaxFitConditionNumber) +
                        "): the samples leave a gap of " +
                        Show(largest_gap * units::kDegreesPerRadian, std::chars_format::fixed, 1) +
                        " degrees without data, too wide to tell orders this high apart; ";
  message += feasible > 0 ? "fit fewer orders (up to " + std::to_string(feasible) +
                                " is well-conditioned on these samples) or measure across the gap"
                          : "no order can be fitted to these samples: measure across the gap";
  throw std::invalid_argument(message);
}

}  // namespace

FourierFit FitFourierSeries(std::span<const ProfileSample> samples, int max_order) {
  if (max_order < 1) {
    throw std::invalid_argument("a Fourier fit needs orders up to at least 1; got max_order = " +
                                std::to_string(max_order));
  }
  std::vector<double> angles;
  angles.reserve(samples.size());
  Eigen::VectorXd values(static_cast<Eigen::Index>(samples.size()));
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const ProfileSample& sample = samples[i];
    if (!std::isfinite(sample.angle) || !std::isfinite(sample.value)) {
      throw std::invalid_argument("sample " + std::to_string(i) + " (angle " + Show(sample.angle) + " rad, value " +
                                  Show(sample.value) + " m) is not finite; every angle and value must be finite");
    }
    angles.push_back(WrapAngle(sample.angle));
    values(static_cast<Eigen::Index>(i)) = sample.value;
  }

  std::vector<double> distinct = angles;
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  const long long unknowns = 2LL * max_order + 1;  // long long: no overflow for any int order
  if (static_cast<long long>(distinct.size()) < unknowns) {
    throw std::invalid_argument("fitting orders up to " + std::to_string(max_order) + " needs at least 2*" +
                                std::to_string(max_order) + "+1 = " + std::to_string(unknowns) +
                                " points at distinct angles; got " + std::to_string(distinct.size()));
  }

  const double entries = static_cast<double>(samples.size()) * static_cast<double>(unknowns);
  if (entries > kMaxFitMatrixEntries) {
    const long long most_orders =
        static_cast<long long>((kMaxFitMatrixEntries / static_cast<double>(samples.size()) - 1.0) / 2.0);
    throw std::invalid_argument(
        "fitting orders up to " + std::to_string(max_order) + " to " + std::to_string(samples.size()) +
        " points needs a " + std::to_string(samples.size()) + " x " + std::to_string(unknowns) +
        " least-squares matrix and its factor (" +
        Show(2.0 * entries * sizeof(double) / 1e9, std::chars_format::fixed, 1) + " GB); at most " +
        std::to_string(static_cast<long long>(kMaxFitMatrixEntries)) + " entries: " +
        (most_orders >= 1 ? "orders up to " + std::to_string(most_orders) + " at these points, or " : std::string()) +
        "every " + std::to_string(static_cast<long long>(std::ceil(entries / kMaxFitMatrixEntries))) +
        "th point at these orders");
  }

  FourierFit fit;
  fit.points = static_cast<int>(samples.size());
  fit.largest_gap = LargestGap(std::move(distinct));

  const Eigen::MatrixXd design = DesignMatrix(angles, max_order);
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(design, Eigen::ComputeThinU | Eigen::ComputeThinV);
  fit.condition_number = ConditionNumber(svd.singularValues());
  if (!(fit.condition_number <= kMaxFitConditionNumber)) {
    FailIllConditioned(design, max_order, fit.condition_number, fit.largest_gap);
  }

  // Fit the deviations from the mean value rather than the values: on a radius of 0.1 m
  // the harmonics are micrometres, and the solver's rounding scales with what it is given.
  const double centre = values.mean();
  const Eigen::VectorXd centred = values.array() - centre;
  const Eigen::VectorXd coefficients = svd.solve(centred);
  const Eigen::VectorXd residuals = centred - design * coefficients;

  const double ss_res = residuals.squaredNorm();
  const double ss_tot = centred.squaredNorm();
  fit.mean = centre + coefficients(0);
  fit.r_squared = ss_tot > 0.0 ? 1.0 - ss_res / ss_tot : 1.0;
  fit.residual_rms = std::sqrt(ss_res / static_cast<double>(fit.points));
  fit.residual_max = residuals.cwiseAbs().maxCoeff();

  // Covariance s^2 (A^T A)^-1 = s^2 W W^T with W = V Sigma^-1; only its 2x2 blocks of
  // (a_n, b_n) are needed, one pair of rows of W each.
  const long long spare = static_cast<long long>(samples.size()) - unknowns;
  const double residual_variance =
      spare > 0 ? ss_res / static_cast<double>(spare) : std::numeric_limits<double>::quiet_NaN();
  const Eigen::MatrixXd w = svd.matrixV() * svd.singularValues().cwiseInverse().asDiagonal();

  for (int n = 1; n <= max_order; ++n) {
    const double a = coefficients(2 * n - 1);
    const double b = coefficients(2 * n);
    const double amplitude = std::hypot(a, b);
    double phase = std::atan2(b, a);
    if (phase <= -kPi) phase = kPi;  // the header promises (-pi, pi]
    fit.harmonics.push_back({n, amplitude, phase});

    const double var_a = residual_variance * w.row(2 * n - 1).squaredNorm();
    const double var_b = residual_variance * w.row(2 * n).squaredNorm();
    const double cov_ab = residual_variance * w.row(2 * n - 1).dot(w.row(2 * n));
    const double var_amplitude =
        amplitude > 0.0 ? (a * a * var_a + 2.0 * a * b * cov_ab + b * b * var_b) / (amplitude * amplitude)
                        : 0.5 * (var_a + var_b);
    fit.amplitude_standard_errors.push_back(std::sqrt(std::max(var_amplitude, 0.0)));
  }
  return fit;
}

}  // namespace ringtol::sampling
