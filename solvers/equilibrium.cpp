#include "solvers/equilibrium.h"

#include <algorithm>
#include <cmath>
#include <limits>

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
double EquilibriumSystem::StepContacts(double psi, const Eigen::VectorXd& x,
                                       std::vector<TrackedContact>& contacts) const {
  const engine::PolarProfile& bore = scene_.ring.inner;
  const double cos_psi = std::cos(psi);
  const double sin_psi = std::sin(psi);
  const Eigen::Vector2d ring_centre = x.head<2>();
  double largest_step = 0.0;
  for (int i = 0; i < rollers(); ++i) {
    TrackedContact& tracked = contacts[static_cast<std::size_t>(i)];
    Contact& c = tracked.contact;
    const engine::BodyPose roller = RollerPose(i, psi, x);
    const engine::PolarProfile& outline = scene_.rollers[static_cast<std::size_t>(i)].outline;
    const engine::RadiusDerivatives d = bore.Evaluate(c.ring_theta);
    // Radial and tangential unit vectors of the bore point in the global frame.
    const Eigen::Vector2d radial(d.cos_theta * cos_psi - d.sin_theta * sin_psi,
                                 d.sin_theta * cos_psi + d.cos_theta * sin_psi);
    const Eigen::Vector2d across(-radial.y(), radial.x());
    const double q = d.r * d.r + d.dr * d.dr;
    const double root_q = std::sqrt(q);
    const double turning = q + d.dr * d.dr - d.r * d.ddr;  // nu' q: > 0 on a convex bore
    const Eigen::Vector2d normal = (d.r * radial - d.dr * across) / root_q;
    const Eigen::Vector2d tangent(-normal.y(), normal.x());
    const Eigen::Vector2d ring_point = ring_centre + d.r * radial;
    double roller_h = outline.radius() + outline.mean_deviation();
    double roller_dh = 0.0;
    double roller_rho = roller_h;
    double roller_theta = c.roller_theta;
    if (!outline.is_circle()) {
      const double phi = std::atan2(normal.y(), normal.x());
      const engine::SupportPoint b = outline.Support(phi - roller.angle, c.roller_theta);
      roller_h = b.h;
      roller_dh = b.dh;
      roller_rho = b.curvature_radius;
      roller_theta = b.theta;
    }
    const Eigen::Vector2d offset = ring_point - roller.centre;
    const double gap = offset.dot(normal) - roller_h;
    const double slope = offset.dot(tangent) - roller_dh;
    const double curvature = q * root_q / turning - roller_rho - gap;
    if (!(curvature > 0.0 && turning > 0.0 && std::isfinite(gap))) return std::numeric_limits<double>::infinity();
    const double dphi = -slope / curvature;
    largest_step = std::max(largest_step, std::abs(dphi));
    // The force balance that follows must use the normal the contact steps to, or the
    // forces converge only linearly. The gap is stationary there: it keeps its value to
    // g'' dphi^2 / 2. Rotation by dphi to fourth order.
    const double cos_step = 1.0 - 0.5 * dphi * dphi;
    const double sin_step = dphi * (1.0 - dphi * dphi / 6.0);
    c.gap = gap;
    c.normal = cos_step * normal + sin_step * tangent;
    c.tangent = cos_step * tangent - sin_step * normal;
    c.gap_curvature = curvature;
    c.ring_point = ring_point;
    c.roller_point = roller.centre + roller_h * normal + roller_dh * tangent;
    c.roller_theta = roller_theta;
    // dtheta = dphi / nu' with nu' = turning / q.
    tracked.theta_per_normal = q / turning;
    c.ring_theta += dphi * tracked.theta_per_normal;
  }
  return largest_step;
}

void EquilibriumSystem::FinishContacts(double psi, std::vector<TrackedContact>& contacts) const {
  for (int i = 0; i < rollers(); ++i) {
    TrackedContact& tracked = contacts[static_cast<std::size_t>(i)];
    engine::Contact& c = tracked.contact;
    c.normal_angle = std::atan2(c.normal.y(), c.normal.x());
    const double roller_angle = engine::RollerBodyAngle(scene_, i, psi);
    if (scene_.rollers[static_cast<std::size_t>(i)].outline.is_circle()) c.roller_theta = c.normal_angle - roller_angle;
    tracked.ring_offset = c.ring_theta - (c.normal_angle - psi);
    tracked.roller_offset = c.roller_theta - (c.normal_angle - roller_angle);
  }
}

void EquilibriumSystem::FollowContacts(const Eigen::VectorXd& dx, std::vector<TrackedContact>& contacts) const {
  for (int i = 0; i < rollers(); ++i) {
    TrackedContact& tracked = contacts[static_cast<std::size_t>(i)];
    const Contact& c = tracked.contact;
    double dg_slope = c.tangent.dot(dx.head<2>());  // d g' from moving the ring
    const int s = travel_index_[static_cast<std::size_t>(i)];
    if (s >= 0) dg_slope -= axes_[static_cast<std::size_t>(i)].dot(c.tangent) * dx[s];
    tracked.contact.ring_theta -= dg_slope / c.gap_curvature * tracked.theta_per_normal;
  }
}

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
  Eigen::VectorXd& dgap = dgap_;      // d g_i / d x
  Eigen::VectorXd& dphi = dphi_;      // d phi_i / d x
  Eigen::VectorXd& dforce = dforce_;  // d F_i / d x
  dgap.resize(size_);
  dphi.resize(size_);
  dforce.resize(size_);
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
