#include "solvers/auto.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

#include "solvers/simulation.h"
#include "solvers/validity.h"

namespace ringtol::solvers {
namespace {

// The linear rung never refuses inside auto: auto weighs its estimate itself.
LinearOptions Unlimited() {
  LinearOptions options;
  options.max_relative_error = 1.0;
  options.min_error_limit = std::numeric_limits<double>::infinity();
  return options;
}

double SmallestForce(const Trajectory& path) {
  double smallest = std::numeric_limits<double>::infinity();
  for (const double force : path.contact_force) smallest = std::min(smallest, force);
  return smallest;
}

// [N] SupportForce's least value over the path's angles.
double SmallestSupportForce(const engine::Scene& scene, const Trajectory& path) {
  const std::size_t z = scene.rollers.size();
  double smallest = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < path.psi.size(); ++k) {
    smallest = std::min(smallest, SupportForce(scene, std::span<const double>(path.contact_force).subspan(k * z, z)));
  }
  return smallest;
}

}  // namespace

AutoSolver::AutoSolver(AutoOptions options)
    : options_(options), linear_(Unlimited()), quasistatic_(options.quasistatic), dynamic_(options.dynamic) {}

Equilibrium AutoSolver::SolveStatic(const engine::Scene& scene) const { return quasistatic_.SolveStatic(scene); }

std::string_view AutoSolver::LinearVerdict(const engine::Scene& scene, const Trajectory& path) const {
  LinearMargins margins;
  margins.error_estimate = path.error_estimate;
  margins.smallest_force = SmallestForce(path);
  for (const double force : path.contact_force) margins.largest_force = std::max(margins.largest_force, force);
  for (const Eigen::Vector2d& centre : path.centre) {
    margins.reach = std::max(margins.reach, (centre - path.centre.front()).norm());
  }
  const std::size_t rollers = scene.rollers.size();
  margins.largest_travel.assign(rollers, 0.0);
  for (std::size_t k = 0; k < path.travel.size(); ++k) {
    margins.largest_travel[k % rollers] = std::max(margins.largest_travel[k % rollers], std::abs(path.travel[k]));
  }
  return LinearVerdict(scene, margins);
}

std::string_view AutoSolver::LinearVerdict(const engine::Scene& scene, const LinearMargins& margins) const {
  const double error = margins.error_estimate;
  if (!(error <= options_.budget)) return "its error estimate exceeds the budget";
  double force_error = 0.0;
  if (scene.contact.model == engine::ContactLaw::Model::kPenalty) {
    force_error = kMarginFactor * error * ContactStiffness(scene, margins.largest_force);
  } else {
    force_error = error > 0.0 ? kMarginFactor * error / margins.reach * margins.largest_force : 0.0;
  }
  if (!(margins.smallest_force > force_error)) return "a contact force lies within its error estimate of zero";
  const std::size_t rollers = scene.rollers.size();
  for (std::size_t i = 0; i < rollers; ++i) {
    if (scene.rollers[i].mount != engine::RollerMount::kSpring) continue;
    if (!(scene.rollers[i].spring.travel_limit - margins.largest_travel[i] > kMarginFactor * error)) {
      return "a spring roller's travel lies within its error estimate of its limit";
    }
  }
  return {};
}

double AutoSolver::InertiaForceBound(const engine::Scene& scene, double contact_stiffness) {
  const engine::MotionLaw& law = scene.motion;
  double rate = 0.0;
  double acceleration = 0.0;
  double start = 0.0;
  for (std::size_t j = 0; j < law.segments().size(); ++j) {
    const double end = law.Breakpoints()[j];
    // The rate is linear inside a segment: largest at one of its ends.
    rate = std::max({rate, std::abs(law.RateIn(j, start)), std::abs(law.RateIn(j, end))});
    acceleration = std::max(acceleration, std::abs(law.segments()[j].acceleration));
    start = end;
  }
  const double mass = scene.ring.mass;
  return SumOverPathTerms(scene, [&](double w) {
    return std::min(mass * (rate * rate * w * w + acceleration * w), contact_stiffness);
  });
}

double AutoSolver::ContactStiffness(const engine::Scene& scene, double largest_force) {
  if (scene.contact.model != engine::ContactLaw::Model::kPenalty) return std::numeric_limits<double>::infinity();
  // dF/d delta = e k delta^(e - 1) with delta = (F / k)^(1/e), largest at the largest force.
  const double k = scene.contact.stiffness;
  const double e = scene.contact.exponent;
  return e * k * std::pow(largest_force / k, (e - 1.0) / e);
}

Trajectory AutoSolver::SolveRevolution(const engine::Scene& scene, int steps) const {
  Trajectory linear = linear_.SolveRevolution(scene, steps);  // checked against the domain already
  if (linear.status == Status::kOk && LinearVerdict(scene, linear).empty()) {
    linear.rung = Rung::kLinear;
    return linear;
  }
  return SolveExact(scene, steps);
}

Trajectory AutoSolver::SolveExact(const engine::Scene& scene, int steps) const {
  Trajectory quasistatic = quasistatic_.SolveRevolution(scene, steps);
  quasistatic.rung = Rung::kQuasistatic;
  if (quasistatic.status != Status::kOk) return quasistatic;
  ValidityCheck(scene, {.contacts_may_open = true}).Check(quasistatic);
  if (quasistatic.status != Status::kOk) return quasistatic;
  double largest_force = 0.0;
  for (const double force : quasistatic.contact_force) largest_force = std::max(largest_force, force);
  // A redundant roller's contact may open and close under the ring's inertia as it does
  // in the quasistatic path; only the support the ring needs must hold.
  if (InertiaForceBound(scene, ContactStiffness(scene, largest_force)) <
      options_.inertia_force_share * SmallestSupportForce(scene, quasistatic)) {
    return quasistatic;
  }
  Trajectory dynamic = dynamic_.SolveRevolution(scene, steps);
  dynamic.rung = Rung::kDynamic;
  return dynamic;
}

}  // namespace ringtol::solvers
