// The exact-geometry quasi-static rung: no inertia, the ring centre and the spring
// rollers' travel from force balance at each ring angle (solvers/equilibrium.h), with
// rigid contact or the penalty law of docs/model.md §4.
//
// Each angle is a Newton iteration with the analytic Jacobian, started from a quartic
// extrapolation of the five previous angles. Newton converges quadratically (an update e
// is followed by one of about K e^2), and the solver measures K as it goes: once K e^2
// is safely below the tolerance the angle is accepted, so one update per angle usually
// suffices (every 16th angle still runs to a confirmed convergence, re-measuring K).
// The static equilibrium before rotation continues the error-free assembly's with the same
// joint iteration; the error-free assembly's own, and any that does not settle that way,
// is searched from scratch: rigid contact first, then, for the penalty law, a compliance
// correction and a damped Newton iteration.
#pragma once

#include <memory>
#include <vector>

#include "solvers/equilibrium.h"
#include "solvers/nominal_cache.h"
#include "solvers/solver.h"

namespace ringtol::solvers {

struct QuasistaticOptions {
  // Converged when the last Newton update, or the next one as the measured quadratic
  // convergence predicts it, is below its tolerance: |dx_centre|, |dx_travel| <=
  // position_tolerance [m] (1 pm: ~1e4 ulp of a 0.3 m coordinate, far below any
  // tolerance studied), contact normals within 100 rad/m times that, and, for rigid
  // contact, |dF| <= force_tolerance [N]. Campaigns loosen it to 1 % of their sampling
  // budget (jobs/campaign/campaign.h), where one update per angle then suffices even when the
  // rollers' lobes pass too fast between angles for the predictor to follow them.
  double position_tolerance = 1e-12;
  double force_tolerance = 1e-9;
  int max_iterations = 30;  // per angle, [1, 1000]
  // A second touching point within this distance of touching makes the contact two-point
  // [m]; checked only where Blaschke's rolling theorem cannot rule it out (a roller
  // whose largest curvature radius plus the gap reaches the bore's smallest).
  double two_point_tolerance = 1e-9;
};

struct NominalStatics;
class QuasistaticSolver;

// A revolution of `steps` angles solved first at every stride-th angle and at the last
// (the coarse samples, coarse().psi), the angles between two coarse samples then solved
// on demand, continued from the earlier one's converged state. The quasistatic
// equilibrium at an angle does not depend on the path that led to it, so every angle
// agrees with the dense revolution's to the Newton tolerance. Keeps a reference to the
// scene, which must outlive it; one thread at a time.
class SparseRevolution {
 public:
  // A converged state: the unknowns and the contacts found there.
  struct State {
    Eigen::VectorXd x;
    std::vector<TrackedContact> contacts;
  };

  // The coarse samples, with the status of their run: when it is not kOk, the angles
  // solved before the failure.
  const Trajectory& coarse() const { return coarse_; }
  // The dense index (psi = 2 pi k / steps) of every coarse sample, 0 and steps included.
  const std::vector<int>& coarse_indices() const { return indices_; }
  // The angles strictly between coarse samples j and j + 1 (j + 1 < coarse samples solved),
  // in order, with a status like SolveRevolution's; `initial` is left empty.
  Trajectory SolveSegment(int j) const;

 private:
  friend class QuasistaticSolver;
  SparseRevolution(const QuasistaticOptions& options, const engine::Scene& scene, int steps);

  QuasistaticOptions options_;
  EquilibriumSystem system_;
  int steps_ = 0;
  Trajectory coarse_;
  std::vector<int> indices_;
  std::vector<State> states_;
};

// Thread-safe. Keeps the static equilibrium of the last error-free assembly it saw: a
// scene's own static solve starts from it (a few joint Newton iterations, where the
// errors are small against the contacts' compliance) and falls back to a search from
// scratch when that does not settle; which path a scene takes never depends on what was
// kept, so results do not depend on the order scenes are solved in.
class QuasistaticSolver final : public Solver {
 public:
  explicit QuasistaticSolver(QuasistaticOptions options = {}) : options_(options) {}
  std::string_view name() const override { return "quasistatic"; }
  Equilibrium SolveStatic(const engine::Scene& scene) const override;
  Trajectory SolveRevolution(const engine::Scene& scene, int steps) const override;
  // The revolution of `steps` angles at every `stride`-th one (2 <= stride) and the last,
  // the rest on demand (SparseRevolution).
  std::unique_ptr<SparseRevolution> SolveSparse(const engine::Scene& scene, int steps, int stride) const;
  const QuasistaticOptions& options() const { return options_; }

  // Static equilibrium plus the contacts found there (the linear solver linearises at
  // it), searched from scratch.
  Equilibrium SolveStatic(const EquilibriumSystem& system, Eigen::VectorXd& x,
                          std::vector<TrackedContact>& contacts) const;

 private:
  // The static equilibrium of `system`'s scene: continued from the error-free assembly's
  // when the scene has errors and that settles, else searched from scratch.
  Equilibrium SolveStaticFromNominal(const EquilibriumSystem& system, Eigen::VectorXd& x,
                                     std::vector<TrackedContact>& contacts) const;
  // The error-free assembly of `scene`, cached.
  std::shared_ptr<const NominalStatics> Nominal(const engine::Scene& scene) const;
  // The static equilibrium as a revolution's angle 0, recorded in `trajectory`; false
  // (with the trajectory's status saying why) when there is none.
  bool StartRevolution(const EquilibriumSystem& system, Eigen::VectorXd& x, std::vector<TrackedContact>& contacts,
                       Trajectory& trajectory) const;

  QuasistaticOptions options_;
  NominalCache<NominalStatics> nominal_;
};

}  // namespace ringtol::solvers
