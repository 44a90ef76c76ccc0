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

#include <cmath>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "engine/contact.h"
#include "engine/scene.h"

namespace ringtol::solvers {

// The ring's rotation psi [rad] with its cosine and sine, which every contact step needs
// and a revolution computes once per angle; and, optionally, the cosine and sine of every
// roller's body angle there (engine::RollerBodyAngle), computed by the contact steps of
// lobed rollers when not given.
struct RingTurn {
  double psi = 0.0;
  double cos_psi = 1.0;
  double sin_psi = 0.0;
  std::span<const Eigen::Vector2d> spin;
};

// A contact followed along a trajectory: the last answer is the next search's start.
struct TrackedContact {
  engine::Contact contact;
  bool valid = false;
  double ring_offset = 0.0;    // [rad] touching point's body angle minus its normal's body angle
  double roller_offset = 0.0;  // [rad] same for the roller
  double theta_per_normal = 1.0;  // [-] d ring_theta / d normal_angle at the touching point
  double theta_per_shift = 0.0;   // [rad/m] d ring_theta / d (tangential shift of the bore against the roller)
  double force = 0.0;      // [N] contact force at the gap as the continuation left it (ContinuationUpdate)
  double stiffness = 0.0;  // [N/m] its derivative with respect to the penetration there (penalty law)
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

  // The unknowns x, of any Eigen vector type (fixed-size in the continuation iteration).
  using State = Eigen::Ref<const Eigen::VectorXd>;

  engine::BodyPose RingPose(double psi, const State& x) const;
  engine::BodyPose RollerPose(int i, double psi, const State& x) const;
  // Roller i's centre [m] for the unknowns x: where its position errors and its travel put it.
  Eigen::Vector2d RollerCentre(int i, const State& x) const;

  // Finds every contact for state x at ring angle psi, warm-started from `contacts`.
  // Returns the index of the first roller whose search failed, or -1.
  int UpdateContacts(double psi, const State& x, std::vector<TrackedContact>& contacts) const;

  // One iteration of the continuation Newton method at ring angle turn.psi, which
  // steps the contact searches and the force balance together:
  //  1. every contact search takes one Newton step, parametrised by the bore's touching
  //     angle theta (for a circular roller the common normal then needs no inner search):
  //     each contact is evaluated exactly at its current theta (the gap along that
  //     normal, an upper bound of the true gap that differs from it by g'' dphi^2 / 2),
  //     and its normal turns by dphi = -g' / g'';
  //  2. the force balance along the stepped normals gives the update `step` of x, which
  //     is applied;
  //  3. every contact follows it: its touching angle by the implicit derivative
  //     dphi/dx = -(dg'/dx) / g'' (which makes 1-3 a full Newton step of the joint
  //     system), its gap to first order.
  // N is the storage of x (fixed-size N = size(), or Eigen::Dynamic); instantiated for
  // N = 2 .. 8 and Eigen::Dynamic. Requires valid contacts. Returns the largest normal
  // turn of step 1 [rad], or infinity when a contact cannot be stepped or the balance is
  // singular (x and the contacts are then unusable). Each contact's force is left at its
  // followed gap, to first order in the update (its error is F'' dg^2 / 2, ~1e-11 N for
  // a 1e-10 m update on the article's contacts). Leaves normal_angle, ring_offset,
  // roller_theta and the touching points as they were: the normal vector is current,
  // its angle would cost an atan2 per contact and step. roller_offset is current: it is
  // the warm start of the roller's own search.
  template <int N>
  double ContinuationUpdate(const RingTurn& turn, Eigen::Matrix<double, N, 1>& x,
                            std::vector<TrackedContact>& contacts, Eigen::Matrix<double, N, 1>& step) const;

  // Contact force of roller i [N] and its derivative with respect to the gap [N/m]
  // (penalty law; rigid forces are unknowns of x).
  double ContactForce(int i, const State& x, const engine::Contact& c) const;

  // Residual at x for the given contacts; optionally the Jacobian d r/d x, and the
  // sensitivities to a small change of each contact's gap function g_i(phi) that the
  // linear rung needs (both size() x rollers()): to its value at the contact, and to its
  // slope dg_i/dphi there, which turns the contact normal by -slope / g''.
  void Evaluate(const State& x, const std::vector<TrackedContact>& contacts, Eigen::VectorXd& residual,
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
  // What the continuation needs of each roller at every iteration, gathered once.
  struct RollerConstants {
    Eigen::Vector2d centre;   // [m] at zero travel, errors included
    Eigen::Vector2d axis;     // unit travel axis (spring rollers)
    int travel = -1;          // index of its travel in x, or -1
    bool round = true;        // a circle: its support needs no search
    double radius = 0.0;      // [m] of the circle, when round
    double spring_stiffness = 0.0;  // [N/m]
    double spring_preload = 0.0;    // [N]
  };

  const engine::Scene& scene_;
  bool rigid_ = false;
  double contact_stiffness_ = 0.0;  // [N/m^e] of the penalty law
  double contact_exponent_ = 1.0;   // [-]
  int springs_ = 0;
  int size_ = 0;
  std::vector<int> travel_index_;
  std::vector<RollerConstants> roller_;
};

}  // namespace ringtol::solvers
