// One simulation as the article reports it (docs/model.md §5): run a solver over one
// revolution and reduce the path to D_trajectory, Dist_init, the static offset, the
// sensor's runout and swing and the contact-force range.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/enclosing_circle.h"
#include "engine/error_motion.h"
#include "engine/option_range.h"
#include "engine/scene.h"
#include "solvers/dynamic.h"
#include "solvers/solver.h"

namespace ringtol::solvers {

// The most angles per revolution any run takes: the automatic resolution's ceiling and
// the largest `steps` a file or the command line may ask for.
inline constexpr int kMaxSteps = 2000000;

// Which of the revolution's angles are evaluated at full cost. kDense: every one, the
// reference. kRefined: every `refine_stride`-th and the last, then only the stretches
// between them where the first-order path in closed form (the linear rung's, which
// carries the rollers' fast lobes) plus the exact path's rest interpolated between the
// stretch's ends, within a bound on that second-order rest, could lie outside the
// enclosing circle or beyond the sensor signal's extremes, or where a contact force or a
// spring travel is within twice its first-order chord bound (LinearSolver::ChordStraying)
// of failing. What is left unevaluated then changes none of D_trajectory, runout and the
// status: they equal the dense grid's to the solver's tolerance (docs/model.md). Not
// certified: the swing (its counter-moves are the ripple the stride skips) and the
// force range, both read at the evaluated angles. result.trajectory and result.sensor
// hold those angles only. Linear and quasistatic rungs; the dynamic rung, a filtered
// swing rule and bores a roller could bridge (a two-point search) stay dense, and a
// sample that fails anywhere is rerun dense, which states the failure.
// kSpectral: the linear rung (alone, or as auto's first step) read from its phasors at a
// coarse grid of every `refine_stride`-th angle and the stretches a chord bound cannot
// settle (solvers/spectral.h): D_trajectory, Dist_init, the force range, the error
// estimate and the status equal the dense grid's to round-off; the sensor is read in
// closed form, to second order, and the runout and swing from its whole signal. The
// exact rungs, and scenes the bounds do not cover, run dense.
enum class AngleMode { kDense, kRefined, kSpectral };
inline constexpr NameTable<AngleMode, 3> kAngleModeNames = {
    {{AngleMode::kDense, "dense"}, {AngleMode::kRefined, "refined"}, {AngleMode::kSpectral, "spectral"}}};

// What a campaign trades of the reported values' definition for speed (docs/model.md §5,
// "Accuracy settings"). kFull: every output as the mode above defines it, the reference.
// kFast, two changes whose outputs stay bounded but move within the path tolerance's
// budget (measured against kFull on 16,384 default samples):
// - the spectral mode also tries the cubic Hermite bound (LinearPath::StrayingOver) on a
//   stretch the chord bound leaves open, so it refines about half as many angles. The
//   certified outputs, statuses and rungs do not move; the runout, the swing and the life
//   values read the second-order rest interpolated across more of the revolution: runout
//   0.027, swing 0.036, life D_trajectory 0.025, life runout 0.031 um at most;
// - the life samples the rollers' lobe curves kFastCurveLooseness times looser
//   (solvers/life.h), its hull widened by the larger straying: with the first, life
//   D_trajectory 0.041, life runout 0.049, error motion 0.006 um at most.
enum class Accuracy { kFull, kFast };
inline constexpr NameTable<Accuracy, 2> kAccuracyNames = {{{Accuracy::kFull, "full"}, {Accuracy::kFast, "fast"}}};

// Each field's range is the Range beside it; IsValid checks them all.
struct SimulationOptions {
  // Angles per revolution; 0 chooses them from the scene (ChooseSteps).
  int steps = 0;
  static constexpr Range kStepsRange = Between(0, kMaxSteps);
  AngleMode angles = AngleMode::kDense;
  // kRefined: evaluate every this many of the `steps` angles first. Eight keeps the
  // ring's harmonics (<= 50 per revolution) resolved on the coarse grid at campaign
  // resolutions, so only the roller lobes' ripple decides what is refined.
  int refine_stride = 8;
  static constexpr Range kRefineStrideRange = AtLeast(2);
  // Automatic resolution: samples per period of the fastest undulation in the path [-].
  // The sampled enclosing circle misses a smooth path by at most |c''| dpsi^2 / 8, so 32
  // samples keep that below 0.5 % of the fastest term's amplitude; two or fewer alias it
  // (engine::MinimumSteps).
  double samples_per_undulation = 32.0;
  static constexpr Range kSamplesPerUndulationRange = Above(2.0);
  int min_steps = 360;  // floor of the automatic resolution
  static constexpr Range kMinStepsRange = Between(1, kMaxSteps);
  int max_steps = kMaxSteps;  // ceiling of the automatic resolution: min_steps..kMaxSteps
  // [m] > 0: instead of resolving every undulation, the fewest steps whose bound on the
  // sampling error of D_trajectory and runout (and of the swing, at twice this;
  // SamplingErrorBound) is at most this. Tiny fast terms
  // (a roller's high lobes pass ~60 n times per revolution at sub-micrometre amplitude)
  // then cost what they are worth; campaigns set it, single runs keep the exact rule.
  double path_tolerance = 0.0;
  static constexpr Range kPathToleranceRange = AtLeast(0.0);
  // Also read the life values over every revolution the assembly will turn (solvers/life.h,
  // SimulationResult::life): the lobes of the rollers' spin-ratio groups as closed curves
  // from the linear rung's phasors, summed onto the path less its lobes. Costs those
  // curves and a hull, no solve. kRefined angles then run dense: the stretches they skip
  // are chosen for one revolution's extremes, not for the life's.
  bool life = false;
  // Keep the path's points in SimulationResult: trajectory.psi, centre, travel and
  // contact_force, and sensor (the angles evaluated, or every angle). false leaves them
  // empty (the metrics, the rung, the error estimate, the initial equilibrium and the
  // steady and life values stay): a campaign reads no point, and with spectral angles
  // copying them is a share of a sample's cost. Single runs, replays and plots keep them.
  bool keep_trajectory = true;
  Accuracy accuracy = Accuracy::kFull;

  // Whether every field lies in its range; the first that does not is described in
  // *invalid (engine/option_range.h).
  bool IsValid(InvalidOption* invalid = nullptr) const;
};

// Which solver runs a simulation and how, as a campaign file's [solver] table, the command
// line (--solver, --steps, --relative-tolerance, --dynamic-start) and the report's replays state it; one
// factory makes the solver from it, so the rules below hold wherever a solver is made.
struct SolverSettings {
  // A single run's default; campaigns and allocations default to Rung::kAuto, whose
  // budget for the linear rung's error is kAutoShareOfPathTolerance of path_tolerance.
  Rung rung = Rung::kQuasistatic;
  // Angles per revolution and the sampling budget. With a budget (path_tolerance > 0) the
  // quasistatic rung converges each angle to kAngleShareOfPathTolerance of it instead of
  // its default 1 pm: solving far below what the sampling may miss buys nothing, and at
  // that tolerance one Newton update per angle suffices where the rollers' lobes outrun
  // the predictor (half the cost of a campaign's sample).
  SimulationOptions simulation;
  // [-] the dynamic rung's integration tolerance, in DynamicOptions::kRelativeToleranceRange
  double relative_tolerance = 1e-6;
  DynamicStart dynamic_start = DynamicStart::kQuasistaticEquilibrium;  // the dynamic rung's start

  // Whether `simulation` and relative_tolerance lie in their ranges; the first field that
  // does not is described in *invalid ("simulation.steps", "relative_tolerance").
  bool IsValid(InvalidOption* invalid = nullptr) const;
};

// The rung's name, for the dynamic rung its start ("dynamic, start
// quasistatic_equilibrium"), and an accuracy other than full ("auto, accuracy fast"): what
// a results file records as its solver, so summaries and reports state the setting.
std::string SolverDescription(const SolverSettings& settings);
inline constexpr double kAngleShareOfPathTolerance = 0.01;
// The auto rung's budget for the linear rung's error estimate (the bound on what its
// second-order path misses), as a share of
// path_tolerance [-]: the sampling bound may use the whole budget, so the model's error is
// held to half of it, and the total to 1.5 path_tolerance.
inline constexpr double kAutoShareOfPathTolerance = 0.5;

// Never fails: every Rung has a solver.
std::unique_ptr<Solver> MakeSolver(const SolverSettings& settings);

// Steps for one revolution: options.steps if set, else enough that the fastest term of
// the path (ring order n passes n times, roller order m passes m R/r_b times per
// revolution, and the exact model's second-order products twice as fast) is sampled
// `samples_per_undulation` times per period, so no harmonic aliases; with a
// path_tolerance, the fewest that meet it. Either count is rounded up to
// FourierFriendlySteps (within max_steps).
int ChooseSteps(const engine::Scene& scene, const SimulationOptions& options);

// The smallest count >= at_least (>= 1) that is 8 times a product of 2s, 3s and 5s: a
// revolution of it passes the error motion's filter (a Fourier transform of the
// revolution, engine::GaussianFilterClosed) in n log n time, where a count with a large
// prime factor p takes n p (a prime 3,253 angles: 0.12 s against 0.1 ms).
int FourierFriendlySteps(int at_least);

// Upper bounds [m] on how far each metric of a revolution sampled at `steps` angles can be
// from the continuous revolution's, to first order in the error amplitudes. The path and
// the sensor signal are sums of terms, one per error harmonic: amplitude g A (A the
// harmonic's radial amplitude, g a gain, below) at rate w per revolution (ring order n:
// w = n; roller order m: w = m R / r_b). Between two samples dpsi apart a term strays from
// the chord by at most min(2, w^2 dpsi^2 / 8) g A; the sums of these bound how far the
// continuous path strays from the sampled polygon (`path`) and the continuous signal from
// the sampled one's interpolant (eta). Then
//   D_trajectory: the sampled circle encloses the polygon, so 0 <= D - D_N <= 2 path;
//   runout (max - min): 0 <= TIR - TIR_N <= 2 eta;
//   swing: a rise and a counter-move each move by at most 2 eta, so |swing - swing_N|
//     <= 4 eta; with the rule's filter, a term at or above half the sampling rate aliases
//     and counts 2 g A instead.
// Gains: G = 1 / sigma_min of the fixed rollers' unit contact normals for the centre (rigid
// support by the fixed rollers, the spring roller following); a ring harmonic meets every
// fixed contact at once, so sqrt(fixed rollers) G, and passes the sensor itself with gain
// 1. Second-order products of amplitudes are left out. Dist_init has no bound of this
// kind: the enclosing circle's centre is only Hoelder-1/2 in the path (it can move by
// sqrt(path (2 R + path)) for a circle of radius R), so docs/model.md §5 states its
// convergence as measured. With fewer than two fixed rollers every bound is infinite.
struct SamplingErrorBounds {
  double path = 0.0;          // the continuous path lies within this of the sampled polygon
  double d_trajectory = 0.0;  // 2 path
  double runout = 0.0;        // 2 eta
  double swing = 0.0;         // 4 eta (aliased terms counted in full when filtered)

  // What the step rule keeps within its budget: the largest of D_trajectory's and runout's
  // bounds and half the swing's. The swing reads two extremes and a counter-move, so it
  // is allowed twice the budget rather than costing twice the steps' worth of accuracy.
  double Largest() const;
};
SamplingErrorBounds SamplingErrorBoundsAt(const engine::Scene& scene, int steps);

// SamplingErrorBoundsAt(scene, steps).Largest(): the step rule's measure.
double SamplingErrorBound(const engine::Scene& scene, int steps);

// The sum over the first-order path's terms (gains as above) of gain A weight(w), w the
// term's rate per revolution: with weight(w) = w^k a bound on |d^k c / d psi^k| [m/rad^k].
// Infinite with fewer than two fixed rollers.
double SumOverPathTerms(const engine::Scene& scene, const std::function<double(double rate)>& weight);

// The one-revolution metrics over many revolutions (solvers/life.h).
struct LifeValues {
  double d_trajectory = 0.0;         // [m] over the union of the revolutions' centre paths
  double runout = 0.0;               // [m] the sensor's max - min over every revolution
  engine::ErrorMotion error_motion;  // [m] of the axis along the sensor's direction
};

struct RollerForceRange {
  double min = 0.0;  // [N]
  double max = 0.0;  // [N]
  // [-] share of the revolution's angles at which the roller carries nothing: off the bore,
  // the ring resting on the others (docs/model.md §7, "Contacts that open"); 0 while it
  // touches throughout.
  double off_bore = 0.0;
};

struct SimulationResult {
  Status status = Status::kOk;
  std::string message;
  int steps = 0;
  double d_trajectory = 0.0;    // [m] diameter of the smallest circle enclosing the path
  double dist_init = 0.0;       // [m] static equilibrium to that circle's centre
  double static_offset = 0.0;   // [m] error-free static equilibrium to the static equilibrium
  double runout = 0.0;          // [m] sensor: total indicator reading, max - min
  double swing = 0.0;           // [m] sensor: peak-to-valley swing by the scene's SwingRule
  double min_contact_force = 0.0;  // [N] over all rollers and angles
  std::vector<RollerForceRange> contact_force;  // per roller
  engine::Circle enclosing_circle;              // [m]
  std::vector<double> sensor;                   // [m] sensor reading per angle
  Trajectory trajectory;
  // The same metrics over the trajectory's later, steady revolution (Trajectory::steady)
  // when the solver gives one; its own status says whether they are usable.
  std::shared_ptr<const SimulationResult> steady;
  // With SimulationOptions::life and status ok: the values over every revolution, and the
  // revolutions after which the rollers' phases repeat (0: never; LifeResult::cycle).
  std::optional<LifeValues> life;
  int life_cycle = 0;
  // Why `life` is empty although SimulationOptions::life asked for it, status ok: a roller
  // left the bore, and the life reads the linear rung's phasors, which assume every contact
  // closed (docs/model.md §9). The revolution's own outputs stand. Empty otherwise.
  std::string life_missing;
};

// Never throws for numerical outcomes; status says whether the numbers are usable (they
// are zero otherwise).
SimulationResult Simulate(const engine::Scene& scene, const Solver& solver, const SimulationOptions& options = {});

}  // namespace ringtol::solvers
