// One simulation as the article reports it (model.md §5): run a solver over one
// revolution and reduce the path to D_trajectory, Dist_init, the static offset, the
// sensor runout and the contact-force range.
#pragma once

#include <memory>
#include <vector>

#include "engine/enclosing_circle.h"
#include "engine/scene.h"
#include "solvers/solver.h"

namespace ringtol::solvers {

struct SimulationOptions {
  // Angles per revolution; 0 chooses them from the scene (ChooseSteps).
  int steps = 0;
  // Automatic resolution: samples per period of the fastest undulation in the path [-].
  // The sampled enclosing circle misses a smooth path by at most |c''| dpsi^2 / 8, so 32
  // samples keep that below 0.5 % of the fastest term's amplitude.
  double samples_per_undulation = 32.0;
  int min_steps = 360;       // floor of the automatic resolution
  int max_steps = 2000000;   // ceiling of the automatic resolution
};

// Steps for one revolution: options.steps if set, else enough that the fastest term of
// the path (ring order n passes n times, roller order m passes m R/r_b times per
// revolution, and the exact model's second-order products twice as fast) is sampled
// `samples_per_undulation` times per period, so no harmonic aliases.
int ChooseSteps(const engine::Scene& scene, const SimulationOptions& options);

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
