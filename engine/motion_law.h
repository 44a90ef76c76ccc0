// The ring's imposed rotation angle psi(t): a piecewise law of constant-acceleration
// segments, so that angle, rate and acceleration are closed forms everywhere and the
// integrator can restart exactly where the acceleration or the rate jumps.
//
// Segment j starts at t_j = sum of the earlier durations, with the rate it is given
// (start_rate) or, when that is unset, the rate the previous segment ended with (0 before
// the first). Its rate is then rate_j + a_j (t - t_j). After the last segment the ring
// keeps the last rate forever: a law that ends at rest stays at rest. Before t = 0 the
// ring is at rest at psi = 0.
#pragma once

#include <limits>
#include <numbers>
#include <optional>
#include <vector>

namespace ringtol::engine {

struct MotionSegment {
  double duration = 0.0;      // [s] > 0, finite
  double acceleration = 0.0;  // [rad/s^2] finite; negative slows, and reverses past rest
  // [rad/s] rate at the segment's start, finite; unset continues the previous segment's
  // end rate, a value makes a step in rate (the article's law starts with one).
  std::optional<double> start_rate;

  bool operator==(const MotionSegment&) const = default;
};

class MotionLaw {
 public:
  // Throws std::invalid_argument naming the first bad segment (index from 0) when the
  // list is empty, a duration is not positive and finite, or a rate or acceleration is
  // not finite.
  explicit MotionLaw(std::vector<MotionSegment> segments);

  double Angle(double t) const;         // [rad]   continuous
  double Rate(double t) const;          // [rad/s] right-continuous at a step
  double Acceleration(double t) const;  // [rad/s^2] right-continuous

  // [s] every segment boundary after t = 0 (the end of the last segment included), in
  // increasing order: where the rate or the acceleration may jump.
  const std::vector<double>& Breakpoints() const { return ends_; }

  // [s] the sum of the segment durations.
  double Duration() const { return ends_.back(); }

  // [s] the earliest t >= t_from with Angle(t) == psi; +inf when the ring never gets
  // there (it stops short, or turns the other way for good).
  double TimeAtAngle(double psi, double t_from = 0.0) const;

  // [s] the first time the ring is not at rest: where the rate leaves zero, by a step or
  // by an acceleration; +inf when it never turns.
  double RotationStart() const;

  const std::vector<MotionSegment>& segments() const { return segments_; }

  // Segment by segment, for an integrator that must not see a jump inside a step: the
  // index of the segment that holds t (t in [start, end); segments().size() after the
  // last), and the rate of segment j's own polynomial at any t, continued past its ends.
  // Rate(t) == RateIn(SegmentAt(t), t).
  std::size_t SegmentAt(double t) const;
  double AngleIn(std::size_t j, double t) const;  // [rad]
  double RateIn(std::size_t j, double t) const;   // [rad/s]

  friend bool operator==(const MotionLaw&, const MotionLaw&) = default;

 private:
  std::vector<MotionSegment> segments_;
  std::vector<double> starts_;       // [s]
  std::vector<double> ends_;         // [s]
  std::vector<double> start_angle_;  // [rad]
  std::vector<double> start_rate_;   // [rad/s] resolved
  double end_angle_ = 0.0;           // [rad] after the last segment
  double end_rate_ = 0.0;            // [rad/s]
};

// The article's law (its Eq. 1): at rest for `settle` [s] while the ring settles under
// the preload (no rest when 0), then a step to `rate` [rad/s] (negative turns the ring
// clockwise) held for `revolutions` turns (and on).
MotionLaw ArticleLaw(double settle = 0.5, double rate = 1.5 * std::numbers::pi, double revolutions = 3.0);

// The test bench's trapezoid: at rest for `settle` [s], then 810 deg/s^2 over 45 deg, 270
// deg/s over 810 deg and 810 deg/s^2 down over 45 deg: 2.5 revolutions, ending at rest.
MotionLaw TestBenchLaw(double settle = 0.5);

}  // namespace ringtol::engine
