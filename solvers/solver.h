// The common interface of the solver ladder. Every rung (linear, quasistatic, dynamic)
// turns a Scene into the ring centre's path over one
// revolution plus the static equilibrium before rotation; solvers/simulation.h turns that
// into the published metrics. A solver never throws for a numerical outcome: it returns a
// Status saying whether its numbers are usable.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "engine/enum_names.h"
#include "engine/scene.h"

namespace ringtol::solvers {

enum class Status {
  kOk,                       // every number is usable
  kLiftOff,                  // a contact would have to pull (force <= 0): the assembly rattles; path unusable
  kNotConverged,             // the iteration failed at some angle; path unusable
  kTwoPointContact,          // a roller touches the bore at two places; the model does not apply
  kRingNotConvex,            // scene cannot be simulated (see message)
  kRollerNotConvex,          // scene cannot be simulated (see message)
  kRollerDoesNotFit,         // a roller is too large or overlaps another, or a spring roller's travel exceeds its limit
  kStaticallyIndeterminate,  // rigid contact with more than two fixed rollers: use the penalty law
  kIntegrationFailed,        // the dynamic integrator gave up (step-size collapse, repeated failures; see message)
  kNonFinite,                // the dynamic state or the linearised path turned NaN or infinite
  kBeyondLinearRange,        // the linear rung's error bound (of its second-order path) exceeds its limit; path unusable
};

// Stable lower_snake_case names used in every output file, listed in the order of the
// values, which are numbered 0, 1, ... (results files store the numbers).
inline constexpr NameTable<Status, 11> kStatusNames = {{{Status::kOk, "ok"},
                                                        {Status::kLiftOff, "lift_off"},
                                                        {Status::kNotConverged, "not_converged"},
                                                        {Status::kTwoPointContact, "two_point_contact"},
                                                        {Status::kRingNotConvex, "ring_not_convex"},
                                                        {Status::kRollerNotConvex, "roller_not_convex"},
                                                        {Status::kRollerDoesNotFit, "roller_does_not_fit"},
                                                        {Status::kStaticallyIndeterminate, "statically_indeterminate"},
                                                        {Status::kIntegrationFailed, "integration_failed"},
                                                        {Status::kNonFinite, "non_finite"},
                                                        {Status::kBeyondLinearRange, "beyond_linear_range"}}};
static_assert([] {
  for (std::size_t i = 0; i < kStatusNames.size(); ++i) {
    if (static_cast<std::size_t>(kStatusNames[i].value) != i) return false;
  }
  return true;
}(), "kStatusNames lists every Status in the order of its number");
constexpr std::string_view StatusName(Status status) { return NameOf(kStatusNames, status); }

// The rungs of the ladder, cheapest first, and `auto`, which picks one of them per scene
// (solvers/auto.h); their names are what files and the command line say (`solver.name`,
// `--solver`), and results files store a path's rung by its number (0..2; auto is never a
// path's rung). SolverSettings (solvers/simulation.h) picks one and MakeSolver makes it.
enum class Rung { kLinear, kQuasistatic, kDynamic, kAuto };
inline constexpr NameTable<Rung, 4> kRungNames = {{{Rung::kLinear, "linear"},
                                                   {Rung::kQuasistatic, "quasistatic"},
                                                   {Rung::kDynamic, "dynamic"},
                                                   {Rung::kAuto, "auto"}}};

// engine::CheckGeometry as a solver status (kOk when the scene can be simulated), with
// its reason in `message`.
Status CheckSceneGeometry(const engine::Scene& scene, std::string& message);

// Static equilibrium (or any single configuration) of the assembly.
struct Equilibrium {
  Status status = Status::kOk;
  std::string message;                                  // reason when status != kOk
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();     // [m] ring centre
  std::vector<double> travel;                           // [m] per roller, along its axis; 0 for fixed
  std::vector<double> contact_force;                    // [N] per roller, >= 0 when usable
  int iterations = 0;                                   // Newton iterations used
};

// The path over one whole revolution, psi_k = 2 pi k / steps, k = 0 .. steps: steps + 1
// samples, because with roller lobes (R / r_b is rarely an integer) the path does not
// close, and the enclosing circle must see its end.
struct Trajectory {
  Status status = Status::kOk;
  std::string message;
  double failure_angle = 0.0;                  // [rad] where status != kOk arose
  Equilibrium initial;                         // static equilibrium before rotation starts
  std::vector<double> psi;                     // [rad]
  std::vector<Eigen::Vector2d> centre;         // [m]
  std::vector<double> travel;                  // [m] psi-major: travel[k * rollers + i]
  std::vector<double> contact_force;           // [N] psi-major: contact_force[k * rollers + i]
  int total_iterations = 0;                    // Newton iterations (dynamic: integrator steps) over the run
  // [m] >= 0: the rung's own estimate of how far its approximation moves D_trajectory
  // (the linear rung: its neglected second-order terms, LinearOptions); 0 for the rungs
  // that solve the exact model, whose error is their tolerance.
  double error_estimate = 0.0;
  // The rung that computed the path: set by a solver that chooses one (auto), else by
  // Simulate from the solver's name; empty for a solver outside the ladder.
  std::optional<Rung> rung;
  // A later revolution of the same run, for a solver that simulates time (dynamic): the
  // steady state after the start transient, with `initial` still the state at rotation
  // start; its own status says whether it is usable (the law may stop before it). Null for
  // the time-free rungs, when not asked for, and when the first revolution failed.
  std::shared_ptr<const Trajectory> steady;
};

class Solver {
 public:
  virtual ~Solver() = default;
  virtual std::string_view name() const = 0;

  // Static equilibrium at psi = 0, before rotation starts.
  virtual Equilibrium SolveStatic(const engine::Scene& scene) const = 0;

  // One revolution in `steps` equal increments (steps >= 1, steps + 1 samples including
  // both ends). On failure the trajectory
  // holds the angles solved so far and the status says why it stopped.
  virtual Trajectory SolveRevolution(const engine::Scene& scene, int steps) const = 0;
};

}  // namespace ringtol::solvers
