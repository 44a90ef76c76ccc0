#include "solvers/equilibrium.h"

#include <cmath>

namespace ringtol::solvers {

using engine::Contact;
using engine::RollerMount;

EquilibriumSystem::EquilibriumSystem(const engine::Scene& scene)
    : scene_(scene), rigid_(scene.contact.model == engine::ContactLaw::Model::kRigid) {
  const int z = rollers();
  travel_index_.assign(static_cast<std::size_t>(z), -1);
  for (int i = 0; i < z; ++i) {
    roller_centres_.push_back(engine::RollerCentre(scene, i));
    axes_.push_back(engine::SpringAxis(scene, i));
    if (scene.rollers[static_cast<std::size_t>(i)].mount == RollerMount::kSpring) {
      travel_index_[static_cast<std::size_t>(i)] = 2 + springs_++;
    }
  }
  size_ = 2 + springs_ + (rigid_ ? z : 0);
}

engine::BodyPose EquilibriumSystem::RingPose(double psi, const Eigen::VectorXd& x) const {
  return {x.head<2>(), psi};
}

engine::BodyPose EquilibriumSystem::RollerPose(int i, double psi, const Eigen::VectorXd& x) const {
  const auto k = static_cast<std::size_t>(i);
  Eigen::Vector2d centre = roller_centres_[k];
  if (travel_index_[k] >= 0) centre += x[travel_index_[k]] * axes_[k];
  return {centre, engine::RollerBodyAngle(scene_, i, psi)};
}

int EquilibriumSystem::UpdateContacts(double psi, const Eigen::VectorXd& x,
                                      std::vector<TrackedContact>& contacts) const {
  const int z = rollers();
  contacts.resize(static_cast<std::size_t>(z));
  const engine::BodyPose ring = RingPose(psi, x);
  for (int i = 0; i < z; ++i) {
    TrackedContact& tracked = contacts[static_cast<std::size_t>(i)];
    const engine::BodyPose roller = RollerPose(i, psi, x);
    const engine::PolarProfile& outline = scene_.rollers[static_cast<std::size_t>(i)].outline;
    engine::ContactGuess guess;
    const engine::ContactGuess* start = nullptr;
    if (tracked.valid) {
      guess.normal_angle = tracked.contact.normal_angle;
      guess.ring_theta = guess.normal_angle - ring.angle + tracked.ring_offset;
      guess.roller_theta = guess.normal_angle - roller.angle + tracked.roller_offset;
      start = &guess;
    }
    tracked.contact = engine::FindContact(scene_.ring.inner, ring, outline, roller, start);
    tracked.valid = tracked.contact.converged;
    if (!tracked.valid) return i;
    tracked.ring_offset = tracked.contact.ring_theta - (tracked.contact.normal_angle - ring.angle);
    tracked.roller_offset = tracked.contact.roller_theta - (tracked.contact.normal_angle - roller.angle);
  }
  return -1;
}

// The article's exponent 1.5 is the common case: sqrt is several times cheaper than pow.
double EquilibriumSystem::PenaltyForce(double gap) const {
  if (!(gap < 0.0)) return 0.0;
  const double e = scene_.contact.exponent;
  return scene_.contact.stiffness * (e == 1.5 ? -gap * std::sqrt(-gap) : std::pow(-gap, e));
}

double EquilibriumSystem::PenaltyStiffness(double gap) const {
  if (!(gap < 0.0)) return 0.0;
  const double e = scene_.contact.exponent;
  return scene_.contact.stiffness * e * (e == 1.5 ? std::sqrt(-gap) : std::pow(-gap, e - 1.0));
}

double EquilibriumSystem::ContactForce(int i, const Eigen::VectorXd& x, const Contact& c) const {
  return rigid_ ? x[force_index(i)] : PenaltyForce(c.gap);
}

void EquilibriumSystem::Evaluate(const Eigen::VectorXd& x, const std::vector<TrackedContact>& contacts,
                                 Eigen::VectorXd& residual, Eigen::MatrixXd* jacobian,
                                 Eigen::MatrixXd* gap_sensitivity, Eigen::MatrixXd* slope_sensitivity) const {
  const int z = rollers();
  residual.setZero(size_);
  if (jacobian != nullptr) jacobian->setZero(size_, size_);
  if (gap_sensitivity != nullptr) gap_sensitivity->setZero(size_, z);
  if (slope_sensitivity != nullptr) slope_sensitivity->setZero(size_, z);
  Eigen::VectorXd dgap(size_);   // d g_i / d x
  Eigen::VectorXd dphi(size_);   // d phi_i / d x
  Eigen::VectorXd dforce(size_); // d F_i / d x
  for (int i = 0; i < z; ++i) {
    const Contact& c = contacts[static_cast<std::size_t>(i)].contact;
    const int s = travel_index_[static_cast<std::size_t>(i)];
    const Eigen::Vector2d& u = axes_[static_cast<std::size_t>(i)];
    const double force = ContactForce(i, x, c);
    residual.head<2>() += force * c.normal;
    if (s >= 0) {
      const engine::Spring& spring = scene_.rollers[static_cast<std::size_t>(i)].spring;
      residual[s] += spring.preload - spring.stiffness * x[s] - force * c.normal.dot(u);
    }
    if (rigid_) residual[force_index(i)] = kGapRowScale * c.gap;
    if (jacobian == nullptr && gap_sensitivity == nullptr && slope_sensitivity == nullptr) continue;

    dgap.setZero();
    dphi.setZero();
    dgap.head<2>() = c.normal;
    dphi.head<2>() = -c.tangent / c.gap_curvature;
    if (s >= 0) {
      dgap[s] = -u.dot(c.normal);
      dphi[s] = u.dot(c.tangent) / c.gap_curvature;
    }
    const double stiffness = rigid_ ? 0.0 : PenaltyStiffness(c.gap);
    if (rigid_) {
      dforce.setZero();
      dforce[force_index(i)] = 1.0;
    } else {
      dforce = -stiffness * dgap;
    }
    if (jacobian != nullptr) {
      Eigen::MatrixXd& J = *jacobian;
      J.topRows<2>() += c.normal * dforce.transpose() + force * c.tangent * dphi.transpose();
      if (s >= 0) {
        const engine::Spring& spring = scene_.rollers[static_cast<std::size_t>(i)].spring;
        J(s, s) -= spring.stiffness;
        J.row(s) -= c.normal.dot(u) * dforce.transpose() + force * c.tangent.dot(u) * dphi.transpose();
      }
      if (rigid_) J.row(force_index(i)) = kGapRowScale * dgap.transpose();
    }
    if (gap_sensitivity != nullptr) {
      Eigen::MatrixXd& B = *gap_sensitivity;
      if (rigid_) {
        B(force_index(i), i) = kGapRowScale;
      } else {
        B.block<2, 1>(0, i) = -stiffness * c.normal;
        if (s >= 0) B(s, i) = stiffness * c.normal.dot(u);
      }
    }
    if (slope_sensitivity != nullptr) {
      // A slope change dg' moves the minimum of g by dphi = -dg' / g''; the gap itself is
      // stationary there, so only the force direction turns.
      Eigen::MatrixXd& S = *slope_sensitivity;
      const double turn = -1.0 / c.gap_curvature;  // dphi per unit slope change
      S.block<2, 1>(0, i) = force * turn * c.tangent;
      if (s >= 0) S(s, i) = -force * turn * c.tangent.dot(u);
    }
  }
}

Eigen::VectorXd EquilibriumSystem::Tolerances(double position_tolerance, double force_tolerance) const {
  Eigen::VectorXd tolerance = Eigen::VectorXd::Constant(size_, position_tolerance);
  if (rigid_) tolerance.tail(rollers()).setConstant(force_tolerance);
  return tolerance;
}

}  // namespace ringtol::solvers
