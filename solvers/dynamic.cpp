#include "solvers/dynamic.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <sstream>

#include <arkode/arkode_erkstep.h>
#include <Eigen/Eigenvalues>
#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include "engine/contact.h"
#include "engine/units.h"
#include "solvers/quasistatic.h"
#include "solvers/validity.h"

namespace ringtol::solvers {
namespace {

using engine::Scene;

// Adams' STEP: h0 + (h1 - h0) a^2 (3 - 2 a), a = (x - x0) / (x1 - x0) clamped to [0, 1].
double Step(double x, double x0, double h0, double x1, double h1) {
  const double a = std::clamp((x - x0) / (x1 - x0), 0.0, 1.0);
  return h0 + (h1 - h0) * a * a * (3.0 - 2.0 * a);
}

// d STEP / dx.
double StepSlope(double x, double x0, double h0, double x1, double h1) {
  const double a = (x - x0) / (x1 - x0);
  if (a <= 0.0 || a >= 1.0) return 0.0;
  return (h1 - h0) * 6.0 * a * (1.0 - a) / (x1 - x0);
}

// mu(v) of docs/model.md §4 in Adams' contact form: odd in v, through 0 with slope
// 1.5 mu_s / v_s as the cubic step from -mu_s at -v_s to mu_s at v_s, then a step from
// mu_s down to mu_d between v_s and v_d. Smooth through v = 0, where a rolling roller's
// slip keeps changing sign: a law flat at 0 (a step in |v| from 0 to v_s) would make the
// slip follow sqrt(t - t0) there and cost the integrator hundreds of steps per crossing.
double FrictionCoefficient(double v, const engine::Friction& f) {
  const double speed = std::abs(v);
  if (speed < f.stiction_velocity) {
    return Step(v, -f.stiction_velocity, -f.static_coefficient, f.stiction_velocity, f.static_coefficient);
  }
  return std::copysign(
      Step(speed, f.stiction_velocity, f.static_coefficient, f.transition_velocity, f.dynamic_coefficient), v);
}

// d mu / dv of FrictionCoefficient (even in v).
double FrictionSlope(double v, const engine::Friction& f) {
  const double speed = std::abs(v);
  if (speed < f.stiction_velocity) {
    return StepSlope(v, -f.stiction_velocity, -f.static_coefficient, f.stiction_velocity, f.static_coefficient);
  }
  return StepSlope(speed, f.stiction_velocity, f.static_coefficient, f.transition_velocity, f.dynamic_coefficient);
}

// SUNDIALS' *GetReturnFlagName hand over a malloc'ed string the caller frees.
std::string FlagName(char* name) {
  const std::string copy = name != nullptr ? name : "an unknown flag";
  std::free(name);
  return copy;
}

std::string Seconds(double t) {
  std::ostringstream out;
  out.precision(6);
  out << t << " s";
  return out.str();
}

// The equations of motion. State y = [centre (2) [m]; centre velocity (2) [m/s];
// per spring roller: travel [m], then its rate [m/s] unless massless; per roller with
// spin dynamics: spin angle [rad], spin rate [rad/s]].
class RingDynamics {
 public:
  RingDynamics(const Scene& scene, const DynamicOptions& options)
      : scene_(scene),
        options_(options),
        model_(scene.dynamics),
        spin_states_(model_.friction && !model_.rolling_without_slip) {
    const int z = rollers();
    int next = 4;
    for (int i = 0; i < z; ++i) {
      const engine::Roller& roller = scene.rollers[static_cast<std::size_t>(i)];
      centres_.push_back(engine::RollerCentre(scene, i));
      axes_.push_back(engine::SpringAxis(scene, i));
      travel_.push_back(roller.mount == engine::RollerMount::kSpring ? next : -1);
      if (roller.mount == engine::RollerMount::kSpring) next += model_.massless_spring_rollers ? 1 : 2;
    }
    for (int i = 0; i < z; ++i) {
      spin_.push_back(spin_states_ ? next : -1);
      if (spin_states_) next += 2;
    }
    size_ = next;
    const auto n = static_cast<std::size_t>(z);
    guesses_.resize(n);
    have_guess_.assign(n, false);
    touching_.resize(n);
    depth_.assign(n, 0.0);
    normal_force_.assign(n, 0.0);
    friction_force_.assign(n, 0.0);
    slip_.assign(n, 0.0);
    spin_angle_.assign(n, 0.0);
    spin_rate_.assign(n, 0.0);
    travel_rate_.assign(n, 0.0);
  }

  int rollers() const { return static_cast<int>(scene_.rollers.size()); }
  int size() const { return size_; }
  int travel_index(int i) const { return travel_[static_cast<std::size_t>(i)]; }
  const std::string& failure() const { return failure_; }

  // The motion-law segment whose polynomial Derivatives uses, whatever t it is given: an
  // integration step that ends on a breakpoint must not see the next segment's rate.
  void set_segment(std::size_t segment) { segment_ = segment; }

  // What the scene must give for its bodies to have dynamics; empty when it does.
  std::string MissingInertia() const {
    if (!(scene_.ring.mass > 0.0)) return "the ring needs a positive mass";
    for (int i = 0; i < rollers(); ++i) {
      const engine::Roller& roller = scene_.rollers[static_cast<std::size_t>(i)];
      if (travel_index(i) >= 0 && !model_.massless_spring_rollers && !(roller.mass > 0.0)) {
        return "spring roller " + roller.name + " needs a positive mass (or massless_spring_rollers)";
      }
      if (spin_[static_cast<std::size_t>(i)] >= 0 && !(roller.spin_inertia > 0.0)) {
        return "roller " + roller.name + " needs a positive spin inertia (or rolling_without_slip)";
      }
    }
    if (model_.massless_spring_rollers && !(scene_.contact.max_damping > 0.0)) {
      return "massless spring rollers need contact damping (max_damping > 0)";
    }
    return {};
  }

  // For the quasistatic start, finds the equilibrium InitialState starts from; kOk, or the
  // quasistatic rung's status with its reason. The article's start needs nothing.
  Status FindStart(std::string& message) {
    if (options_.start != DynamicStart::kQuasistaticEquilibrium) return Status::kOk;
    const Equilibrium equilibrium = QuasistaticSolver().SolveStatic(scene_);
    if (equilibrium.status != Status::kOk) {
      message = "the quasistatic equilibrium the run starts from: " + equilibrium.message;
      return equilibrium.status;
    }
    start_ = equilibrium;
    return Status::kOk;
  }

  // At rest, rollers at their psi = 0 spin angle, spinning as they would roll at the law's
  // rate at t = 0. After FindStart for the quasistatic start, ring and spring rollers at
  // that equilibrium; otherwise (the article's start) the ring centred and spring rollers
  // pressed against it where spring and contact stiffness balance, as an assembled roller
  // sits. (Starting them at zero travel would add a flight to the bore and an impact,
  // microseconds of physics no one asked about that cost a third of a run.)
  void InitialState(double* y) const {
    std::fill(y, y + size_, 0.0);
    const double rate = scene_.motion.Rate(0.0);
    if (start_) {
      y[0] = start_->centre.x();
      y[1] = start_->centre.y();
    }
    for (int i = 0; i < rollers(); ++i) {
      const auto k = static_cast<std::size_t>(i);
      if (spin_[k] >= 0) {
        y[spin_[k]] = engine::RollerBodyAngle(scene_, i, 0.0);
        y[spin_[k] + 1] = engine::SpinRatio(scene_, i) * rate;
      }
      if (travel_[k] >= 0) y[travel_[k]] = start_ ? start_->travel[k] : BalancedTravel(i);
    }
  }

  // dy/dt at (t, y). Returns 0, or 1 (recoverable: CVODE retries with a smaller step) when
  // a contact search fails, a roller sinks deeper than half its radius or a massless
  // spring roller leaves the bore, with the reason in failure().
  int Derivatives(double t, const double* y, double* dydt) {
    evaluated_at_ = t;
    const engine::MotionLaw& law = scene_.motion;
    const double psi = law.AngleIn(segment_, t);
    const double ring_rate = law.RateIn(segment_, t);
    const Eigen::Vector2d centre(y[0], y[1]);
    const Eigen::Vector2d velocity(y[2], y[3]);
    Eigen::Vector2d ring_force = Eigen::Vector2d::Zero();
    std::fill(dydt, dydt + size_, 0.0);
    dydt[0] = y[2];
    dydt[1] = y[3];
    for (int i = 0; i < rollers(); ++i) {
      const auto k = static_cast<std::size_t>(i);
      const engine::Roller& roller = scene_.rollers[k];
      const int s = travel_[k];
      const int b = spin_[k];
      Eigen::Vector2d roller_centre = centres_[k];
      if (s >= 0) roller_centre += y[s] * axes_[k];
      if (b >= 0) {
        spin_angle_[k] = y[b];
        spin_rate_[k] = y[b + 1];
      } else if (model_.rolling_without_slip) {
        spin_angle_[k] = engine::RollerBodyAngle(scene_, i, psi);
        spin_rate_[k] = engine::SpinRatio(scene_, i) * ring_rate;
      } else {
        spin_angle_[k] = engine::RollerBodyAngle(scene_, i, 0.0);
        spin_rate_[k] = 0.0;
      }
      const engine::Contact c =
          engine::FindContact(scene_.ring.inner, {centre, psi}, roller.outline, {roller_centre, spin_angle_[k]},
                              have_guess_[k] ? &guesses_[k] : nullptr);
      if (!c.converged) {
        failure_ = "the contact search of roller " + roller.name + " failed at t = " + Seconds(t);
        have_guess_[k] = false;
        return 1;
      }
      guesses_[k] = {c.normal_angle, c.ring_theta, c.roller_theta};
      have_guess_[k] = true;
      const double depth = -c.gap;
      if (depth > 0.5 * roller.outline.radius()) {
        failure_ = "roller " + roller.name + " sinks " + std::to_string(depth * units::kMillimetresPerMetre) + " mm into the bore at t = " +
                   Seconds(t);
        return 1;
      }
      // Velocities of the two touching material points, the roller's without its travel
      // rate: their difference along the normal is the gap rate, along the tangent the slip.
      const Eigen::Vector2d across_ring = c.ring_point - centre;
      const Eigen::Vector2d across_roller = c.roller_point - roller_centre;
      const Eigen::Vector2d relative = velocity + ring_rate * Eigen::Vector2d(-across_ring.y(), across_ring.x()) -
                                       spin_rate_[k] * Eigen::Vector2d(-across_roller.y(), across_roller.x());
      double travel_rate = 0.0;
      if (s >= 0 && !model_.massless_spring_rollers) travel_rate = y[s + 1];
      const ContactLoad load = [&] {
        if (s >= 0 && model_.massless_spring_rollers) {
          return MasslessTravelRate(roller, y[s], depth, relative, c, axes_[k], travel_rate);
        }
        return Load(depth, relative - travel_rate * axes_[k], c);
      }();
      if (!load.valid) {
        failure_ = "massless spring roller " + roller.name + " leaves the bore at t = " + Seconds(t);
        return 1;
      }
      travel_rate_[k] = travel_rate;
      touching_[k] = {c.normal,
                      c.tangent,
                      relative - travel_rate * axes_[k],
                      velocity - travel_rate * axes_[k],
                      depth,
                      c.normal_angle,
                      c.ring_theta,
                      c.roller_theta,
                      c.gap_curvature,
                      psi,
                      ring_rate};
      depth_[k] = depth;
      normal_force_[k] = load.normal;
      friction_force_[k] = load.friction;
      slip_[k] = load.slip;
      // On the ring: pushed outward along n and dragged against its slip. On the roller:
      // the reaction.
      const Eigen::Vector2d on_ring = load.normal * c.normal - load.friction * c.tangent;
      ring_force += on_ring;
      if (s >= 0) {
        const engine::Spring& spring = roller.spring;
        dydt[s] = travel_rate;
        if (!model_.massless_spring_rollers) {
          dydt[s + 1] = (spring.preload - spring.stiffness * y[s] - on_ring.dot(axes_[k])) / roller.mass;
        }
      }
      if (b >= 0) {
        dydt[b] = y[b + 1];
        dydt[b + 1] = -(across_roller.x() * on_ring.y() - across_roller.y() * on_ring.x()) / roller.spin_inertia;
      }
    }
    dydt[2] = ring_force.x() / scene_.ring.mass;
    dydt[3] = ring_force.y() / scene_.ring.mass;
    return 0;
  }

  // The separation event functions at (t, y): each roller's penetration [m], which falls
  // through zero when its contact opens. (A force that drops to zero while the bodies
  // still overlap is not an opening: at an ideal step in speed the damping term does that
  // for a fraction of a microsecond, until the spring catches the roller up.) CVODE asks
  // for them at the end of every accepted step, where its corrector has just evaluated
  // the dynamics at that time (the kept values differ from exact ones by the corrector's
  // tolerance, which only moves a sign change by as much), and at every output time
  // inside that same step. Answering an output time with the step end's values only
  // hides an opening that also closes within the step, which checking at step ends
  // misses anyway; so while every contact overlaps by at least a quarter of the deepest,
  // the kept values serve. Otherwise, and while CVODE locates a sign change, they are
  // evaluated exactly. (Exact evaluations at the ~360 outputs of a revolution would add
  // a third to its cost.)
  int Separation(double t, const double* y, double* depth) {
    const auto [shallowest, deepest] = std::minmax_element(depth_.begin(), depth_.end());
    const bool comfortable = *shallowest > 0.25 * *deepest;
    if (t != evaluated_at_ && !comfortable) {
      std::vector<double> rates(static_cast<std::size_t>(size_));
      if (const int flag = Derivatives(t, y, rates.data()); flag != 0) return flag;
    }
    std::copy(depth_.begin(), depth_.end(), depth);
    return 0;
  }

  // d(dy/dt)/dy at (t, y), dense, column-major with leading dimension size(); `jacobian`
  // must hold size()^2 zeros. Exact, including the contact's slide along both surfaces
  // as the state moves: the slip is a difference of two surface speeds near 1.4 m/s and
  // the friction law turns a slip of um/s into newtons, so that geometric term dominates
  // the spin rows. Returns what Derivatives returns.
  //
  // With the contact normal at angle phi, h_ring and h_roller the two support functions
  // (body frames) and u the ring's velocity minus the roller's translation:
  //   depth = -g,  slip = u . t + psi' h_ring(phi) - omega h_roller(phi),
  //   depth rate = -u . n + psi' h_ring'(phi) - omega h_roller'(phi),
  // and phi moves with the state as d phi = -(d g' / d q) / g'' (g' = 0 at the contact).
  int Jacobian(double t, const double* y, double* jacobian) {
    std::vector<double> rates(static_cast<std::size_t>(size_));
    if (const int flag = Derivatives(t, y, rates.data()); flag != 0) return flag;
    const auto n = static_cast<std::size_t>(size_);
    auto at = [&](int row, int column) -> double& {
      return jacobian[static_cast<std::size_t>(column) * n + static_cast<std::size_t>(row)];
    };
    at(0, 2) = 1.0;
    at(1, 3) = 1.0;
    // Local variables of one contact: ring x, y, vx, vy, roller travel, travel rate, spin
    // angle, spin rate.
    enum { kX, kY, kVx, kVy, kTravel, kTravelRate, kSpin, kSpinRate, kLocal };
    using Row = Eigen::Matrix<double, 1, kLocal>;
    const engine::ContactLaw& law = scene_.contact;
    for (int i = 0; i < rollers(); ++i) {
      const auto k = static_cast<std::size_t>(i);
      const engine::Roller& roller = scene_.rollers[k];
      const Touching& touch = touching_[k];
      const Eigen::Vector2d& normal = touch.normal;
      const Eigen::Vector2d& tangent = touch.tangent;
      const Eigen::Vector2d& axis = axes_[k];
      const engine::SupportPoint ring =
          scene_.ring.inner.Support(touch.normal_angle - touch.psi, touch.ring_theta);
      const engine::SupportPoint body =
          roller.outline.Support(touch.normal_angle - spin_angle_[k], touch.roller_theta);
      const double ring_bend = ring.curvature_radius - ring.h;  // h_ring''
      const double body_bend = body.curvature_radius - body.h;  // h_roller''
      const double psi_rate = touch.ring_rate;
      const double omega = spin_rate_[k];
      // The contact direction: g' = (x - c) . t + h_ring' - h_roller'.
      Row phi = Row::Zero();
      if (touch.gap_curvature > 0.0) {
        phi(kX) = -tangent.x() / touch.gap_curvature;
        phi(kY) = -tangent.y() / touch.gap_curvature;
        phi(kTravel) = axis.dot(tangent) / touch.gap_curvature;
        phi(kSpin) = -body_bend / touch.gap_curvature;
      }
      Row spin_frame = phi;  // the roller's body angle of the contact, phi - beta
      spin_frame(kSpin) -= 1.0;
      Row depth = Row::Zero();
      depth(kX) = -normal.x();
      depth(kY) = -normal.y();
      depth(kTravel) = axis.dot(normal);
      depth(kSpin) = -body.dh;
      Row depth_rate = (-touch.motion.dot(tangent) + psi_rate * ring_bend - omega * body_bend) * phi;
      depth_rate(kVx) -= normal.x();
      depth_rate(kVy) -= normal.y();
      depth_rate(kTravelRate) += axis.dot(normal);
      depth_rate(kSpinRate) -= body.dh;
      depth_rate(kSpin) += omega * body_bend;
      Row slip = (-touch.motion.dot(normal) + psi_rate * ring.dh - omega * body.dh) * phi;
      slip(kVx) += tangent.x();
      slip(kVy) += tangent.y();
      slip(kTravelRate) -= axis.dot(tangent);
      slip(kSpinRate) -= body.h;
      slip(kSpin) += omega * body.dh;
      const double normal_force = normal_force_[k];
      const double friction = friction_force_[k];
      Row d_normal = Row::Zero();
      Row d_friction = Row::Zero();
      if (normal_force > 0.0) {
        const double d = touch.depth;
        const double rate = -touch.relative.dot(normal);
        const double stiffness = law.stiffness * law.exponent * std::pow(d, law.exponent - 1.0) +
                                 StepSlope(d, 0.0, 0.0, law.full_damping_penetration, law.max_damping) * rate;
        d_normal = stiffness * depth + Damping(d) * depth_rate;
        if (spin_states_) {
          const double v = touch.relative.dot(tangent);
          d_friction = FrictionSlope(v, scene_.friction) * normal_force * slip +
                       FrictionCoefficient(v, scene_.friction) * d_normal;
        }
      }
      // On the ring F = F_n n - F_t t, with n and t turning with phi; on the roller the
      // torque -(r x F) = h_roller F_t + h_roller' F_n, its lever turning with phi - beta.
      Eigen::Matrix<double, 2, kLocal> force =
          normal * d_normal - tangent * d_friction + (normal_force * tangent + friction * normal) * phi;
      Row torque = body.h * d_friction + body.dh * d_normal + (friction * body.dh + normal_force * body_bend) * spin_frame;
      const int s = travel_[k];
      const int b = spin_[k];
      const bool massless = s >= 0 && model_.massless_spring_rollers;
      // A massless roller's travel rate follows the state through its axial balance
      // P - k_s s - F . a = 0: dv = -(k_s ds + (dF/dq . a) dq) / (dF/dv . a).
      Row travel_rate = Row::Zero();
      if (massless) {
        Row balance = -(axis.transpose() * force);
        balance(kTravel) -= roller.spring.stiffness;
        const double along_rate = -balance(kTravelRate);
        balance(kTravelRate) = 0.0;
        travel_rate = balance / along_rate;
        const Eigen::Vector2d force_per_rate = force.col(kTravelRate);
        const double torque_per_rate = torque(kTravelRate);
        force += force_per_rate * travel_rate;
        force.col(kTravelRate).setZero();
        torque += torque_per_rate * travel_rate;
        torque(kTravelRate) = 0.0;
      }
      // Global state index of each local variable, or -1 where it is not a state.
      std::array<int, kLocal> index = {0, 1, 2, 3, -1, -1, -1, -1};
      if (s >= 0) {
        index[kTravel] = s;
        if (!massless) index[kTravelRate] = s + 1;
      }
      if (b >= 0) {
        index[kSpin] = b;
        index[kSpinRate] = b + 1;
      }
      for (int local = 0; local < kLocal; ++local) {
        const int column = index[static_cast<std::size_t>(local)];
        if (column < 0) continue;
        const Eigen::Vector2d d_force = force.col(local);
        at(2, column) += d_force.x() / scene_.ring.mass;
        at(3, column) += d_force.y() / scene_.ring.mass;
        if (massless) at(s, column) += travel_rate(local);
        if (s >= 0 && !massless) at(s + 1, column) -= d_force.dot(axis) / roller.mass;
        if (b >= 0) at(b + 1, column) += torque(local) / roller.spin_inertia;
      }
      if (s >= 0 && !massless) {
        at(s, s + 1) = 1.0;
        at(s + 1, s) -= roller.spring.stiffness / roller.mass;
      }
      if (b >= 0) at(b, b + 1) = 1.0;
    }
    return 0;
  }

  // Absolute tolerance of each state.
  void Tolerances(double* tolerance) const {
    const double scale = options_.relative_tolerance / 1e-8;
    const double position = 1e-11 * scale;  // [m]
    const double speed = 1e-8 * scale;      // [m/s]
    const double angle = 1e-9 * scale;      // [rad]
    const double spin_rate = 1e-6 * scale;  // [rad/s]
    for (int j = 0; j < 4; ++j) tolerance[j] = j < 2 ? position : speed;
    for (int i = 0; i < rollers(); ++i) {
      const auto k = static_cast<std::size_t>(i);
      if (travel_[k] >= 0) {
        tolerance[travel_[k]] = position;
        if (!model_.massless_spring_rollers) tolerance[travel_[k] + 1] = speed;
      }
      if (spin_[k] >= 0) {
        tolerance[spin_[k]] = angle;
        tolerance[spin_[k] + 1] = spin_rate;
      }
    }
  }

  // The sample at (t, y), evaluated without disturbing what Separation keeps from the
  // integrator's own last evaluation (an output between steps would otherwise force an
  // exact re-evaluation at the next step's end).
  DynamicSample Observe(double t, const double* y) {
    const double evaluated_at = evaluated_at_;
    const std::vector<double> depth = depth_;
    std::vector<double> rates(static_cast<std::size_t>(size_));
    Derivatives(t, y, rates.data());
    DynamicSample sample = Sample(t, y);
    evaluated_at_ = evaluated_at;
    depth_ = depth;
    return sample;
  }

  // The sample at the state last given to Derivatives.
  DynamicSample Sample(double t, const double* y) const {
    DynamicSample sample;
    sample.time = t;
    sample.psi = scene_.motion.AngleIn(segment_, t);
    sample.centre = Eigen::Vector2d(y[0], y[1]);
    for (int i = 0; i < rollers(); ++i) sample.travel.push_back(travel_index(i) >= 0 ? y[travel_index(i)] : 0.0);
    sample.spin_angle = spin_angle_;
    sample.spin_rate = spin_rate_;
    sample.penetration = depth_;
    sample.normal_force = normal_force_;
    sample.friction_force = friction_force_;
    sample.slip = slip_;
    return sample;
  }

 private:
  struct ContactLoad {
    double normal = 0.0;    // [N]
    double friction = 0.0;  // [N] on the ring, against +tangent when the slip is positive
    double slip = 0.0;      // [m/s]
    bool valid = true;
  };

  // The contact law at penetration `depth` with the touching points moving apart at
  // `relative` (ring point minus roller point).
  ContactLoad Load(double depth, const Eigen::Vector2d& relative, const engine::Contact& c) const {
    ContactLoad load;
    load.slip = relative.dot(c.tangent);
    const engine::ContactLaw& law = scene_.contact;
    if (depth <= 0.0) return load;
    const double depth_rate = -relative.dot(c.normal);
    load.normal = std::max(law.stiffness * std::pow(depth, law.exponent) + Damping(depth) * depth_rate, 0.0);
    if (spin_states_) load.friction = FrictionCoefficient(load.slip, scene_.friction) * load.normal;
    return load;
  }

  double Damping(double depth) const {
    const engine::ContactLaw& law = scene_.contact;
    return Step(depth, 0.0, 0.0, law.full_damping_penetration, law.max_damping);
  }

  // A massless spring roller moves so that spring, contact stiffness and contact damping
  // balance along its axis a: preload - k_s s = F_n (n . a) - F_t (t . a). Given the
  // friction coefficient, that fixes F_n, and F_n = k delta^e + c (delta'_0 + v (n . a))
  // fixes the travel rate v in closed form. Friction depends on v only through the slip's
  // share along the axis (t . a, zero for a roller on a round bore), so a fixed point on
  // mu converges in a couple of passes. Invalid when the contact carries no damping there
  // or pulls: no rate balances it.
  ContactLoad MasslessTravelRate(const engine::Roller& roller, double travel, double depth,
                                 const Eigen::Vector2d& relative, const engine::Contact& c, const Eigen::Vector2d& axis,
                                 double& rate) const {
    const double damping = Damping(depth);
    const double along_normal = axis.dot(c.normal);
    const double along_tangent = axis.dot(c.tangent);
    if (!(depth > 0.0) || !(damping * along_normal > 0.0)) return {.valid = false};
    const double wanted = roller.spring.preload - roller.spring.stiffness * travel;
    const engine::ContactLaw& law = scene_.contact;
    const double elastic = law.stiffness * std::pow(depth, law.exponent);
    const double depth_rate_at_rest = -relative.dot(c.normal);
    ContactLoad load;
    double mu = 0.0;
    for (int pass = 0; pass < 8; ++pass) {
      const double normal = wanted / (along_normal - mu * along_tangent);
      const double next = ((normal - elastic) / damping - depth_rate_at_rest) / along_normal;
      const bool settled = std::abs(next - rate) <= 1e-14 * std::max(1.0, std::abs(next));
      rate = next;
      load = Load(depth, relative - rate * axis, c);
      if (!spin_states_ || settled) break;
      mu = FrictionCoefficient(load.slip, scene_.friction);
    }
    load.valid = load.normal > 0.0;
    return load;
  }

  // [m] Travel at which spring roller i, at rest against the centred ring at psi = 0,
  // pushes with exactly its contact's elastic force: preload - k_s s = k delta(s)^e (n . a).
  // Newton on s; the contact search gives delta(s) and n exactly.
  double BalancedTravel(int i) const {
    const auto k = static_cast<std::size_t>(i);
    const engine::Roller& roller = scene_.rollers[k];
    const engine::ContactLaw& law = scene_.contact;
    const engine::BodyPose ring{Eigen::Vector2d::Zero(), 0.0};
    const double spin = engine::RollerBodyAngle(scene_, i, 0.0);
    double travel = 0.0;
    for (int iteration = 0; iteration < 50; ++iteration) {
      const engine::Contact c =
          engine::FindContact(scene_.ring.inner, ring, roller.outline, {centres_[k] + travel * axes_[k], spin});
      const double depth = std::max(-c.gap, 0.0);
      const double along = axes_[k].dot(c.normal);
      const double residual = roller.spring.preload - roller.spring.stiffness * travel -
                              law.stiffness * std::pow(depth, law.exponent) * along;
      // d(residual)/ds: the spring, and the contact stiffening as the roller digs in
      // (d delta / ds = n . a); beyond the bore, only the spring until delta > 0.
      const double slope = -roller.spring.stiffness -
                           (depth > 0.0 ? law.stiffness * law.exponent * std::pow(depth, law.exponent - 1.0) * along * along : 0.0);
      double step = -residual / slope;
      if (depth == 0.0) step = c.gap / along + 1e-9;  // reach the bore first
      travel += step;
      if (std::abs(step) < 1e-15) break;
    }
    return travel;
  }

  const Scene& scene_;
  const DynamicOptions& options_;
  std::optional<Equilibrium> start_;  // the quasistatic start, once FindStart found it
  engine::DynamicModel model_;
  bool spin_states_;
  int size_ = 0;
  std::vector<Eigen::Vector2d> centres_;  // [m] roller centres at zero travel, errors included
  std::vector<Eigen::Vector2d> axes_;
  std::vector<int> travel_;  // index of roller i's travel in y, or -1
  std::vector<int> spin_;    // index of roller i's spin angle in y, or -1
  // Warm starts of the contact searches: the answer does not depend on them.
  std::vector<engine::ContactGuess> guesses_;
  std::vector<bool> have_guess_;
  // What the Jacobian needs of each contact at the last evaluation.
  struct Touching {
    Eigen::Vector2d normal = Eigen::Vector2d::UnitX();
    Eigen::Vector2d tangent = Eigen::Vector2d::UnitY();
    Eigen::Vector2d relative = Eigen::Vector2d::Zero();  // [m/s] ring point minus roller point
    Eigen::Vector2d motion = Eigen::Vector2d::Zero();    // [m/s] ring velocity minus roller translation
    double depth = 0.0;                                  // [m]
    double normal_angle = 0.0;                           // [rad] phi
    double ring_theta = 0.0;                             // [rad] warm starts of the support searches
    double roller_theta = 0.0;                           // [rad]
    double gap_curvature = 0.0;                          // [m] g''(phi)
    double psi = 0.0;                                    // [rad] ring angle
    double ring_rate = 0.0;                              // [rad/s]
  };
  std::vector<Touching> touching_;
  std::vector<double> depth_;  // [m] penetration per roller
  double evaluated_at_ = std::numeric_limits<double>::quiet_NaN();  // [s] time of the last evaluation
  // Per roller at the last evaluation, for Sample.
  std::vector<double> normal_force_;    // [N]
  std::vector<double> friction_force_;  // [N]
  std::vector<double> slip_;            // [m/s]
  std::vector<double> spin_angle_;      // [rad]
  std::vector<double> spin_rate_;       // [rad/s]
  std::vector<double> travel_rate_;     // [m/s]
  std::size_t segment_ = 0;
  std::string failure_;
};

// Advances the dynamics through the motion law's breakpoints with the chosen method:
// CVODE (variable-order BDF, dense direct linear solver, analytic Jacobian) or ARKODE's
// explicit Runge-Kutta (ERKStep, 4th order, fixed step). Owns every SUNDIALS object it
// creates.
class Integrator {
 public:
  Integrator(RingDynamics& dynamics, const engine::MotionLaw& law, const DynamicOptions& options)
      : dynamics_(dynamics), law_(law), breakpoints_(law.Breakpoints()),
        explicit_(options.method == DynamicMethod::kExplicitRungeKutta) {
    SUNContext_Create(nullptr, &context_);
    const auto n = static_cast<sunindextype>(dynamics.size());
    y_ = N_VNew_Serial(n, context_);
    dynamics.InitialState(N_VGetArrayPointer(y_));
    if (explicit_) {
      erk_ = ERKStepCreate(&Rhs, 0.0, y_, context_);
      ok_ = erk_ != nullptr && ERKStepSetTableNum(erk_, ARKODE_ZONNEVELD_5_3_4) == ARK_SUCCESS &&
            ERKStepSetFixedStep(erk_, options.explicit_step) == ARK_SUCCESS &&
            ERKStepSetUserData(erk_, this) == ARK_SUCCESS &&
            ERKStepSetMaxNumSteps(erk_, -1) == ARK_SUCCESS &&
            ERKStepSetErrHandlerFn(erk_, &SilentErrors, nullptr) == ARK_SUCCESS;
    } else {
      tolerance_ = N_VNew_Serial(n, context_);
      dynamics.Tolerances(N_VGetArrayPointer(tolerance_));
      matrix_ = SUNDenseMatrix(n, n, context_);
      linear_solver_ = SUNLinSol_Dense(y_, matrix_, context_);
      cvode_ = CVodeCreate(CV_BDF, context_);
      ok_ = cvode_ != nullptr && CVodeInit(cvode_, &Rhs, 0.0, y_) == CV_SUCCESS &&
            CVodeSVtolerances(cvode_, options.relative_tolerance, tolerance_) == CV_SUCCESS &&
            CVodeSetUserData(cvode_, this) == CV_SUCCESS &&
            CVodeSetLinearSolver(cvode_, linear_solver_, matrix_) == CV_SUCCESS &&
            (options.difference_quotient_jacobian || CVodeSetJacFn(cvode_, &Jacobian) == CV_SUCCESS) &&
            CVodeSetMaxNumSteps(cvode_, options.max_steps) == CV_SUCCESS &&
            CVodeSetErrHandlerFn(cvode_, &SilentErrors, nullptr) == CV_SUCCESS;
    }
    if (!ok_) {
      status_ = Status::kIntegrationFailed;
      message_ = explicit_ ? "ARKODE could not be set up" : "CVODE could not be set up";
    }
  }

  ~Integrator() {
    ERKStepFree(&erk_);
    CVodeFree(&cvode_);
    SUNLinSolFree(linear_solver_);
    SUNMatDestroy(matrix_);
    N_VDestroy(tolerance_);
    N_VDestroy(y_);
    SUNContext_Free(&context_);
  }

  Integrator(const Integrator&) = delete;
  Integrator& operator=(const Integrator&) = delete;

  double time() const { return t_; }
  const double* state() const { return N_VGetArrayPointer(y_); }
  const std::string& message() const { return message_; }
  Status status() const { return status_; }
  // Integrator steps since the start, over every restart.
  long steps() const { return steps_before_restart_ + CurrentSteps(); }

  // From now on, stop at every moment a contact opens (its penetration falls through
  // zero) and record it in openings(): a separation between two samples is still found.
  // BDF only; the explicit baseline sees contacts at its samples.
  void WatchSeparations() {
    if (explicit_ || !ok_) return;
    watching_ = CVodeRootInit(cvode_, dynamics_.rollers(), &SeparationEvent) == CV_SUCCESS;
    if (watching_) {
      std::vector<int> falling(static_cast<std::size_t>(dynamics_.rollers()), -1);
      CVodeSetRootDirection(cvode_, falling.data());
      // A contact unloading onto zero exactly at a restart is no event.
      CVodeSetNoInactiveRootWarn(cvode_);
    }
  }

  struct Opening {
    double time = 0.0;  // [s]
    int roller = 0;
    std::vector<double> depth;  // [m] every roller's penetration then, the opening one's 0
  };
  const std::vector<Opening>& openings() const { return openings_; }

  // Advances to t_out (>= time()), restarting at each breakpoint of the law on the way,
  // where the right-hand side jumps. False, with status() and message(), on failure.
  bool AdvanceTo(double t_out) {
    if (!ok_) return false;
    while (t_ < t_out) {
      // Steps run freely past output times (the integrator interpolates there) but end
      // exactly on the next breakpoint, where the integration restarts.
      const auto next = std::upper_bound(breakpoints_.begin(), breakpoints_.end(), t_);
      const double breakpoint = next == breakpoints_.end() ? std::numeric_limits<double>::max() : *next;
      const double target = std::min(t_out, breakpoint);
      dynamics_.set_segment(law_.SegmentAt(t_));
      double reached = t_;
      int flag = 0;
      if (explicit_) {
        ERKStepSetStopTime(erk_, breakpoint);
        flag = ERKStepEvolve(erk_, target, y_, &reached, ARK_NORMAL);
      } else {
        CVodeSetStopTime(cvode_, breakpoint);
        flag = CVode(cvode_, target, y_, &reached, CV_NORMAL);
      }
      if (flag == CV_ROOT_RETURN) {
        std::vector<int> found(static_cast<std::size_t>(dynamics_.rollers()));
        CVodeGetRootInfo(cvode_, found.data());
        std::vector<double> depth(found.size());
        if (const int depth_flag = dynamics_.Separation(reached, state(), depth.data()); depth_flag != 0) {
          depth.assign(found.size(), 0.0);  // unknown: every contact counts as open
        }
        for (std::size_t i = 0; i < found.size(); ++i) {
          if (found[i] != 0) depth[i] = 0.0;
        }
        for (int i = 0; i < dynamics_.rollers(); ++i) {
          if (found[static_cast<std::size_t>(i)] != 0) openings_.push_back({reached, i, depth});
        }
        t_ = reached;
        continue;
      }
      if (flag < 0) {
        ok_ = false;
        status_ = Status::kIntegrationFailed;
        message_ = explicit_ ? "ARKODE stopped with " + FlagName(ERKStepGetReturnFlagName(flag))
                             : "CVODE stopped with " + FlagName(CVodeGetReturnFlagName(flag));
        message_ += " at t = " + Seconds(reached);
        if (!dynamics_.failure().empty()) message_ += ": " + dynamics_.failure();
        if (!explicit_ && flag == CV_TOO_MUCH_WORK) {
          message_ += " (the step budget between two outputs ran out: a stiff switch such as stiction with a tiny "
                      "transition velocity; rolling_without_slip removes it)";
        }
        return false;
      }
      t_ = reached;
      const double* y = state();
      for (int j = 0; j < dynamics_.size(); ++j) {
        if (!std::isfinite(y[j])) {
          ok_ = false;
          status_ = Status::kNonFinite;
          message_ = "the state turned non-finite at t = " + Seconds(t_);
          return false;
        }
      }
      if (t_ >= breakpoint) {
        t_ = breakpoint;
        steps_before_restart_ += CurrentSteps();
        if (explicit_) {
          ERKStepReInit(erk_, &Rhs, t_, y_);
        } else {
          CVodeReInit(cvode_, t_, y_);
        }
      }
    }
    return true;
  }

 private:
  long CurrentSteps() const {
    long count = 0;
    if (explicit_) {
      ERKStepGetNumSteps(erk_, &count);
    } else {
      CVodeGetNumSteps(cvode_, &count);
    }
    return count;
  }

  static int Rhs(sunrealtype t, N_Vector y, N_Vector dydt, void* user_data) {
    auto* self = static_cast<Integrator*>(user_data);
    return self->dynamics_.Derivatives(t, N_VGetArrayPointer(y), N_VGetArrayPointer(dydt));
  }

  static int SeparationEvent(sunrealtype t, N_Vector y, sunrealtype* depth, void* user_data) {
    auto* self = static_cast<Integrator*>(user_data);
    return self->dynamics_.Separation(t, N_VGetArrayPointer(y), depth);
  }

  static int Jacobian(sunrealtype t, N_Vector y, N_Vector, SUNMatrix jacobian, void* user_data, N_Vector, N_Vector,
                      N_Vector) {
    auto* self = static_cast<Integrator*>(user_data);
    SUNMatZero(jacobian);
    return self->dynamics_.Jacobian(t, N_VGetArrayPointer(y), SUNDenseMatrix_Data(jacobian));
  }

  // Failures come back as a Status with the integrator's flag name; its own stderr
  // report would only duplicate that in every campaign log.
  static void SilentErrors(int, const char*, const char*, char*, void*) {}

  RingDynamics& dynamics_;
  const engine::MotionLaw& law_;
  std::vector<double> breakpoints_;
  bool explicit_;
  SUNContext context_ = nullptr;
  N_Vector y_ = nullptr;
  N_Vector tolerance_ = nullptr;
  SUNMatrix matrix_ = nullptr;
  SUNLinearSolver linear_solver_ = nullptr;
  void* cvode_ = nullptr;
  void* erk_ = nullptr;
  double t_ = 0.0;
  long steps_before_restart_ = 0;
  bool watching_ = false;
  std::vector<Opening> openings_;
  bool ok_ = false;
  Status status_ = Status::kOk;
  std::string message_;
};

Equilibrium Record(const DynamicSample& sample) {
  Equilibrium e;
  e.centre = sample.centre;
  e.travel = sample.travel;
  e.contact_force = sample.normal_force;
  return e;
}

// The sample at the integrator's current state: evaluating the dynamics there makes the
// contact loads belong to it.
DynamicSample Observe(RingDynamics& dynamics, const Integrator& integrator) {
  return dynamics.Observe(integrator.time(), integrator.state());
}

// Checks what a dynamic run needs before it starts and finds its start; kOk when it can run.
Status Prepare(const Scene& scene, RingDynamics& dynamics, std::string& message) {
  Status status = CheckSceneGeometry(scene, message);
  if (status != Status::kOk) return status;
  message = dynamics.MissingInertia();
  if (!message.empty()) return Status::kIntegrationFailed;
  if (scene.contact.model != engine::ContactLaw::Model::kPenalty) {
    message = "the dynamic solver needs the penalty contact law";
    return Status::kIntegrationFailed;
  }
  return dynamics.FindStart(message);
}

// Samples revolution `revolution` (0 = the first after rotation starts) of a run already
// at or before its start. The status is kOk, a lift-off or the integrator's failure.
Trajectory SampleRevolution(const Scene& scene, RingDynamics& dynamics, Integrator& integrator, int revolution,
                            int steps) {
  Trajectory trajectory;
  const engine::MotionLaw& law = scene.motion;
  const double start = law.RotationStart();
  // A law that starts clockwise samples the revolution at psi_k = -2 pi k / steps.
  const double sense = law.RateIn(law.SegmentAt(start), start) < 0.0 ? -1.0 : 1.0;
  const double first_angle = sense * 2.0 * std::numbers::pi * revolution;
  const auto z = static_cast<std::size_t>(dynamics.rollers());
  std::size_t watched = integrator.openings().size();  // the openings weighed so far
  for (int k = 0; k <= steps; ++k) {
    const double psi = sense * 2.0 * std::numbers::pi * k / steps;
    const double t = k == 0 && revolution == 0 ? start : law.TimeAtAngle(first_angle + psi, start);
    if (!std::isfinite(t)) {
      trajectory.status = Status::kIntegrationFailed;
      trajectory.message = "the motion law stops before revolution " + std::to_string(revolution + 1) + " ends";
      trajectory.failure_angle = psi;
      return trajectory;
    }
    if (!integrator.AdvanceTo(t)) {
      trajectory.status = integrator.status();
      trajectory.message = integrator.message();
      trajectory.failure_angle = psi;
      return trajectory;
    }
    const DynamicSample sample = Observe(dynamics, integrator);
    // A contact that opens fails the run only where the ring loses the support it needs
    // (solvers/validity.h, RollerLosingSupport); a redundant roller may leave and regain
    // the bore.
    for (; trajectory.status == Status::kOk && watched < integrator.openings().size(); ++watched) {
      const auto& opening = integrator.openings()[watched];
      if (RollerLosingSupport(scene, opening.depth) < 0) continue;
      trajectory.status = Status::kLiftOff;
      trajectory.failure_angle = law.Angle(opening.time) - law.Angle(start) - first_angle;
      trajectory.message = "the contact of roller " + scene.rollers[static_cast<std::size_t>(opening.roller)].name +
                           " opens at t = " + Seconds(opening.time);
    }
    trajectory.psi.push_back(psi);
    trajectory.centre.push_back(sample.centre);
    for (std::size_t i = 0; i < z; ++i) {
      trajectory.travel.push_back(sample.travel[i]);
      trajectory.contact_force.push_back(sample.normal_force[i]);
    }
    if (const int lost = RollerLosingSupport(scene, sample.penetration); trajectory.status == Status::kOk && lost >= 0) {
      trajectory.status = Status::kLiftOff;
      trajectory.failure_angle = psi;
      trajectory.message =
          "roller " + scene.rollers[static_cast<std::size_t>(lost)].name + " separates from the bore at t = " + Seconds(t);
    }
  }
  trajectory.total_iterations = static_cast<int>(integrator.steps());
  return trajectory;
}

// Empty when `step` [s] keeps h |lambda| within the explicit method's stability interval
// on the negative real axis (2.78 for 4th-order Runge-Kutta) for every eigenvalue
// lambda of the Jacobian at (t, y); else why not, with the limit.
std::string ExplicitStepTooLarge(RingDynamics& dynamics, double t, const double* y, double step) {
  constexpr double kStabilityInterval = 2.78;
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(dynamics.size(), dynamics.size());
  if (dynamics.Jacobian(t, y, jacobian.data()) != 0) return {};
  const double largest = jacobian.eigenvalues().cwiseAbs().maxCoeff();
  const double limit = kStabilityInterval / largest;
  if (step <= limit) return {};
  std::ostringstream out;
  out.precision(3);
  out << "the explicit step " << step << " s exceeds the stability limit " << limit
      << " s of this scene (largest |eigenvalue| " << largest << " 1/s at t = " << t << " s)";
  return out.str();
}

// A run integrated to the moment rotation starts, or the reason it could not get there.
struct SettledRun {
  RingDynamics dynamics;
  std::unique_ptr<Integrator> integrator;  // null when status != kOk before integrating
  Status status = Status::kOk;
  std::string message;

  SettledRun(const Scene& scene, const DynamicOptions& options) : dynamics(scene, options) {
    status = Prepare(scene, dynamics, message);
    if (status != Status::kOk) return;
    const double start = scene.motion.RotationStart();
    if (!std::isfinite(start)) {
      status = Status::kIntegrationFailed;
      message = "the motion law never turns the ring";
      return;
    }
    integrator = std::make_unique<Integrator>(dynamics, scene.motion, options);
    const bool is_explicit = options.method == DynamicMethod::kExplicitRungeKutta;
    // An unstable explicit run need not blow up: the contact law's clamp at zero force
    // bounds it into a rattle that looks like lift-off. So the step is checked against
    // the spectrum before the run and again once the assembly has settled.
    if (is_explicit) {
      message = ExplicitStepTooLarge(dynamics, integrator->time(), integrator->state(), options.explicit_step);
      if (!message.empty()) {
        status = Status::kIntegrationFailed;
        return;
      }
    }
    if (!integrator->AdvanceTo(start)) {
      status = integrator->status();
      message = integrator->message();
      if (is_explicit) message += " (an explicit step above the stability limit ends runs this way)";
      return;
    }
    // Settled, with the rollers still and every contact loaded, the spectrum is at its
    // widest (stiction's slope is steepest at zero slip).
    if (is_explicit) {
      message = ExplicitStepTooLarge(dynamics, integrator->time(), integrator->state(), options.explicit_step);
      if (!message.empty()) status = Status::kIntegrationFailed;
    }
  }

};

}  // namespace

bool DynamicOptions::IsValid(InvalidOption* invalid) const {
  return CheckOption("explicit_step", explicit_step, kExplicitStepRange, invalid) &&
         CheckOption("steady_revolution", steady_revolution, kSteadyRevolutionRange, invalid) &&
         CheckOption("relative_tolerance", relative_tolerance, kRelativeToleranceRange, invalid) &&
         CheckOption("max_steps", max_steps, kMaxStepsRange, invalid);
}

Eigen::VectorXd InitialDynamicState(const Scene& scene, const DynamicOptions& options) {
  RingDynamics dynamics(scene, options);
  std::string unused;
  dynamics.FindStart(unused);
  Eigen::VectorXd state(dynamics.size());
  dynamics.InitialState(state.data());
  return state;
}

DynamicsEvaluation EvaluateDynamics(const Scene& scene, double t, const Eigen::VectorXd& state,
                                    const DynamicOptions& options) {
  RingDynamics dynamics(scene, options);
  DynamicsEvaluation evaluation;
  if (state.size() != dynamics.size()) {
    evaluation.status = Status::kIntegrationFailed;
    evaluation.message = "the state has " + std::to_string(state.size()) + " entries, the scene needs " +
                         std::to_string(dynamics.size());
    return evaluation;
  }
  dynamics.set_segment(scene.motion.SegmentAt(t));
  evaluation.rates.resize(dynamics.size());
  evaluation.jacobian = Eigen::MatrixXd::Zero(dynamics.size(), dynamics.size());
  if (dynamics.Jacobian(t, state.data(), evaluation.jacobian.data()) != 0 ||
      dynamics.Derivatives(t, state.data(), evaluation.rates.data()) != 0) {
    evaluation.status = Status::kIntegrationFailed;
    evaluation.message = dynamics.failure();
  }
  return evaluation;
}

Equilibrium DynamicSolver::SolveStatic(const Scene& scene) const {
  SettledRun run(scene, options_);
  Equilibrium result;
  if (run.status != Status::kOk) {
    result.status = run.status;
    result.message = run.message;
    return result;
  }
  result = Record(Observe(run.dynamics, *run.integrator));
  result.iterations = static_cast<int>(run.integrator->steps());
  return result;
}

Trajectory DynamicSolver::SolveRevolution(const Scene& scene, int steps) const {
  SettledRun run(scene, options_);
  if (run.status != Status::kOk) {
    Trajectory failed;
    failed.status = run.status;
    failed.message = run.message;
    return failed;
  }
  RingDynamics& dynamics = run.dynamics;
  Integrator& integrator = *run.integrator;
  const Equilibrium initial = Record(Observe(dynamics, integrator));
  // The article's settle may bounce (the ring falls onto its fixed rollers); from rotation start on,
  // any contact that opens, even between two samples, is weighed against the support rule.
  integrator.WatchSeparations();
  Trajectory trajectory = SampleRevolution(scene, dynamics, integrator, 0, steps);
  trajectory.initial = initial;
  const int later = options_.steady_revolution;
  // A law that stops before the later revolution ends leaves it with that reason as status.
  if (trajectory.status == Status::kOk && later > 0) {
    auto steady = std::make_shared<Trajectory>(SampleRevolution(scene, dynamics, integrator, later, steps));
    steady->initial = initial;
    trajectory.total_iterations = steady->total_iterations;
    trajectory.steady = std::move(steady);
  }
  return trajectory;
}

DynamicHistory DynamicSolver::SolveHistory(const Scene& scene, double interval, double duration) const {
  DynamicHistory history;
  RingDynamics dynamics(scene, options_);
  history.status = Prepare(scene, dynamics, history.message);
  if (history.status != Status::kOk) return history;
  Integrator integrator(dynamics, scene.motion, options_);
  if (options_.method == DynamicMethod::kExplicitRungeKutta) {
    history.message = ExplicitStepTooLarge(dynamics, 0.0, integrator.state(), options_.explicit_step);
    if (!history.message.empty()) {
      history.status = Status::kIntegrationFailed;
      return history;
    }
  }
  const auto count = static_cast<long>(std::floor(duration / interval + 1e-9));
  for (long k = 0; k <= count; ++k) {
    if (!integrator.AdvanceTo(static_cast<double>(k) * interval)) {
      history.status = integrator.status();
      history.message = integrator.message();
      return history;
    }
    history.samples.push_back(Observe(dynamics, integrator));
  }
  return history;
}

}  // namespace ringtol::solvers
