// One simulation as the article reports it (docs/model.md §5): run a solver over one
// revolution and reduce the path to D_trajectory, Dist_init, the static offset, the
// sensor runout and the contact-force range.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "engine/enclosing_circle.h"
#include "engine/scene.h"
#include "solvers/dynamic.h"
#include "solvers/solver.h"

namespace ringtol::solvers {

// The most angles per revolution any run takes: the automatic resolution's ceiling and
// the largest `steps` a file or the command line may ask for.
inline constexpr int kMaxSteps = 2000000;

struct SimulationOptions {
  // Angles per revolution, 0..kMaxSteps; 0 chooses them from the scene (ChooseSteps).
  int steps = 0;
  // Automatic resolution: samples per period of the fastest undulation in the path [-].
  // The sampled enclosing circle misses a smooth path by at most |c''| dpsi^2 / 8, so 32
  // samples keep that below 0.5 % of the fastest term's amplitude.
  double samples_per_undulation = 32.0;
  int min_steps = 360;       // floor of the automatic resolution
  int max_steps = kMaxSteps;  // ceiling of the automatic resolution
  // > 0 [m]: instead of resolving every undulation, the fewest steps whose bound on the
  // sampling error of D_trajectory (SamplingErrorBound) is at most this. Tiny fast terms
  // (a roller's high lobes pass ~60 n times per revolution at sub-micrometre amplitude)
  // then cost what they are worth; campaigns set it, single runs keep the exact rule.
  double path_tolerance = 0.0;
};

// Which solver runs a simulation and how, as a campaign file's [solver] table, the command
// line (--solver, --steps, --relative-tolerance, --dynamic-start) and the report's replays state it; one
// factory makes the solver from it, so the rules below hold wherever a solver is made.
struct SolverSettings {
  Rung rung = Rung::kQuasistatic;
  // Angles per revolution and the sampling budget. With a budget (path_tolerance > 0) the
  // quasistatic rung converges each angle to kAngleShareOfPathTolerance of it instead of
  // its default 1 pm: solving far below what the sampling may miss buys nothing, and at
  // that tolerance one Newton update per angle suffices where the rollers' lobes outrun
  // the predictor (half the cost of a campaign's sample).
  SimulationOptions simulation;
  double relative_tolerance = 1e-6;  // [-] in (0, 1): the dynamic rung's integration tolerance
  DynamicStart dynamic_start = DynamicStart::kQuasistaticEquilibrium;  // the dynamic rung's start
};

// The rung's name, and for the dynamic rung its start ("dynamic, start
// quasistatic_equilibrium"): what a results file records as its solver.
std::string SolverDescription(const SolverSettings& settings);
inline constexpr double kAngleShareOfPathTolerance = 0.01;

// Never fails: every Rung has a solver.
std::unique_ptr<Solver> MakeSolver(const SolverSettings& settings);

// Steps for one revolution: options.steps if set, else enough that the fastest term of
// the path (ring order n passes n times, roller order m passes m R/r_b times per
// revolution, and the exact model's second-order products twice as fast) is sampled
// `samples_per_undulation` times per period, so no harmonic aliases.
int ChooseSteps(const engine::Scene& scene, const SimulationOptions& options);

// Upper bound [m] on how much D_trajectory sampled at `steps` angles can fall short of the
// continuous path's, to first order in the error amplitudes. The path is a sum of terms,
// one per error harmonic: amplitude G A (A the harmonic's radial amplitude, G the gain
// from a contact's gap to the centre, below) at rate w per revolution (ring order n:
// w = n; roller order m: w = m R / r_b). Between two samples dpsi apart a term strays
// from the chord by at most min(2, w^2 dpsi^2 / 8) G A; the true path lies within the sum
// of these of the sampled polygon, so within that much of the sampled enclosing circle,
// whose diameter is short by at most twice the sum. G = 1 / sigma_min of the fixed
// rollers' unit contact normals (rigid support by the fixed rollers, the spring roller
// following); a ring harmonic meets every fixed contact at once, so its gain is
// sqrt(fixed rollers) times that. Second-order products of amplitudes are left out. With
// fewer than two fixed rollers the bound is infinite.
double SamplingErrorBound(const engine::Scene& scene, int steps);

struct RollerForceRange {
  double min = 0.0;  // [N]
  double max = 0.0;  // [N]
};

struct SimulationResult {
  Status status = Status::kOk;
  std::string message;
  int steps = 0;
  double d_trajectory = 0.0;    // [m] diameter of the smallest circle enclosing the path
  double dist_init = 0.0;       // [m] static equilibrium to that circle's centre
  double static_offset = 0.0;   // [m] error-free static equilibrium to the static equilibrium
  double runout = 0.0;          // [m] sensor: largest peak to nearest valley
  double runout_total = 0.0;    // [m] sensor: max - min
  double min_contact_force = 0.0;  // [N] over all rollers and angles
  std::vector<RollerForceRange> contact_force;  // per roller
  engine::Circle enclosing_circle;              // [m]
  std::vector<double> sensor;                   // [m] sensor reading per angle
  Trajectory trajectory;
  // The same metrics over the trajectory's later, steady revolution (Trajectory::steady)
  // when the solver gives one; its own status says whether they are usable.
  std::shared_ptr<const SimulationResult> steady;
};

// Never throws for numerical outcomes; status says whether the numbers are usable (they
// are zero otherwise).
SimulationResult Simulate(const engine::Scene& scene, const Solver& solver, const SimulationOptions& options = {});

}  // namespace ringtol::solvers
