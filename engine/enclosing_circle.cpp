#include "engine/enclosing_circle.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

namespace ringtol::engine {
namespace {

using Point = Eigen::Vector2d;

// A point counts as inside when it is within kInsideSlack * (radius + scale) of the
// circle. Without slack, points that lie on the circle up to rounding (co-circular inputs,
// the defining points themselves) keep restarting the inner loops and the expected O(n)
// degrades towards O(n^3). The slack is a few hundred ulps of the problem scale: well above
// the rounding of the circle constructions below, yet it bounds how much larger than the
// exact MEC the result can be; the final radius pass removes its effect on containment.
// (16 ulps already makes exactly co-circular input measurably slower.)
constexpr double kInsideSlack = 256.0 * std::numeric_limits<double>::epsilon();

// A triple whose cross product is this small relative to its longest squared side is
// treated as collinear: its circumcircle would be enormous and dominated by rounding, and
// such a circle never bounds a minimum enclosing circle in exact arithmetic.
constexpr double kCollinearRatio = 1e-12;

// Fixed seed so every run and every platform shuffles identically.
constexpr std::uint64_t kShuffleSeed = 0x5eed;

// SplitMix64: fully specified here, so unlike std::shuffle with
// std::uniform_int_distribution its sequence does not depend on the standard library, and
// it needs no 2.5 kB state to seed on every call as std::mt19937_64 would.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}

  std::uint64_t Next() {
    state_ += 0x9e3779b97f4a7c15ULL;
    std::uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }

  // Uniform in [0, bound) up to a bias below bound / 2^32, harmless for an order that only
  // needs to be random enough to keep the expected cost linear. Multiply-shift on the high
  // 32 bits (exact in 64-bit arithmetic) instead of a 64-bit division halves the cost of
  // the shuffle; the division remains for sets beyond 2^32 points.
  std::size_t Below(std::size_t bound) {
    const std::uint64_t r = Next();
    const auto b = static_cast<std::uint64_t>(bound);
    if (b <= (std::uint64_t{1} << 32)) return static_cast<std::size_t>(((r >> 32) * b) >> 32);
    return static_cast<std::size_t>(r % b);
  }

 private:
  std::uint64_t state_;
};

// Circle in the translated frame, with the squared acceptance radius precomputed because
// the containment test runs once per point per loop.
struct LocalCircle {
  Point centre;
  double radius;
  double accept_squared;
};

class Builder {
 public:
  explicit Builder(double scale) : scale_(scale) {}

  LocalCircle Make(const Point& centre, double radius) const {
    const double accept = radius + kInsideSlack * (radius + scale_);
    return {centre, radius, accept * accept};
  }

  static bool Contains(const LocalCircle& c, const Point& p) {
    return (p - c.centre).squaredNorm() <= c.accept_squared;
  }

  LocalCircle Diameter(const Point& a, const Point& b) const {
    const Point centre = 0.5 * (a + b);
    // The larger of the two rounded distances, so both ends are inside by construction.
    return Make(centre, std::sqrt(std::max((a - centre).squaredNorm(), (b - centre).squaredNorm())));
  }

  LocalCircle Circumcircle(const Point& a, const Point& b, const Point& c) const {
    // Solved relative to a: the differences keep the significant digits that absolute
    // coordinates would spend on the common offset.
    const Point u = b - a;
    const Point v = c - a;
    const double uu = u.squaredNorm();
    const double vv = v.squaredNorm();
    const double ww = (c - b).squaredNorm();
    const double cross = u.x() * v.y() - u.y() * v.x();
    if (std::abs(cross) <= kCollinearRatio * std::max({uu, vv, ww})) {
      // Nearly collinear: the circle through the two extreme points contains the third.
      if (uu >= vv && uu >= ww) return Diameter(a, b);
      if (vv >= ww) return Diameter(a, c);
      return Diameter(b, c);
    }
    const double inv = 0.5 / cross;
    const Point offset((v.y() * uu - u.y() * vv) * inv, (u.x() * vv - v.x() * uu) * inv);
    const Point centre = a + offset;
    const double r2 = std::max({(a - centre).squaredNorm(), (b - centre).squaredNorm(),
                                (c - centre).squaredNorm()});
    return Make(centre, std::sqrt(r2));
  }

 private:
  double scale_;
};

}  // namespace

Circle MinimumEnclosingCircle(std::span<const Point> points) {
  if (points.empty()) {
    throw std::invalid_argument("MinimumEnclosingCircle: the point set is empty");
  }
  const std::size_t n = points.size();

  // Copy, translate to the first point and shuffle in one pass (inside-out Fisher-Yates).
  // The translation makes every later difference and the slack relative to the set's
  // extent rather than to its distance from the origin.
  const Point origin = points.front();
  std::vector<Point> q(n);
  SplitMix64 random(kShuffleSeed);
  double scale = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!points[i].allFinite()) {
      throw std::invalid_argument("MinimumEnclosingCircle: non-finite coordinate");
    }
    const Point local = points[i] - origin;
    scale = std::max(scale, local.cwiseAbs().maxCoeff());
    const std::size_t j = random.Below(i + 1);
    if (j != i) q[i] = q[j];
    q[j] = local;
  }

  // Invariant of each loop: c is the smallest circle containing the points visited so far
  // with the loop's fixed points on its boundary (Welzl's lemma).
  const Builder builder(scale);
  LocalCircle c = builder.Make(q[0], 0.0);
  for (std::size_t i = 1; i < n; ++i) {
    if (Builder::Contains(c, q[i])) continue;
    c = builder.Make(q[i], 0.0);
    for (std::size_t j = 0; j < i; ++j) {
      if (Builder::Contains(c, q[j])) continue;
      c = builder.Diameter(q[i], q[j]);
      for (std::size_t k = 0; k < j; ++k) {
        if (Builder::Contains(c, q[k])) continue;
        c = builder.Circumcircle(q[i], q[j], q[k]);
      }
    }
  }

  // Radius from the caller's own points and the returned centre, so containment holds
  // exactly for anyone who checks (p - centre).norm() <= radius. sqrt is monotonic, so the
  // square root of the largest squared distance is the largest distance.
  Circle result;
  result.centre = origin + c.centre;
  double max_squared = 0.0;
  for (const Point& p : points) {
    max_squared = std::max(max_squared, (p - result.centre).squaredNorm());
  }
  result.radius = std::sqrt(max_squared);
  return result;
}

}  // namespace ringtol::engine
