// The first rung: first-order kinematics. The force balance of solvers/equilibrium.h is
// linearised once about the static equilibrium of the error-free assembly; every error
// source then enters as an additive change of a contact's gap,
//   dg_i(psi) = dr_ring(phi_i - psi) - dr_roller_i(phi_i - gamma_i(psi)) - dp_i . n_i,
// and the centre, travels and forces respond as y(psi) = y0 + Y dg(psi). Each error term
// is a rotating phasor, so the path is a sum of phasors evaluated in closed form at every
// angle: exact to first order in amplitude / radius, with a second-order error.
#pragma once

#include <memory>

#include "solvers/nominal_cache.h"
#include "solvers/quasistatic.h"
#include "solvers/solver.h"

namespace ringtol::solvers {

struct LinearOptions {
  // Options of the quasistatic solve of the error-free assembly that is linearised.
  QuasistaticOptions nominal;
};

struct NominalResponse;

// Thread-safe. Keeps the linearisation of the last error-free assembly it saw (a static
// solve and a factorisation, about a third of a revolution's cost) and reuses it while
// the scene without its errors stays the same, as it does for every sample of a campaign.
class LinearSolver final : public Solver {
 public:
  explicit LinearSolver(LinearOptions options = {}) : options_(options) {}
  std::string_view name() const override { return "linear"; }
  Equilibrium SolveStatic(const engine::Scene& scene) const override;
  Trajectory SolveRevolution(const engine::Scene& scene, int steps) const override;

 private:
  std::shared_ptr<const NominalResponse> Nominal(const engine::Scene& scene) const;

  LinearOptions options_;
  NominalCache<NominalResponse> nominal_;
};

}  // namespace ringtol::solvers
