#include "solvers/linear.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <mutex>
#include <numbers>

#include <Eigen/LU>

namespace ringtol::solvers {
namespace {

using engine::Scene;
using Complex = std::complex<double>;

// Outputs y = [centre (2); travel per spring roller; contact force per roller (Z)]: the
// travel rows are x's (fixed rollers do not travel, and carry no rows to evaluate).
struct Linearisation {
  std::shared_ptr<const NominalResponse> nominal;
  Eigen::VectorXd offset;            // y at psi-independent errors: y0 + Y dg_constant
  Eigen::MatrixXcd phasors;          // one column per error term: y += Re[v e^{-i rate psi}]
  std::vector<double> rates;         // [rad of phase per rad of ring angle]
};

}  // namespace

// The error-free assembly's response: everything of the linearisation that does not
// depend on the errors, and the costly part (a static solve and a factorisation).
struct NominalResponse {
  engine::Scene perfect;             // the key: the scene without its errors
  Equilibrium equilibrium;           // its static equilibrium, with a status
  int rollers = 0;
  std::vector<int> travel_row;       // row of roller i's travel in y, or -1 (fixed)
  int first_force_row = 0;           // row of roller 0's contact force in y
  std::vector<engine::Contact> contacts;  // at the equilibrium
  Eigen::VectorXd y0;                // outputs at the equilibrium
  // Response of the outputs to each contact's gap value (columns 0..Z-1) and gap slope
  // (Z..2Z-1).
  Eigen::MatrixXd response;
};

namespace {

std::shared_ptr<const NominalResponse> ComputeNominal(engine::Scene perfect, const QuasistaticOptions& options) {
  auto nominal = std::make_shared<NominalResponse>();
  nominal->perfect = std::move(perfect);
  const engine::Scene& scene = nominal->perfect;
  const EquilibriumSystem system(scene);
  const QuasistaticSolver quasistatic(options);
  Eigen::VectorXd x;
  std::vector<TrackedContact> contacts;
  nominal->equilibrium = quasistatic.SolveStatic(system, x, contacts);
  if (nominal->equilibrium.status != Status::kOk) return nominal;

  const int z = system.rollers();
  nominal->rollers = z;
  Eigen::VectorXd residual;
  Eigen::MatrixXd jacobian;
  Eigen::MatrixXd gap_sensitivity;
  Eigen::MatrixXd slope_sensitivity;
  system.Evaluate(x, contacts, residual, &jacobian, &gap_sensitivity, &slope_sensitivity);
  const auto lu = jacobian.partialPivLu();
  // Response of x to each contact's gap value (columns 0..Z-1) and gap slope (Z..2Z-1).
  Eigen::MatrixXd dx(system.size(), 2 * z);
  dx << -lu.solve(gap_sensitivity), -lu.solve(slope_sensitivity);

  const int springs = system.size() - 2 - (system.rigid() ? z : 0);
  nominal->first_force_row = 2 + springs;
  const int outputs = nominal->first_force_row + z;
  Eigen::MatrixXd& response = nominal->response;
  Eigen::VectorXd& y0 = nominal->y0;
  response = Eigen::MatrixXd::Zero(outputs, 2 * z);
  y0 = Eigen::VectorXd::Zero(outputs);
  y0.head<2>() = x.head<2>();
  response.topRows<2>() = dx.topRows<2>();
  for (int i = 0; i < z; ++i) {
    const engine::Contact& c = contacts[static_cast<std::size_t>(i)].contact;
    nominal->contacts.push_back(c);
    const int s = system.travel_index(i);
    nominal->travel_row.push_back(s);
    if (s >= 0) {
      y0[s] = x[s];
      response.row(s) = dx.row(s);
    }
    const int f = nominal->first_force_row + i;
    y0[f] = system.ContactForce(i, x, c);
    if (system.rigid()) {
      response.row(f) = dx.row(system.force_index(i));
    } else {
      // F = k delta^e with delta = -(g + dg_i + dg/dx dx): dF = -k e delta^(e-1) (dg_i + dg/dx dx).
      const double e = scene.contact.exponent;
      const double stiffness = scene.contact.stiffness * e * std::pow(std::max(-c.gap, 0.0), e - 1.0);
      Eigen::RowVectorXd gap_gradient = Eigen::RowVectorXd::Zero(system.size());
      gap_gradient.head<2>() = c.normal.transpose();
      if (s >= 0) gap_gradient[s] = -engine::SpringAxis(scene, i).dot(c.normal);
      Eigen::RowVectorXd row = gap_gradient * dx;
      row[i] += 1.0;
      response.row(f) = -stiffness * row;
    }
  }
  return nominal;
}

Linearisation Linearise(const Scene& scene, std::shared_ptr<const NominalResponse> nominal_response) {
  Linearisation lin;
  lin.nominal = std::move(nominal_response);
  const NominalResponse& nominal = *lin.nominal;
  if (nominal.equilibrium.status != Status::kOk) return lin;
  const int z = nominal.rollers;
  const Eigen::MatrixXd& response = nominal.response;
  const auto outputs = response.rows();

  // Every error term as a change of each contact's gap function near its nominal
  // direction phi_i: a bore harmonic a e^{i n theta} adds Re[a e^{i n (phi - psi)}] to
  // g_i(phi), with slope Re[i n a e^{i n (phi - psi)}]; a roller harmonic subtracts.
  auto gap_and_slope = [&](int i, Complex value, double order) -> Eigen::VectorXcd {
    return (response.col(i).cast<Complex>() + Complex(0.0, order) * response.col(z + i).cast<Complex>()) * value;
  };
  Eigen::VectorXd constant(2 * z);
  std::vector<Eigen::VectorXcd> columns;
  const engine::PolarProfile& ring = scene.ring.inner;
  for (int n = 1; n <= ring.max_order(); ++n) {
    const Complex a(ring.cos_coefficient(n), ring.sin_coefficient(n));
    if (a == Complex(0.0)) continue;
    Eigen::VectorXcd v = Eigen::VectorXcd::Zero(outputs);
    for (int i = 0; i < z; ++i) {
      const double phi = nominal.contacts[static_cast<std::size_t>(i)].normal_angle;
      v += gap_and_slope(i, a * std::polar(1.0, n * phi), n);
    }
    columns.push_back(v);
    lin.rates.push_back(n);
  }
  for (int i = 0; i < z; ++i) {
    const engine::Contact& c = nominal.contacts[static_cast<std::size_t>(i)];
    const engine::PolarProfile& outline = scene.rollers[static_cast<std::size_t>(i)].outline;
    const Eigen::Vector2d shift = engine::RollerCentre(scene, i) - engine::RollerCentre(nominal.perfect, i);
    constant[i] = ring.mean_deviation() - outline.mean_deviation() - shift.dot(c.normal);
    constant[z + i] = -shift.dot(c.tangent);
    const double body0 = engine::RollerBodyAngle(scene, i, 0.0);
    for (int m = 1; m <= outline.max_order(); ++m) {
      const Complex a(outline.cos_coefficient(m), outline.sin_coefficient(m));
      if (a == Complex(0.0)) continue;
      columns.push_back(-gap_and_slope(i, a * std::polar(1.0, m * (c.normal_angle - body0)), m));
      lin.rates.push_back(m * engine::SpinRatio(scene, i));
    }
  }
  lin.offset = nominal.y0 + response * constant;
  lin.phasors.resize(outputs, static_cast<Eigen::Index>(columns.size()));
  for (std::size_t p = 0; p < columns.size(); ++p) lin.phasors.col(static_cast<Eigen::Index>(p)) = columns[p];
  return lin;
}

// Outputs y at psi_k = 2 pi k / steps for k = 0 .. samples - 1, handed to
// sink(first, y) a chunk of angles (columns of y, from angle `first`) at a time. Angles go in chunks through one small matrix product
// each: whole-revolution temporaries of ~150 KB cost more in heap traffic (glibc returns
// them to the kernel on free) than the arithmetic.
template <typename Sink>
void EvaluatePath(const Linearisation& lin, int steps, int samples, Sink sink) {
  constexpr int kChunk = 256;
  const auto terms = lin.phasors.cols();
  const auto outputs = lin.offset.size();
  // y_k = offset + [cos(rate psi_k), sin(rate psi_k)] . [Re v; Im v] per output: one
  // product of a (angles x 2 terms) table with (2 terms x outputs) weights per chunk,
  // long along the angles so that the product kernel vectorises over them.
  Eigen::MatrixXd weights(2 * terms, outputs);
  weights << lin.phasors.real().transpose(), lin.phasors.imag().transpose();
  const double dpsi = 2.0 * std::numbers::pi / steps;
  // Unit phasors of every term, turned by a fixed increment per angle: one complex product
  // per term and angle, the terms side by side so their recurrences run in parallel
  // rather than as one long dependency chain. The round-off accumulated after 1e5 steps
  // is ~1e-11 relative.
  const auto n_terms = static_cast<std::size_t>(terms);
  std::vector<double> re(n_terms, 1.0);
  std::vector<double> im(n_terms, 0.0);
  std::vector<double> step_re(n_terms);
  std::vector<double> step_im(n_terms);
  for (std::size_t p = 0; p < n_terms; ++p) {
    step_re[p] = std::cos(lin.rates[p] * dpsi);
    step_im[p] = -std::sin(lin.rates[p] * dpsi);
  }
  Eigen::MatrixXd table(kChunk, 2 * terms);
  Eigen::MatrixXd chunk(kChunk, outputs);
  for (int first = 0; first < samples; first += kChunk) {
    const int count = std::min(kChunk, samples - first);
    for (int k = 0; k < count; ++k) {
      for (std::size_t p = 0; p < n_terms; ++p) {
        table(k, static_cast<Eigen::Index>(p)) = re[p];
        table(k, terms + static_cast<Eigen::Index>(p)) = -im[p];
        const double next_re = re[p] * step_re[p] - im[p] * step_im[p];
        im[p] = re[p] * step_im[p] + im[p] * step_re[p];
        re[p] = next_re;
      }
    }
    chunk.topRows(count).noalias() = table.topRows(count) * weights;
    chunk.topRows(count).rowwise() += lin.offset.transpose();
    sink(first, chunk.topRows(count).transpose());
  }
}

template <typename Column>
void FillEquilibrium(const Linearisation& lin, const Column& y, Equilibrium& e) {
  const NominalResponse& nominal = *lin.nominal;
  const int z = nominal.rollers;
  e.centre = y.template head<2>();
  e.travel.resize(static_cast<std::size_t>(z));
  e.contact_force.resize(static_cast<std::size_t>(z));
  for (int i = 0; i < z; ++i) {
    const int s = nominal.travel_row[static_cast<std::size_t>(i)];
    e.travel[static_cast<std::size_t>(i)] = s >= 0 ? y(s) : 0.0;
    e.contact_force[static_cast<std::size_t>(i)] = y(nominal.first_force_row + i);
  }
}

}  // namespace

std::shared_ptr<const NominalResponse> LinearSolver::Nominal(const Scene& scene) const {
  engine::Scene perfect = engine::WithoutErrors(scene);
  {
    const std::lock_guard<std::mutex> lock(cache_mutex_);
    if (cache_ != nullptr && cache_->perfect == perfect) return cache_;
  }
  std::shared_ptr<const NominalResponse> nominal = ComputeNominal(std::move(perfect), options_.nominal);
  const std::lock_guard<std::mutex> lock(cache_mutex_);
  cache_ = nominal;
  return nominal;
}

Equilibrium LinearSolver::SolveStatic(const Scene& scene) const {
  const Linearisation lin = Linearise(scene, Nominal(scene));
  if (lin.nominal->equilibrium.status != Status::kOk) return lin.nominal->equilibrium;
  Equilibrium e;
  EvaluatePath(lin, 1, 1, [&](int, const auto& y) { FillEquilibrium(lin, y.col(0), e); });
  return e;
}

Trajectory LinearSolver::SolveRevolution(const Scene& scene, int steps) const {
  Trajectory trajectory;
  const Linearisation lin = Linearise(scene, Nominal(scene));
  const NominalResponse& nominal = *lin.nominal;
  if (nominal.equilibrium.status != Status::kOk) {
    trajectory.status = nominal.equilibrium.status;
    trajectory.message = "the error-free assembly cannot be linearised: " + nominal.equilibrium.message;
    trajectory.initial = nominal.equilibrium;
    return trajectory;
  }
  const int z = nominal.rollers;
  const auto n = static_cast<std::size_t>(steps) + 1;
  trajectory.psi.resize(n);
  trajectory.centre.resize(n);
  trajectory.travel.resize(n * static_cast<std::size_t>(z));
  trajectory.contact_force.resize(n * static_cast<std::size_t>(z));
  // The trajectory's arrays as matrices with one column per angle.
  Eigen::Map<Eigen::Matrix2Xd> centre(trajectory.centre.front().data(), 2, static_cast<Eigen::Index>(n));
  Eigen::Map<Eigen::MatrixXd> travel(trajectory.travel.data(), z, static_cast<Eigen::Index>(n));
  Eigen::Map<Eigen::MatrixXd> force(trajectory.contact_force.data(), z, static_cast<Eigen::Index>(n));
  EvaluatePath(lin, steps, steps + 1, [&](int first, const auto& y) {
    const auto count = y.cols();
    if (first == 0) FillEquilibrium(lin, y.col(0), trajectory.initial);
    centre.middleCols(first, count) = y.template topRows<2>();
    force.middleCols(first, count) = y.middleRows(nominal.first_force_row, z);
    for (int i = 0; i < z; ++i) {
      const int s = nominal.travel_row[static_cast<std::size_t>(i)];
      if (s >= 0) travel.row(i).segment(first, count) = y.row(s);
    }
  });
  for (std::size_t k = 0; k < n; ++k) trajectory.psi[k] = 2.0 * std::numbers::pi * static_cast<double>(k) / steps;
  Eigen::Index roller = 0;
  Eigen::Index angle = 0;
  if (force.minCoeff(&roller, &angle) <= 0.0) {
    // The first angle at which any force turns tensile, as the quasistatic rung reports.
    for (angle = 0; angle < force.cols(); ++angle) {
      if (force.col(angle).minCoeff(&roller) <= 0.0) break;
    }
    trajectory.status = Status::kLiftOff;
    trajectory.failure_angle = trajectory.psi[static_cast<std::size_t>(angle)];
    trajectory.message = "roller " + scene.rollers[static_cast<std::size_t>(roller)].name +
                         "'s linearised contact force turns tensile";
  }
  return trajectory;
}

}  // namespace ringtol::solvers
