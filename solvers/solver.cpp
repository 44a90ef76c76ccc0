#include "solvers/solver.h"

#include <stdexcept>

#include "solvers/dynamic.h"
#include "solvers/linear.h"
#include "solvers/quasistatic.h"

namespace ringtol::solvers {

Status CheckSceneGeometry(const engine::Scene& scene, std::string& message) {
  const engine::GeometryCheck check = engine::CheckGeometry(scene);
  message = check.message;
  switch (check.issue) {
    case engine::GeometryIssue::kNone: return Status::kOk;
    case engine::GeometryIssue::kRingNotConvex: return Status::kRingNotConvex;
    case engine::GeometryIssue::kRollerNotConvex: return Status::kRollerNotConvex;
    case engine::GeometryIssue::kRollerDoesNotFit: return Status::kRollerDoesNotFit;
  }
  return Status::kOk;
}

std::vector<std::string> SolverNames() { return {"linear", "quasistatic", "dynamic"}; }

std::unique_ptr<Solver> MakeSolver(std::string_view name) { return MakeSolver(name, DynamicOptions{}); }

std::unique_ptr<Solver> MakeSolver(std::string_view name, const DynamicOptions& dynamic) {
  if (name == "linear") return std::make_unique<LinearSolver>();
  if (name == "quasistatic") return std::make_unique<QuasistaticSolver>();
  if (name == "dynamic") return std::make_unique<DynamicSolver>(dynamic);
  std::string valid;
  for (const std::string& n : SolverNames()) valid += (valid.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown solver '" + std::string(name) + "' (valid: " + valid + ")");
}

}  // namespace ringtol::solvers
