#include "solvers/life.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <iterator>
#include <limits>
#include <numeric>
#include <ranges>
#include <span>
#include <stdexcept>
#include <vector>

#include "engine/check.h"
#include "engine/enclosing_circle.h"
#include "engine/sensor.h"
#include "engine/units.h"

namespace ringtol::solvers {
namespace {

// A curve's hull is sampled finely enough that the curve strays from the samples' chords
// by at most this share of the sum of its terms' amplitudes; the hull is then widened by
// what it may miss, so it always holds the curve.
constexpr double kCurveStraying = 2e-4;
// The most samples a curve's hull takes per order of its fastest term: (2 pi / 128)^2 / 8,
// 3e-4 of the term's amplitude.
constexpr int kMostCurveSamplesPerOrder = 128;
// Spin ratios this close (relative) are one: phase-locked rollers of equal diameters turn
// in step.
constexpr double kSameRatio = 1e-12;

// The lobes of the rollers whose phases move together, as one closed curve in their common
// phase u = ratio psi: sum over terms of cosine cos(order u) + sine sin(order u) [m]. One
// roller's unless the scene locks the rollers' phases.
struct PhaseCurve {
  double ratio = 0.0;  // engine::SpinRatio of its rollers
  int roller = 0;      // its (first) roller
  std::vector<int> order;
  std::vector<Eigen::Vector2d> cosine, sine;
  int max_order = 0;

  Eigen::Vector2d At(double u) const {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    const std::complex<double> step = std::polar(1.0, u);
    std::complex<double> power = 1.0;
    int power_order = 0;
    for (std::size_t p = 0; p < order.size(); ++p) {
      if (order[p] < power_order) power = 1.0, power_order = 0;
      for (; power_order < order[p]; ++power_order) power *= step;
      sum += cosine[p] * power.real() + sine[p] * power.imag();
    }
    return sum;
  }

  // Calls visit(q, cos, sin) for u = u0 + q du, q = 0 .. count - 1, with the cosines and
  // sines of order[p] u for every term: each order's phasor turned by its step from one
  // angle to the next, from libm again every kAnchor angles so the recurrence's round-off
  // stays near 1e-14 of the amplitudes.
  template <typename Visit>
  void ForEachAngle(double u0, double du, std::size_t count, Visit visit) const {
    constexpr std::size_t kAnchor = 256;
    const std::size_t terms = order.size();
    // Cosine and sine parts apart: std::complex's product checks for infinities per call.
    std::vector<double> now_cos(terms), now_sin(terms), step_cos(terms), step_sin(terms);
    for (std::size_t p = 0; p < terms; ++p) {
      step_cos[p] = std::cos(order[p] * du);
      step_sin[p] = std::sin(order[p] * du);
    }
    for (std::size_t q = 0; q < count; ++q) {
      if (q % kAnchor == 0) {
        for (std::size_t p = 0; p < terms; ++p) {
          const double phase = order[p] * (u0 + du * static_cast<double>(q));
          now_cos[p] = std::cos(phase);
          now_sin[p] = std::sin(phase);
        }
      }
      visit(q, now_cos, now_sin);
      for (std::size_t p = 0; p < terms; ++p) {
        const double turned = now_cos[p] * step_cos[p] - now_sin[p] * step_sin[p];
        now_sin[p] = now_sin[p] * step_cos[p] + now_cos[p] * step_sin[p];
        now_cos[p] = turned;
      }
    }
  }

  // At(u0 + q du) for q = 0 .. count - 1, added to out[q].
  void AddAlong(double u0, double du, std::size_t count, std::vector<Eigen::Vector2d>& out) const {
    ForEachAngle(u0, du, count, [&](std::size_t q, const std::vector<double>& c, const std::vector<double>& s) {
      Eigen::Vector2d sum = Eigen::Vector2d::Zero();
      for (std::size_t p = 0; p < order.size(); ++p) sum += cosine[p] * c[p] + sine[p] * s[p];
      out[q] += sum;
    });
  }
};

// Each roller's lobes as a curve in its own phase; with `locked`, the rollers of one spin
// ratio as one curve, since they keep the relative phase they were assembled at.
std::vector<PhaseCurve> PhaseCurves(const PhasorSum& sum, bool locked) {
  std::vector<PhaseCurve> curves;
  for (std::size_t p = 0; p < sum.rates.size(); ++p) {
    if (sum.roller[p] < 0) continue;
    const double ratio = sum.rates[p] / sum.order[p];
    auto curve = std::find_if(curves.begin(), curves.end(), [&](const PhaseCurve& c) {
      return locked ? std::abs(c.ratio - ratio) <= kSameRatio * ratio : c.roller == sum.roller[p];
    });
    if (curve == curves.end()) curve = curves.insert(curves.end(), PhaseCurve{ratio, sum.roller[p], {}, {}, {}, 0});
    curve->order.push_back(sum.order[p]);
    curve->cosine.push_back(sum.cosine.col(static_cast<Eigen::Index>(p)).head<2>());
    curve->sine.push_back(sum.sine.col(static_cast<Eigen::Index>(p)).head<2>());
    curve->max_order = std::max(curve->max_order, sum.order[p]);
  }
  // At() walks the orders upwards.
  for (PhaseCurve& curve : curves) {
    std::vector<std::size_t> by_order(curve.order.size());
    for (std::size_t q = 0; q < by_order.size(); ++q) by_order[q] = q;
    std::ranges::sort(by_order, {}, [&](std::size_t q) { return curve.order[q]; });
    PhaseCurve sorted{curve.ratio, curve.roller, {}, {}, {}, curve.max_order};
    for (const std::size_t q : by_order) {
      sorted.order.push_back(curve.order[q]);
      sorted.cosine.push_back(curve.cosine[q]);
      sorted.sine.push_back(curve.sine[q]);
    }
    curve = std::move(sorted);
  }
  return curves;
}

// The curve as the error motion's filter passes it: a term of order o turns o ratio times
// a revolution of the ring.
PhaseCurve Filtered(PhaseCurve curve, const engine::ErrorMotionFilter& filter) {
  for (std::size_t p = 0; p < curve.order.size(); ++p) {
    const double transmission = filter.Transmission(curve.order[p] * curve.ratio);
    curve.cosine[p] *= transmission;
    curve.sine[p] *= transmission;
  }
  return curve;
}

// The curves whose phases repeat after `cycle` revolutions, and those that take every
// phase. Only phase-locked rollers repeat: a curve whose spin ratio is p/q with q <=
// kLongestCycle turns on by the same q phases for ever, as long as the rational curves'
// common cycle stays within kLongestCycle (else they all count as filling). Every other
// curve's phase, at any angle and in any revolution of that cycle, takes every value
// (Kronecker's theorem): independent rollers because slip and assembly set their phases,
// locked ones because their ratios are irrational.
struct CurveCycle {
  std::vector<PhaseCurve> repeating, filling;
  int cycle = 1;
};
CurveCycle SplitByCycle(std::vector<PhaseCurve> curves, bool locked) {
  CurveCycle split;
  if (!locked) {
    split.filling = std::move(curves);
    return split;
  }
  long cycle = 1;
  for (PhaseCurve& curve : curves) {
    int denominator = 0;
    for (int d = 1; d <= kLongestCycle && denominator == 0; ++d) {
      const double turns = curve.ratio * d;
      if (std::abs(turns - std::round(turns)) <= kSameRatio * turns) denominator = d;
    }
    if (denominator > 0) {
      cycle = std::lcm(cycle, static_cast<long>(denominator));
      split.repeating.push_back(std::move(curve));
    } else {
      split.filling.push_back(std::move(curve));
    }
  }
  if (cycle > kLongestCycle) {
    std::ranges::move(split.repeating, std::back_inserter(split.filling));
    split.repeating.clear();
    cycle = 1;
  }
  split.cycle = static_cast<int>(cycle);
  return split;
}

double Cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

// The convex hull's vertices, counter-clockwise (Andrew's monotone chain). Hand-written
// because Boost.Geometry's hull compares coordinates with a tolerance, which merges the
// vertices of a lobe's curve a few nanometres wide; here only the cross product's sign
// decides, so a hull of any size is exact to round-off.
std::vector<Eigen::Vector2d> ConvexHull(std::vector<Eigen::Vector2d> points) {
  std::ranges::sort(points, [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  if (points.size() < 3) return points;
  std::vector<Eigen::Vector2d> hull(2 * points.size());
  std::size_t k = 0;
  for (const Eigen::Vector2d& p : points) {
    while (k >= 2 && Cross(hull[k - 2], hull[k - 1], p) <= 0.0) --k;
    hull[k++] = p;
  }
  const std::size_t lower = k + 1;
  for (auto p = points.rbegin() + 1; p != points.rend(); ++p) {
    while (k >= lower && Cross(hull[k - 2], hull[k - 1], *p) <= 0.0) --k;
    hull[k++] = *p;
  }
  hull.resize(k - 1);
  return hull;
}

// Whether p lies in the counter-clockwise convex polygon `hull` (3 or more vertices) or on
// its boundary: the wedge at hull[0] holding p, found by bisection, then its far edge.
bool InHull(const std::vector<Eigen::Vector2d>& hull, const Eigen::Vector2d& p) {
  const std::size_t n = hull.size();
  if (Cross(hull[0], hull[1], p) < 0.0 || Cross(hull[0], hull[n - 1], p) > 0.0) return false;
  std::size_t low = 1, high = n - 1;
  while (high - low > 1) {
    const std::size_t middle = (low + high) / 2;
    (Cross(hull[0], hull[middle], p) >= 0.0 ? low : high) = middle;
  }
  return Cross(hull[low], hull[low + 1], p) >= 0.0;
}

// The convex hull of a densely sampled path: the hull of every few of its points first,
// then of that hull's vertices and the points outside it. Exact (a point in the hull of
// some points is in the hull of all), and cheaper than sorting every point wherever the
// path wanders inside its own hull.
std::vector<Eigen::Vector2d> PathHull(std::span<const Eigen::Vector2d> path) {
  constexpr std::size_t kFirstStride = 8;
  std::vector<Eigen::Vector2d> first;
  first.reserve(path.size() / kFirstStride + 1);
  for (std::size_t j = 0; j < path.size(); j += kFirstStride) first.push_back(path[j]);
  const std::vector<Eigen::Vector2d> inner = ConvexHull(std::move(first));
  if (inner.size() < 3) return ConvexHull(std::vector<Eigen::Vector2d>(path.begin(), path.end()));
  std::vector<Eigen::Vector2d> candidates = inner;
  for (std::size_t j = 0; j < path.size(); ++j) {
    if (j % kFirstStride != 0 && !InHull(inner, path[j])) candidates.push_back(path[j]);
  }
  return ConvexHull(std::move(candidates));
}

// The Minkowski sum of two convex polygons as ConvexHull gives them (counter-clockwise):
// their edges merged by direction, from the sum of their lowest vertices.
std::vector<Eigen::Vector2d> MinkowskiSum(std::vector<Eigen::Vector2d> a, std::vector<Eigen::Vector2d> b) {
  if (a.size() < 3 || b.size() < 3) {
    std::vector<Eigen::Vector2d> sums;
    for (const Eigen::Vector2d& p : a) {
      for (const Eigen::Vector2d& q : b) sums.push_back(p + q);
    }
    return ConvexHull(std::move(sums));
  }
  const auto lowest = [](std::vector<Eigen::Vector2d>& polygon) {
    std::ranges::rotate(polygon, std::ranges::min_element(polygon, [](const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
                          return p.y() < q.y() || (p.y() == q.y() && p.x() < q.x());
                        }));
  };
  lowest(a);
  lowest(b);
  const std::size_t na = a.size(), nb = b.size();
  a.push_back(a[0]);
  a.push_back(a[1]);
  b.push_back(b[0]);
  b.push_back(b[1]);
  std::vector<Eigen::Vector2d> sum;
  sum.reserve(na + nb);
  std::size_t i = 0, j = 0;
  while (i < na || j < nb) {
    sum.push_back(a[i] + b[j]);
    const Eigen::Vector2d edge_a = a[i + 1] - a[i], edge_b = b[j + 1] - b[j];
    const double turn = edge_a.x() * edge_b.y() - edge_a.y() * edge_b.x();
    if (turn >= 0.0 && i < na) ++i;
    if (turn <= 0.0 && j < nb) ++j;
  }
  return sum;
}

// Samples of a curve over one turn of its phase, and how far the curve strays from their
// chords [m]. A term of order o and amplitude A (an ellipse c cos + s sin: A = sqrt(|c|^2 +
// |s|^2) bounds its radius) strays by at most A min(2, (o du)^2 / 8) between samples du
// apart, so the step that keeps the sum within kCurveStraying of sum A is
// sqrt(8 kCurveStraying sum A / sum A o^2): the fast terms' amplitudes set it, not their
// orders alone. `looseness` >= 1 multiplies kCurveStraying and the cap's straying alike
// (Accuracy::kFast), dividing the samples by its square root.
struct CurveSamples {
  std::vector<Eigen::Vector2d> points;
  double straying = 0.0;  // [m]
  // [m] the curve's range along the sensor's ray through the error motion's filter (each
  // term scaled by its transmission at order x ratio turns a revolution), widened by
  // twice what the filtered curve may stray from the samples: an upper bound on it.
  double motion_range = 0.0;
};
CurveSamples SampleCurve(const PhaseCurve& curve, const Eigen::Vector2d& ray, const engine::ErrorMotionFilter& filter,
                         double looseness) {
  const std::size_t terms = curve.order.size();
  double amplitude = 0.0, weighted = 0.0;
  std::vector<double> amplitudes(terms), along_cos(terms), along_sin(terms), transmissions(terms);
  for (std::size_t p = 0; p < terms; ++p) {
    amplitudes[p] = std::hypot(curve.cosine[p].norm(), curve.sine[p].norm());
    amplitude += amplitudes[p];
    weighted += amplitudes[p] * curve.order[p] * curve.order[p];
    transmissions[p] = filter.Transmission(curve.order[p] * curve.ratio);
    along_cos[p] = transmissions[p] * ray.dot(curve.cosine[p]);
    along_sin[p] = transmissions[p] * ray.dot(curve.sine[p]);
  }
  constexpr int kFewest = 16;
  const auto per_order = static_cast<int>(std::ceil(kMostCurveSamplesPerOrder / std::sqrt(looseness)));
  const int most = per_order * std::max(curve.max_order, 1);
  const double share = looseness * kCurveStraying;
  const int count =
      weighted > 0.0
          ? std::clamp(static_cast<int>(std::ceil(units::kRadiansPerRevolution / std::sqrt(8.0 * share * amplitude / weighted))),
                       kFewest, most)
          : kFewest;
  const double du = units::kRadiansPerRevolution / count;
  CurveSamples samples{std::vector<Eigen::Vector2d>(static_cast<std::size_t>(count)), 0.0, 0.0};
  double low = std::numeric_limits<double>::infinity(), high = -low;
  curve.ForEachAngle(0.0, du, samples.points.size(),
                     [&](std::size_t q, const std::vector<double>& c, const std::vector<double>& s) {
                       Eigen::Vector2d point = Eigen::Vector2d::Zero();
                       double motion = 0.0;
                       for (std::size_t p = 0; p < terms; ++p) {
                         point += curve.cosine[p] * c[p] + curve.sine[p] * s[p];
                         motion += along_cos[p] * c[p] + along_sin[p] * s[p];
                       }
                       samples.points[q] = point;
                       low = std::min(low, motion);
                       high = std::max(high, motion);
                     });
  double filtered_straying = 0.0;
  for (std::size_t p = 0; p < terms; ++p) {
    const double chord = curve.order[p] * du;
    const double strays = amplitudes[p] * std::min(2.0, chord * chord / 8.0);
    samples.straying += strays;
    filtered_straying += transmissions[p] * strays;
  }
  samples.motion_range = high - low + 2.0 * filtered_straying;
  return samples;
}

// The lobes' first order at psi_j = 2 pi j / steps, j < steps, at the drawn phases [m].
std::vector<Eigen::Vector2d> LobesAt(const std::vector<PhaseCurve>& curves, std::size_t steps) {
  const double dpsi = units::kRadiansPerRevolution / static_cast<double>(steps);
  std::vector<Eigen::Vector2d> lobes(steps, Eigen::Vector2d::Zero());
  for (const PhaseCurve& curve : curves) curve.AddAlong(0.0, curve.ratio * dpsi, steps, lobes);
  return lobes;
}

// What the revolutions of a cycle are made of, revolution-major at psi_j = 2 pi j / steps:
// the curves that repeat, at their phases, on top of the centre less every curve (`rest`)
// and the signal less them; the axis motion from the same curves and rest through the
// error motion's filter.
struct CycleParts {
  const std::vector<PhaseCurve>& curves;
  std::span<const Eigen::Vector2d> rest;    // [m]
  std::span<const double> signal_rest;      // [m]
  const std::vector<PhaseCurve>& filtered;  // the curves through the filter
  std::span<const double> motion_rest;      // [m] the ray's component of `rest`, filtered
};
struct CycleRevolutions {
  std::vector<Eigen::Vector2d> turned;  // [m] the centre; empty where no curve repeats: `rest`
  std::vector<double> motion;           // [m] filtered
  double low = 0.0, high = 0.0;         // [m] the signal's extremes
};
CycleRevolutions OverCycle(const CycleParts& parts, const Eigen::Vector2d& ray, int revolutions) {
  const std::vector<PhaseCurve>& curves = parts.curves;
  const std::span<const Eigen::Vector2d> rest = parts.rest;
  const std::span<const double> signal_rest = parts.signal_rest;
  const std::size_t steps = rest.size();
  CycleRevolutions cycle;
  if (curves.empty()) {
    // One revolution, the path as it is: no copy of it on the campaigns' hot path.
    cycle.motion.assign(parts.motion_rest.begin(), parts.motion_rest.end());
    const auto [low, high] = std::ranges::minmax(signal_rest);
    cycle.low = low;
    cycle.high = high;
    return cycle;
  }
  const double dpsi = units::kRadiansPerRevolution / static_cast<double>(steps);
  cycle.turned.reserve(steps * static_cast<std::size_t>(revolutions));
  cycle.motion.reserve(cycle.turned.capacity());
  cycle.low = std::numeric_limits<double>::infinity();
  cycle.high = -cycle.low;
  for (int k = 0; k < revolutions; ++k) {
    for (std::size_t j = 0; j < steps; ++j) {
      Eigen::Vector2d lobes = Eigen::Vector2d::Zero(), filtered = Eigen::Vector2d::Zero();
      for (std::size_t c = 0; c < curves.size(); ++c) {
        const double turns = std::fmod(curves[c].ratio * k, 1.0);
        const double u = curves[c].ratio * dpsi * static_cast<double>(j) + units::kRadiansPerRevolution * turns;
        lobes += curves[c].At(u);
        filtered += parts.filtered[c].At(u);
      }
      cycle.turned.push_back(rest[j] + lobes);
      cycle.motion.push_back(parts.motion_rest[j] + ray.dot(filtered));
      const double reading = signal_rest[j] + ray.dot(lobes);
      cycle.low = std::min(cycle.low, reading);
      cycle.high = std::max(cycle.high, reading);
    }
  }
  return cycle;
}

// What EveryRevolution and EveryRevolutionFromRest share: the path less its lobes and the
// signal less them at the same angles.
LifeValues EveryRevolutionOf(const engine::Scene& scene, std::vector<PhaseCurve> curves,
                             std::span<const Eigen::Vector2d> rest, std::span<const double> signal_rest, int& cycle,
                             Accuracy accuracy) {
  const std::size_t steps = rest.size();
  const Eigen::Vector2d ray = engine::Direction(scene.sensor_angle);
  const CurveCycle split = SplitByCycle(std::move(curves), scene.phase_locked_rollers);
  cycle = split.filling.empty() ? split.cycle : 0;
  const engine::ErrorMotionFilter& filter = scene.error_motion_filter;
  const auto through_filter = [&](const std::vector<PhaseCurve>& unfiltered) {
    std::vector<PhaseCurve> filtered;
    filtered.reserve(unfiltered.size());
    for (const PhaseCurve& curve : unfiltered) filtered.push_back(Filtered(curve, filter));
    return filtered;
  };
  // The rest repeats every revolution: one closed revolution through the filter is exact.
  std::vector<double> motion_rest(steps);
  for (std::size_t j = 0; j < steps; ++j) motion_rest[j] = ray.dot(rest[j]);
  if (filter.filtered()) motion_rest = engine::GaussianFilterClosed(motion_rest, filter.cutoff_upr);
  const CycleRevolutions revolutions = OverCycle(
      {split.repeating, rest, signal_rest, through_filter(split.repeating), motion_rest}, ray, split.cycle);
  const std::span<const Eigen::Vector2d> points =
      revolutions.turned.empty() ? rest : std::span<const Eigen::Vector2d>(revolutions.turned);
  LifeValues every;
  every.error_motion = engine::MeasureErrorMotion(revolutions.motion, static_cast<int>(steps));
  every.runout = revolutions.high - revolutions.low;
  if (split.filling.empty()) {
    every.d_trajectory = 2.0 * engine::MinimumEnclosingCircle(points).radius;
    return every;
  }
  // Every phase of the curves that fill, at every angle of every revolution of the cycle:
  // the hull of the sum is the sum of the hulls, and each curve's range along the ray adds
  // to every range, at one angle or over all, while the average over the revolutions
  // (the synchronous motion) keeps none of it.
  std::vector<Eigen::Vector2d> hull = PathHull(points);
  double filled = 0.0, filled_motion = 0.0, straying = 0.0;
  for (const PhaseCurve& curve : split.filling) {
    const CurveSamples samples = SampleCurve(curve, ray, filter, accuracy == Accuracy::kFast ? kFastCurveLooseness : 1.0);
    hull = MinkowskiSum(hull, ConvexHull(samples.points));
    const auto [low, high] = std::ranges::minmax(samples.points | std::views::transform([&](const Eigen::Vector2d& g) {
                                                   return ray.dot(g);
                                                 }));
    filled += high - low + 2.0 * samples.straying;
    // The axis motion reads the curve through the error motion's filter.
    filled_motion += samples.motion_range;
    straying += samples.straying;
  }
  // The sampled curves' hulls lie inside the curves' and within `straying` of them: widened
  // by it, the circle encloses every revolution and is at most 2 straying too wide.
  every.d_trajectory = 2.0 * (engine::MinimumEnclosingCircle(hull).radius + straying);
  every.runout += filled;
  every.error_motion.asynchronous += filled_motion;
  every.error_motion.total += filled_motion;
  return every;
}

}  // namespace

engine::Scene AtRevolution(const engine::Scene& scene, int k) {
  engine::Scene turned = scene;
  for (std::size_t i = 0; i < scene.rollers.size(); ++i) {
    // The whole turns drop out first, so a late revolution keeps its phase's precision.
    const double turns = std::fmod(k * engine::SpinRatio(scene, static_cast<int>(i)), 1.0);
    turned.rollers[i].spin_phase = std::remainder(scene.rollers[i].spin_phase + units::kRadiansPerRevolution * turns,
                                                  units::kRadiansPerRevolution);
  }
  return turned;
}

double ArtefactForm(const engine::Scene& scene, int steps) {
  std::vector<double> form(static_cast<std::size_t>(steps));
  const double dpsi = units::kRadiansPerRevolution / steps;
  for (int j = 0; j < steps; ++j) {
    form[static_cast<std::size_t>(j)] = scene.ring.inner.Evaluate(scene.sensor_angle - dpsi * j).r;
  }
  const engine::Fundamental fundamental = engine::FundamentalOf(form);
  double low = std::numeric_limits<double>::infinity(), high = -low;
  for (int j = 0; j < steps; ++j) {
    const double rest = form[static_cast<std::size_t>(j)] - fundamental.At(dpsi * j);
    low = std::min(low, rest);
    high = std::max(high, rest);
  }
  return high - low;
}

namespace {

// SimulateLife, keeping the first revolution's result in `first` when asked: LinearLife
// reads its path again.
LifeResult SolveRevolutions(const engine::Scene& scene, const Solver& solver, const SimulationOptions& options,
                            int revolutions, SimulationResult* first) {
  if (revolutions < 1) throw std::invalid_argument("SimulateLife: revolutions must be at least 1");
  SimulationOptions dense = options;
  dense.angles = AngleMode::kDense;
  dense.keep_trajectory = true;  // the revolutions' points are what is read
  LifeResult life;
  const Eigen::Vector2d ray = engine::Direction(scene.sensor_angle);
  std::vector<Eigen::Vector2d> points;
  std::vector<double> motion;
  double low = std::numeric_limits<double>::infinity(), high = -low;
  // The filter reads the motion of the revolutions either side of those read, as an
  // analyser recording on does; they are solved for that alone.
  const int margin = scene.error_motion_filter.MarginRevolutions();
  int steps = 0;
  for (int k = -margin; k < revolutions + margin; ++k) {
    const SimulationResult one = Simulate(AtRevolution(scene, k), solver, dense);
    if (one.status != Status::kOk) {
      life.status = one.status;
      life.message = (k < 0 || k >= revolutions ? "revolution " + std::to_string(k + 1) +
                                                      " (beside those read, for the error motion's filter)"
                                                : "revolution " + std::to_string(k + 1) + " of " +
                                                      std::to_string(revolutions)) +
                     ": " + one.message;
      return life;
    }
    if (k == -margin) steps = dense.steps = one.steps;
    const auto n = static_cast<std::size_t>(steps);
    // Every revolution comes back at the first one's angles.
    RINGTOL_CHECK(one.steps == steps && one.trajectory.centre.size() >= n && one.sensor.size() >= n, k, one.steps,
                  steps, one.trajectory.centre.size(), one.sensor.size());
    for (std::size_t j = 0; j < n; ++j) motion.push_back(ray.dot(one.trajectory.centre[j]));
    if (k < 0 || k >= revolutions) continue;
    if (k == 0 && first != nullptr) *first = one;
    for (std::size_t j = 0; j < n; ++j) {
      points.push_back(one.trajectory.centre[j]);
      low = std::min(low, one.sensor[j]);
      high = std::max(high, one.sensor[j]);
    }
    life.revolutions = k + 1;
  }
  life.steps = steps;
  life.values.d_trajectory = 2.0 * engine::MinimumEnclosingCircle(points).radius;
  life.values.runout = high - low;
  life.motion = engine::FilterErrorMotion(motion, steps, scene.error_motion_filter);
  life.values.error_motion = engine::MeasureErrorMotion(life.motion, steps);
  life.artefact = ArtefactForm(scene, steps);
  return life;
}

}  // namespace

LifeResult SimulateLife(const engine::Scene& scene, const Solver& solver, const SimulationOptions& options,
                        int revolutions) {
  return SolveRevolutions(scene, solver, options, revolutions, nullptr);
}

LifeValues EveryRevolution(const engine::Scene& scene, const SimulationResult& one, const PhasorSum& sum,
                           int& cycle, Accuracy accuracy) {
  const auto steps = static_cast<std::size_t>(one.steps);
  if (one.status != Status::kOk || one.trajectory.centre.size() < steps || one.sensor.size() < steps || steps < 3) {
    throw std::invalid_argument("EveryRevolution: needs a valid revolution at its dense angles");
  }
  if (!sum.usable) throw std::invalid_argument("EveryRevolution: needs the scene's phasors");
  std::vector<PhaseCurve> curves = PhaseCurves(sum, scene.phase_locked_rollers);
  const std::vector<Eigen::Vector2d> lobes = LobesAt(curves, steps);
  const Eigen::Vector2d ray = engine::Direction(scene.sensor_angle);
  std::vector<Eigen::Vector2d> rest(steps);
  std::vector<double> signal_rest(steps);
  for (std::size_t j = 0; j < steps; ++j) {
    rest[j] = one.trajectory.centre[j] - lobes[j];
    signal_rest[j] = one.sensor[j] - ray.dot(lobes[j]);
  }
  return EveryRevolutionOf(scene, std::move(curves), rest, signal_rest, cycle, accuracy);
}

LifeValues EveryRevolutionFromRest(const engine::Scene& scene, std::span<const Eigen::Vector2d> rest,
                                   std::span<const double> signal_rest, const PhasorSum& sum, int& cycle,
                                   Accuracy accuracy) {
  const std::size_t steps = rest.size();
  if (steps < 3 || signal_rest.size() != steps) {
    throw std::invalid_argument("EveryRevolutionFromRest: needs the path and the signal at the same 3 or more angles");
  }
  if (!sum.usable) throw std::invalid_argument("EveryRevolutionFromRest: needs the scene's phasors");
  return EveryRevolutionOf(scene, PhaseCurves(sum, scene.phase_locked_rollers), rest, signal_rest, cycle, accuracy);
}

LifeResult LinearLife(const engine::Scene& scene, const LinearSolver& linear, const SimulationOptions& options,
                      int revolutions) {
  SimulationResult one;
  LifeResult life = SolveRevolutions(scene, linear, options, revolutions, &one);
  if (life.status != Status::kOk) return life;
  SimulationOptions dense = options;
  dense.angles = AngleMode::kDense;
  dense.keep_trajectory = true;
  const PhasorSum sum = linear.Phasors(scene);
  life.asymptotic = EveryRevolution(scene, one, sum, life.cycle, options.accuracy);

  // The same assembly with round rollers, at the same angles: what the second-order
  // correction owes to the lobes is the difference of the two paths less the lobes' first
  // order.
  engine::Scene round = scene;
  for (engine::Roller& roller : round.rollers) {
    roller.outline = engine::PolarProfile(roller.outline.radius(), roller.outline.mean_deviation(), {});
  }
  dense.steps = one.steps;
  const SimulationResult plain = Simulate(round, linear, dense);
  if (plain.status != Status::kOk) {
    life.status = plain.status;
    life.message = "the assembly with round rollers: " + plain.message;
    return life;
  }
  const auto steps = static_cast<std::size_t>(one.steps);
  // The lobes at their drawn phases: the same sum however the curves are grouped.
  const std::vector<Eigen::Vector2d> lobes = LobesAt(PhaseCurves(sum, false), steps);
  for (std::size_t j = 0; j < steps; ++j) {
    life.correction =
        std::max(life.correction, (one.trajectory.centre[j] - lobes[j] - plain.trajectory.centre[j]).norm());
  }
  life.error_estimate = one.trajectory.error_estimate + 4.0 * life.correction;
  return life;
}

}  // namespace ringtol::solvers
