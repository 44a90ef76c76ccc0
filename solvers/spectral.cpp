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

namespace {

// How far the second-order correction (SecondOrderTerms::At) can stray between two
// evaluated angles [m, N]: not bounded yet, so every stretch is open and the mode
// evaluates every angle (docs/model.md §5). A bound of the correction and of its remainder
// over a stretch, from bounds on the first-order inputs there, is what makes stretches
// settle.
constexpr double kCorrectionStraying = std::numeric_limits<double>::infinity();

}  // namespace

std::optional<SpectralResult> SimulateSpectral(const engine::Scene& scene, const LinearSolver& linear, int steps,
                                               int stride) {
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
      certain = std::min(force_a, force_b) > straying.contact_force[i] + kCorrectionStraying;
      if (scene.rollers[i].mount != engine::RollerMount::kFixed) {
        const double travel = std::max(std::abs(samples.travel[j * z + i]), std::abs(samples.travel[(j + 1) * z + i]));
        certain = certain && travel + straying.travel[i] + kCorrectionStraying <= scene.rollers[i].spring.travel_limit;
      }
    }
    if (!certain) refine(j);
  }
  if (!valid()) return std::nullopt;

  // The extremes: each pass refines the stretches whose ends, widened by the chord bound,
  // reach beyond what the evaluated angles give; the extremes only grow, so it ends when
  // none is left. What campaigns record of the forces is certified: the smallest over
  // every contact and the largest; each roller's own range is read at the evaluated angles.
  engine::Circle circle;
  double smallest_force = 0.0;
  double largest_force = 0.0;
  for (bool changed = true; changed;) {
    circle = engine::MinimumEnclosingCircle(samples.centre);
    const auto [low, high] = std::minmax_element(samples.contact_force.begin(), samples.contact_force.end());
    smallest_force = *low;
    largest_force = *high;
    std::vector<std::size_t> wanted;
    for (std::size_t j = 0; j < segments; ++j) {
      if (refined[j]) continue;
      const double farthest =
          std::max((samples.centre[j] - circle.centre).norm(), (samples.centre[j + 1] - circle.centre).norm());
      bool open = farthest + straying.centre + kCorrectionStraying > circle.radius;
      for (std::size_t i = 0; i < z && !open; ++i) {
        const double force_a = samples.contact_force[j * z + i];
        const double force_b = samples.contact_force[(j + 1) * z + i];
        const double bound = straying.contact_force[i] + kCorrectionStraying;
        open = std::min(force_a, force_b) - bound < smallest_force || std::max(force_a, force_b) + bound > largest_force;
      }
      if (open) wanted.push_back(j);
    }
    changed = !wanted.empty();
    for (const std::size_t j : wanted) refine(j);
    if (!valid()) return std::nullopt;
  }
  // The estimate, as SolveRevolution forms it from the largest remainder over the angles
  // (each of which is evaluated while the correction is not bounded between them).
  double largest_remainder = 0.0;
  double farthest = 0.0;
  double reach = 0.0;
  const Eigen::Vector2d start = samples.centre.front();
  for (std::size_t s = 0; s < samples.size(); ++s) {
    // max() would drop a NaN: the estimate must carry it.
    if (!(samples.remainder[s] <= largest_remainder)) largest_remainder = samples.remainder[s];
    farthest = std::max(farthest, samples.centre[s].norm());
    reach = std::max(reach, (samples.centre[s] - start).norm());
  }
  const double error_estimate = path.EstimateFrom(largest_remainder, farthest);

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

  const std::string refusal = LinearRangeRefusal(linear.options(), kept.error_estimate, reach);
  if (!refusal.empty()) {
    result.status = kept.status = Status::kBeyondLinearRange;
    result.message = kept.message = refusal;
    return spectral;
  }

  result.enclosing_circle = circle;
  result.d_trajectory = 2.0 * circle.radius;
  result.dist_init = (start - circle.centre).norm();
  result.contact_force = forces;
  result.min_contact_force = smallest_force;

  // The signal at every angle: its first-order part summed there, the rest (the sensor's
  // second-order terms and the centre's correction along the ray) interpolated between
  // the evaluated angles (which straddle every angle, the coarse grid's ends being 0 and
  // steps).
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
