#include "solvers/validity.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "engine/units.h"

namespace ringtol::solvers {

std::string Micrometres(double metres) {
  std::ostringstream out;
  out.precision(4);
  out << metres * units::kMicrometresPerMetre << " um";
  return out.str();
}

std::string Degrees(double radians) {
  std::ostringstream out;
  out.precision(6);
  out << radians * units::kDegreesPerRadian << " deg";
  return out.str();
}

ValidityCheck::ValidityCheck(const engine::Scene& scene, ValidityOptions options)
    : scene_(scene),
      options_(options),
      ring_min_radius_bound_(1.0 / scene.ring.inner.ExtremesBounds().max_curvature) {
  // 1 / x is monotone under rounding, so bounds on the curvatures give bounds on what
  // RingMinRadius and RollerMaxRadius compute.
  for (const engine::Roller& roller : scene.rollers) {
    const double least_curvature = roller.outline.ExtremesBounds().min_curvature;
    roller_max_radius_bound_.push_back(least_curvature > 0.0 ? 1.0 / least_curvature
                                                             : std::numeric_limits<double>::infinity());
  }
}

double ValidityCheck::RingMinRadius() const { return 1.0 / scene_.ring.inner.MaxCurvature(); }

double ValidityCheck::RollerMaxRadius(int i) const {
  return 1.0 / scene_.rollers[static_cast<std::size_t>(i)].outline.MinCurvature();
}

Status ValidityCheck::Check(double psi, const Eigen::Vector2d& centre, std::span<const double> travel,
                            std::span<const double> contact_force, std::string& message,
                            std::span<const engine::Contact> contacts) const {
  for (std::size_t i = 0; i < scene_.rollers.size(); ++i) {
    const engine::Roller& roller = scene_.rollers[i];
    const double force = contact_force[i];
    if (!(force > 0.0)) {
      std::ostringstream reason;
      reason << "roller " << roller.name << " lifts off at psi = " << Degrees(psi) << " (its contact force would be "
             << force << " N)";
      message = reason.str();
      return Status::kLiftOff;
    }
    const bool spring = roller.mount == engine::RollerMount::kSpring;
    if (spring && !(std::abs(travel[i]) <= roller.spring.travel_limit)) {
      message = "spring roller " + roller.name + " would travel " + Micrometres(travel[i]) + " at psi = " +
                Degrees(psi) + ", beyond its travel limit of " + Micrometres(roller.spring.travel_limit);
      return Status::kRollerDoesNotFit;
    }
    // Single-point contact is certain while the roller is flatter nowhere than the bore
    // is curved (a penetrating contact's gap < 0 only tightens this).
    const int index = static_cast<int>(i);
    if (roller_max_radius_bound_[i] < ring_min_radius_bound_ || RollerMaxRadius(index) < RingMinRadius()) continue;
    const engine::BodyPose ring_pose{centre, psi};
    Eigen::Vector2d roller_centre = engine::RollerCentre(scene_, index);
    if (spring) roller_centre += travel[i] * engine::SpringAxis(scene_, index);
    const engine::BodyPose roller_pose{roller_centre, engine::RollerBodyAngle(scene_, index, psi)};
    const engine::Contact contact = i < contacts.size()
                                        ? contacts[i]
                                        : engine::FindContact(scene_.ring.inner, ring_pose, roller.outline, roller_pose);
    if (!contact.converged || (NeedsTwoPointSearch(index, contact.gap) &&
                               !engine::IsSinglePoint(scene_.ring.inner, ring_pose, roller.outline, roller_pose,
                                                      contact, options_.two_point_tolerance))) {
      message = "roller " + roller.name + " touches the bore at two points at psi = " + Degrees(psi) +
                ": the bore curves tighter than the roller there";
      return Status::kTwoPointContact;
    }
  }
  return Status::kOk;
}

void ValidityCheck::Check(Equilibrium& equilibrium) const {
  if (equilibrium.status != Status::kOk) return;
  equilibrium.status =
      Check(0.0, equilibrium.centre, equilibrium.travel, equilibrium.contact_force, equilibrium.message);
}

void ValidityCheck::Check(Trajectory& trajectory) const {
  if (trajectory.status != Status::kOk) return;
  Check(trajectory.initial);
  if (trajectory.initial.status != Status::kOk) {
    trajectory.status = trajectory.initial.status;
    trajectory.message = "the static equilibrium before rotation: " + trajectory.initial.message;
    trajectory.failure_angle = 0.0;
    return;
  }
  const std::size_t z = scene_.rollers.size();
  for (std::size_t k = 0; k < trajectory.psi.size(); ++k) {
    const Status status = Check(trajectory.psi[k], trajectory.centre[k],
                                std::span<const double>(trajectory.travel).subspan(k * z, z),
                                std::span<const double>(trajectory.contact_force).subspan(k * z, z), trajectory.message);
    if (status != Status::kOk) {
      trajectory.status = status;
      trajectory.failure_angle = trajectory.psi[k];
      return;
    }
  }
}

}  // namespace ringtol::solvers
