#include "solvers/quasistatic.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <span>
#include <type_traits>

#include <Eigen/LU>
#include <Eigen/QR>

#include "solvers/validity.h"

namespace ringtol::solvers {
namespace {

using engine::Scene;

struct NewtonOutcome {
  bool converged = false;
  int iterations = 0;
};

// Newton's method with a backtracking line search on the residual norm; with `damped` it
// also regularises singular steps (Levenberg), which the static solve needs when a
// penalty contact starts out open and carries no stiffness.
NewtonOutcome Newton(const EquilibriumSystem& system, double psi, Eigen::VectorXd& x,
                     std::vector<TrackedContact>& contacts, const Eigen::VectorXd& tolerance, int max_iterations,
                     bool damped) {
  // Residuals below this are round-off [N]: the line search accepts any step there.
  constexpr double kResidualFloor = 1e-9;
  constexpr int kMaxHalvings = 30;
  NewtonOutcome outcome;
  if (system.UpdateContacts(psi, x, contacts) >= 0) return outcome;
  Eigen::VectorXd residual;
  Eigen::MatrixXd jacobian;
  system.Evaluate(x, contacts, residual, &jacobian);
  Eigen::VectorXd trial_residual;
  Eigen::MatrixXd trial_jacobian;
  std::vector<TrackedContact> trial_contacts;
  double damping = 0.0;
  for (int iteration = 1; iteration <= max_iterations; ++iteration) {
    outcome.iterations = iteration;
    Eigen::MatrixXd system_matrix = jacobian;
    if (damping > 0.0) system_matrix.diagonal().array() -= damping;
    const Eigen::VectorXd step = system_matrix.partialPivLu().solve(-residual);
    if (!step.allFinite()) {
      if (!damped) return outcome;
      damping = std::max(10.0 * damping, 1e-6 * jacobian.cwiseAbs().maxCoeff() + 1e-3);
      continue;
    }
    if ((step.cwiseAbs().array() <= tolerance.array()).all()) {
      x += step;
      outcome.converged = true;
      return outcome;
    }
    double alpha = 1.0;
    bool accepted = false;
    for (int halving = 0; halving < kMaxHalvings && !accepted; ++halving, alpha *= 0.5) {
      const Eigen::VectorXd candidate = x + alpha * step;
      trial_contacts = contacts;
      if (system.UpdateContacts(psi, candidate, trial_contacts) >= 0) continue;
      system.Evaluate(candidate, trial_contacts, trial_residual, &trial_jacobian);
      if (trial_residual.norm() <= (1.0 - 1e-4 * alpha) * residual.norm() || residual.norm() <= kResidualFloor) {
        x = candidate;
        contacts.swap(trial_contacts);
        residual.swap(trial_residual);
        jacobian.swap(trial_jacobian);
        accepted = true;
      }
    }
    if (!accepted) {
      if (!damped) return outcome;
      damping = std::max(10.0 * damping, 1e-6 * jacobian.cwiseAbs().maxCoeff() + 1e-3);
    } else {
      damping *= 0.1;
    }
  }
  return outcome;
}

// Polynomial extrapolation of the converged states (unknowns and touching angles) at the
// last few equally spaced angles to the next: with degree d its error is O(dpsi^(d+1)).
// Newton's first update is about that error e, its second about K e^2 (K ~ 4e3 /m for
// the article's penalty contacts): at 720 steps degree 2 leaves e ~ 3e-8 m and needs a
// second iteration, degree 4 leaves e ~ 1e-10 m and one suffices. Higher degrees gain
// little more and amplify round-off by sum |binomial| = 2^(d+1) - 1.
class Predictor {
 public:
  static constexpr int kDegree = 4;
  static constexpr int kDepth = kDegree + 1;

  void Push(const EquilibriumSystem::State& x, const std::vector<TrackedContact>& contacts) {
    const auto unknowns = static_cast<std::size_t>(x.size());
    rows_ = unknowns + contacts.size();
    history_.resize(rows_ * kDepth);
    newest_ = newest_ + 1 == kDepth ? 0 : newest_ + 1;
    double* column = history_.data() + static_cast<std::size_t>(newest_) * rows_;
    for (std::size_t r = 0; r < unknowns; ++r) column[r] = x[static_cast<Eigen::Index>(r)];
    for (std::size_t i = 0; i < contacts.size(); ++i) column[unknowns + i] = contacts[i].contact.ring_theta;
    // Weights (-1)^(j+1) binomial(d+1, j) of the newest j = 1 .. d+1 states: the
    // polynomial of degree d = known - 1 through them, evaluated one step ahead.
    if (known_ < kDepth) {
      ++known_;
      double binomial = 1.0;
      for (int j = 1; j <= known_; ++j) {
        binomial *= static_cast<double>(known_ - j + 1) / j;
        weight_by_age_[static_cast<std::size_t>(j - 1)] = (j % 2 == 1 ? 1.0 : -1.0) * binomial;
      }
    }
  }

  // Overwrites x and each contact's touching angle with the prediction.
  template <typename Vector>
  void Predict(Vector& x, std::vector<TrackedContact>& contacts) const {
    const auto unknowns = static_cast<std::size_t>(x.size());
    std::array<const double*, kDepth> by_age{};
    for (int j = 0, slot = newest_; j < known_; ++j, slot = slot == 0 ? kDepth - 1 : slot - 1) {
      by_age[static_cast<std::size_t>(j)] = history_.data() + static_cast<std::size_t>(slot) * rows_;
    }
    for (std::size_t r = 0; r < rows_; ++r) {
      double prediction = 0.0;
      for (std::size_t j = 0; j < static_cast<std::size_t>(known_); ++j) prediction += weight_by_age_[j] * by_age[j][r];
      if (r < unknowns) {
        x[static_cast<Eigen::Index>(r)] = prediction;
      } else {
        contacts[r - unknowns].contact.ring_theta = prediction;
      }
    }
  }

 private:
  std::size_t rows_ = 0;
  std::vector<double> history_;                 // kDepth columns of rows_ values, a ring buffer
  std::array<double, kDepth> weight_by_age_{};  // of the newest, second newest, ... state
  int newest_ = -1;                             // slot of the newest state
  int known_ = 0;                               // states held
};

// What the continuation iteration has learnt of its own convergence. Newton converges
// quadratically: an update of size e is followed by one of about K e^2. Where the
// prediction is good, K e^2 is far below the tolerance after the first update, and the
// iteration that would only confirm it (half the cost of an angle) can be skipped.
struct ConvergenceModel {
  // Largest K observed [1/m]: the ratio of a second update to the square of the first,
  // at angles that ran a second iteration. Zero until the first observation.
  double constant = 0.0;
  int angles_since_check = 0;
};

// Trust in the model: accept one update only when K e^2 times this is within tolerance,
// and run the confirming iteration anyway at every kCheckInterval-th angle so a K that
// grows along the revolution (a contact unloading, a tighter bore) is noticed.
constexpr double kConvergenceSafety = 4.0;
constexpr int kCheckInterval = 16;

// Newton's method for one angle of a revolution, started from a good prediction: each
// iteration steps the contact searches and the force balance together
// (EquilibriumSystem::ContinuationUpdate), so an iteration costs one bore evaluation per
// contact. Converged when the last update (or the update the convergence model predicts
// next) is within tolerance. Returns false (leaving x and the contacts unusable) when it
// does not converge; the caller then falls back to Newton().
template <int N>
bool ContinuationNewton(const EquilibriumSystem& system, const RingTurn& turn, Eigen::Matrix<double, N, 1>& x,
                        std::vector<TrackedContact>& contacts, const Eigen::Matrix<double, N, 1>& tolerance,
                        int max_iterations, ConvergenceModel& model, int& iterations) {
  // Updates are compared as lengths: each unknown and the normal angles by its tolerance.
  const double length = tolerance[0];
  // Contact normals within this of the common normal: the gap is then exact to
  // g'' dphi^2 / 2 and the force direction to dphi, which moves the centre by about
  // dphi F / k_contact (~1e-4 m per radian for the article's contacts): at 100 rad per
  // metre of position tolerance (1e-10 rad at the default 1 pm) that stays a hundred
  // times below the position tolerance.
  const double normal_tolerance = 100.0 * length;  // [rad]
  // A second update below this is round-off, not a measure of K [m].
  const double round_off = 1e-3 * length;
  const bool check = ++model.angles_since_check >= kCheckInterval || model.constant == 0.0;
  Eigen::Matrix<double, N, 1> step(x.size());
  double previous_update = 0.0;
  for (int iteration = 1; iteration <= max_iterations; ++iteration) {
    iterations = iteration;
    const double contact_step = system.ContinuationUpdate<N>(turn, x, contacts, step);
    if (!std::isfinite(contact_step)) return false;
    const double update =
        length * std::max((step.cwiseAbs().array() / tolerance.array()).maxCoeff(), contact_step / normal_tolerance);
    if (iteration >= 2) {
      model.constant = std::max(model.constant, std::max(update, round_off) / (previous_update * previous_update));
    }
    previous_update = update;
    const bool predicted = !check && kConvergenceSafety * model.constant * update * update <= length;
    if (update <= length || predicted) {
      if (iteration >= 2) model.angles_since_check = 0;
      return true;
    }
  }
  return false;
}

// The continuation iteration carries contact normals as vectors only: their angle costs
// an atan2, and only the rare two-point check needs it.
engine::Contact WithNormalAngle(engine::Contact c) {
  c.normal_angle = std::atan2(c.normal.y(), c.normal.x());
  return c;
}

// Sets every contact's force for the unknowns x [N] (after a full contact search; the
// continuation keeps them itself).
void SetForces(const EquilibriumSystem& system, const EquilibriumSystem::State& x,
               std::vector<TrackedContact>& contacts) {
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    contacts[i].force = system.ContactForce(static_cast<int>(i), x, contacts[i].contact);
  }
}

// Why a converged configuration is not a valid one, if it is not: the rungs' shared
// verdict (solvers/validity.h) on x and the contacts, which carry their forces
// (SetForces, or the continuation's own). `scratch` holds the configuration's numbers.
struct Configuration {
  std::vector<double> travel;
  std::vector<double> force;
  std::vector<engine::Contact> contacts;
};

// The validity rules of the exact time-free model, whose contacts may open (validity.h).
ValidityOptions ExactRungValidity(const QuasistaticOptions& options) {
  return {.two_point_tolerance = options.two_point_tolerance, .contacts_may_open = true};
}

Status Classify(const EquilibriumSystem& system, const ValidityCheck& check, double psi,
                const EquilibriumSystem::State& x, const std::vector<TrackedContact>& contacts,
                Configuration& scratch, std::string& message) {
  const auto z = static_cast<std::size_t>(system.rollers());
  scratch.travel.resize(z);
  scratch.force.resize(z);
  scratch.contacts.resize(z);
  for (std::size_t k = 0; k < z; ++k) {
    const int s = system.travel_index(static_cast<int>(k));
    scratch.travel[k] = s >= 0 ? x[s] : 0.0;
    scratch.force[k] = contacts[k].force;
    const engine::Contact& c = contacts[k].contact;
    scratch.contacts[k] = check.NeedsTwoPointSearch(static_cast<int>(k), c.gap) ? WithNormalAngle(c) : c;
  }
  return check.Check(psi, x.head<2>(), scratch.travel, scratch.force, message, scratch.contacts);
}

// A contact search that finds no isolated touching point, for a roller flat enough to
// bridge the bore, has met a gap function with two minima and a maximum between them
// (g'' < 0 where it started): the contact is two-point, the case the shared check
// reports for the other rungs. Sets `message` when so.
bool BridgesTheBore(const EquilibriumSystem& system, const ValidityCheck& check, int roller, double psi,
                    std::string& message) {
  if (!check.NeedsTwoPointSearch(roller, 0.0)) return false;
  message = "roller " + system.scene().rollers[static_cast<std::size_t>(roller)].name +
            " finds no single touching point at psi = " + Degrees(psi) +
            ": it is flatter than the bore there and touches it at two points";
  return true;
}

Equilibrium Record(const EquilibriumSystem& system, const EquilibriumSystem::State& x,
                   const std::vector<TrackedContact>& contacts) {
  Equilibrium e;
  e.centre = x.head<2>();
  for (int i = 0; i < system.rollers(); ++i) {
    const int s = system.travel_index(i);
    e.travel.push_back(s >= 0 ? x[s] : 0.0);
    e.contact_force.push_back(contacts[static_cast<std::size_t>(i)].force);
  }
  return e;
}

// cos and sin of every roller's body angle at a revolution's angles psi_k = 2 pi k / steps,
// asked for in order: each turned by its fixed increment per angle (one complex product)
// and restarted from libm every kAnchor angles, which keeps round-off below ~1e-14.
class RollerSpins {
 public:
  static constexpr int kAnchor = 64;

  RollerSpins(const Scene& scene, int steps) : scene_(scene), steps_(steps), spin_(scene.rollers.size()) {
    for (int i = 0; i < static_cast<int>(scene.rollers.size()); ++i) {
      increment_.push_back(engine::Direction(engine::SpinRatio(scene, i) * 2.0 * std::numbers::pi / steps));
    }
  }

  std::span<const Eigen::Vector2d> At(int k) {
    for (std::size_t i = 0; i < spin_.size(); ++i) {
      if (k % kAnchor == 0 || k != next_) {
        spin_[i] = engine::Direction(engine::RollerBodyAngle(scene_, static_cast<int>(i), 2.0 * std::numbers::pi * k / steps_));
      } else {
        const Eigen::Vector2d& a = spin_[i];
        const Eigen::Vector2d& b = increment_[i];
        spin_[i] = Eigen::Vector2d(a.x() * b.x() - a.y() * b.y(), a.y() * b.x() + a.x() * b.y());
      }
    }
    next_ = k + 1;
    return spin_;
  }

 private:
  const Scene& scene_;
  int steps_;
  int next_ = -1;
  std::vector<Eigen::Vector2d> spin_;
  std::vector<Eigen::Vector2d> increment_;
};

// Solves the angles `indices` (increasing, after `from`) of a revolution of `steps`,
// continued from the converged state x0 and its contacts at angle `from`, with the
// unknowns in storage of N (fixed-size for the common systems, Eigen::Dynamic for the
// rest). Appends each solved angle to the trajectory, and its state to `saved` when
// given; stops at the first failure with the trajectory's status saying why. The
// predictor extrapolates equally spaced angles: it restarts from the last state where the
// spacing changes.
template <int N>
void Continue(const QuasistaticOptions& options, const EquilibriumSystem& system, int steps, int from,
              std::span<const int> indices, const Eigen::VectorXd& x0, std::vector<TrackedContact>& contacts,
              Trajectory& trajectory, std::vector<SparseRevolution::State>* saved) {
  using Vector = Eigen::Matrix<double, N, 1>;
  const Scene& scene = system.scene();
  const auto z = static_cast<std::size_t>(system.rollers());
  const ValidityCheck check(scene, ExactRungValidity(options));
  Configuration scratch;
  const Eigen::VectorXd dynamic_tolerance = system.Tolerances(options.position_tolerance, options.force_tolerance);
  const Vector tolerance = dynamic_tolerance;
  Vector x = x0;
  Vector previous = x;
  Vector predicted = x;
  Predictor predictor;
  ConvergenceModel model;
  engine::NearbyAngle psi_trig;
  RollerSpins spins(scene, steps);
  const bool lobed = std::any_of(scene.rollers.begin(), scene.rollers.end(),
                                 [](const engine::Roller& r) { return !r.outline.is_circle(); });
  {
    // The angle continued from, as the trigonometric recurrences would have passed it.
    double cos_psi = 1.0;
    double sin_psi = 0.0;
    psi_trig.Evaluate(2.0 * std::numbers::pi * from / steps, cos_psi, sin_psi);
    if (lobed) spins.At(from);
  }
  predictor.Push(x, contacts);
  int spacing = 0;
  int last = from;
  for (const int k : indices) {
    if (k - last != spacing) {
      if (spacing != 0) {
        predictor = Predictor();
        predictor.Push(x, contacts);
      }
      spacing = k - last;
    }
    last = k;
    RingTurn turn;
    turn.psi = 2.0 * std::numbers::pi * k / steps;
    psi_trig.Evaluate(turn.psi, turn.cos_psi, turn.sin_psi);
    if (lobed) turn.spin = spins.At(k);
    const double psi = turn.psi;
    previous = x;
    predictor.Predict(x, contacts);
    predicted = x;
    int iterations = 0;
    bool converged =
        ContinuationNewton<N>(system, turn, x, contacts, tolerance, options.max_iterations, model, iterations);
    trajectory.total_iterations += iterations;
    if (!converged) {
      // The robust path: a full contact search at every iteration, with line search.
      Eigen::VectorXd restart = predicted;
      for (TrackedContact& c : contacts) c.valid = false;
      const NewtonOutcome outcome =
          Newton(system, psi, restart, contacts, dynamic_tolerance, options.max_iterations, false);
      trajectory.total_iterations += outcome.iterations;
      converged = outcome.converged;
      x = restart;
      if (converged) SetForces(system, x, contacts);
    }
    if (!converged) {
      trajectory.status = Status::kNotConverged;
      trajectory.message = "Newton iteration did not converge at psi = " + Degrees(psi);
      std::string reason;
      contacts.clear();
      const int lost = system.UpdateContacts(psi, previous, contacts);
      if (lost < 0) {
        SetForces(system, previous, contacts);
        if (Classify(system, check, psi, previous, contacts, scratch, reason) == Status::kLiftOff) {
          trajectory.status = Status::kLiftOff;
          trajectory.message = reason;
        }
      } else if (BridgesTheBore(system, check, lost, psi, trajectory.message)) {
        trajectory.status = Status::kTwoPointContact;
      }
      trajectory.failure_angle = psi;
      return;
    }
    const Status status = Classify(system, check, psi, x, contacts, scratch, trajectory.message);
    if (status != Status::kOk) {
      trajectory.status = status;
      trajectory.failure_angle = psi;
      return;
    }
    predictor.Push(x, contacts);
    trajectory.psi.push_back(psi);
    trajectory.centre.push_back(x.template head<2>());
    for (std::size_t i = 0; i < z; ++i) {
      const int s = system.travel_index(static_cast<int>(i));
      trajectory.travel.push_back(s >= 0 ? x[s] : 0.0);
      trajectory.contact_force.push_back(contacts[i].force);
    }
    if (saved != nullptr) saved->push_back({Eigen::VectorXd(x), contacts});
  }
}

// Calls f with std::integral_constant<int, N>, N the storage Continue takes for a system
// of `size` unknowns.
template <typename F>
void WithStorage(int size, F&& f) {
  switch (size) {
    case 2: f(std::integral_constant<int, 2>{}); break;
    case 3: f(std::integral_constant<int, 3>{}); break;
    case 4: f(std::integral_constant<int, 4>{}); break;
    case 5: f(std::integral_constant<int, 5>{}); break;
    case 6: f(std::integral_constant<int, 6>{}); break;
    case 7: f(std::integral_constant<int, 7>{}); break;
    case 8: f(std::integral_constant<int, 8>{}); break;
    default: f(std::integral_constant<int, Eigen::Dynamic>{}); break;
  }
}

// Records angle 0, the static equilibrium x and its contacts, at the start of a trajectory.
void RecordStart(const EquilibriumSystem& system, const Eigen::VectorXd& x, std::vector<TrackedContact>& contacts,
                 Trajectory& trajectory) {
  SetForces(system, x, contacts);
  trajectory.psi.push_back(0.0);
  trajectory.centre.push_back(x.head<2>());
  for (int i = 0; i < system.rollers(); ++i) {
    const int s = system.travel_index(i);
    trajectory.travel.push_back(s >= 0 ? x[s] : 0.0);
    trajectory.contact_force.push_back(contacts[static_cast<std::size_t>(i)].force);
  }
}

}  // namespace

Equilibrium QuasistaticSolver::SolveStatic(const EquilibriumSystem& system, Eigen::VectorXd& x,
                                           std::vector<TrackedContact>& contacts) const {
  const Scene& scene = system.scene();
  Equilibrium result;
  result.status = CheckSceneGeometry(scene, result.message);
  if (result.status != Status::kOk) return result;
  const int fixed = engine::FixedRollerCount(scene);
  const Eigen::VectorXd tolerance = system.Tolerances(options_.position_tolerance, options_.force_tolerance);
  // The static solve starts far from the answer; allow many more iterations than a step.
  const int static_iterations = 10 * options_.max_iterations;

  NewtonOutcome outcome;
  if (system.rigid()) {
    if (fixed > 2) {
      result.status = Status::kStaticallyIndeterminate;
      result.message = "rigid contact with " + std::to_string(fixed) +
                       " fixed rollers is statically indeterminate: use the penalty contact law";
      return result;
    }
    x.setZero(system.size());
    contacts.clear();
    outcome = Newton(system, 0.0, x, contacts, tolerance, static_iterations, false);
  } else {
    x.setZero(system.size());
    contacts.clear();
    Scene rigid_scene = scene;
    rigid_scene.contact.model = engine::ContactLaw::Model::kRigid;
    const EquilibriumSystem rigid(rigid_scene);
    Eigen::VectorXd xr = Eigen::VectorXd::Zero(rigid.size());
    std::vector<TrackedContact> rigid_contacts;
    if (fixed <= 2 &&
        Newton(rigid, 0.0, xr, rigid_contacts, rigid.Tolerances(options_.position_tolerance, options_.force_tolerance),
               static_iterations, false)
            .converged) {
      // Compliance correction: make each contact penetrate by the depth that carries its
      // rigid force, solving dg/dx * dx = -delta in the least-squares sense.
      const int z = system.rollers();
      Eigen::MatrixXd gap_gradient = Eigen::MatrixXd::Zero(z, system.size());
      Eigen::VectorXd depth(z);
      for (int i = 0; i < z; ++i) {
        const engine::Contact& c = rigid_contacts[static_cast<std::size_t>(i)].contact;
        gap_gradient.block<1, 2>(i, 0) = c.normal.transpose();
        const int s = system.travel_index(i);
        if (s >= 0) gap_gradient(i, s) = -engine::SpringAxis(scene, i).dot(c.normal);
        depth[i] = std::pow(std::max(xr[rigid.force_index(i)], 0.0) / scene.contact.stiffness, 1.0 / scene.contact.exponent);
      }
      x = xr.head(system.size()) + gap_gradient.completeOrthogonalDecomposition().solve(-depth);
      contacts = rigid_contacts;
    } else {
      for (int i = 0; i < system.rollers(); ++i) {
        const int s = system.travel_index(i);
        if (s < 0) continue;
        const double preload = scene.rollers[static_cast<std::size_t>(i)].spring.preload;
        x[s] = std::pow(preload / scene.contact.stiffness, 1.0 / scene.contact.exponent);
      }
    }
    outcome = Newton(system, 0.0, x, contacts, tolerance, static_iterations, true);
  }
  result.iterations = outcome.iterations;
  if (!outcome.converged) {
    result.status = Status::kNotConverged;
    result.message = "no static equilibrium found in " + std::to_string(outcome.iterations) + " Newton iterations";
    std::vector<TrackedContact> probe;
    const int lost = system.UpdateContacts(0.0, x, probe);
    if (lost >= 0 && BridgesTheBore(system, ValidityCheck(scene, ExactRungValidity(options_)), lost, 0.0,
                                    result.message)) {
      result.status = Status::kTwoPointContact;
      return result;
    }
    for (int i = 0; i < system.rollers() && !contacts.empty(); ++i) {
      const auto k = static_cast<std::size_t>(i);
      if (k < contacts.size() && contacts[k].valid && system.ContactForce(i, x, contacts[k].contact) <= 0.0) {
        result.status = Status::kLiftOff;
        result.message = "roller " + scene.rollers[k].name + " carries no load in the static equilibrium";
      }
    }
    return result;
  }
  system.UpdateContacts(0.0, x, contacts);
  SetForces(system, x, contacts);
  Configuration scratch;
  const Status status = Classify(system, ValidityCheck(scene, ExactRungValidity(options_)), 0.0, x, contacts,
                                 scratch, result.message);
  Equilibrium recorded = Record(system, x, contacts);
  recorded.iterations = outcome.iterations;
  recorded.status = status;
  recorded.message = result.message;
  return recorded;
}

// The error-free assembly's static equilibrium: where every static solve of a scene with
// errors starts.
struct NominalStatics {
  engine::Scene perfect;  // the key: the scene without its errors
  Equilibrium equilibrium;
  Eigen::VectorXd x;
  std::vector<TrackedContact> contacts;
};

std::shared_ptr<const NominalStatics> QuasistaticSolver::Nominal(const Scene& scene) const {
  return nominal_.Get(scene, [this](engine::Scene perfect) {
    auto nominal = std::make_shared<NominalStatics>();
    nominal->perfect = std::move(perfect);
    const EquilibriumSystem system(nominal->perfect);
    nominal->equilibrium = SolveStatic(system, nominal->x, nominal->contacts);
    return std::shared_ptr<const NominalStatics>(std::move(nominal));
  });
}

Equilibrium QuasistaticSolver::SolveStaticFromNominal(const EquilibriumSystem& system, Eigen::VectorXd& x,
                                                      std::vector<TrackedContact>& contacts) const {
  const Scene& scene = system.scene();
  const bool has_errors = engine::HasErrors(scene);
  Equilibrium refused;
  refused.status = CheckSceneGeometry(scene, refused.message);
  if (refused.status != Status::kOk) return refused;
  if (has_errors && !(system.rigid() && engine::FixedRollerCount(scene) > 2)) {
    const std::shared_ptr<const NominalStatics> nominal = Nominal(scene);
    if (nominal->equilibrium.status == Status::kOk && nominal->x.size() == system.size()) {
      x = nominal->x;
      contacts = nominal->contacts;
      const Eigen::VectorXd tolerance = system.Tolerances(options_.position_tolerance, options_.force_tolerance);
      // The errors move the equilibrium by about their own size, far less than the
      // contacts' compliance lets it move: the joint iteration of a revolution settles in
      // a few steps. A confirmed convergence only: no prediction from a model of it.
      const double normal_tolerance = 100.0 * tolerance[0];
      Eigen::VectorXd step;
      for (int iteration = 1; iteration <= options_.max_iterations; ++iteration) {
        const double turn = system.ContinuationUpdate<Eigen::Dynamic>(RingTurn{}, x, contacts, step);
        if (!std::isfinite(turn)) break;
        if ((step.cwiseAbs().array() <= tolerance.array()).all() && turn <= normal_tolerance) {
          system.UpdateContacts(0.0, x, contacts);
          SetForces(system, x, contacts);
          std::string message;
          Configuration scratch;
          const Status status = Classify(system, ValidityCheck(scene, ExactRungValidity(options_)), 0.0, x,
                                         contacts, scratch, message);
          Equilibrium recorded = Record(system, x, contacts);
          recorded.iterations = iteration;
          recorded.status = status;
          recorded.message = message;
          return recorded;
        }
      }
    }
  } else if (!has_errors) {
    const std::shared_ptr<const NominalStatics> nominal = Nominal(scene);
    x = nominal->x;
    contacts = nominal->contacts;
    return nominal->equilibrium;
  }
  return SolveStatic(system, x, contacts);
}

Equilibrium QuasistaticSolver::SolveStatic(const Scene& scene) const {
  const EquilibriumSystem system(scene);
  Eigen::VectorXd x;
  std::vector<TrackedContact> contacts;
  return SolveStaticFromNominal(system, x, contacts);
}

bool QuasistaticSolver::StartRevolution(const EquilibriumSystem& system, Eigen::VectorXd& x,
                                        std::vector<TrackedContact>& contacts, Trajectory& trajectory) const {
  trajectory.initial = SolveStaticFromNominal(system, x, contacts);
  if (trajectory.initial.status != Status::kOk) {
    trajectory.status = trajectory.initial.status;
    trajectory.message = trajectory.initial.message;
    return false;
  }
  RecordStart(system, x, contacts, trajectory);
  return true;
}

Trajectory QuasistaticSolver::SolveRevolution(const Scene& scene, int steps) const {
  Trajectory trajectory;
  const EquilibriumSystem system(scene);
  Eigen::VectorXd x;
  std::vector<TrackedContact> contacts;
  const auto n = static_cast<std::size_t>(steps) + 1;
  const auto z = static_cast<std::size_t>(system.rollers());
  trajectory.psi.reserve(n);
  trajectory.centre.reserve(n);
  trajectory.travel.reserve(n * z);
  trajectory.contact_force.reserve(n * z);
  if (!StartRevolution(system, x, contacts, trajectory)) return trajectory;
  std::vector<int> indices(static_cast<std::size_t>(steps));
  for (int k = 1; k <= steps; ++k) indices[static_cast<std::size_t>(k - 1)] = k;
  WithStorage(system.size(), [&](auto storage) {
    Continue<decltype(storage)::value>(options_, system, steps, 0, indices, x, contacts, trajectory, nullptr);
  });
  return trajectory;
}

SparseRevolution::SparseRevolution(const QuasistaticOptions& options, const engine::Scene& scene, int steps)
    : options_(options), system_(scene), steps_(steps) {}

std::unique_ptr<SparseRevolution> QuasistaticSolver::SolveSparse(const Scene& scene, int steps, int stride) const {
  auto sparse = std::unique_ptr<SparseRevolution>(new SparseRevolution(options_, scene, steps));
  const EquilibriumSystem& system = sparse->system_;
  Trajectory& coarse = sparse->coarse_;
  Eigen::VectorXd x;
  std::vector<TrackedContact> contacts;
  if (!StartRevolution(system, x, contacts, coarse)) return sparse;
  sparse->indices_.push_back(0);
  sparse->states_.push_back({x, contacts});
  std::vector<int> indices;
  for (int k = stride; k < steps; k += stride) indices.push_back(k);
  indices.push_back(steps);
  sparse->indices_.insert(sparse->indices_.end(), indices.begin(), indices.end());
  WithStorage(system.size(), [&](auto storage) {
    Continue<decltype(storage)::value>(options_, system, steps, 0, indices, x, contacts, coarse, &sparse->states_);
  });
  return sparse;
}

Trajectory SparseRevolution::SolveSegment(int j) const {
  Trajectory segment;
  const int from = indices_[static_cast<std::size_t>(j)];
  const int to = indices_[static_cast<std::size_t>(j) + 1];
  std::vector<int> indices;
  for (int k = from + 1; k < to; ++k) indices.push_back(k);
  const State& start = states_[static_cast<std::size_t>(j)];
  std::vector<TrackedContact> contacts = start.contacts;
  WithStorage(system_.size(), [&](auto storage) {
    Continue<decltype(storage)::value>(options_, system_, steps_, from, indices, start.x, contacts, segment, nullptr);
  });
  return segment;
}

}  // namespace ringtol::solvers
