#include "solvers/simulation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <span>

#include <Eigen/Eigenvalues>

#include "engine/sensor.h"
#include "solvers/auto.h"
#include "solvers/dynamic.h"
#include "solvers/life.h"
#include "solvers/linear.h"
#include "solvers/quasistatic.h"
#include "solvers/spectral.h"
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

bool SimulationOptions::IsValid(InvalidOption* invalid) const {
  return CheckOption("steps", steps, kStepsRange, invalid) &&
         CheckOption("refine_stride", refine_stride, kRefineStrideRange, invalid) &&
         CheckOption("samples_per_undulation", samples_per_undulation, kSamplesPerUndulationRange, invalid) &&
         CheckOption("min_steps", min_steps, kMinStepsRange, invalid) &&
         CheckOption("max_steps", max_steps, Between(min_steps, kMaxSteps), invalid) &&
         CheckOption("path_tolerance", path_tolerance, kPathToleranceRange, invalid);
}

bool SolverSettings::IsValid(InvalidOption* invalid) const {
  return CheckOptions("simulation", simulation, invalid) &&
         CheckOption("relative_tolerance", relative_tolerance, DynamicOptions::kRelativeToleranceRange, invalid);
}

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
  if (settings.simulation.accuracy != Accuracy::kFull) {
    description += ", accuracy " + std::string(NameOf(kAccuracyNames, settings.simulation.accuracy));
  }
  return description;
}

int FourierFriendlySteps(int at_least) {
  for (int n = 8 * std::max(1, (at_least + 7) / 8);; n += 8) {
    int rest = n / 8;
    for (const int factor : {2, 3, 5}) {
      while (rest % factor == 0) rest /= factor;
    }
    if (rest == 1) return n;
  }
}

int ChooseSteps(const engine::Scene& scene, const SimulationOptions& options) {
  if (options.steps > 0) return options.steps;
  const auto friendly = [&](int steps) { return std::min(FourierFriendlySteps(steps), options.max_steps); };
  const double fastest = 2.0 * engine::FastestHarmonicRate(scene);
  const double wanted = std::ceil(options.samples_per_undulation * fastest);
  const int undulation_rule = static_cast<int>(
      std::clamp(wanted, static_cast<double>(options.min_steps), static_cast<double>(options.max_steps)));
  if (!(options.path_tolerance > 0.0)) return friendly(undulation_rule);
  // The bound falls monotonically with steps: bisect for the fewest that meet the budget,
  // never more than the undulation rule, which resolves every term; rounding up keeps it.
  if (SamplingErrorBound(scene, options.min_steps) <= options.path_tolerance) return friendly(options.min_steps);
  int low = options.min_steps;
  int high = undulation_rule;
  if (SamplingErrorBound(scene, high) > options.path_tolerance) return friendly(high);
  while (high - low > 1) {
    const int middle = low + (high - low) / 2;
    (SamplingErrorBound(scene, middle) <= options.path_tolerance ? high : low) = middle;
  }
  return friendly(high);
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
  // The last sample closes the revolution at its first angle: a share counts it once.
  const std::size_t angles = path.psi.size() > 1 ? path.psi.size() - 1 : path.psi.size();
  for (std::size_t k = 0; k < path.psi.size(); ++k) {
    for (std::size_t i = 0; i < z; ++i) {
      const double f = path.contact_force[k * z + i];
      result.contact_force[i].min = std::min(result.contact_force[i].min, f);
      result.contact_force[i].max = std::max(result.contact_force[i].max, f);
      if (k < angles && !(f > 0.0)) result.contact_force[i].off_bore += 1.0 / static_cast<double>(angles);
    }
  }
  result.min_contact_force = std::numeric_limits<double>::infinity();
  for (const RollerForceRange& range : result.contact_force) {
    result.min_contact_force = std::min(result.min_contact_force, range.min);
  }
}

// The refined mode's allowance for what the first-order chord bounds leave out: the linear
// rung's second order and the exact model's remainder beyond it, which stray no more than
// the first-order terms they are products of (the sensor's reading is second order in both
// rungs). Doubling the bound covers them with that margin.
constexpr double kSecondOrderAllowance = 2.0;

// The revolution as the refined mode (AngleMode::kRefined) holds it: every dense angle's
// outputs, filled where evaluated. Segment j runs from coarse sample j to j + 1.
class RefinedRevolution {
 public:
  RefinedRevolution(const engine::Scene& scene, int steps) : scene_(scene), steps_(steps), z_(scene.rollers.size()) {
    const auto n = static_cast<std::size_t>(steps) + 1;
    known_.assign(n, 0);
    read_.assign(n, 0);
    centre_.resize(n);
    travel_.resize(n * z_);
    force_.resize(n * z_);
    signal_.resize(n);
    theta_.resize(n);
  }

  // Takes the outputs of a trajectory whose samples sit at these dense indices.
  void Take(const Trajectory& trajectory, std::span<const int> indices) {
    for (std::size_t s = 0; s < indices.size() && s < trajectory.psi.size(); ++s) {
      const auto k = static_cast<std::size_t>(indices[s]);
      known_[k] = 1;
      centre_[k] = trajectory.centre[s];
      std::copy_n(trajectory.travel.begin() + static_cast<std::ptrdiff_t>(s * z_), z_, travel_.begin() + static_cast<std::ptrdiff_t>(k * z_));
      std::copy_n(trajectory.contact_force.begin() + static_cast<std::ptrdiff_t>(s * z_), z_, force_.begin() + static_cast<std::ptrdiff_t>(k * z_));
    }
  }

  // Reads the sensor at dense angles first .. last (solved), in order, each reading warm
  // started from the one before (or from the nearest read angle before first).
  void Read(int first, int last) {
    int previous = first;
    while (previous >= 0 && !read_[static_cast<std::size_t>(previous)]) --previous;
    double theta = scene_.sensor_angle;
    if (previous >= 0) theta = theta_[static_cast<std::size_t>(previous)] - Psi(first) + Psi(previous);
    for (int k = first; k <= last; ++k) {
      const auto at = static_cast<std::size_t>(k);
      if (read_[at]) {
        theta = theta_[at] - (Psi(k + 1) - Psi(k));
        continue;
      }
      const engine::SensorReading reading =
          engine::ReadSensor(scene_.ring.inner, {centre_[at], Psi(k)}, scene_.sensor_angle, theta, &track_);
      read_[at] = 1;
      signal_[at] = reading.distance;
      theta_[at] = reading.ring_theta;
      theta = reading.ring_theta - (Psi(k + 1) - Psi(k));
    }
  }

  double Psi(int k) const { return 2.0 * std::numbers::pi * static_cast<double>(k) / steps_; }
  bool known(int k) const { return known_[static_cast<std::size_t>(k)] != 0; }
  bool read(int k) const { return read_[static_cast<std::size_t>(k)] != 0; }
  const Eigen::Vector2d& centre(int k) const { return centre_[static_cast<std::size_t>(k)]; }
  double travel(int k, std::size_t i) const { return travel_[static_cast<std::size_t>(k) * z_ + i]; }
  double force(int k, std::size_t i) const { return force_[static_cast<std::size_t>(k) * z_ + i]; }
  double signal(int k) const { return signal_[static_cast<std::size_t>(k)]; }
  int steps() const { return steps_; }

 private:
  const engine::Scene& scene_;
  int steps_;
  std::size_t z_;
  std::vector<char> known_, read_;
  std::vector<Eigen::Vector2d> centre_;
  std::vector<double> travel_, force_, signal_, theta_;
  engine::SensorTrack track_;
};

// The linearisation whose chord bounds certify the refined mode, kept across calls: a
// campaign's scenes share one error-free assembly.
const LinearSolver& CertifyingLinearisation() {
  static const LinearSolver solver;
  return solver;
}

// AngleMode::kRefined (simulation.h): nullopt where the mode does not apply or the
// coarse revolution fails, for the dense mode to decide (and state the failure where it
// arises).
std::optional<SimulationResult> SimulateRefined(const engine::Scene& scene, const Solver& solver,
                                                const SimulationOptions& options, int steps) {
  const auto* quasistatic = dynamic_cast<const QuasistaticSolver*>(&solver);
  const auto* linear = dynamic_cast<const LinearSolver*>(&solver);
  const int stride = options.refine_stride;
  if ((quasistatic == nullptr && linear == nullptr) || scene.sensor_swing.cutoff_upr > 0.0 || stride < 2 ||
      steps < 4 * stride) {
    return std::nullopt;
  }
  const ValidityCheck validity(scene);
  const int rollers = static_cast<int>(scene.rollers.size());
  const auto z = static_cast<std::size_t>(rollers);
  // Penetrating contacts have gaps <= 0, so a roller that needs no two-point search at a
  // zero gap needs none anywhere; one that might is checked at every angle, densely.
  for (int i = 0; i < rollers; ++i) {
    if (quasistatic != nullptr && validity.NeedsTwoPointSearch(i, 0.0)) return std::nullopt;
  }
  const double dpsi_coarse = 2.0 * std::numbers::pi * stride / steps;
  const ChordStraying straying = CertifyingLinearisation().ChordStrayingAt(scene, dpsi_coarse);
  if (!straying.usable) return std::nullopt;

  SimulationResult result;
  result.steps = steps;
  RefinedRevolution revolution(scene, steps);
  std::vector<int> coarse;
  for (int k = 0; k < steps; k += stride) coarse.push_back(k);
  coarse.push_back(steps);
  const std::size_t segments = coarse.size() - 1;
  std::vector<char> evaluated(segments, 0);  // the segment's inner angles solved and read
  Trajectory head;                            // the initial equilibrium and the run's totals
  // The linear rung's path at every dense angle, in closed form (first order plus its
  // second order): it carries the fast part, the rollers' lobes, so what the exact path
  // adds to it between two evaluated angles is only its remainder, of third order.
  Trajectory linear_path = (linear != nullptr ? *linear : CertifyingLinearisation()).SolveRevolution(scene, steps);
  if (linear != nullptr) {
    validity.Check(linear_path);
    if (linear_path.status != Status::kOk) {
      result.status = linear_path.status;
      result.message = linear_path.message;
      result.trajectory = std::move(linear_path);
      return result;
    }
    std::vector<int> all(static_cast<std::size_t>(steps) + 1);
    for (int k = 0; k <= steps; ++k) all[static_cast<std::size_t>(k)] = k;
    revolution.Take(linear_path, all);
    head.initial = linear_path.initial;
    head.error_estimate = linear_path.error_estimate;
  } else if (linear_path.status != Status::kOk && linear_path.status != Status::kBeyondLinearRange) {
    return std::nullopt;
  }
  std::unique_ptr<SparseRevolution> sparse;
  // How far the exact path's rest, q - the linear rung's path, strays from its chord
  // between two evaluated angles [m]: every point of the rest lies within half the linear
  // rung's error estimate (SecondOrderTerms::EstimateFrom), so it strays by at most the
  // estimate, doubled for margin, plus the two ends' Newton tolerance.
  double rest_bound = 0.0;
  if (quasistatic != nullptr) {
    rest_bound = kSecondOrderAllowance * linear_path.error_estimate + 2.0 * quasistatic->options().position_tolerance;
    sparse = quasistatic->SolveSparse(scene, steps, stride);
    Trajectory first = sparse->coarse();
    validity.Check(first);
    if (first.status != Status::kOk) return std::nullopt;
    revolution.Take(first, coarse);
    head.initial = first.initial;
    head.total_iterations = first.total_iterations;
  }
  // The sensor reads e_s . c + rho(aim - psi - c_t / R) + c_t^2 / (2 R) to second order
  // (rho the bore's form, c_t the centre across the ray): what it adds to e_s . c is the
  // bore's form, slow (order <= its harmonics), plus a rest of at most
  // max|rho'| |c_t| / R + c_t^2 / (2 R), which strays by at most twice that.
  const engine::PolarProfile& bore = scene.ring.inner;
  double form_straying = 0.0;
  double steepest = 0.0;
  for (int n = 1; n <= bore.max_order(); ++n) {
    const double amplitude = std::hypot(bore.cos_coefficient(n), bore.sin_coefficient(n));
    form_straying += amplitude * std::min(2.0, n * n * dpsi_coarse * dpsi_coarse / 8.0);
    steepest += n * amplitude;
  }
  double across = 0.0;
  for (const Eigen::Vector2d& c : linear_path.centre) across = std::max(across, c.norm());
  across += rest_bound;
  const double signal_bound = kSecondOrderAllowance * form_straying +
                              2.0 * (steepest * across + across * across / 2.0) / bore.radius() + rest_bound;
  const Eigen::Vector2d ray = engine::Direction(scene.sensor_angle);
  for (const int k : coarse) revolution.Read(k, k);
  const auto evaluate = [&](std::size_t j) {
    const int first = coarse[j] + 1;
    const int last = coarse[j + 1] - 1;
    evaluated[j] = 1;
    if (first > last) return true;
    if (sparse != nullptr) {
      const Trajectory segment = sparse->SolveSegment(static_cast<int>(j));
      head.total_iterations += segment.total_iterations;
      if (segment.status != Status::kOk) return false;
      std::vector<int> indices(static_cast<std::size_t>(last - first + 1));
      for (int k = first; k <= last; ++k) indices[static_cast<std::size_t>(k - first)] = k;
      revolution.Take(segment, indices);
    }
    revolution.Read(first, last);
    return true;
  };

  // The domain: a dense angle of an unevaluated segment lies within the chord bounds of
  // the chord between its ends, so a force that stays above zero by more than its bound
  // and a travel that stays inside its limit by more than its bound at both ends cannot
  // fail the validity check between them. The linear rung's path is dense and checked.
  if (sparse != nullptr) {
    for (std::size_t j = 0; j < segments; ++j) {
      const int a = coarse[j];
      const int b = coarse[j + 1];
      bool certain = true;
      for (std::size_t i = 0; i < z && certain; ++i) {
        const double force_bound = kSecondOrderAllowance * straying.contact_force[i];
        const double travel_bound = kSecondOrderAllowance * straying.travel[i];
        certain = std::min(revolution.force(a, i), revolution.force(b, i)) > force_bound;
        if (scene.rollers[i].mount != engine::RollerMount::kFixed) {
          certain = certain && std::max(std::abs(revolution.travel(a, i)), std::abs(revolution.travel(b, i))) +
                                       travel_bound <= scene.rollers[i].spring.travel_limit;
        }
      }
      if (!certain && !evaluate(j)) return std::nullopt;
    }
  }

  // The extremes: a segment can hold a dense angle beyond the current enclosing circle or
  // the signal's extremes only if its estimate there lies within the bound of them. Each
  // pass evaluates those segments; the extremes only grow, so it ends when none is left.
  // The force range is read at the evaluated angles: the dense grid's lies within
  // kSecondOrderAllowance times ChordStraying::contact_force of it (the forces vary by
  // little more than that bound, so certifying them would evaluate every angle).
  std::vector<Eigen::Vector2d> points;
  engine::Circle circle;
  std::vector<RollerForceRange> forces(z);
  double signal_max = 0.0;
  double signal_min = 0.0;
  for (bool changed = true; changed;) {
    points.clear();
    signal_max = -std::numeric_limits<double>::infinity();
    signal_min = std::numeric_limits<double>::infinity();
    forces.assign(z, {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()});
    for (int k = 0; k <= steps; ++k) {
      if (!revolution.known(k)) continue;
      points.push_back(revolution.centre(k));
      for (std::size_t i = 0; i < z; ++i) {
        forces[i].min = std::min(forces[i].min, revolution.force(k, i));
        forces[i].max = std::max(forces[i].max, revolution.force(k, i));
      }
      if (!revolution.read(k)) continue;
      signal_max = std::max(signal_max, revolution.signal(k));
      signal_min = std::min(signal_min, revolution.signal(k));
    }
    circle = engine::MinimumEnclosingCircle(points);
    std::vector<std::size_t> wanted;
    for (std::size_t j = 0; j < segments; ++j) {
      if (evaluated[j]) continue;
      const int a = coarse[j];
      const int b = coarse[j + 1];
      // Each dense angle between the ends: the first-order path there plus the rest
      // interpolated between the ends', within rest_bound of the exact point; the
      // signal likewise, its rest being what the sensor adds to the first-order centre.
      const Eigen::Vector2d rest_a = revolution.centre(a) - linear_path.centre[static_cast<std::size_t>(a)];
      const Eigen::Vector2d rest_b = revolution.centre(b) - linear_path.centre[static_cast<std::size_t>(b)];
      const double signal_rest_a = revolution.signal(a) - ray.dot(linear_path.centre[static_cast<std::size_t>(a)]);
      const double signal_rest_b = revolution.signal(b) - ray.dot(linear_path.centre[static_cast<std::size_t>(b)]);
      bool open = false;
      for (int k = a + 1; k < b && !open; ++k) {
        const double t = static_cast<double>(k - a) / (b - a);
        const Eigen::Vector2d& near = linear_path.centre[static_cast<std::size_t>(k)];
        const double reading = ray.dot(near) + (1.0 - t) * signal_rest_a + t * signal_rest_b;
        open = reading + signal_bound > signal_max || reading - signal_bound < signal_min;
        if (sparse != nullptr) {
          const Eigen::Vector2d point = near + (1.0 - t) * rest_a + t * rest_b;
          open = open || (point - circle.centre).norm() > circle.radius - rest_bound;
        }
      }
      if (open) wanted.push_back(j);
    }
    changed = !wanted.empty();
    for (const std::size_t j : wanted) {
      if (!evaluate(j)) return std::nullopt;
    }
  }

  const Equilibrium nominal = solver.SolveStatic(engine::WithoutErrors(scene));
  if (nominal.status != Status::kOk) {
    result.status = nominal.status;
    result.message = "the error-free assembly has no valid static equilibrium: " + nominal.message;
    return result;
  }
  result.enclosing_circle = circle;
  result.d_trajectory = 2.0 * circle.radius;
  result.dist_init = (head.initial.centre - circle.centre).norm();
  result.static_offset = (head.initial.centre - nominal.centre).norm();
  result.contact_force = forces;
  result.min_contact_force = std::numeric_limits<double>::infinity();
  for (const RollerForceRange& range : forces) result.min_contact_force = std::min(result.min_contact_force, range.min);
  // The trajectory and the signal at the angles evaluated at full cost, in order.
  Trajectory& kept = result.trajectory;
  kept.initial = head.initial;
  kept.total_iterations = head.total_iterations;
  kept.error_estimate = head.error_estimate;
  for (int k = 0; k <= steps; ++k) {
    if (!revolution.read(k)) continue;
    kept.psi.push_back(revolution.Psi(k));
    kept.centre.push_back(revolution.centre(k));
    for (std::size_t i = 0; i < z; ++i) {
      kept.travel.push_back(revolution.travel(k, i));
      kept.contact_force.push_back(revolution.force(k, i));
    }
    result.sensor.push_back(revolution.signal(k));
  }
  result.runout = signal_max - signal_min;
  result.swing = engine::Swing(result.sensor, scene.sensor_swing.resolution);
  return result;
}

// SimulationResult::life around a revolution measured at its dense angles. The lobes'
// curves are the linear rung's phasors whatever rung solved the path: a rung that solves
// the exact model has no phasors of its own, and the curves' share of the path is first
// order in the lobes for every rung (docs/model.md §9).
void ReadLife(const engine::Scene& scene, const Solver& solver, Accuracy accuracy, SimulationResult& result) {
  static const LinearSolver kPhasorSource;
  const auto* linear = dynamic_cast<const LinearSolver*>(&solver);
  const auto* automatic = dynamic_cast<const AutoSolver*>(&solver);
  const LinearSolver& source = linear != nullptr ? *linear : automatic != nullptr ? automatic->linear() : kPhasorSource;
  // The life's revolutions are the linear rung's phasors about this one, which hold only
  // while every contact of the error-free assembly stays closed. A redundant roller that
  // leaves the bore (the support rule let the path through) costs the life, not the sample.
  for (std::size_t i = 0; i < result.contact_force.size(); ++i) {
    if (result.contact_force[i].min > 0.0) continue;
    result.life_missing = "the life values assume every contact stays closed, and roller " + scene.rollers[i].name +
                          " leaves the bore over " +
                          std::to_string(std::lround(100.0 * result.contact_force[i].off_bore)) + " % of the turn";
    return;
  }
  const PhasorSum sum = source.Phasors(scene);
  if (!sum.usable) {
    result.status = Status::kNotConverged;
    result.message = "the life values need the linear rung's phasors, and the error-free assembly cannot be linearised";
    return;
  }
  result.life = EveryRevolution(scene, result, sum, result.life_cycle, accuracy);
}

// AngleMode::kSpectral for the linear rung and auto's first step: the spectral result when
// it settles the scene, else the trajectory auto's exact rungs give (to be measured
// densely), else nullopt for the dense evaluation to decide.
struct SpectralOutcome {
  std::optional<SimulationResult> settled;
  std::optional<Trajectory> escalated;
  const LinearSolver* rung = nullptr;  // the linear rung that gave `settled`
};

SpectralOutcome SimulateSpectralRung(const engine::Scene& scene, const Solver& solver, const SimulationOptions& options,
                                     int steps) {
  SpectralOutcome outcome;
  const auto* linear = dynamic_cast<const LinearSolver*>(&solver);
  const auto* automatic = dynamic_cast<const AutoSolver*>(&solver);
  if (linear == nullptr && automatic == nullptr) return outcome;
  // The linear rung alone is held to the budget auto would give it, so both record the
  // same estimate for a path they both settle.
  const double target = automatic != nullptr       ? automatic->budget()
                        : options.path_tolerance > 0.0 ? kAutoShareOfPathTolerance * options.path_tolerance
                                                       : std::numeric_limits<double>::infinity();
  const LinearSolver& rung = linear != nullptr ? *linear : automatic->linear();
  std::optional<SpectralResult> spectral = SimulateSpectral(scene, rung, steps, options.refine_stride, target,
                                                            options.life, options.keep_trajectory, options.accuracy);
  if (!spectral) return outcome;
  if (automatic != nullptr &&
      (spectral->result.status != Status::kOk || !automatic->LinearVerdict(scene, spectral->margins).empty())) {
    outcome.escalated = automatic->SolveExact(scene, steps);
    return outcome;
  }
  outcome.settled = std::move(spectral->result);
  outcome.rung = &rung;
  outcome.settled->life = spectral->life;
  outcome.settled->life_cycle = spectral->life_cycle;
  return outcome;
}

// Simulate's result before its points are dropped: the spectral evaluation keeps points
// only where keep_trajectory asks; the other modes keep them all, and Simulate drops them.
SimulationResult SimulateAnyAngles(const engine::Scene& scene, const Solver& solver,
                                   const SimulationOptions& options) {
  SimulationResult result;
  result.steps = ChooseSteps(scene, options);
  result.status = CheckSceneGeometry(scene, result.message);
  if (result.status != Status::kOk) return result;
  if (options.angles == AngleMode::kRefined && !options.life) {
    if (std::optional<SimulationResult> refined = SimulateRefined(scene, solver, options, result.steps)) {
      return std::move(*refined);
    }
  }
  std::optional<Trajectory> escalated;
  if (options.angles == AngleMode::kSpectral) {
    SpectralOutcome outcome = SimulateSpectralRung(scene, solver, options, result.steps);
    if (outcome.settled) {
      SimulationResult& settled = *outcome.settled;
      if (settled.status != Status::kOk) return std::move(settled);
      // The rung's own static equilibrium of the error-free assembly: the one it linearised
      // at and kept, read back without a second search (the quasistatic rung's would find
      // it again to its Newton tolerance).
      const Equilibrium nominal = outcome.rung->SolveStatic(engine::WithoutErrors(scene));
      if (nominal.status != Status::kOk) {
        result.status = nominal.status;
        result.message = "the error-free assembly has no valid static equilibrium: " + nominal.message;
        return result;
      }
      settled.static_offset = (settled.trajectory.initial.centre - nominal.centre).norm();
      return std::move(settled);
    }
    escalated = std::move(outcome.escalated);
  }
  result.trajectory = escalated ? std::move(*escalated) : solver.SolveRevolution(scene, result.steps);
  if (!result.trajectory.rung) result.trajectory.rung = ValueNamed(kRungNames, solver.name());
  // One verdict for every rung: a rung's own checks may miss what another's catch. A
  // contact may open where the rung's equations let it (RollerLosingSupport).
  const ValidityCheck validity(scene, {.contacts_may_open = result.trajectory.rung != Rung::kLinear});
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
  if (options.life) ReadLife(scene, solver, options.accuracy, result);
  return result;
}

}  // namespace

SimulationResult Simulate(const engine::Scene& scene, const Solver& solver, const SimulationOptions& options) {
  SimulationResult result = SimulateAnyAngles(scene, solver, options);
  if (!options.keep_trajectory) {
    Trajectory& path = result.trajectory;
    path.psi.clear();
    path.centre.clear();
    path.travel.clear();
    path.contact_force.clear();
    result.sensor.clear();
  }
  return result;
}

}  // namespace ringtol::solvers
