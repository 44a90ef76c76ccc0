#include "engine/sensor.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace ringtol::engine {

SensorReading ReadSensor(const PolarProfile& ring, const BodyPose& ring_pose, double sensor_angle,
                         double theta_guess, SensorTrack* track) {
  SensorTrack local;
  SensorTrack& trig = track != nullptr ? *track : local;
  // f(theta) = cross(e_s, c + r(theta) e(theta + psi)): the bore point's offset from the
  // ray. With the centre near the origin, f changes sign within +-90 deg of the ray.
  constexpr double kTolerance = 1e-14;  // [rad]
  constexpr int kMaxIterations = 100;
  double cs = 1.0;
  double ss = 0.0;
  trig.sensor.Evaluate(sensor_angle, cs, ss);
  const double centre_cross = cs * ring_pose.centre.y() - ss * ring_pose.centre.x();
  const double aim = sensor_angle - ring_pose.angle;
  double lo = aim - std::numbers::pi / 2.0;
  double hi = aim + std::numbers::pi / 2.0;
  double theta = theta_guess;
  if (!(theta > lo && theta < hi)) theta = aim + std::remainder(theta_guess - aim, 2.0 * std::numbers::pi);
  if (!(theta > lo && theta < hi)) theta = aim;
  double cos_aim = 1.0;
  double sin_aim = 0.0;
  trig.aim.Evaluate(aim, cos_aim, sin_aim);
  RadiusDerivatives d;
  double s = 0.0;  // sin(theta - aim) = cross(e_s, e(theta + psi))
  double c = 1.0;  // cos(theta - aim)
  double step = 0.0;
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    double cos_theta = 1.0;
    double sin_theta = 0.0;
    trig.bore.Evaluate(theta, cos_theta, sin_theta);
    d = ring.EvaluateAt(theta, cos_theta, sin_theta);
    s = sin_theta * cos_aim - cos_theta * sin_aim;
    c = cos_theta * cos_aim + sin_theta * sin_aim;
    const double f = centre_cross + d.r * s;
    const double df = d.dr * s + d.r * c;
    if (f < 0.0) lo = theta; else hi = theta;
    step = -f / df;
    // Newton's next correction would be about f'' / (2 f') step^2 (plus ~step^3 / 6
    // where f'' vanishes, as on a circle): once that is below the tolerance, this step
    // is the last one needed, and is taken by Taylor series below.
    constexpr double kShortStep = 1e-5;  // [rad] step^3 / 6 ~ 2e-16
    const double ddf = (d.ddr - d.r) * s + 2.0 * d.dr * c;
    if (df > 0.0 && std::abs(step) <= kShortStep && std::abs(ddf / (2.0 * df)) * step * step <= kTolerance) break;
    double next = theta + step;
    if (!(df > 0.0) || !(next > lo && next < hi)) next = 0.5 * (lo + hi);
    theta = next;
    step = 0.0;
  }
  // The last Newton step taken by Taylor series rather than another evaluation: the
  // terms left out are third order in it, ~r step^3 / 6 < 1e-16 m.
  const double half_step2 = 0.5 * step * step;
  const double r = d.r + d.dr * step + d.ddr * half_step2;
  const double along = cs * ring_pose.centre.x() + ss * ring_pose.centre.y() + r * (c * (1.0 - half_step2) - s * step);
  return {along, theta + step};
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
