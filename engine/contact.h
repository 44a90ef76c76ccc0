// Exact contact geometry between a roller outline and the ring's bore, both convex polar
// profiles in their own moving frames.
//
// For a convex roller inside a convex bore, the clearance along a direction phi is the
// difference of support functions, g(phi) = h_ring(phi) - h_roller(phi), and the contact
// is its minimum over phi: the common normal. With h'' = rho - h (rho = radius of
// curvature) the search has analytic derivatives
//   g'(phi)  = (ring touching point - roller touching point) . t(phi)
//   g''(phi) = rho_ring - rho_roller - g,
// so g is convex near the contact whenever the bore is flatter than the roller, which is
// also the condition for the contact to be a single point. FindContact runs a bracketed
// Newton iteration on g' = 0; IsSinglePoint checks the whole near side for a second
// touching point when that condition cannot be certified up front.
#pragma once

#include <Eigen/Core>

#include "engine/profile.h"

namespace ringtol::engine {

// Position of a body's centre [m] and the global angle of its body x axis [rad].
struct BodyPose {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double angle = 0.0;
};

struct Contact {
  bool converged = false;        // false: no common normal found; nothing below is usable
  double gap = 0.0;              // [m] signed clearance, < 0 is penetration
  double normal_angle = 0.0;     // [rad] global angle phi of the contact normal n
  Eigen::Vector2d normal = Eigen::Vector2d::Zero();   // outward from the ring's centre
  Eigen::Vector2d tangent = Eigen::Vector2d::Zero();  // n rotated by +90 deg
  Eigen::Vector2d ring_point = Eigen::Vector2d::Zero();    // [m] global
  Eigen::Vector2d roller_point = Eigen::Vector2d::Zero();  // [m] global
  double gap_curvature = 0.0;    // [m] g''(phi); <= 0 means the contact is not isolated
  double ring_theta = 0.0;       // [rad] ring body angle of the touching point
  double roller_theta = 0.0;     // [rad] roller body angle of the touching point
};

// Where to start looking; the converged answer does not depend on it. A previous Contact
// along a trajectory is the natural warm start.
struct ContactGuess {
  double normal_angle = 0.0;
  double ring_theta = 0.0;
  double roller_theta = 0.0;
};

// Searches directions within +-90 deg of the guess (or of the direction from the ring's
// centre to the roller's centre when guess is null). Never throws.
Contact FindContact(const PolarProfile& ring, const BodyPose& ring_pose, const PolarProfile& roller,
                    const BodyPose& roller_pose, const ContactGuess* guess = nullptr);

// Clearance along direction phi [m] (no search): the function FindContact minimises.
double GapAlong(const PolarProfile& ring, const BodyPose& ring_pose, const PolarProfile& roller,
                const BodyPose& roller_pose, double phi);

// True when no second local minimum of g within +-90 deg of the contact comes within
// tolerance [m] of touching (g <= max(contact.gap, 0) + tolerance) and no direction has a
// smaller gap than the contact. Costs `samples` gap evaluations.
bool IsSinglePoint(const PolarProfile& ring, const BodyPose& ring_pose, const PolarProfile& roller,
                   const BodyPose& roller_pose, const Contact& contact, double tolerance,
                   int samples = 256);

}  // namespace ringtol::engine
