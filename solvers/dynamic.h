// The dynamic rung: planar dynamics of the ring (x, y free, rotation imposed by the scene's
// motion law), of each spring roller along its axis and of each roller's spin, with the
// contact and friction laws of docs/model.md §4:
//   F_n = k delta^e + STEP(delta, 0, 0, d, c_max) delta'   (clamped at 0: no adhesion)
//   F_t = mu(v_slip) F_n against the slip, mu the cubic STEP from -mu_s at -v_s to mu_s at
//         v_s (Adams' contact friction: smooth through zero slip), then to mu_d at v_d.
// Roller shape errors follow each roller's actual spin angle, which friction drives. The
// scene's DynamicModel (engine/scene.h) says which of these states to keep.
//
// Where the run starts is DynamicOptions::start. By default the ring starts at rest at the
// quasistatic equilibrium of the penalty law (solvers/quasistatic.h), which is a dynamic
// equilibrium too (at rest the damping and friction forces vanish), as a multibody user's
// static-equilibrium analysis would place it before a dynamic run; the article's start
// puts the ring centred and lets it settle under the preload while the law holds it
// still, which after 0.5 s it has not finished doing (docs/model.md §8). SolveStatic
// reports the state when rotation starts. SolveRevolution samples the first revolution
// after that at the times the imposed angle passes psi_k = 2 pi k / steps and, from the
// same run, a later revolution as Trajectory::steady, so the start transient's share is
// visible.
//
// The system is stiff (a spring roller of grams against c_max: eigenvalues near -4e7 1/s;
// stiction on a roller's spin near -1e6 1/s), so the integrator is SUNDIALS CVODE's
// variable-order BDF with a dense direct linear solver. Integration restarts at every
// breakpoint of the motion law, where the rate or the acceleration jumps. Failures
// (step-size collapse, repeated error-test or Newton failures, a contact search that
// fails, a non-finite state, penetration deeper than half a roller's radius, a massless
// spring roller that leaves the bore, an explicit step above its stability limit) come
// back as a status, never as numbers. From rotation start on, CVODE's root finder watches
// each contact's penetration: a contact that opens, even between two samples, is kLiftOff
// at the moment it opens (at samples too, a contact without overlap is kLiftOff).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/option_range.h"
#include "solvers/solver.h"

namespace ringtol::solvers {

enum class DynamicMethod {
  // CVODE's variable-order BDF with error control and the analytic Jacobian: the default,
  // stable at any step the accuracy allows.
  kImplicitBdf,
  // ARKODE's explicit 4th-order Runge-Kutta (Zonneveld 5-3-4) at a fixed step, kept as a
  // baseline. Stable only below ~2.8 / |lambda_max|: ~70 ns for the full model (spring
  // roller against c_max), ~2 us with massless spring rollers (roller spin under
  // stiction), ~30 us with rolling imposed too (the ring against c_max). Above it the
  // state blows up and the run ends with kNonFinite or kIntegrationFailed.
  kExplicitRungeKutta,
};

// The state a dynamic run starts from at t = 0, before the motion law's first segment.
enum class DynamicStart {
  // At rest at the quasistatic equilibrium at psi = 0 with the scene's penalty law: ring
  // centre and spring travel where contact, spring and preload balance, every roller at
  // its psi = 0 spin angle and spinning as it would roll at the law's rate at t = 0 (0
  // for a law that starts with a settle). Nothing is left to settle, so the first
  // revolution differs from a steady one only by the dynamic effects of the speed.
  kQuasistaticEquilibrium,
  // The article's start: the ring centred and at rest, spring rollers pressed against it
  // where spring and contact stiffness balance, every roller still; the ring settles
  // under the preload while the law holds it (the article's 0.5 s leaves it ~150 um
  // short of its equilibrium: a creep transient the first revolution carries).
  kArticleSettle,
};
// Stable names in files and on the command line (`start`, `--dynamic-start`).
inline constexpr NameTable<DynamicStart, 2> kDynamicStartNames = {
    {{DynamicStart::kQuasistaticEquilibrium, "quasistatic_equilibrium"}, {DynamicStart::kArticleSettle, "article_settle"}}};

// Each field's range is the Range beside it; IsValid checks them all.
struct DynamicOptions {
  DynamicMethod method = DynamicMethod::kImplicitBdf;
  DynamicStart start = DynamicStart::kQuasistaticEquilibrium;
  double explicit_step = 1e-6;  // [s] the fixed step of kExplicitRungeKutta
  static constexpr Range kExplicitStepRange = Above(0.0);
  // Which later revolution after rotation starts (counting the first as 0) is reported as
  // Trajectory::steady; 0 reports none. By the default, the fourth, a creep transient of
  // the start (time constant c_max / k_contact ~ 0.5 s, 4 s ago at 270 deg/s) has decayed
  // to e^-8 of its size. When the motion law stops before that revolution ends, its status
  // is kIntegrationFailed and says so.
  int steady_revolution = 3;
  static constexpr Range kSteadyRevolutionRange = AtLeast(0);
  // CVODE's local error test: the weighted RMS norm of the estimated local error, with
  // weights 1 / (relative_tolerance |y_j| + absolute_j), must stay <= 1. The absolute
  // tolerances per kind of state scale with relative_tolerance from these values at 1e-8
  // (so one knob trades accuracy for speed): 1e-11 m, 1e-8 m/s, 1e-9 rad, 1e-6 rad/s.
  // At the default the error in D_trajectory against a 1e-11 reference is <= 0.02 um for
  // ring orders 2 to 20 at 0.14 mm (docs/usage.md, "Which rung when": `ringtol bench ladder`); 1e-5 is about 1.5
  // times faster at <= 0.13 um. Below 1: a tolerance of 100 % accepts any step.
  double relative_tolerance = 1e-6;  // [-]
  static constexpr Range kRelativeToleranceRange = Inside(0.0, 1.0);
  // BDF steps allowed between two outputs (an output every sample angle, and at the end
  // of the settle) before the run stops with kIntegrationFailed (CV_TOO_MUCH_WORK):
  // the default runs take a few hundred. The explicit method's fixed step sets its work
  // in advance and has no such limit.
  long max_steps = 100'000;
  static constexpr Range kMaxStepsRange = AtLeast(1);
  // Let CVODE build the Newton matrix by difference quotients (one dynamics evaluation
  // per state) instead of the analytic Jacobian: a cross-check, and a fallback.
  bool difference_quotient_jacobian = false;

  // Whether every field lies in its range; the first that does not is described in
  // *invalid (engine/option_range.h).
  bool IsValid(InvalidOption* invalid = nullptr) const;
};

// One sample of a time history: the state and what each contact carries.
struct DynamicSample {
  double time = 0.0;                               // [s]
  double psi = 0.0;                                // [rad] imposed ring angle
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // [m]
  std::vector<double> travel;                      // [m] per roller, 0 for fixed ones
  std::vector<double> spin_angle;                  // [rad] per roller, body x axis from global +x
  std::vector<double> spin_rate;                   // [rad/s] per roller
  std::vector<double> penetration;                 // [m] per roller, > 0 while touching
  std::vector<double> normal_force;                // [N] per roller, >= 0
  std::vector<double> friction_force;              // [N] per roller, on the ring along the contact tangent
  std::vector<double> slip;                        // [m/s] per roller, ring point minus roller point, along the tangent
};

struct DynamicHistory {
  Status status = Status::kOk;
  std::string message;
  std::vector<DynamicSample> samples;  // up to the failure when status != kOk
};

// The equations of motion themselves, for tests and tools. The state is laid out as
// [x, y [m], vx, vy [m/s]; per spring roller in scene order: travel [m], and its rate
// [m/s] unless massless; per roller when friction turns them (friction on, rolling not
// imposed): spin angle [rad], spin rate [rad/s]].
struct DynamicsEvaluation {
  Status status = Status::kOk;  // kIntegrationFailed (with message) where Derivatives would refuse
  std::string message;
  Eigen::VectorXd rates;        // dy/dt
  Eigen::MatrixXd jacobian;     // d(dy/dt)/dy, the analytic one the integrator uses
};
// The state the integrator starts from at t = 0 (options.start). For the quasistatic start,
// the article's when the quasistatic equilibrium cannot be found (a run then stops with
// that status instead).
Eigen::VectorXd InitialDynamicState(const engine::Scene& scene, const DynamicOptions& options = {});
// dy/dt and its Jacobian at time t [s] and `state`.
DynamicsEvaluation EvaluateDynamics(const engine::Scene& scene, double t, const Eigen::VectorXd& state,
                                    const DynamicOptions& options = {});

class DynamicSolver final : public Solver {
 public:
  explicit DynamicSolver(DynamicOptions options = {}) : options_(options) {}
  std::string_view name() const override { return "dynamic"; }
  Equilibrium SolveStatic(const engine::Scene& scene) const override;
  Trajectory SolveRevolution(const engine::Scene& scene, int steps) const override;

  // The state every `interval` [s] (> 0) from t = 0 to `duration` [s] (>= 0).
  DynamicHistory SolveHistory(const engine::Scene& scene, double interval, double duration) const;

  const DynamicOptions& options() const { return options_; }

 private:
  DynamicOptions options_;
};

}  // namespace ringtol::solvers
