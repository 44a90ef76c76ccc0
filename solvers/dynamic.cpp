#include "solvers/dynamic.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include "engine/contact.h"

namespace ringtol::solvers {
namespace {

using engine::Scene;

// Adams' STEP: h0 + (h1 - h0) a^2 (3 - 2 a), a = (x - x0) / (x1 - x0) clamped to [0, 1].
double Step(double x, double x0, double h0, double x1, double h1) {
  const double a = std::clamp((x - x0) / (x1 - x0), 0.0, 1.0);
  return h0 + (h1 - h0) * a * a * (3.0 - 2.0 * a);
}

// mu(v) of model.md §4: 0 at rest, mu_s at v_s, mu_d from v_d on, odd in v.
double FrictionCoefficient(double v, const engine::Friction& f) {
  const double speed = std::abs(v);
  const double mu = speed < f.stiction_velocity
                        ? Step(speed, 0.0, 0.0, f.stiction_velocity, f.static_coefficient)
                        : Step(speed, f.stiction_velocity, f.static_coefficient, f.transition_velocity,
                               f.dynamic_coefficient);
  return std::copysign(mu, v);
}

std::string Seconds(double t) {
  std::ostringstream out;
  out.precision(6);
  out << t << " s";
  return out.str();
}

// The equations of motion. State y = [centre (2) [m]; centre velocity (2) [m/s];
// per spring roller: travel [m], travel rate [m/s]; per roller with spin dynamics:
// spin angle [rad], spin rate [rad/s]].
class RingDynamics {
 public:
  RingDynamics(const Scene& scene, const DynamicOptions& options)
      : scene_(scene), options_(options), spin_states_(options.friction && !options.rolling_without_slip) {
    const int z = rollers();
    int next = 4;
    for (int i = 0; i < z; ++i) {
      const engine::Roller& roller = scene.rollers[static_cast<std::size_t>(i)];
      centres_.push_back(engine::RollerCentre(scene, i));
      axes_.push_back(engine::SpringAxis(scene, i));
      travel_.push_back(roller.mount == engine::RollerMount::kSpring ? next : -1);
      if (roller.mount == engine::RollerMount::kSpring) next += 2;
    }
    for (int i = 0; i < z; ++i) {
      spin_.push_back(spin_states_ ? next : -1);
      if (spin_states_) next += 2;
    }
    size_ = next;
    guesses_.resize(static_cast<std::size_t>(z));
    have_guess_.assign(static_cast<std::size_t>(z), false);
    normal_force_.assign(static_cast<std::size_t>(z), 0.0);
  }

  int rollers() const { return static_cast<int>(scene_.rollers.size()); }
  int size() const { return size_; }
  int travel_index(int i) const { return travel_[static_cast<std::size_t>(i)]; }
  const std::vector<double>& normal_force() const { return normal_force_; }
  const std::string& failure() const { return failure_; }

  // The motion-law segment whose polynomial Derivatives uses, whatever t it is given: an
  // integration step that ends on a breakpoint must not see the next segment's rate.
  void set_segment(std::size_t segment) { segment_ = segment; }

  // What the scene must give for its bodies to have dynamics; empty when it does.
  std::string MissingInertia() const {
    if (!(scene_.ring.mass > 0.0)) return "the ring needs a positive mass";
    for (int i = 0; i < rollers(); ++i) {
      const engine::Roller& roller = scene_.rollers[static_cast<std::size_t>(i)];
      if (travel_index(i) >= 0 && !(roller.mass > 0.0)) return "spring roller " + roller.name + " needs a positive mass";
      if (spin_[static_cast<std::size_t>(i)] >= 0 && !(roller.spin_inertia > 0.0)) {
        return "roller " + roller.name + " needs a positive spin inertia (or rolling_without_slip)";
      }
    }
    return {};
  }

  void InitialState(double* y) const {
    std::fill(y, y + size_, 0.0);
    for (int i = 0; i < rollers(); ++i) {
      if (spin_[static_cast<std::size_t>(i)] >= 0) y[spin_[static_cast<std::size_t>(i)]] = engine::RollerBodyAngle(scene_, i, 0.0);
    }
  }

  // dy/dt at (t, y). Returns 0, or 1 (recoverable: CVODE retries with a smaller step) when
  // a contact search fails or a roller sinks deeper than half its radius, with the reason
  // in failure().
  int Derivatives(double t, const double* y, double* dydt) {
    const MotionLaw& law = options_.law;
    const double psi = law.AngleIn(segment_, t);
    const double ring_rate = law.RateIn(segment_, t);
    const Eigen::Vector2d centre(y[0], y[1]);
    const Eigen::Vector2d velocity(y[2], y[3]);
    Eigen::Vector2d ring_force = Eigen::Vector2d::Zero();
    std::fill(dydt, dydt + size_, 0.0);
    dydt[0] = y[2];
    dydt[1] = y[3];
    const engine::ContactLaw& contact_law = scene_.contact;
    for (int i = 0; i < rollers(); ++i) {
      const auto k = static_cast<std::size_t>(i);
      const engine::Roller& roller = scene_.rollers[k];
      const int s = travel_[k];
      const int b = spin_[k];
      Eigen::Vector2d roller_centre = centres_[k];
      Eigen::Vector2d roller_velocity = Eigen::Vector2d::Zero();
      if (s >= 0) {
        roller_centre += y[s] * axes_[k];
        roller_velocity = y[s + 1] * axes_[k];
      }
      double spin_angle = 0.0;
      double spin_rate = 0.0;
      if (b >= 0) {
        spin_angle = y[b];
        spin_rate = y[b + 1];
      } else if (options_.rolling_without_slip) {
        spin_angle = engine::RollerBodyAngle(scene_, i, psi);
        spin_rate = engine::SpinRatio(scene_, i) * ring_rate;
      } else {
        spin_angle = engine::RollerBodyAngle(scene_, i, 0.0);
      }
      const engine::BodyPose ring_pose{centre, psi};
      const engine::BodyPose roller_pose{roller_centre, spin_angle};
      const engine::Contact c = engine::FindContact(scene_.ring.inner, ring_pose, roller.outline, roller_pose,
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
        failure_ = "roller " + roller.name + " sinks " + std::to_string(depth * 1e3) + " mm into the bore at t = " +
                   Seconds(t);
        return 1;
      }
      // Velocities of the two touching material points; their difference along the
      // normal is the gap rate, along the tangent the slip.
      const Eigen::Vector2d across_ring = c.ring_point - centre;
      const Eigen::Vector2d across_roller = c.roller_point - roller_centre;
      const Eigen::Vector2d ring_point_velocity = velocity + ring_rate * Eigen::Vector2d(-across_ring.y(), across_ring.x());
      const Eigen::Vector2d roller_point_velocity =
          roller_velocity + spin_rate * Eigen::Vector2d(-across_roller.y(), across_roller.x());
      const Eigen::Vector2d relative = ring_point_velocity - roller_point_velocity;
      double normal = 0.0;
      if (depth > 0.0) {
        const double depth_rate = -relative.dot(c.normal);
        const double elastic = contact_law.stiffness * std::pow(depth, contact_law.exponent);
        const double damping = Step(depth, 0.0, 0.0, contact_law.full_damping_penetration, contact_law.max_damping);
        normal = std::max(elastic + damping * depth_rate, 0.0);
      }
      normal_force_[k] = normal;
      const double slip = relative.dot(c.tangent);
      const double tangential =
          options_.friction && !options_.rolling_without_slip ? FrictionCoefficient(slip, scene_.friction) * normal : 0.0;
      // On the ring: pushed outward along n, dragged against the slip. On the roller: the
      // reaction.
      const Eigen::Vector2d on_ring = normal * c.normal - tangential * c.tangent;
      ring_force += on_ring;
      if (s >= 0) {
        const engine::Spring& spring = roller.spring;
        dydt[s] = y[s + 1];
        dydt[s + 1] = (spring.preload - spring.stiffness * y[s] - on_ring.dot(axes_[k])) / roller.mass;
      }
      if (b >= 0) {
        const Eigen::Vector2d on_roller = -on_ring;
        dydt[b] = y[b + 1];
        dydt[b + 1] = (across_roller.x() * on_roller.y() - across_roller.y() * on_roller.x()) / roller.spin_inertia;
      }
    }
    dydt[2] = ring_force.x() / scene_.ring.mass;
    dydt[3] = ring_force.y() / scene_.ring.mass;
    return 0;
  }

  // Absolute tolerance of each state.
  void Tolerances(double* tolerance) const {
    for (int j = 0; j < 4; ++j) tolerance[j] = j < 2 ? options_.position_tolerance : options_.velocity_tolerance;
    for (int i = 0; i < rollers(); ++i) {
      const auto k = static_cast<std::size_t>(i);
      if (travel_[k] >= 0) {
        tolerance[travel_[k]] = options_.position_tolerance;
        tolerance[travel_[k] + 1] = options_.velocity_tolerance;
      }
      if (spin_[k] >= 0) {
        tolerance[spin_[k]] = options_.angle_tolerance;
        tolerance[spin_[k] + 1] = options_.spin_rate_tolerance;
      }
    }
  }

 private:
  const Scene& scene_;
  const DynamicOptions& options_;
  bool spin_states_;
  int size_ = 0;
  std::vector<Eigen::Vector2d> centres_;  // [m] roller centres at zero travel, errors included
  std::vector<Eigen::Vector2d> axes_;
  std::vector<int> travel_;  // index of roller i's travel in y, or -1
  std::vector<int> spin_;    // index of roller i's spin angle in y, or -1
  // Warm starts of the contact searches: the answer does not depend on them.
  std::vector<engine::ContactGuess> guesses_;
  std::vector<bool> have_guess_;
  std::vector<double> normal_force_;  // [N] at the last evaluation
  std::size_t segment_ = 0;
  std::string failure_;
};

// CVODE (BDF, dense direct linear solver, difference-quotient Jacobian) advancing the
// dynamics through the motion law's breakpoints. Owns every SUNDIALS object it creates.
class Integrator {
 public:
  Integrator(RingDynamics& dynamics, const DynamicOptions& options)
      : dynamics_(dynamics), options_(options), breakpoints_(options.law.Breakpoints()) {
    SUNContext_Create(nullptr, &context_);
    const auto n = static_cast<sunindextype>(dynamics.size());
    y_ = N_VNew_Serial(n, context_);
    tolerance_ = N_VNew_Serial(n, context_);
    dynamics.InitialState(N_VGetArrayPointer(y_));
    dynamics.Tolerances(N_VGetArrayPointer(tolerance_));
    matrix_ = SUNDenseMatrix(n, n, context_);
    linear_solver_ = SUNLinSol_Dense(y_, matrix_, context_);
    cvode_ = CVodeCreate(CV_BDF, context_);
    ok_ = cvode_ != nullptr && CVodeInit(cvode_, &Rhs, 0.0, y_) == CV_SUCCESS &&
          CVodeSVtolerances(cvode_, options.relative_tolerance, tolerance_) == CV_SUCCESS &&
          CVodeSetUserData(cvode_, this) == CV_SUCCESS &&
          CVodeSetLinearSolver(cvode_, linear_solver_, matrix_) == CV_SUCCESS &&
          CVodeSetMaxNumSteps(cvode_, options.max_steps) == CV_SUCCESS &&
          CVodeSetErrHandlerFn(cvode_, &SilentErrors, nullptr) == CV_SUCCESS;
    if (!ok_) message_ = "CVODE could not be set up";
  }

  ~Integrator() {
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

  // Advances to t_out (>= time()), restarting at each breakpoint of the law on the way,
  // where the right-hand side jumps. False, with status() and message(), on failure.
  bool AdvanceTo(double t_out) {
    if (!ok_) return false;
    while (t_ < t_out) {
      // Steps run freely past output times (CVODE interpolates there) but end exactly on
      // the next breakpoint, where the integration restarts.
      const auto next = std::upper_bound(breakpoints_.begin(), breakpoints_.end(), t_);
      const double breakpoint = next == breakpoints_.end() ? std::numeric_limits<double>::max() : *next;
      const double target = std::min(t_out, breakpoint);
      dynamics_.set_segment(options_.law.SegmentAt(t_));
      CVodeSetStopTime(cvode_, breakpoint);
      double reached = t_;
      const int flag = CVode(cvode_, target, y_, &reached, CV_NORMAL);
      if (flag < 0) {
        ok_ = false;
        status_ = Status::kIntegrationFailed;
        message_ = std::string("CVODE stopped with ") + CVodeGetReturnFlagName(flag) + " at t = " + Seconds(reached);
        if (!dynamics_.failure().empty()) message_ += ": " + dynamics_.failure();
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
        CVodeReInit(cvode_, t_, y_);
      }
    }
    return true;
  }


 private:
  long CurrentSteps() const {
    long count = 0;
    CVodeGetNumSteps(cvode_, &count);
    return count;
  }

  static int Rhs(sunrealtype t, N_Vector y, N_Vector dydt, void* user_data) {
    auto* self = static_cast<Integrator*>(user_data);
    return self->dynamics_.Derivatives(t, N_VGetArrayPointer(y), N_VGetArrayPointer(dydt));
  }

  // Failures come back as a Status with CVODE's flag name; its own stderr report would
  // only duplicate that in every campaign log.
  static void SilentErrors(int, const char*, const char*, char*, void*) {}

  RingDynamics& dynamics_;
  const DynamicOptions& options_;
  std::vector<double> breakpoints_;
  SUNContext context_ = nullptr;
  N_Vector y_ = nullptr;
  N_Vector tolerance_ = nullptr;
  SUNMatrix matrix_ = nullptr;
  SUNLinearSolver linear_solver_ = nullptr;
  void* cvode_ = nullptr;
  double t_ = 0.0;
  long steps_before_restart_ = 0;
  bool ok_ = false;
  Status status_ = Status::kOk;
  std::string message_;
};

Equilibrium Record(const RingDynamics& dynamics, const double* y) {
  Equilibrium e;
  e.centre = Eigen::Vector2d(y[0], y[1]);
  for (int i = 0; i < dynamics.rollers(); ++i) {
    const int s = dynamics.travel_index(i);
    e.travel.push_back(s >= 0 ? y[s] : 0.0);
    e.contact_force.push_back(dynamics.normal_force()[static_cast<std::size_t>(i)]);
  }
  return e;
}

// Evaluates the dynamics at the integrator's current state so that the recorded contact
// forces belong to it.
void Refresh(RingDynamics& dynamics, const Integrator& integrator) {
  std::vector<double> scratch(static_cast<std::size_t>(dynamics.size()));
  dynamics.Derivatives(integrator.time(), integrator.state(), scratch.data());
}

// Checks what a dynamic run needs before it starts; kOk when it can run.
Status Prepare(const Scene& scene, const RingDynamics& dynamics, const MotionLaw& law, std::string& message) {
  Status status = CheckSceneGeometry(scene, message);
  if (status != Status::kOk) return status;
  message = dynamics.MissingInertia();
  if (!message.empty()) return Status::kIntegrationFailed;
  if (!std::isfinite(law.RotationStart())) {
    message = "the motion law never turns the ring";
    return Status::kIntegrationFailed;
  }
  if (scene.contact.model != engine::ContactLaw::Model::kPenalty) {
    message = "the dynamic solver needs the penalty contact law";
    return Status::kIntegrationFailed;
  }
  return Status::kOk;
}

}  // namespace

Equilibrium DynamicSolver::SolveStatic(const Scene& scene) const {
  Equilibrium result;
  RingDynamics dynamics(scene, options_);
  result.status = Prepare(scene, dynamics, options_.law, result.message);
  if (result.status != Status::kOk) return result;
  Integrator integrator(dynamics, options_);
  if (!integrator.AdvanceTo(options_.law.RotationStart())) {
    result.status = integrator.status();
    result.message = integrator.message();
    return result;
  }
  Refresh(dynamics, integrator);
  result = Record(dynamics, integrator.state());
  result.iterations = static_cast<int>(integrator.steps());
  return result;
}

Trajectory DynamicSolver::SolveRevolution(const Scene& scene, int steps) const {
  Trajectory trajectory;
  RingDynamics dynamics(scene, options_);
  trajectory.status = Prepare(scene, dynamics, options_.law, trajectory.message);
  if (trajectory.status != Status::kOk) return trajectory;
  const MotionLaw& law = options_.law;
  const double start = law.RotationStart();
  Integrator integrator(dynamics, options_);
  auto fail = [&](double psi) {
    trajectory.status = integrator.status();
    trajectory.message = integrator.message();
    trajectory.failure_angle = psi;
    return trajectory;
  };
  if (!integrator.AdvanceTo(start)) return fail(0.0);
  Refresh(dynamics, integrator);
  trajectory.initial = Record(dynamics, integrator.state());
  const double first_angle = 2.0 * std::numbers::pi * options_.revolution;
  const int z = dynamics.rollers();
  for (int k = 0; k <= steps; ++k) {
    const double psi = 2.0 * std::numbers::pi * k / steps;
    const double t = k == 0 && options_.revolution == 0 ? start : law.TimeAtAngle(first_angle + psi, start);
    if (!std::isfinite(t)) {
      trajectory.status = Status::kIntegrationFailed;
      trajectory.message = "the motion law stops before the revolution ends";
      trajectory.failure_angle = psi;
      return trajectory;
    }
    if (!integrator.AdvanceTo(t)) return fail(psi);
    Refresh(dynamics, integrator);
    const Equilibrium sample = Record(dynamics, integrator.state());
    trajectory.psi.push_back(psi);
    trajectory.centre.push_back(sample.centre);
    for (int i = 0; i < z; ++i) {
      const double force = sample.contact_force[static_cast<std::size_t>(i)];
      trajectory.travel.push_back(sample.travel[static_cast<std::size_t>(i)]);
      trajectory.contact_force.push_back(force);
      if (trajectory.status == Status::kOk && force <= 0.0) {
        trajectory.status = Status::kLiftOff;
        trajectory.failure_angle = psi;
        trajectory.message = "roller " + scene.rollers[static_cast<std::size_t>(i)].name + " separates from the bore at t = " +
                             Seconds(t);
      }
    }
  }
  trajectory.total_iterations = static_cast<int>(integrator.steps());
  return trajectory;
}

}  // namespace ringtol::solvers
