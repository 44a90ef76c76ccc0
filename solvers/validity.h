// The one verdict on whether a solved configuration lies inside the model's domain, shared
// by every rung so that no rung reports kOk where another refuses (docs/model.md §7).
// A configuration (ring centre, spring travels and contact forces at a ring angle psi) is
// valid when, for every roller,
//   1. its contact force is > 0, or the ring keeps without it
//      the support it needs (RollerLosingSupport)                 else kLiftOff
//   2. a spring roller's |travel| <= its travel limit             else kRollerDoesNotFit
//   3. it touches the bore at one point only                      else kTwoPointContact
// in that order. A contact that opens while the ring keeps its support is the normal state
// of a support with more fixed rollers than a spring needs to press the ring onto: the
// exact rungs follow it (ValidityOptions::contacts_may_open). The linear rung's path, and
// every shortcut built on it, assumes each contact of the error-free assembly stays closed:
// for it such an opening is kBeyondLinearRange, for an exact rung to follow. Condition 3 is searched only where Blaschke's rolling theorem cannot rule
// it out (a roller whose largest curvature radius reaches the bore's smallest); the
// roller's body angle is the rolling one (engine::RollerBodyAngle), which the time-free
// rungs use and the dynamic rung's friction-driven spin follows while the roller rolls.
// The outlines' convexity is the scene's (solvers::CheckSceneGeometry), which Simulate
// checks before any rung runs.
//
// A trajectory is checked at its samples, in angle order: the first invalid sample
// decides. Between samples only the dynamic rung watches the contacts (its root finder);
// the time-free rungs are, as their path is, a sampled statement.
#pragma once

#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/contact.h"
#include "engine/scene.h"
#include "solvers/solver.h"

namespace ringtol::solvers {

struct ValidityOptions {
  // A second touching point within this distance of touching makes the contact two-point
  // [m] (QuasistaticOptions::two_point_tolerance, the same rule).
  double two_point_tolerance = 1e-9;
  // Whether the model that solved the configuration lets a contact open: true for the
  // exact rungs (quasistatic, dynamic), whose equations are unilateral; false (the
  // default) for the linear rung and the shortcuts built on its path.
  bool contacts_may_open = false;
};

// The support rule (docs/model.md §7, "Contacts that open"). `load` [N or m] is positive
// for each roller whose contact carries load (a force, or a penetration). The ring keeps the
// support it needs while every spring roller touches (its spring pushes it out to its
// travel limit otherwise) and, beyond three rollers, at least one fixed roller does: the
// springs press the ring onto whichever touch, and whether an equilibrium exists on them
// (a fixed roller opposite a spring holds the ring, the contacts' curvature holding it
// sideways) is the exact rungs' equations' to decide, not a count's. Without a spring
// roller three fixed rollers must touch, or every fixed roller where there are fewer. On
// three rollers every contact is needed: any opening breaks it (the article's lift-off).
// Returns the first roller, in scene order, whose lost contact breaks that rule, or -1
// while it holds.
int RollerLosingSupport(const engine::Scene& scene, std::span<const double> load);

// [N] The least force the support rests on at one configuration: the smallest spring
// roller's, and the k-th largest fixed roller's for the k fixed rollers the rule needs (the
// largest beyond three rollers with a spring).
// What a push on the ring must overcome before it loses a support it needs; on three
// rollers, the smallest contact force.
double SupportForce(const engine::Scene& scene, std::span<const double> contact_force);

// Thread-safe once made; keeps a reference to the scene, which must outlive it.
class ValidityCheck {
 public:
  explicit ValidityCheck(const engine::Scene& scene, ValidityOptions options = {});

  // The configuration at ring angle psi [rad]: centre [m], travel [m] and contact_force
  // [N] per roller (travel 0 for fixed rollers). `contacts`, when given (one per roller,
  // at this configuration), saves the contact search of condition 3. kOk or the failed
  // condition's status, with its reason in `message`.
  Status Check(double psi, const Eigen::Vector2d& centre, std::span<const double> travel,
               std::span<const double> contact_force, std::string& message,
               std::span<const engine::Contact> contacts = {}) const;

  // Every sample of a trajectory whose status is kOk, its `initial` equilibrium first; the
  // first failure sets the trajectory's status, message and failure_angle, and the path
  // stays as solved. A trajectory already failed is left as it is.
  void Check(Trajectory& trajectory) const;

  // The static equilibrium at psi = 0, when its status is kOk.
  void Check(Equilibrium& equilibrium) const;

  // Whether condition 3 needs roller i's contact searched at a contact of this gap [m]:
  // where Blaschke's theorem cannot certify a single point (largest roller curvature
  // radius + gap >= smallest bore curvature radius). The profiles' bounds on their
  // curvature settle most scenes; the exact extremes, built then, decide the rest.
  bool NeedsTwoPointSearch(int i, double gap) const {
    if (roller_max_radius_bound_[static_cast<std::size_t>(i)] + gap < ring_min_radius_bound_) return false;
    return RollerMaxRadius(i) + gap >= RingMinRadius();
  }

 private:
  double RingMinRadius() const;        // [m] smallest curvature radius of the bore
  double RollerMaxRadius(int i) const;  // [m] largest curvature radius of roller i

  const engine::Scene& scene_;
  ValidityOptions options_;
  // Bounds from engine::PolarProfile::ExtremesBounds(): <= RingMinRadius() and >=
  // RollerMaxRadius(i) (+inf where the roller's bound says nothing) [m].
  double ring_min_radius_bound_ = 0.0;
  std::vector<double> roller_max_radius_bound_;
};

// Lengths and angles as messages state them: "12.34 um", "45 deg".
std::string Micrometres(double metres);
std::string Degrees(double radians);

}  // namespace ringtol::solvers
