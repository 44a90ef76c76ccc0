#include "solvers/solver.h"


namespace ringtol::solvers {

Status CheckSceneGeometry(const engine::Scene& scene, std::string& message) {
  const engine::GeometryCheck check = engine::CheckGeometry(scene);
  message = check.message;
  switch (check.issue) {
    case engine::GeometryIssue::kNone: return Status::kOk;
    case engine::GeometryIssue::kRingNotConvex: return Status::kRingNotConvex;
    case engine::GeometryIssue::kRollerNotConvex: return Status::kRollerNotConvex;
    case engine::GeometryIssue::kRollerDoesNotFit:
    case engine::GeometryIssue::kRollersOverlap: return Status::kRollerDoesNotFit;
  }
  return Status::kOk;
}

}  // namespace ringtol::solvers
