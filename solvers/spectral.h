// The linear rung read from its phasors (AngleMode::kSpectral, solvers/simulation.h): its
// path is a sum of rotating phasors (solvers/linear.h LinearPath), so it is evaluated on a
// coarse grid of every stride-th angle, and then only on the stretches between two coarse
// angles where a bound (each term strays from its chord by at most min(2, w^2 dpsi^2 / 8)
// of its amplitude; with Accuracy::kFast also the tighter Hermite bound of
// LinearPath::StrayingOver) leaves open whether a dense angle there lies
// outside the enclosing circle or beyond the contact forces' extremes, or whether a force
// could reach zero or a travel its limit there. What is left unevaluated changes none of
// these, so D_trajectory, Dist_init, the smallest and the largest contact force and the
// status equal the dense evaluation's to round-off (each roller's own force range is read
// at the evaluated angles, within its chord bound). The sensor is read in closed form
// (LinearPath::Samples::signal) instead of by a Newton solve per angle; runout and swing
// take the signal's first-order part at every angle (one vectorised series,
// LinearPath::FirstOrderSignal) plus its second-order rest interpolated between the
// evaluated angles, within LinearPath::Straying::signal_rest of the dense reading.
#pragma once

#include <limits>
#include <optional>
#include <vector>

#include "engine/scene.h"
#include "solvers/life.h"
#include "solvers/linear.h"
#include "solvers/simulation.h"

namespace ringtol::solvers {

// What the auto rung weighs to let the linear path settle a scene (AutoSolver::
// LinearVerdict), as the spectral evaluation knows it.
struct LinearMargins {
  double error_estimate = 0.0;        // [m] Trajectory::error_estimate
  double smallest_force = 0.0;        // [N] over every contact and angle
  double largest_force = 0.0;         // [N]
  double reach = 0.0;                 // [m] the path's largest distance from its start
  std::vector<double> largest_travel; // [m] per roller, an upper bound on |travel| (0 fixed)
};

struct SpectralResult {
  SimulationResult result;  // all but static_offset, which needs the caller's solver
  LinearMargins margins;
  int evaluated = 0;        // angles evaluated at full cost, coarse and refined
  // [m] how far the signal runout and swing are read from can be from the exact reading of
  // the same path at any angle: the sensor's and the correction's rest interpolated across
  // the unevaluated stretches, plus the closed form's third order (below 1e-10 m).
  double signal_error = 0.0;
  // With `life`: the every-revolution values, and how far the centre they read can be
  // from the dense path's [m] (the correction interpolated across unevaluated stretches:
  // D_trajectory and the synchronous value within twice it, the runout within twice
  // signal_error).
  std::optional<LifeValues> life;
  int life_cycle = 0;  // LifeResult::cycle
  double centre_error = 0.0;
};

// nullopt where the evaluation does not apply (a roller the bore might touch twice, which
// needs a contact search at every angle; fewer than four coarse stretches; a path that
// cannot be linearised) or where any evaluated angle fails the validity check: the dense
// evaluation then runs and states the failure where it arises. steps >= 1, stride >= 2.
// The linear rung's own range limit (LinearOptions) applies as in SolveRevolution.
//
// The error estimate bounds the remainder over runs of coarse stretches at once
// (SecondOrderTerms::Over), which costs no angle but is looser than At's own remainder at
// each angle. The target [m] is the smaller of `estimate_target` (the auto rung's budget;
// infinite: none) and the linear rung's own range limit at the coarse angles' reach.
// Where a run's bound alone would carry the estimate above the target, its stretches are
// bounded one by one, and a stretch still above it is evaluated at every angle, where At's
// remainder is exact. Each level counts the smaller of its bound and the finer level's,
// floored at the target's share: the estimate stays continuous in the scene, never falls
// below the target once a bound exceeds it, and is below the target exactly where the
// dense path's own remainder is.
//
// With `life`, also the every-revolution life values (solvers/life.h) from the centre and
// the signal less their lobes at every angle (LinearPath::FirstOrderWithoutLobes), each
// plus its second order interpolated between the evaluated angles.
//
// keep_trajectory false: result.trajectory's points and result.sensor stay empty
// (SimulationOptions::keep_trajectory).
//
// Accuracy::kFull decides by the chord bound alone; kFast by the smaller of it and the
// Hermite bound (LinearPath::StrayingOver), which leaves about half the stretches
// unevaluated that the chord bound refines: the outputs above stay certified, while the
// runout, the swing and the life values, which read the rest interpolated across the
// unevaluated stretches, move within signal_error and centre_error. The auto rung's
// margins read the chord bound either way, so its verdicts do not depend on the setting.
std::optional<SpectralResult> SimulateSpectral(const engine::Scene& scene, const LinearSolver& linear, int steps,
                                               int stride,
                                               double estimate_target = std::numeric_limits<double>::infinity(),
                                               bool life = false, bool keep_trajectory = true,
                                               Accuracy accuracy = Accuracy::kFull);

}  // namespace ringtol::solvers
