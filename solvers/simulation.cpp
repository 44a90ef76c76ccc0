#include "solvers/simulation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Eigenvalues>

#include "engine/sensor.h"
#include "solvers/auto.h"
#include "solvers/dynamic.h"
#include "solvers/linear.h"
#include "solvers/quasistatic.h"
#include "solvers/validity.h"

namespace ringtol::solvers {

namespace {

QuasistaticOptions QuasistaticFor(const SolverSettings& settings) {
  QuasistaticOptions options;
  if (settings.simulation.path_tolerance > 0.0) {
    options.position_tolerance = kAngleShareOfPathTolerance * settings.simulation.path_tolerance;
  }
  return options;
}

DynamicOptions DynamicFor(const SolverSettings& settings) {
  DynamicOptions options;
  options.relative_tolerance = settings.relative_tolerance;
  options.start = settings.dynamic_start;
  return options;
}

}  // namespace

std::unique_ptr<Solver> MakeSolver(const SolverSettings& settings) {
  switch (settings.rung) {
    case Rung::kLinear:
      return std::make_unique<LinearSolver>();
    case Rung::kQuasistatic:
      return std::make_unique<QuasistaticSolver>(QuasistaticFor(settings));
    case Rung::kDynamic:
      return std::make_unique<DynamicSolver>(DynamicFor(settings));
    case Rung::kAuto: {
      AutoOptions options;
      options.budget = kAutoShareOfPathTolerance * settings.simulation.path_tolerance;
      options.quasistatic = QuasistaticFor(settings);
      options.dynamic = DynamicFor(settings);
      return std::make_unique<AutoSolver>(options);
    }
  }
  return std::make_unique<QuasistaticSolver>();
}

std::string SolverDescription(const SolverSettings& settings) {
  std::string description(NameOf(kRungNames, settings.rung));
  if (settings.rung == Rung::kDynamic) description += ", start " + std::string(NameOf(kDynamicStartNames, settings.dynamic_start));
  return description;
}

int ChooseSteps(const engine::Scene& scene, const SimulationOptions& options) {
  if (options.steps > 0) return options.steps;
  const double fastest = 2.0 * engine::FastestHarmonicRate(scene);
  const double wanted = std::ceil(options.samples_per_undulation * fastest);
  const int undulation_rule = static_cast<int>(
      std::clamp(wanted, static_cast<double>(options.min_steps), static_cast<double>(options.max_steps)));
  if (!(options.path_tolerance > 0.0)) return undulation_rule;
  // The bound falls monotonically with steps: bisect for the fewest that meet the budget,
  // never more than the undulation rule, which resolves every term.
  if (SamplingErrorBound(scene, options.min_steps) <= options.path_tolerance) return options.min_steps;
  int low = options.min_steps;
  int high = undulation_rule;
  if (SamplingErrorBound(scene, high) > options.path_tolerance) return high;
  while (high - low > 1) {
    const int middle = low + (high - low) / 2;
    (SamplingErrorBound(scene, middle) <= options.path_tolerance ? high : low) = middle;
  }
  return high;
}

double SamplingErrorBounds::Largest() const { return std::max({d_trajectory, runout, 0.5 * swing}); }

namespace {

// Calls term(path_gain, sensor_gain, amplitude, rate) for each error harmonic's term of the
// first-order path (SamplingErrorBoundsAt states the gains); false, calling nothing, when
// fewer than two fixed rollers support the centre (every gain infinite).
template <typename Term>
bool ForEachPathTerm(const engine::Scene& scene, Term term) {
  const int rollers = static_cast<int>(scene.rollers.size());
  Eigen::Matrix2d normal_products = Eigen::Matrix2d::Zero();
  int fixed = 0;
  for (int i = 0; i < rollers; ++i) {
    if (scene.rollers[static_cast<std::size_t>(i)].mount != engine::RollerMount::kFixed) continue;
    const Eigen::Vector2d normal = engine::Direction(scene.rollers[static_cast<std::size_t>(i)].angle);
    normal_products += normal * normal.transpose();
    ++fixed;
  }
  const double sigma_min_squared = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(normal_products).eigenvalues()(0);
  if (fixed < 2 || !(sigma_min_squared > 0.0)) return false;
  const double gain = 1.0 / std::sqrt(sigma_min_squared);
  const double ring_gain = gain * std::sqrt(static_cast<double>(fixed));
  for (const engine::Harmonic& h : scene.ring.inner.harmonics()) {
    term(ring_gain, ring_gain + 1.0, h.amplitude, static_cast<double>(h.order));
  }
  for (int i = 0; i < rollers; ++i) {
    const double spin = engine::SpinRatio(scene, i);
    for (const engine::Harmonic& h : scene.rollers[static_cast<std::size_t>(i)].outline.harmonics()) {
      term(gain, gain, h.amplitude, static_cast<double>(h.order) * spin);
    }
  }
  return true;
}

}  // namespace

SamplingErrorBounds SamplingErrorBoundsAt(const engine::Scene& scene, int steps) {
  const double dpsi = 2.0 * std::numbers::pi / static_cast<double>(steps);
  const auto straying = [dpsi](double rate) { return std::min(2.0, rate * rate * dpsi * dpsi / 8.0); };
  const bool filtered = scene.sensor_swing.cutoff_upr > 0.0;
  const double nyquist = 0.5 * static_cast<double>(steps);
  const auto filtered_straying = [&](double rate) { return filtered && rate >= nyquist ? 2.0 : straying(rate); };

  double path = 0.0;
  double signal = 0.0;
  double filtered_signal = 0.0;
  const bool supported = ForEachPathTerm(scene, [&](double path_gain, double sensor_gain, double amplitude, double rate) {
    path += path_gain * amplitude * straying(rate);
    signal += sensor_gain * amplitude * straying(rate);
    filtered_signal += sensor_gain * amplitude * filtered_straying(rate);
  });
  if (!supported) {
    constexpr double kInfinite = std::numeric_limits<double>::infinity();
    return {kInfinite, kInfinite, kInfinite, kInfinite};
  }
  return {path, 2.0 * path, 2.0 * signal, 4.0 * filtered_signal};
}

double SumOverPathTerms(const engine::Scene& scene, const std::function<double(double rate)>& weight) {
  double bound = 0.0;
  const bool supported = ForEachPathTerm(scene, [&](double path_gain, double, double amplitude, double rate) {
    bound += path_gain * amplitude * weight(rate);
  });
  return supported ? bound : std::numeric_limits<double>::infinity();
}

double SamplingErrorBound(const engine::Scene& scene, int steps) { return SamplingErrorBoundsAt(scene, steps).Largest(); }

namespace {

// The article's metrics of one sampled revolution; `nominal` is the error-free assembly's
// static equilibrium.
void Measure(const engine::Scene& scene, const Trajectory& path, const Eigen::Vector2d& nominal,
             SimulationResult& result) {
  result.enclosing_circle = engine::MinimumEnclosingCircle(path.centre);
  result.d_trajectory = 2.0 * result.enclosing_circle.radius;
  result.dist_init = (path.initial.centre - result.enclosing_circle.centre).norm();
  result.static_offset = (path.initial.centre - nominal).norm();

  result.sensor.reserve(path.psi.size());
  double theta = scene.sensor_angle;
  engine::SensorTrack track;
  for (std::size_t k = 0; k < path.psi.size(); ++k) {
    const engine::SensorReading reading =
        engine::ReadSensor(scene.ring.inner, {path.centre[k], path.psi[k]}, scene.sensor_angle, theta, &track);
    // The bore turns under the fixed sensor: the next ray meets it dpsi earlier in the
    // ring's body frame.
    const double next_psi = k + 1 < path.psi.size() ? path.psi[k + 1] : path.psi[k];
    theta = reading.ring_theta - (next_psi - path.psi[k]);
    result.sensor.push_back(reading.distance);
  }
  const engine::Runout runout = engine::MeasureRunout(result.sensor, scene.sensor_swing);
  result.runout = runout.total;
  result.swing = runout.swing;

  const std::size_t z = scene.rollers.size();
  result.contact_force.assign(z, {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()});
  for (std::size_t k = 0; k < path.psi.size(); ++k) {
    for (std::size_t i = 0; i < z; ++i) {
      const double f = path.contact_force[k * z + i];
      result.contact_force[i].min = std::min(result.contact_force[i].min, f);
      result.contact_force[i].max = std::max(result.contact_force[i].max, f);
    }
  }
  result.min_contact_force = std::numeric_limits<double>::infinity();
  for (const RollerForceRange& range : result.contact_force) {
    result.min_contact_force = std::min(result.min_contact_force, range.min);
  }
}

}  // namespace

SimulationResult Simulate(const engine::Scene& scene, const Solver& solver, const SimulationOptions& options) {
  SimulationResult result;
  result.steps = ChooseSteps(scene, options);
  result.status = CheckSceneGeometry(scene, result.message);
  if (result.status != Status::kOk) return result;
  result.trajectory = solver.SolveRevolution(scene, result.steps);
  if (!result.trajectory.rung) result.trajectory.rung = ValueNamed(kRungNames, solver.name());
  // One verdict for every rung: a rung's own checks may miss what another's catch.
  const ValidityCheck validity(scene);
  validity.Check(result.trajectory);
  const Trajectory& path = result.trajectory;
  if (path.status != Status::kOk) {
    result.status = path.status;
    result.message = path.message;
    return result;
  }
  const Equilibrium nominal = solver.SolveStatic(engine::WithoutErrors(scene));
  if (nominal.status != Status::kOk) {
    result.status = nominal.status;
    result.message = "the error-free assembly has no valid static equilibrium: " + nominal.message;
    return result;
  }
  Measure(scene, path, nominal.centre, result);
  if (path.steady) {
    auto steady = std::make_shared<SimulationResult>();
    steady->steps = result.steps;
    Trajectory later = *path.steady;
    validity.Check(later);
    steady->status = later.status;
    steady->message = later.message;
    if (steady->status == Status::kOk) Measure(scene, later, nominal.centre, *steady);
    result.steady = std::move(steady);
  }
  return result;
}

}  // namespace ringtol::solvers
