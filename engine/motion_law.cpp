#include "engine/motion_law.h"
#include "engine/units.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ringtol::engine {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Smallest dt in [lo, hi] with c + r dt + a dt^2 / 2 = 0, or +inf. The roots come from
// the cancellation-free form of the quadratic formula; a root that rounding puts a few
// ulps outside the interval still counts, clamped into it.
double FirstRoot(double c, double r, double a, double lo, double hi) {
  const double scale = std::max({1.0, lo, std::isfinite(hi) ? hi : 0.0});
  const double slack = 8.0 * std::numeric_limits<double>::epsilon() * scale;
  double roots[2] = {kInfinity, kInfinity};
  if (a == 0.0) {
    if (r != 0.0) roots[0] = -c / r;
    else if (c == 0.0) roots[0] = lo;
  } else {
    const double discriminant = r * r - 2.0 * a * c;
    if (discriminant < 0.0) return kInfinity;
    const double q = -0.5 * (r + std::copysign(std::sqrt(discriminant), r));
    if (q != 0.0) {
      roots[0] = q / (0.5 * a);
      roots[1] = c / q;
    } else {
      roots[0] = 0.0;  // r = 0 and c = 0: the double root at dt = 0
    }
  }
  double best = kInfinity;
  for (const double root : roots) {
    if (root >= lo - slack && root <= hi + slack) best = std::min(best, std::clamp(root, lo, hi));
  }
  return best;
}

}  // namespace

MotionLaw::MotionLaw(std::vector<MotionSegment> segments) : segments_(std::move(segments)) {
  if (segments_.empty()) throw std::invalid_argument("a motion law needs at least one segment");
  double t = 0.0;
  double angle = 0.0;
  double rate = 0.0;
  for (std::size_t j = 0; j < segments_.size(); ++j) {
    const MotionSegment& s = segments_[j];
    const std::string where = "motion segment " + std::to_string(j) + ": ";
    if (!(std::isfinite(s.duration) && s.duration > 0.0)) {
      throw std::invalid_argument(where + "duration must be positive and finite, got " + std::to_string(s.duration));
    }
    if (!std::isfinite(s.acceleration)) throw std::invalid_argument(where + "acceleration must be finite");
    if (s.start_rate && !std::isfinite(*s.start_rate)) throw std::invalid_argument(where + "start rate must be finite");
    if (s.start_rate) rate = *s.start_rate;
    starts_.push_back(t);
    start_angle_.push_back(angle);
    start_rate_.push_back(rate);
    angle += rate * s.duration + 0.5 * s.acceleration * s.duration * s.duration;
    rate += s.acceleration * s.duration;
    t += s.duration;
    ends_.push_back(t);
  }
  end_angle_ = angle;
  end_rate_ = rate;
}

std::size_t MotionLaw::SegmentAt(double t) const {
  if (t >= ends_.back()) return segments_.size();
  if (t <= 0.0) return 0;
  return static_cast<std::size_t>(std::upper_bound(starts_.begin(), starts_.end(), t) - starts_.begin()) - 1;
}

double MotionLaw::AngleIn(std::size_t j, double t) const {
  if (j >= segments_.size()) return end_angle_ + end_rate_ * (t - ends_.back());
  const double dt = t - starts_[j];
  return start_angle_[j] + start_rate_[j] * dt + 0.5 * segments_[j].acceleration * dt * dt;
}

double MotionLaw::RateIn(std::size_t j, double t) const {
  if (j >= segments_.size()) return end_rate_;
  return start_rate_[j] + segments_[j].acceleration * (t - starts_[j]);
}

double MotionLaw::Angle(double t) const { return t <= 0.0 ? 0.0 : AngleIn(SegmentAt(t), t); }

double MotionLaw::Rate(double t) const { return t < 0.0 ? 0.0 : RateIn(SegmentAt(t), t); }

double MotionLaw::Acceleration(double t) const {
  const std::size_t j = SegmentAt(t);
  return t < 0.0 || j >= segments_.size() ? 0.0 : segments_[j].acceleration;
}

double MotionLaw::TimeAtAngle(double psi, double t_from) const {
  t_from = std::max(t_from, 0.0);
  for (std::size_t j = 0; j < segments_.size(); ++j) {
    if (ends_[j] < t_from) continue;
    const double lo = std::max(0.0, t_from - starts_[j]);
    const double dt =
        FirstRoot(start_angle_[j] - psi, start_rate_[j], segments_[j].acceleration, lo, segments_[j].duration);
    if (std::isfinite(dt)) return starts_[j] + dt;
  }
  const double lo = std::max(0.0, t_from - ends_.back());
  const double dt = FirstRoot(end_angle_ - psi, end_rate_, 0.0, lo, kInfinity);
  return std::isfinite(dt) ? ends_.back() + dt : kInfinity;
}

double MotionLaw::RotationStart() const {
  for (std::size_t j = 0; j < segments_.size(); ++j) {
    if (start_rate_[j] != 0.0 || segments_[j].acceleration != 0.0) return starts_[j];
  }
  return end_rate_ != 0.0 ? ends_.back() : kInfinity;
}

namespace {

// A law that first holds the ring still for `settle` [s] (no segment when settle is 0).
MotionLaw AfterSettle(double settle, std::vector<MotionSegment> motion) {
  if (settle != 0.0) motion.insert(motion.begin(), {.duration = settle, .acceleration = 0.0, .start_rate = 0.0});
  return MotionLaw(std::move(motion));
}

}  // namespace

MotionLaw ArticleLaw(double settle, double rate, double revolutions) {
  return AfterSettle(settle, {{.duration = revolutions * 2.0 * std::numbers::pi / std::abs(rate), .acceleration = 0.0,
                               .start_rate = rate}});
}

MotionLaw TestBenchLaw(double settle) {
  constexpr double kAcceleration = 810.0 * units::kRadiansPerDegree;  // [rad/s^2]
  constexpr double kRate = 270.0 * units::kRadiansPerDegree;          // [rad/s]
  constexpr double kRamp = kRate / kAcceleration;    // [s] 1/3 s: 45 deg at mean 135 deg/s
  constexpr double kCruise = 810.0 * units::kRadiansPerDegree / kRate;  // [s] 3 s
  return AfterSettle(settle, {{.duration = kRamp, .acceleration = kAcceleration, .start_rate = 0.0},
                              {.duration = kCruise, .acceleration = 0.0, .start_rate = std::nullopt},
                              {.duration = kRamp, .acceleration = -kAcceleration, .start_rate = std::nullopt}});
}

}  // namespace ringtol::engine
