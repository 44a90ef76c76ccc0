#include "solvers/equilibrium.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/LU>

namespace ringtol::solvers {

using engine::Contact;
using engine::RollerMount;

EquilibriumSystem::EquilibriumSystem(const engine::Scene& scene)
    : scene_(scene),
      rigid_(scene.contact.model == engine::ContactLaw::Model::kRigid),
      contact_stiffness_(scene.contact.stiffness),
      contact_exponent_(scene.contact.exponent) {
  const int z = rollers();
  travel_index_.assign(static_cast<std::size_t>(z), -1);
  for (int i = 0; i < z; ++i) {
    const engine::Roller& r = scene.rollers[static_cast<std::size_t>(i)];
    RollerConstants roller;
    roller.centre = engine::RollerCentre(scene, i);
    roller.axis = engine::SpringAxis(scene, i);
    if (r.mount == RollerMount::kSpring) {
      roller.travel = travel_index_[static_cast<std::size_t>(i)] = 2 + springs_++;
      roller.spring_stiffness = r.spring.stiffness;
      roller.spring_preload = r.spring.preload;
    }
    roller.round = r.outline.is_circle();
    roller.radius = r.outline.radius() + r.outline.mean_deviation();
    roller_.push_back(roller);
  }
  size_ = 2 + springs_ + (rigid_ ? z : 0);
}

engine::BodyPose EquilibriumSystem::RingPose(double psi, const State& x) const { return {x.head<2>(), psi}; }

Eigen::Vector2d EquilibriumSystem::RollerCentre(int i, const State& x) const {
  const RollerConstants& roller = roller_[static_cast<std::size_t>(i)];
  Eigen::Vector2d centre = roller.centre;
  if (roller.travel >= 0) centre += x[roller.travel] * roller.axis;
  return centre;
}

engine::BodyPose EquilibriumSystem::RollerPose(int i, double psi, const State& x) const {
  return {RollerCentre(i, x), engine::RollerBodyAngle(scene_, i, psi)};
}

int EquilibriumSystem::UpdateContacts(double psi, const State& x, std::vector<TrackedContact>& contacts) const {
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

EquilibriumSystem::Penalty EquilibriumSystem::PenaltyLaw(double gap) const {
  if (!(gap < 0.0)) return {};
  const double e = contact_exponent_;
  const double k = contact_stiffness_;
  // delta^(e-1) once for both: the article's e = 1.5 needs only a sqrt, several times
  // cheaper than pow.
  const double root = e == 1.5 ? std::sqrt(-gap) : std::pow(-gap, e - 1.0);
  return {k * root * -gap, k * e * root};
}

double EquilibriumSystem::ContactForce(int i, const State& x, const Contact& c) const {
  return rigid_ ? x[force_index(i)] : PenaltyLaw(c.gap).force;
}

void EquilibriumSystem::Evaluate(const State& x, const std::vector<TrackedContact>& contacts, Eigen::VectorXd& residual,
                                 Eigen::MatrixXd* jacobian, Eigen::MatrixXd* gap_sensitivity,
                                 Eigen::MatrixXd* slope_sensitivity) const {
  const int z = rollers();
  residual.setZero(size_);
  if (jacobian != nullptr) jacobian->setZero(size_, size_);
  if (gap_sensitivity != nullptr) gap_sensitivity->setZero(size_, z);
  if (slope_sensitivity != nullptr) slope_sensitivity->setZero(size_, z);
  for (int i = 0; i < z; ++i) {
    const Contact& c = contacts[static_cast<std::size_t>(i)].contact;
    const int s = travel_index_[static_cast<std::size_t>(i)];
    const int f = force_index(i);
    const Eigen::Vector2d& u = roller_[static_cast<std::size_t>(i)].axis;
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

namespace {

// Solves J dx = -r for a Newton step of the continuation. The systems are tiny (3
// unknowns for the article's penalty scene, 6 for rigid contact) and fixed-size where the
// caller's are, with Eigen's closed-form inverse up to 4 x 4, several times cheaper there
// than a pivoted LU. Rigid contact with as many contacts as position unknowns (the
// article's 2 fixed + 1 spring) is block triangular, since the gaps do not depend on the
// forces: [A B; G 0] [dp; dF] = -[r_p; r_g] gives dp from G dp = -r_g and then dF from
// B dF = -r_p - A dp, two 3 x 3 solves instead of one 6 x 6.
template <int P, typename Matrix, typename Vector>
bool SolveBlockTriangular(const Matrix& jacobian, const Vector& residual, Vector& step) {
  const Eigen::Matrix<double, P, P> a = jacobian.template topLeftCorner<P, P>();
  const Eigen::Matrix<double, P, P> b = jacobian.template topRightCorner<P, P>();
  const Eigen::Matrix<double, P, P> g = jacobian.template bottomLeftCorner<P, P>();
  const Eigen::Matrix<double, P, 1> dp = -(g.inverse() * residual.template tail<P>());
  const Eigen::Matrix<double, P, 1> df = -(b.inverse() * (residual.template head<P>() + a * dp));
  step.resize(2 * P);
  step << dp, df;
  return step.allFinite();
}

template <int N>
bool SolveNewtonStep(bool block_triangular, int rollers, const Eigen::Matrix<double, N, N>& jacobian,
                     const Eigen::Matrix<double, N, 1>& residual, Eigen::Matrix<double, N, 1>& step) {
  if (block_triangular) {
    if constexpr (N == 6 || N == Eigen::Dynamic) {
      if (rollers == 3) return SolveBlockTriangular<3>(jacobian, residual, step);
    }
    if constexpr (N == 8 || N == Eigen::Dynamic) {
      if (rollers == 4) return SolveBlockTriangular<4>(jacobian, residual, step);
    }
  }
  if constexpr (N != Eigen::Dynamic && N <= 4) {
    step = -(jacobian.inverse() * residual);
  } else {
    step = jacobian.partialPivLu().solve(-residual);
  }
  return step.allFinite();
}

}  // namespace

template <int N>
double EquilibriumSystem::ContinuationUpdate(const RingTurn& turn, Eigen::Matrix<double, N, 1>& x,
                                             std::vector<TrackedContact>& contacts,
                                             Eigen::Matrix<double, N, 1>& step) const {
  using Vector = Eigen::Matrix<double, N, 1>;
  using Matrix = Eigen::Matrix<double, N, N>;
  constexpr double kCannotStep = std::numeric_limits<double>::infinity();
  const engine::PolarProfile& bore = scene_.ring.inner;
  const int z = rollers();
  const Eigen::Vector2d ring_centre = x.template head<2>();
  Vector residual = Vector::Zero(size_);
  Matrix jacobian = Matrix::Zero(size_, size_);
  double largest_turn = 0.0;
  // The bore is summed four contacts at a time, the costliest part of an iteration.
  for (int first = 0; first < z; first += 4) {
    const int count = std::min(4, z - first);
    double cos_theta[4] = {1.0, 1.0, 1.0, 1.0};
    double sin_theta[4] = {0.0, 0.0, 0.0, 0.0};
    for (int k = 0; k < count; ++k) {
      TrackedContact& tracked = contacts[static_cast<std::size_t>(first + k)];
      tracked.bore_angle.Evaluate(tracked.contact.ring_theta, cos_theta[k], sin_theta[k]);
    }
    engine::RadiusDerivatives bore_at[4];
    if (bore.sampled()) {
      // A bore of many harmonics interpolates its samples instead.
      for (int k = 0; k < count; ++k) {
        bore_at[k] = bore.EvaluateAt(contacts[static_cast<std::size_t>(first + k)].contact.ring_theta, cos_theta[k],
                                     sin_theta[k]);
      }
    } else {
      bore.EvaluateFourAt(cos_theta, sin_theta, bore_at);
    }
    for (int k = 0; k < count; ++k) {
      const int i = first + k;
      const engine::RadiusDerivatives& d = bore_at[k];
      TrackedContact& tracked = contacts[static_cast<std::size_t>(i)];
      Contact& c = tracked.contact;
      const RollerConstants& roller = roller_[static_cast<std::size_t>(i)];
      const int s = roller.travel;
      Eigen::Vector2d roller_centre = roller.centre;
      if (s >= 0) roller_centre += x[s] * roller.axis;

      // 1. The contact's step: the bore point's radial and tangential unit vectors in the
      // global frame, its outward normal, and the clearance along it.
      const Eigen::Vector2d radial(d.cos_theta * turn.cos_psi - d.sin_theta * turn.sin_psi,
                                   d.sin_theta * turn.cos_psi + d.cos_theta * turn.sin_psi);
      const Eigen::Vector2d across(-radial.y(), radial.x());
      const double q = d.r * d.r + d.dr * d.dr;
      const double root_q = std::sqrt(q);
      const double turning = q + d.dr * d.dr - d.r * d.ddr;  // nu' q: > 0 on a convex bore
      const double inverse_root_q = 1.0 / root_q;
      const double inverse_turning = 1.0 / turning;
      const Eigen::Vector2d normal = (d.r * inverse_root_q) * radial - (d.dr * inverse_root_q) * across;
      const Eigen::Vector2d tangent(-normal.y(), normal.x());
      double roller_h = roller.radius;
      double roller_dh = 0.0;
      double roller_rho = roller.radius;
      if (!roller.round) {
        // The normal in the roller's body frame; a roller is nearly round, and its touching
        // point follows from one evaluation there (PolarProfile::SupportTowardNearlyRound).
        // Its offset is needed to kRollerOffsetTolerance only: an error e moves the roller's
        // touching point along the tangent by r_b e, which turns the converged normal by
        // r_b e / g'' (g'' ~ R - r_b) and the force with it; for the article's contacts
        // (~2e5 N/m, ~20 N) that moves the ring by ~2e-6 e [m], 2e-18 m at 1e-12 rad.
        constexpr double kRollerOffsetTolerance = 1e-12;  // [rad]
        const Eigen::Vector2d spin = turn.spin.empty() ? engine::Direction(engine::RollerBodyAngle(scene_, i, turn.psi))
                                                       : turn.spin[static_cast<std::size_t>(i)];
        const double cos_spin = spin.x();
        const double sin_spin = spin.y();
        const engine::SupportPoint b = scene_.rollers[static_cast<std::size_t>(i)].outline.SupportTowardNearlyRound(
            normal.x() * cos_spin + normal.y() * sin_spin, normal.y() * cos_spin - normal.x() * sin_spin,
            kRollerOffsetTolerance);
        roller_h = b.h;
        roller_dh = b.dh;
        roller_rho = b.curvature_radius;
        tracked.roller_offset = b.theta;
      }
      const Eigen::Vector2d offset = ring_centre + d.r * radial - roller_centre;
      const double gap = offset.dot(normal) - roller_h;
      const double slope = offset.dot(tangent) - roller_dh;
      const double curvature = q * root_q * inverse_turning - roller_rho - gap;
      if (!(curvature > 0.0 && turning > 0.0 && std::isfinite(gap))) return kCannotStep;
      const double inverse_curvature = 1.0 / curvature;
      const double dphi = -slope * inverse_curvature;
      largest_turn = std::max(largest_turn, std::abs(dphi));
      // The force balance that follows must use the normal the contact steps to, or the
      // forces converge only linearly. The gap is stationary there: it keeps its value to
      // g'' dphi^2 / 2. Rotation by dphi to fourth order.
      const double cos_step = 1.0 - 0.5 * dphi * dphi;
      const double sin_step = dphi * (1.0 - (1.0 / 6.0) * dphi * dphi);
      const Eigen::Vector2d n = cos_step * normal + sin_step * tangent;
      const Eigen::Vector2d t(-n.y(), n.x());
      c.gap = gap;
      c.normal = n;
      c.tangent = t;
      c.gap_curvature = curvature;
      // dtheta = dphi / nu' with nu' = turning / q.
      tracked.theta_per_normal = q * inverse_turning;
      tracked.theta_per_shift = tracked.theta_per_normal * inverse_curvature;
      c.ring_theta += dphi * tracked.theta_per_normal;

      // 2. Its share of the force balance (Evaluate, for one contact).
      const int f = force_index(i);
      const Penalty penalty = rigid_ ? Penalty{x[f], 0.0} : PenaltyLaw(gap);
      const double force = penalty.force;
      const double stiffness = penalty.stiffness;
      tracked.force = force;
      tracked.stiffness = stiffness;
      const double force_turn = force * inverse_curvature;
      residual.template head<2>() += force * n;
      jacobian.template block<2, 2>(0, 0) -= stiffness * n * n.transpose() + force_turn * t * t.transpose();
      if (rigid_) {
        residual[f] = kGapRowScale * gap;
        jacobian.template block<2, 1>(0, f) += n;
        jacobian.template block<1, 2>(f, 0) = kGapRowScale * n.transpose();
      }
      if (s >= 0) {
        const double n_u = n.dot(roller.axis);
        const double t_u = t.dot(roller.axis);
        residual[s] += roller.spring_preload - roller.spring_stiffness * x[s] - force * n_u;
        const Eigen::Vector2d coupling = (stiffness * n_u) * n + (force_turn * t_u) * t;
        jacobian.template block<2, 1>(0, s) += coupling;
        jacobian.template block<1, 2>(s, 0) += coupling.transpose();
        jacobian(s, s) -= roller.spring_stiffness + stiffness * n_u * n_u + force_turn * t_u * t_u;
        if (rigid_) {
          jacobian(s, f) -= n_u;
          jacobian(f, s) = -kGapRowScale * n_u;
        }
      }
    }
  }
  if (!SolveNewtonStep<N>(rigid_ && size_ == 2 * z, z, jacobian, residual, step)) return kCannotStep;
  x += step;

  // 3. The contacts follow the bodies: d g = n . dx_ring - n . u ds, and the same along the
  // tangent for g'. The gap then matches x to first order, which is what an iteration
  // accepted after one update reports as its contact force.
  for (int i = 0; i < z; ++i) {
    TrackedContact& tracked = contacts[static_cast<std::size_t>(i)];
    Contact& c = tracked.contact;
    const RollerConstants& roller = roller_[static_cast<std::size_t>(i)];
    Eigen::Vector2d relative = step.template head<2>();
    if (roller.travel >= 0) relative -= step[roller.travel] * roller.axis;
    const double gap_change = c.normal.dot(relative);
    c.gap += gap_change;
    c.ring_theta -= c.tangent.dot(relative) * tracked.theta_per_shift;
    if (rigid_) {
      tracked.force = x[force_index(i)];
    } else {
      // dF = -(dF/d delta) dg; an opened contact carries nothing.
      tracked.force = c.gap < 0.0 ? std::max(0.0, tracked.force - tracked.stiffness * gap_change) : 0.0;
    }
  }
  return largest_turn;
}

#define RINGTOL_INSTANTIATE_CONTINUATION_UPDATE(N)                                                            \
  template double EquilibriumSystem::ContinuationUpdate<N>(const RingTurn&, Eigen::Matrix<double, N, 1>&,      \
                                                           std::vector<TrackedContact>&,                       \
                                                           Eigen::Matrix<double, N, 1>&) const;
RINGTOL_INSTANTIATE_CONTINUATION_UPDATE(2)
RINGTOL_INSTANTIATE_CONTINUATION_UPDATE(3)
RINGTOL_INSTANTIATE_CONTINUATION_UPDATE(4)
RINGTOL_INSTANTIATE_CONTINUATION_UPDATE(5)
RINGTOL_INSTANTIATE_CONTINUATION_UPDATE(6)
RINGTOL_INSTANTIATE_CONTINUATION_UPDATE(7)
RINGTOL_INSTANTIATE_CONTINUATION_UPDATE(8)
RINGTOL_INSTANTIATE_CONTINUATION_UPDATE(Eigen::Dynamic)
#undef RINGTOL_INSTANTIATE_CONTINUATION_UPDATE

Eigen::VectorXd EquilibriumSystem::Tolerances(double position_tolerance, double force_tolerance) const {
  Eigen::VectorXd tolerance = Eigen::VectorXd::Constant(size_, position_tolerance);
  if (rigid_) tolerance.tail(rollers()).setConstant(force_tolerance);
  return tolerance;
}

}  // namespace ringtol::solvers
