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

double EquilibriumSystem::StepContacts(double psi, const Eigen::VectorXd& x,
                                       std::vector<TrackedContact>& contacts) const {
  const engine::PolarProfile& bore = scene_.ring.inner;
  const double cos_psi = std::cos(psi);
  const double sin_psi = std::sin(psi);
  const Eigen::Vector2d ring_centre = x.head<2>();
  double largest_step = 0.0;
  // Steps contact i from the bore's radius and derivatives at its touching angle; false
  // when the contact cannot be stepped.
  auto step_contact = [&](int i, const engine::RadiusDerivatives& d) {
    TrackedContact& tracked = contacts[static_cast<std::size_t>(i)];
    Contact& c = tracked.contact;
    const engine::BodyPose roller = RollerPose(i, psi, x);
    const engine::PolarProfile& outline = scene_.rollers[static_cast<std::size_t>(i)].outline;
    // Radial and tangential unit vectors of the bore point in the global frame.
    const Eigen::Vector2d radial(d.cos_theta * cos_psi - d.sin_theta * sin_psi,
                                 d.sin_theta * cos_psi + d.cos_theta * sin_psi);
    const Eigen::Vector2d across(-radial.y(), radial.x());
    const double q = d.r * d.r + d.dr * d.dr;
    const double root_q = std::sqrt(q);
    const double turning = q + d.dr * d.dr - d.r * d.ddr;  // nu' q: > 0 on a convex bore
    const Eigen::Vector2d normal = (d.r / root_q) * radial - (d.dr / root_q) * across;
    const Eigen::Vector2d tangent(-normal.y(), normal.x());
    const Eigen::Vector2d ring_point = ring_centre + d.r * radial;
    double roller_h = outline.radius() + outline.mean_deviation();
    double roller_dh = 0.0;
    double roller_rho = roller_h;
    if (!outline.is_circle()) {
      // The normal in the roller's body frame, and the touching point as an offset from
      // it, which changes slowly while the roller spins quickly: a warm start that holds.
      const double cos_spin = std::cos(roller.angle);
      const double sin_spin = std::sin(roller.angle);
      const engine::SupportPoint b =
          outline.SupportToward(normal.x() * cos_spin + normal.y() * sin_spin,
                                normal.y() * cos_spin - normal.x() * sin_spin, tracked.roller_offset);
      roller_h = b.h;
      roller_dh = b.dh;
      roller_rho = b.curvature_radius;
      tracked.roller_offset = b.theta;
    }
    const Eigen::Vector2d offset = ring_point - roller.centre;
    const double gap = offset.dot(normal) - roller_h;
    const double slope = offset.dot(tangent) - roller_dh;
    const double curvature = q * root_q / turning - roller_rho - gap;
    if (!(curvature > 0.0 && turning > 0.0 && std::isfinite(gap))) return false;
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
    // dtheta = dphi / nu' with nu' = turning / q.
    tracked.theta_per_normal = q / turning;
    c.ring_theta += dphi * tracked.theta_per_normal;
    return true;
  };
  // The bore is evaluated two contacts at a time, the costliest part of a step.
  const int z = rollers();
  for (int i = 0; i < z; i += 2) {
    double cos_theta[2] = {1.0, 1.0};
    double sin_theta[2] = {0.0, 0.0};
    const int count = std::min(2, z - i);
    for (int k = 0; k < count; ++k) {
      TrackedContact& tracked = contacts[static_cast<std::size_t>(i + k)];
      tracked.bore_angle.Evaluate(tracked.contact.ring_theta, cos_theta[k], sin_theta[k]);
    }
    engine::RadiusDerivatives d[2];
    bore.EvaluatePairAt(cos_theta, sin_theta, d);
    for (int k = 0; k < count; ++k) {
      if (!step_contact(i + k, d[k])) return std::numeric_limits<double>::infinity();
    }
  }
  return largest_step;
}

void EquilibriumSystem::FollowContacts(const Eigen::VectorXd& dx, std::vector<TrackedContact>& contacts) const {
  for (int i = 0; i < rollers(); ++i) {
    TrackedContact& tracked = contacts[static_cast<std::size_t>(i)];
    Contact& c = tracked.contact;
    // The gap and its slope move with the bodies: d g = n . dx_ring - n . u ds, and the
    // same along the tangent for g'. The gap then matches x to first order, which is what
    // an iteration accepted after one update reports as its contact force.
    Eigen::Vector2d roller_shift = Eigen::Vector2d::Zero();
    const int s = travel_index_[static_cast<std::size_t>(i)];
    if (s >= 0) roller_shift = dx[s] * axes_[static_cast<std::size_t>(i)];
    const Eigen::Vector2d relative = dx.head<2>() - roller_shift;
    c.gap += c.normal.dot(relative);
    c.ring_point += dx.head<2>();
    c.roller_point += roller_shift;
    c.ring_theta -= c.tangent.dot(relative) / c.gap_curvature * tracked.theta_per_normal;
  }
}

EquilibriumSystem::Penalty EquilibriumSystem::PenaltyLaw(double gap) const {
  if (!(gap < 0.0)) return {};
  const double e = scene_.contact.exponent;
  const double k = scene_.contact.stiffness;
  // delta^(e-1) once for both: the article's e = 1.5 needs only a sqrt, several times
  // cheaper than pow.
  const double root = e == 1.5 ? std::sqrt(-gap) : std::pow(-gap, e - 1.0);
  return {k * root * -gap, k * e * root};
}

double EquilibriumSystem::ContactForce(int i, const Eigen::VectorXd& x, const Contact& c) const {
  return rigid_ ? x[force_index(i)] : PenaltyLaw(c.gap).force;
}

void EquilibriumSystem::Evaluate(const Eigen::VectorXd& x, const std::vector<TrackedContact>& contacts,
                                 Eigen::VectorXd& residual, Eigen::MatrixXd* jacobian,
                                 Eigen::MatrixXd* gap_sensitivity, Eigen::MatrixXd* slope_sensitivity) const {
  const int z = rollers();
  residual.setZero(size_);
  if (jacobian != nullptr) jacobian->setZero(size_, size_);
  if (gap_sensitivity != nullptr) gap_sensitivity->setZero(size_, z);
  if (slope_sensitivity != nullptr) slope_sensitivity->setZero(size_, z);
  for (int i = 0; i < z; ++i) {
    const Contact& c = contacts[static_cast<std::size_t>(i)].contact;
    const int s = travel_index_[static_cast<std::size_t>(i)];
    const int f = force_index(i);
    const Eigen::Vector2d& u = axes_[static_cast<std::size_t>(i)];
    const Eigen::Vector2d& n = c.normal;
    const Eigen::Vector2d& t = c.tangent;
    const Penalty penalty = rigid_ ? Penalty{x[f], 0.0} : PenaltyLaw(c.gap);
    const double force = penalty.force;
    residual.head<2>() += force * n;
    if (s >= 0) {
      const engine::Spring& spring = scene_.rollers[static_cast<std::size_t>(i)].spring;
      residual[s] += spring.preload - spring.stiffness * x[s] - force * n.dot(u);
    }
    if (rigid_) residual[f] = kGapRowScale * c.gap;
    if (jacobian == nullptr && gap_sensitivity == nullptr && slope_sensitivity == nullptr) continue;

    // The derivatives are sparse: a contact's gap and normal depend only on the ring's
    // centre (columns 0, 1) and its own roller's travel (column s):
    //   dg/dc = n, dg/ds = -u . n, dphi/dc = -t / g'', dphi/ds = (u . t) / g'',
    // and its force on its own force unknown (rigid, column f) or on its gap (penalty).
    const double n_u = n.dot(u);
    const double t_u = t.dot(u);
    const double turn = 1.0 / c.gap_curvature;
    const double stiffness = penalty.stiffness;
    if (jacobian != nullptr) {
      // Ring rows: d(F n)/dx = n dF/dx + F t dphi/dx; spring row: -(n . u) dF/dx -
      // F (t . u) dphi/dx - k_spring.
      Eigen::MatrixXd& J = *jacobian;
      J.block<2, 2>(0, 0) -= stiffness * n * n.transpose() + (force * turn) * t * t.transpose();
      if (rigid_) J.block<2, 1>(0, f) += n;
      if (s >= 0) {
        J.block<2, 1>(0, s) += (stiffness * n_u) * n + (force * turn * t_u) * t;
        J.block<1, 2>(s, 0) += (stiffness * n_u) * n.transpose() + (force * turn * t_u) * t.transpose();
        J(s, s) -= scene_.rollers[static_cast<std::size_t>(i)].spring.stiffness + stiffness * n_u * n_u +
                   force * turn * t_u * t_u;
        if (rigid_) J(s, f) -= n_u;
      }
      if (rigid_) {
        J.block<1, 2>(f, 0) = kGapRowScale * n.transpose();
        if (s >= 0) J(f, s) = -kGapRowScale * n_u;
      }
    }
    if (gap_sensitivity != nullptr) {
      Eigen::MatrixXd& B = *gap_sensitivity;
      if (rigid_) {
        B(f, i) = kGapRowScale;
      } else {
        B.block<2, 1>(0, i) = -stiffness * n;
        if (s >= 0) B(s, i) = stiffness * n_u;
      }
    }
    if (slope_sensitivity != nullptr) {
      // A slope change dg' moves the minimum of g by dphi = -dg' / g''; the gap itself is
      // stationary there, so only the force direction turns.
      Eigen::MatrixXd& S = *slope_sensitivity;
      S.block<2, 1>(0, i) = -force * turn * t;
      if (s >= 0) S(s, i) = force * turn * t_u;
    }
  }
}

Eigen::VectorXd EquilibriumSystem::Tolerances(double position_tolerance, double force_tolerance) const {
  Eigen::VectorXd tolerance = Eigen::VectorXd::Constant(size_, position_tolerance);
  if (rigid_) tolerance.tail(rollers()).setConstant(force_tolerance);
  return tolerance;
}

}  // namespace ringtol::solvers
