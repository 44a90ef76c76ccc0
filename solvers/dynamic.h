// The dynamic rung: planar dynamics of the ring (x, y free, rotation imposed by a motion
// law), of each spring roller along its axis and of each roller's spin, with the contact
// and friction laws of model.md §4:
//   F_n = k delta^e + STEP(delta, 0, 0, d, c_max) delta'   (clamped at 0: no adhesion)
//   F_t = -mu(v_slip) F_n, mu rising to mu_s at v_s, falling to mu_d at v_d, odd in v.
// Roller shape errors follow each roller's actual spin angle, which friction drives.
//
// The ring starts centred and at rest, every roller at zero travel and zero spin, and
// settles under the preload while the law holds the ring still; SolveStatic reports the
// state when rotation starts. SolveRevolution samples a revolution after that (the first
// by default) at the times the imposed angle passes psi_k = 2 pi k / steps.
//
// The system is stiff (the spring roller against c_max: eigenvalues near -4e7 1/s), so
// the default integrator is SUNDIALS CVODE's variable-order BDF with a dense Jacobian.
// Integration restarts at every breakpoint of the motion law, where the rate or the
// acceleration jumps. Failures (step-size collapse, repeated error-test or Newton
// failures, a contact search that fails, a non-finite state, penetration deeper than a
// roller's radius) come back as a status, never as numbers.
#pragma once

#include "solvers/motion_law.h"
#include "solvers/solver.h"

namespace ringtol::solvers {

struct DynamicOptions {
  // The imposed rotation; the default is the article's law (settle 0.5 s, then 270 deg/s).
  MotionLaw law = ArticleLaw();
  // Which revolution after rotation starts SolveRevolution reports: 0 is the first, with
  // the start transient; a later one shows the steady state.
  int revolution = 0;
  // CVODE tolerances: relative, and absolute per kind of state.
  double relative_tolerance = 1e-8;
  double position_tolerance = 1e-11;  // [m]  centre and travel
  double velocity_tolerance = 1e-8;   // [m/s]
  double angle_tolerance = 1e-9;      // [rad] roller spin angles
  double spin_rate_tolerance = 1e-6;  // [rad/s]
  long max_steps = 20'000'000;        // integrator steps over the whole run
  // Friction at the contacts. Off, nothing makes the rollers turn: combine with
  // rolling_without_slip unless non-spinning rollers are what is wanted. Safe when the
  // tangential forces do not matter to the path, which holds for circular rollers at
  // steady speed (friction then only keeps them rolling).
  bool friction = true;
  // Rollers turn at exactly R / r_b times the ring's rate (no spin states, no stiction
  // dynamics) and exchange no tangential force. Safe after the rollers have spun up, i.e.
  // away from starts, stops and reversals: it removes the stiffest eigenvalues (~ -1e6
  // 1/s from stiction on a roller's spin).
  bool rolling_without_slip = false;
};

class DynamicSolver final : public Solver {
 public:
  explicit DynamicSolver(DynamicOptions options = {}) : options_(std::move(options)) {}
  std::string_view name() const override { return "dynamic"; }
  Equilibrium SolveStatic(const engine::Scene& scene) const override;
  Trajectory SolveRevolution(const engine::Scene& scene, int steps) const override;

  const DynamicOptions& options() const { return options_; }

 private:
  DynamicOptions options_;
};

}  // namespace ringtol::solvers
