#include "solvers/contact_compliance.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>

#include <Eigen/Core>
#include <Eigen/SVD>

#include "solvers/quasistatic.h"

namespace ringtol::solvers {
namespace {

// The stiff law's contacts sink this many times less far: what is left of the law's
// effect in it is a thousandth of the scene's, below any share worth a word.
constexpr double kStiffening = 1000.0;
// [m] Each roller's outward offset: small against every radius, so the response is
// linear to h / r ~ 1e-4 at a 10 mm roller, and a million times the statics' 1 pm
// tolerance, so the solves' own error is 1e-6 of it.
constexpr double kOffset = 1e-6;

// [-] The centre's static displacement per unit outward offset of each roller, a column
// per roller, or nothing when one of the solves fails.
std::optional<Eigen::Matrix2Xd> Responses(const QuasistaticSolver& solver, const engine::Scene& scene,
                                          const Eigen::Vector2d& centre) {
  Eigen::Matrix2Xd responses(2, scene.rollers.size());
  for (std::size_t i = 0; i < scene.rollers.size(); ++i) {
    engine::Scene moved = scene;
    moved.rollers[i].radial_offset += kOffset;
    const Equilibrium equilibrium = solver.SolveStatic(moved);
    if (equilibrium.status != Status::kOk) return std::nullopt;
    responses.col(static_cast<Eigen::Index>(i)) = (equilibrium.centre - centre) / kOffset;
  }
  return responses;
}

double SpectralNorm(const Eigen::Matrix2Xd& matrix) {
  return Eigen::JacobiSVD<Eigen::Matrix2Xd>(matrix).singularValues()(0);
}

}  // namespace

ContactCompliance AssessContactCompliance(const engine::Scene& scene) {
  ContactCompliance compliance;
  if (scene.contact.model == engine::ContactLaw::Model::kRigid) return compliance;
  const QuasistaticSolver solver;
  const engine::Scene nominal = engine::WithoutErrors(scene);
  engine::Scene stiff = nominal;
  stiff.contact.stiffness *= std::pow(kStiffening, scene.contact.exponent);
  const Equilibrium at_rest = solver.SolveStatic(nominal);
  const Equilibrium stiff_at_rest = solver.SolveStatic(stiff);
  if (at_rest.status != Status::kOk || stiff_at_rest.status != Status::kOk) return compliance;
  const std::optional<Eigen::Matrix2Xd> law = Responses(solver, nominal, at_rest.centre);
  const std::optional<Eigen::Matrix2Xd> rigid = Responses(solver, stiff, stiff_at_rest.centre);
  if (!law || !rigid) return compliance;

  const std::vector<double>& forces = at_rest.contact_force;
  const auto deepest = std::max_element(forces.begin(), forces.end());
  compliance.assessed = true;
  compliance.roller = static_cast<int>(deepest - forces.begin());
  compliance.force = *deepest;
  compliance.penetration = std::pow(*deepest / scene.contact.stiffness, 1.0 / scene.contact.exponent);
  const double largest = SpectralNorm(*rigid);
  compliance.response_change = largest > 0.0 ? SpectralNorm(*law - *rigid) / largest : 0.0;
  return compliance;
}

}  // namespace ringtol::solvers
