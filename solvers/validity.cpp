#include "solvers/validity.h"

#include <algorithm>
#include <cmath>
#include <functional>
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

namespace {

// Fixed rollers in contact the support needs (RollerLosingSupport): on three rollers
// every one; beyond, one where a spring presses the ring onto it, else three.
std::size_t NeededFixedRollers(const engine::Scene& scene) {
  const auto fixed = static_cast<std::size_t>(engine::FixedRollerCount(scene));
  if (scene.rollers.size() <= 3) return fixed;
  return std::min<std::size_t>(engine::SpringRollerCount(scene) > 0 ? 1 : 3, fixed);
}

}  // namespace

int RollerLosingSupport(const engine::Scene& scene, std::span<const double> load) {
  std::size_t fixed_touching = 0;
  for (std::size_t i = 0; i < scene.rollers.size(); ++i) {
    if (scene.rollers[i].mount == engine::RollerMount::kFixed && load[i] > 0.0) ++fixed_touching;
  }
  const bool fixed_enough = fixed_touching >= NeededFixedRollers(scene);
  for (std::size_t i = 0; i < scene.rollers.size(); ++i) {
    if (load[i] > 0.0) continue;
    if (scene.rollers[i].mount == engine::RollerMount::kSpring || !fixed_enough) return static_cast<int>(i);
  }
  return -1;
}

double SupportForce(const engine::Scene& scene, std::span<const double> contact_force) {
  double spring = std::numeric_limits<double>::infinity();
  std::vector<double> fixed;
  for (std::size_t i = 0; i < scene.rollers.size(); ++i) {
    if (scene.rollers[i].mount == engine::RollerMount::kSpring) {
      spring = std::min(spring, contact_force[i]);
    } else {
      fixed.push_back(contact_force[i]);
    }
  }
  const std::size_t needed = NeededFixedRollers(scene);
  if (needed == 0) return spring;
  std::nth_element(fixed.begin(), fixed.begin() + static_cast<std::ptrdiff_t>(needed - 1), fixed.end(),
                   std::greater<>());
  return std::min(spring, fixed[needed - 1]);
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
      // Weighed only where a contact opens: every angle of every path passes here.
      const bool support_lost = RollerLosingSupport(scene_, contact_force) >= 0;
      if (options_.contacts_may_open && !support_lost) continue;  // the ring rests on the others
      std::ostringstream reason;
      if (support_lost) {
        reason << "roller " << roller.name << " lifts off at psi = " << Degrees(psi) << " (its contact force would be "
               << force << " N)";
        if (scene_.rollers.size() > 3) reason << ", leaving the ring without the support it needs";
      } else {
        reason << "roller " << roller.name << " leaves the bore at psi = " << Degrees(psi)
               << ": the linear rung holds only while every contact stays closed (the quasistatic rung follows it)";
      }
      message = reason.str();
      return support_lost ? Status::kLiftOff : Status::kBeyondLinearRange;
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
