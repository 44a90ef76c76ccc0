#include "solvers/spectral.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

#include "engine/enclosing_circle.h"
#include "engine/sensor.h"
#include "solvers/validity.h"

namespace ringtol::solvers {

std::optional<SpectralResult> SimulateSpectral(const engine::Scene& scene, const LinearSolver& linear, int steps,
                                               int stride, double error_budget) {
  const ValidityCheck validity(scene);
  const std::size_t z = scene.rollers.size();
  if (stride < 2 || steps < 4 * stride) return std::nullopt;
  // Penetrating contacts have gaps <= 0, so a roller that needs no two-point search at a
  // zero gap needs none anywhere.
  for (std::size_t i = 0; i < z; ++i) {
    if (validity.NeedsTwoPointSearch(static_cast<int>(i), 0.0)) return std::nullopt;
  }
  LinearPath path = linear.Path(scene, steps);
  if (path.status() != Status::kOk) return std::nullopt;

  const double dpsi = 2.0 * std::numbers::pi / steps;
  LinearPath::Samples samples;
  path.EvaluateCoarse(stride, samples);
  const std::vector<int>& coarse = path.coarse();
  const std::size_t segments = coarse.size() - 1;
  const LinearPath::Straying straying = path.StrayingAt(dpsi * stride);
  std::vector<char> refined(segments, 0);
  std::vector<std::size_t> first_inner(segments, 0);  // where a refined stretch's samples start
  std::size_t checked = 0;  // samples passed through the validity check
  std::string message;
  const auto refine = [&](std::size_t j) {
    refined[j] = 1;
    first_inner[j] = samples.size();
    path.Refine(static_cast<int>(j), samples);
  };
  // Every evaluated angle must pass the validity check; the dense evaluation states the
  // first failure otherwise.
  const auto valid = [&]() {
    for (; checked < samples.size(); ++checked) {
      const std::span<const double> travel(samples.travel.data() + checked * z, z);
      const std::span<const double> force(samples.contact_force.data() + checked * z, z);
      const double psi = dpsi * samples.index[checked];
      if (validity.Check(psi, samples.centre[checked], travel, force, message) != Status::kOk) return false;
    }
    return true;
  };
  if (!valid()) return std::nullopt;

  // The domain: a dense angle of an unevaluated stretch lies within the chord bound of the
  // chord between its ends, so a force above its bound and a travel inside its limit by
  // more than its bound at both ends cannot fail between them.
  for (std::size_t j = 0; j < segments; ++j) {
    bool certain = true;
    for (std::size_t i = 0; i < z && certain; ++i) {
      const double force_a = samples.contact_force[j * z + i];
      const double force_b = samples.contact_force[(j + 1) * z + i];
      certain = std::min(force_a, force_b) > straying.contact_force[i];
      if (scene.rollers[i].mount != engine::RollerMount::kFixed) {
        const double travel = std::max(std::abs(samples.travel[j * z + i]), std::abs(samples.travel[(j + 1) * z + i]));
        certain = certain && travel + straying.travel[i] <= scene.rollers[i].spring.travel_limit;
      }
    }
    if (!certain) refine(j);
  }
  if (!valid()) return std::nullopt;

  // The extremes: each pass refines the stretches whose ends, widened by the chord bound,
  // reach beyond what the evaluated angles give; the extremes only grow, so it ends when
  // none is left. What campaigns record of the forces is certified: the smallest over
  // every contact and the largest; each roller's own range is read at the evaluated angles.
  engine::Circle circle, error_circle;
  double reach = 0.0;
  double smallest_force = 0.0;
  double largest_force = 0.0;
  const Eigen::Vector2d start = samples.centre.front();
  // exact: also the reach and the second-order error's circle, so that both are the dense
  // path's.
  const auto refine_open = [&](bool exact) {
    for (bool changed = true; changed;) {
      circle = engine::MinimumEnclosingCircle(samples.centre);
      error_circle = engine::MinimumEnclosingCircle(samples.centre_error);
      reach = 0.0;
      for (const Eigen::Vector2d& c : samples.centre) reach = std::max(reach, (c - start).norm());
      const auto [low, high] = std::minmax_element(samples.contact_force.begin(), samples.contact_force.end());
      smallest_force = *low;
      largest_force = *high;
      std::vector<std::size_t> wanted;
      for (std::size_t j = 0; j < segments; ++j) {
        if (refined[j]) continue;
        const auto beyond = [j](const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& centre, double radius,
                                double bound) {
          return std::max((points[j] - centre).norm(), (points[j + 1] - centre).norm()) + bound > radius;
        };
        bool open = beyond(samples.centre, circle.centre, circle.radius, straying.centre) ||
                    (exact && (beyond(samples.centre, start, reach, straying.centre) ||
                               beyond(samples.centre_error, error_circle.centre, error_circle.radius,
                                      straying.CentreErrorBetween(samples, j, j + 1))));
        for (std::size_t i = 0; i < z && !open; ++i) {
          const double force_a = samples.contact_force[j * z + i];
          const double force_b = samples.contact_force[(j + 1) * z + i];
          open = std::min(force_a, force_b) - straying.contact_force[i] < smallest_force ||
                 std::max(force_a, force_b) + straying.contact_force[i] > largest_force;
        }
        if (open) wanted.push_back(j);
      }
      changed = !wanted.empty();
      for (const std::size_t j : wanted) refine(j);
      if (!valid()) return false;
    }
    return true;
  };
  if (!refine_open(false)) return std::nullopt;
  // The second-order error estimate: every dense angle's centre error lies within its
  // stretch's bound (LinearPath::Straying::CentreErrorBetween) of the chord between the
  // stretch's evaluated ends, so twice the largest distance from the evaluated errors'
  // circle's centre that an unevaluated one can reach bounds the dense estimate. Where that
  // bound is within what the estimate is weighed against (the linear rung's range limit
  // at the evaluated reach, a lower bound of the dense one, and error_budget) it stands;
  // otherwise the stretches that could widen the circle are evaluated, and the estimate
  // and the reach are the dense path's.
  double error_estimate = 2.0 * error_circle.radius;
  for (std::size_t j = 0; j < segments; ++j) {
    if (refined[j]) continue;
    const double farthest = std::max((samples.centre_error[j] - error_circle.centre).norm(),
                                     (samples.centre_error[j + 1] - error_circle.centre).norm());
    error_estimate = std::max(error_estimate, 2.0 * (farthest + straying.CentreErrorBetween(samples, j, j + 1)));
  }
  const LinearOptions& options = linear.options();
  const double limit = std::max(options.max_relative_error * reach, options.min_error_limit);
  if (!(error_estimate <= std::min(limit, error_budget))) {
    if (!refine_open(true)) return std::nullopt;
    error_estimate = 2.0 * error_circle.radius;
  }

  SpectralResult spectral;
  SimulationResult& result = spectral.result;
  result.steps = steps;
  spectral.evaluated = static_cast<int>(samples.size());
  // The evaluated angles in order: each coarse angle, then its stretch's when refined.
  std::vector<std::size_t> order;
  order.reserve(samples.size());
  for (std::size_t j = 0; j < segments; ++j) {
    order.push_back(j);
    if (!refined[j]) continue;
    const auto inner = static_cast<std::size_t>(coarse[j + 1] - coarse[j] - 1);
    for (std::size_t q = 0; q < inner; ++q) order.push_back(first_inner[j] + q);
  }
  order.push_back(segments);
  Trajectory& kept = result.trajectory;
  kept.rung = Rung::kLinear;
  kept.initial.centre = start;
  kept.initial.travel.assign(samples.travel.begin(), samples.travel.begin() + static_cast<std::ptrdiff_t>(z));
  kept.initial.contact_force.assign(samples.contact_force.begin(),
                                    samples.contact_force.begin() + static_cast<std::ptrdiff_t>(z));
  kept.error_estimate = error_estimate;
  std::vector<RollerForceRange> forces(z, {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()});
  std::vector<double> largest_travel(z, 0.0);
  for (const std::size_t s : order) {
    kept.psi.push_back(dpsi * samples.index[s]);
    kept.centre.push_back(samples.centre[s]);
    for (std::size_t i = 0; i < z; ++i) {
      kept.travel.push_back(samples.travel[s * z + i]);
      kept.contact_force.push_back(samples.contact_force[s * z + i]);
      forces[i].min = std::min(forces[i].min, samples.contact_force[s * z + i]);
      forces[i].max = std::max(forces[i].max, samples.contact_force[s * z + i]);
      largest_travel[i] = std::max(largest_travel[i], std::abs(samples.travel[s * z + i]));
    }
    result.sensor.push_back(samples.signal[s]);
  }

  if (!(kept.error_estimate <= limit)) {
    result.status = kept.status = Status::kBeyondLinearRange;
    result.message = kept.message = "the first-order path's second-order error, estimated at " +
                                    Micrometres(kept.error_estimate) + " of D_trajectory, exceeds its limit of " +
                                    Micrometres(limit) + ": use the quasistatic rung";
    return spectral;
  }

  result.enclosing_circle = circle;
  result.d_trajectory = 2.0 * circle.radius;
  result.dist_init = (start - circle.centre).norm();
  result.contact_force = forces;
  result.min_contact_force = smallest_force;

  // The signal at every angle: its first-order part summed there, its second-order rest
  // interpolated between the evaluated angles (which straddle every angle, the coarse
  // grid's ends being 0 and steps).
  thread_local std::vector<double> signal;
  path.FirstOrderSignal(signal);
  std::size_t previous = order.front();
  double previous_rest = samples.signal[previous] - signal.front();
  signal.front() += previous_rest;
  for (std::size_t o = 1; o < order.size(); ++o) {
    const std::size_t s = order[o];
    const int a = samples.index[previous];
    const int b = samples.index[s];
    const double rest = samples.signal[s] - signal[static_cast<std::size_t>(b)];
    for (int k = a + 1; k <= b; ++k) {
      const double t = static_cast<double>(k - a) / (b - a);
      signal[static_cast<std::size_t>(k)] += (1.0 - t) * previous_rest + t * rest;
    }
    previous = s;
    previous_rest = rest;
  }
  const engine::Runout runout = engine::MeasureRunout(signal, scene.sensor_swing);
  result.runout = runout.total;
  result.swing = runout.swing;

  spectral.margins.error_estimate = kept.error_estimate;
  spectral.margins.smallest_force = result.min_contact_force;
  spectral.margins.largest_force = largest_force;
  spectral.margins.reach = reach;
  for (std::size_t i = 0; i < z; ++i) largest_travel[i] += straying.travel[i];
  spectral.margins.largest_travel = std::move(largest_travel);
  return spectral;
}

}  // namespace ringtol::solvers
