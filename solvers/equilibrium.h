// Force balance of the ring and its spring rollers at one ring angle: the system of
// equations the quasistatic solver iterates on and the linear solver linearises.
//
// Unknowns x = [ring centre (2) [m]; travel of each spring roller (m) [m];
//               contact force of each roller (Z) [N], rigid contact only].
// Equations:  sum_i F_i n_i = 0                               ring, 2 rows [N]
//             (P_j - k_j s_j) - F_j (n_j . u_j) = 0            each spring roller [N]
//             K_ref g_i = 0                                    each contact, rigid only [N]
// with F_i = k max(-g_i, 0)^e under the penalty law. Because the contact search minimises
// the gap over the normal direction, dg/dx is the normal (envelope theorem) and the
// normal turns at dphi/dx = -(dg'/dx) / g'': the Jacobian is analytic.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "engine/contact.h"
#include "engine/scene.h"

namespace ringtol::solvers {

// A contact followed along a trajectory: the last answer is the next search's start.
struct TrackedContact {
  engine::Contact contact;
  bool valid = false;
  double ring_offset = 0.0;    // [rad] touching point's body angle minus its normal's body angle
  double roller_offset = 0.0;  // [rad] same for the roller
  double theta_per_normal = 1.0;  // [-] d ring_theta / d normal_angle at the touching point
  engine::NearbyAngle bore_angle;  // cos and sin of ring_theta, which moves in small steps
};

class EquilibriumSystem {
 public:
  // Keeps a reference: the scene must outlive the system. A system holds scratch space:
  // one system per solve (and per thread).
  explicit EquilibriumSystem(const engine::Scene& scene);

  int size() const { return size_; }
  int rollers() const { return static_cast<int>(scene_.rollers.size()); }
  bool rigid() const { return rigid_; }
  const engine::Scene& scene() const { return scene_; }
  // Index of roller i's travel in x, or -1 for a fixed roller.
  int travel_index(int i) const { return travel_index_[static_cast<std::size_t>(i)]; }
  // Index of roller i's contact force in x (rigid only), or -1.
  int force_index(int i) const { return rigid_ ? 2 + springs_ + i : -1; }

  // Scale of the rigid gap rows [N/m]: makes 1e-12 m of gap weigh like 1e-6 N of force.
  static constexpr double kGapRowScale = 1e6;

  engine::BodyPose RingPose(double psi, const Eigen::VectorXd& x) const;
  engine::BodyPose RollerPose(int i, double psi, const Eigen::VectorXd& x) const;

  // Finds every contact for state x at ring angle psi, warm-started from `contacts`.
  // Returns the index of the first roller whose search failed, or -1.
  int UpdateContacts(double psi, const Eigen::VectorXd& x, std::vector<TrackedContact>& contacts) const;

  // One Newton step of every contact search, parametrised by the bore's touching angle
  // theta (for a circular roller the common normal then needs no inner search):
  // evaluates each contact exactly at its current theta (the gap along that normal, an
  // upper bound of the true gap that differs from it by g'' dphi^2 / 2), then advances
  // theta by -g' / (g'' nu'). Used inside the continuation Newton iteration, where the
  // contacts converge together with x. Requires valid contacts; returns the largest
  // normal-angle update taken [rad], or infinity if a contact cannot be stepped. Leaves
  // normal_angle, ring_offset and roller_theta as they were: the normal vector is
  // current, its angle would cost an atan2 per contact and step. roller_offset is
  // current: it is the warm start of the roller's own search.
  double StepContacts(double psi, const Eigen::VectorXd& x, std::vector<TrackedContact>& contacts) const;

  // Moves every contact along with a change dx of the unknowns: its touching angle by
  // the implicit derivative dphi/dx = -(dg'/dx) / g'' (with it, StepContacts followed by
  // a force-balance step is a full Newton step of the joint system), its gap and touching
  // points to first order.
  void FollowContacts(const Eigen::VectorXd& dx, std::vector<TrackedContact>& contacts) const;

  // Contact force of roller i [N] and its derivative with respect to the gap [N/m]
  // (penalty law; rigid forces are unknowns of x).
  double ContactForce(int i, const Eigen::VectorXd& x, const engine::Contact& c) const;

  // Residual at x for the given contacts; optionally the Jacobian d r/d x, and the
  // sensitivities to a small change of each contact's gap function g_i(phi) that the
  // linear rung needs (both size() x rollers()): to its value at the contact, and to its
  // slope dg_i/dphi there, which turns the contact normal by -slope / g''.
  void Evaluate(const Eigen::VectorXd& x, const std::vector<TrackedContact>& contacts, Eigen::VectorXd& residual,
                Eigen::MatrixXd* jacobian, Eigen::MatrixXd* gap_sensitivity = nullptr,
                Eigen::MatrixXd* slope_sensitivity = nullptr) const;

  // Convergence scale of each unknown: position tolerance for lengths, force tolerance
  // for forces.
  Eigen::VectorXd Tolerances(double position_tolerance, double force_tolerance) const;

 private:
  // The penalty law at a gap: force k delta^e [N] and stiffness dF/d delta [N/m].
  struct Penalty {
    double force = 0.0;
    double stiffness = 0.0;
  };
  Penalty PenaltyLaw(double gap) const;

  const engine::Scene& scene_;
  bool rigid_ = false;
  int springs_ = 0;
  int size_ = 0;
  std::vector<int> travel_index_;
  std::vector<Eigen::Vector2d> roller_centres_;  // [m] at zero travel, errors included
  std::vector<Eigen::Vector2d> axes_;            // unit travel axes (spring rollers)
};

}  // namespace ringtol::solvers
