// The `auto` rung: per scene, the cheapest rung of the ladder whose estimated error fits
// the scene's budget (docs/model.md §7, "The auto rung").
//
//  1. The linear rung runs first, never refusing (its own range limit is lifted: this rung
//     decides). Its path settles the scene when it is valid (solvers/validity.h) and
//       e = Trajectory::error_estimate (twice the bound on every angle's centre error
//           that the linear rung's second-order path leaves, solvers/linear.h
//           SecondOrderTerms; it bounds D_trajectory's error and the runout's too: a
//           centre error dc moves the sensor's reading by its component along the ray, so
//           max - min by at most 2 |dc|) <= budget,
//       no contact's force is within kMarginFactor e k_c of zero (k_c [N/m] the largest
//           local contact stiffness e_law k delta^(e_law - 1) over the path, the penalty
//           law; a penetration's error is the centre's along n plus the contact's own gap
//           remainder, which the bound counts times its gain to the centre, 1.14 for the
//           article's layout; for rigid contact the force's share e / reach of its
//           largest value stands in), and
//       no spring roller's travel is within kMarginFactor e of its limit,
//     since a path whose status the neglected terms could change must not settle: every
//     failure of the linear rung (lift-off, travel, beyond its range) goes on as well.
//  2. Otherwise the quasistatic rung (the exact time-free model) runs. Its path settles
//     the scene unless the ring's inertia could open a contact the support needs, which
//     the time-free rungs cannot see:
//       F_inertia = sum over the path's terms of g A min(m_ring (omega^2 w^2 + |alpha| w), k_c)
//                 >= inertia_force_share F_min,
//     omega and alpha [rad/s, rad/s^2] the motion law's largest rate and finite
//     acceleration, g A and w each term's amplitude in the path and rate per revolution
//     (SumOverPathTerms, solvers/simulation.h), k_c as in step 1 over the path, F_min the
//     least force its support rests on (SupportForce, solvers/validity.h: on three rollers
//     the smallest contact force; a redundant roller's may reach zero). A term the ring
//     follows asks m a of the contacts; one too fast to follow is absorbed by the
//     contacts' compliance instead, changing a force by at most k_c g A (the contacts are
//     damped far beyond critical, so no resonance lifts that): hence the smaller of the two.
//  3. Then the dynamic rung runs.
// The returned trajectory is the settling rung's, with Trajectory::rung saying which, and
// error_estimate the linear rung's bound when it settled (0 otherwise: the exact rungs'
// error is their tolerance). So auto's statuses are the quasistatic rung's wherever the
// dynamic one is not needed, and its numbers are within `budget` of them.
//
// What auto does not estimate: the dynamic rung's contact damping, which at speed makes
// the steady orbit lag the quasistatic path (docs/model.md §8: 12 um at 270 deg/s for
// the orders the rollers pass). The campaigns' outputs are the steady-speed, time-free
// model's; auto approximates that model, and goes to the dynamic one only where that
// model's premise (the ring stays on its rollers) fails.
#pragma once

#include <string_view>

#include "solvers/dynamic.h"
#include "solvers/linear.h"
#include "solvers/quasistatic.h"
#include "solvers/solver.h"
#include "solvers/spectral.h"

namespace ringtol::solvers {

struct AutoOptions {
  // [m] >= 0: the most the linear rung's estimated error may be for its path to settle a
  // scene; 0 sends every scene with errors to the quasistatic rung. SolverSettings sets it
  // to kAutoShareOfPathTolerance of the campaign's path_tolerance.
  double budget = 0.0;
  // [-] > 0: the share of the smallest contact force the ring's inertial force bound may
  // reach before the dynamic rung is needed. Whole: the bound already adds every term's
  // largest force in phase and at the largest contact stiffness.
  double inertia_force_share = 1.0;
  QuasistaticOptions quasistatic;
  DynamicOptions dynamic;
};

// How far a margin (force to zero, travel to its limit) must exceed the linear rung's
// error estimate times the stiffness that carries it [-]: the estimate bounds the centre's
// error, and a contact's penetration error can reach the centre's error over the support's
// gain (sqrt(2) for the article's three rollers), so twice.
inline constexpr double kMarginFactor = 2.0;

// Thread-safe, as the rungs it holds.
class AutoSolver final : public Solver {
 public:
  explicit AutoSolver(AutoOptions options = {});
  std::string_view name() const override { return "auto"; }
  // The quasistatic rung's (the exact model's, which every rung starts from).
  Equilibrium SolveStatic(const engine::Scene& scene) const override;
  Trajectory SolveRevolution(const engine::Scene& scene, int steps) const override;

  // Why the linear path does not settle the scene (empty when it does); `path` must have
  // passed the validity check. For tests and the docs' numbers.
  std::string_view LinearVerdict(const engine::Scene& scene, const Trajectory& path) const;
  // The same verdict from the path's margins (the spectral evaluation's, whose travel is
  // an upper bound: a path it leaves in doubt does not settle).
  std::string_view LinearVerdict(const engine::Scene& scene, const LinearMargins& margins) const;
  // Steps 2 and 3 alone: the exact rungs, for a scene the linear path did not settle.
  Trajectory SolveExact(const engine::Scene& scene, int steps) const;
  const LinearSolver& linear() const { return linear_; }
  double budget() const { return options_.budget; }  // [m] AutoOptions::budget
  // [N] the inertial force step 2 weighs, with contact_stiffness [N/m] k_c (infinite for
  // rigid contact).
  static double InertiaForceBound(const engine::Scene& scene, double contact_stiffness);
  // [N/m] k_c at the largest force [N]: e k delta^(e - 1) (penalty law), infinite (rigid).
  static double ContactStiffness(const engine::Scene& scene, double largest_force);

 private:
  AutoOptions options_;
  LinearSolver linear_;
  QuasistaticSolver quasistatic_;
  DynamicSolver dynamic_;
};

}  // namespace ringtol::solvers
