#include "engine/sensor.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace ringtol::engine {

SensorReading ReadSensor(const PolarProfile& ring, const BodyPose& ring_pose, double sensor_angle,
                         double theta_guess) {
  // f(theta) = cross(e_s, c + r(theta) e(theta + psi)): the bore point's offset from the
  // ray. With the centre near the origin, f changes sign within +-90 deg of the ray.
  constexpr double kTolerance = 1e-14;  // [rad]
  constexpr int kMaxIterations = 100;
  const double cs = std::cos(sensor_angle);
  const double ss = std::sin(sensor_angle);
  const double centre_cross = cs * ring_pose.centre.y() - ss * ring_pose.centre.x();
  const double aim = sensor_angle - ring_pose.angle;
  double lo = aim - std::numbers::pi / 2.0;
  double hi = aim + std::numbers::pi / 2.0;
  double theta = theta_guess;
  if (!(theta > lo && theta < hi)) theta = aim + std::remainder(theta_guess - aim, 2.0 * std::numbers::pi);
  if (!(theta > lo && theta < hi)) theta = aim;
  const double cos_aim = std::cos(aim);
  const double sin_aim = std::sin(aim);
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    const RadiusDerivatives d = ring.Evaluate(theta);
    // sin and cos of theta - aim from the sincos Evaluate already took.
    const double s = d.sin_theta * cos_aim - d.cos_theta * sin_aim;  // cross(e_s, e(theta + psi))
    const double c = d.cos_theta * cos_aim + d.sin_theta * sin_aim;
    const double f = centre_cross + d.r * s;
    const double df = d.dr * s + d.r * c;
    if (f < 0.0) lo = theta; else hi = theta;
    const double step = -f / df;
    if (df > 0.0 && std::abs(step) <= kTolerance) {
      theta += step;
      break;
    }
    double next = theta + step;
    if (!(df > 0.0) || !(next > lo && next < hi)) next = 0.5 * (lo + hi);
    theta = next;
  }
  const double r = ring.Evaluate(theta).r;
  const double along = cs * ring_pose.centre.x() + ss * ring_pose.centre.y() + r * std::cos(theta - aim);
  return {along, theta};
}

Runout MeasureRunout(std::span<const double> signal) {
  Runout runout;
  if (signal.empty()) return runout;
  const auto [min_it, max_it] = std::minmax_element(signal.begin(), signal.end());
  runout.total = *max_it - *min_it;
  if (runout.total == 0.0) return runout;
  // Walk once around the periodic signal starting at the global maximum, recording the
  // value at every change of direction; neighbouring extremes then alternate.
  const std::size_t n = signal.size();
  const auto start = static_cast<std::size_t>(max_it - signal.begin());
  std::vector<double> extremes{signal[start]};
  int direction = -1;  // leaving the global maximum, the signal first falls (or plateaus)
  double last = signal[start];
  for (std::size_t k = 1; k <= n; ++k) {
    const double value = signal[(start + k) % n];
    if (value == last) continue;
    const int now = value > last ? 1 : -1;
    if (now != direction) {
      extremes.push_back(last);
      direction = now;
    }
    last = value;
  }
  extremes.push_back(signal[start]);
  for (std::size_t k = 1; k < extremes.size(); ++k) {
    runout.peak_to_nearest_valley = std::max(runout.peak_to_nearest_valley, std::abs(extremes[k] - extremes[k - 1]));
  }
  return runout;
}

}  // namespace ringtol::engine
