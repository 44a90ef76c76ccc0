#include "solvers/linear.h"

#include <cmath>
#include <complex>
#include <numbers>

#include <Eigen/LU>

namespace ringtol::solvers {
namespace {

using engine::Scene;
using Complex = std::complex<double>;

// Outputs y = [centre (2); travel per roller (Z); contact force per roller (Z)].
struct Linearisation {
  Equilibrium nominal;
  int rollers = 0;
  Eigen::VectorXd offset;            // y at psi-independent errors: y0 + Y dg_constant
  Eigen::MatrixXcd phasors;          // one column per error term: y += Re[v e^{-i rate psi}]
  std::vector<double> rates;         // [rad of phase per rad of ring angle]
};

Linearisation Linearise(const Scene& scene, const QuasistaticOptions& options) {
  Linearisation lin;
  const Scene perfect = engine::WithoutErrors(scene);
  const EquilibriumSystem system(perfect);
  const QuasistaticSolver quasistatic(options);
  Eigen::VectorXd x;
  std::vector<TrackedContact> contacts;
  lin.nominal = quasistatic.SolveStatic(system, x, contacts);
  if (lin.nominal.status != Status::kOk) return lin;

  const int z = system.rollers();
  lin.rollers = z;
  Eigen::VectorXd residual;
  Eigen::MatrixXd jacobian;
  Eigen::MatrixXd gap_sensitivity;
  Eigen::MatrixXd slope_sensitivity;
  system.Evaluate(x, contacts, residual, &jacobian, &gap_sensitivity, &slope_sensitivity);
  const auto lu = jacobian.partialPivLu();
  // Response of x to each contact's gap value (columns 0..Z-1) and gap slope (Z..2Z-1).
  Eigen::MatrixXd dx(system.size(), 2 * z);
  dx << -lu.solve(gap_sensitivity), -lu.solve(slope_sensitivity);

  const int outputs = 2 + 2 * z;
  Eigen::MatrixXd response = Eigen::MatrixXd::Zero(outputs, 2 * z);
  Eigen::VectorXd y0 = Eigen::VectorXd::Zero(outputs);
  y0.head<2>() = x.head<2>();
  response.topRows<2>() = dx.topRows<2>();
  for (int i = 0; i < z; ++i) {
    const engine::Contact& c = contacts[static_cast<std::size_t>(i)].contact;
    const int s = system.travel_index(i);
    if (s >= 0) {
      y0[2 + i] = x[s];
      response.row(2 + i) = dx.row(s);
    }
    y0[2 + z + i] = system.ContactForce(i, x, c);
    if (system.rigid()) {
      response.row(2 + z + i) = dx.row(system.force_index(i));
    } else {
      // F = k delta^e with delta = -(g + dg_i + dg/dx dx): dF = -k e delta^(e-1) (dg_i + dg/dx dx).
      const double e = scene.contact.exponent;
      const double stiffness = scene.contact.stiffness * e * std::pow(std::max(-c.gap, 0.0), e - 1.0);
      Eigen::RowVectorXd gap_gradient = Eigen::RowVectorXd::Zero(system.size());
      gap_gradient.head<2>() = c.normal.transpose();
      if (s >= 0) gap_gradient[s] = -engine::SpringAxis(perfect, i).dot(c.normal);
      Eigen::RowVectorXd row = gap_gradient * dx;
      row[i] += 1.0;
      response.row(2 + z + i) = -stiffness * row;
    }
  }

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
      const double phi = contacts[static_cast<std::size_t>(i)].contact.normal_angle;
      v += gap_and_slope(i, a * std::polar(1.0, n * phi), n);
    }
    columns.push_back(v);
    lin.rates.push_back(n);
  }
  for (int i = 0; i < z; ++i) {
    const engine::Contact& c = contacts[static_cast<std::size_t>(i)].contact;
    const engine::PolarProfile& outline = scene.rollers[static_cast<std::size_t>(i)].outline;
    const Eigen::Vector2d shift = engine::RollerCentre(scene, i) - engine::RollerCentre(perfect, i);
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
  lin.offset = y0 + response * constant;
  lin.phasors.resize(outputs, static_cast<Eigen::Index>(columns.size()));
  for (std::size_t p = 0; p < columns.size(); ++p) lin.phasors.col(static_cast<Eigen::Index>(p)) = columns[p];
  return lin;
}

// Outputs at psi_k = 2 pi k / steps for k = 0 .. samples - 1, one column per angle.
Eigen::MatrixXd EvaluatePath(const Linearisation& lin, int steps, int samples) {
  const auto terms = lin.phasors.cols();
  Eigen::MatrixXd cosines(terms, samples);
  Eigen::MatrixXd sines(terms, samples);
  const double dpsi = 2.0 * std::numbers::pi / steps;
  for (Eigen::Index p = 0; p < terms; ++p) {
    // Rotate a unit phasor by a fixed increment: one complex product per angle; the
    // accumulated round-off after 1e5 steps is ~1e-11 relative.
    const Complex increment = std::polar(1.0, -lin.rates[static_cast<std::size_t>(p)] * dpsi);
    Complex z(1.0, 0.0);
    for (int k = 0; k < samples; ++k) {
      cosines(p, k) = z.real();
      sines(p, k) = z.imag();
      z *= increment;
    }
  }
  Eigen::MatrixXd path = lin.phasors.real() * cosines - lin.phasors.imag() * sines;
  path.colwise() += lin.offset;
  return path;
}

void FillEquilibrium(const Linearisation& lin, const Eigen::VectorXd& y, Equilibrium& e) {
  const int z = lin.rollers;
  e.centre = y.head<2>();
  e.travel.assign(y.data() + 2, y.data() + 2 + z);
  e.contact_force.assign(y.data() + 2 + z, y.data() + 2 + 2 * z);
}

}  // namespace

Equilibrium LinearSolver::SolveStatic(const Scene& scene) const {
  const Linearisation lin = Linearise(scene, options_.nominal);
  if (lin.nominal.status != Status::kOk) return lin.nominal;
  Equilibrium e;
  FillEquilibrium(lin, EvaluatePath(lin, 1, 1).col(0), e);
  return e;
}

Trajectory LinearSolver::SolveRevolution(const Scene& scene, int steps) const {
  Trajectory trajectory;
  const Linearisation lin = Linearise(scene, options_.nominal);
  if (lin.nominal.status != Status::kOk) {
    trajectory.status = lin.nominal.status;
    trajectory.message = "the error-free assembly cannot be linearised: " + lin.nominal.message;
    trajectory.initial = lin.nominal;
    return trajectory;
  }
  const Eigen::MatrixXd path = EvaluatePath(lin, steps, steps + 1);
  const int z = lin.rollers;
  FillEquilibrium(lin, path.col(0), trajectory.initial);
  const auto n = static_cast<std::size_t>(steps) + 1;
  trajectory.psi.resize(n);
  trajectory.centre.resize(n);
  trajectory.travel.resize(n * static_cast<std::size_t>(z));
  trajectory.contact_force.resize(n * static_cast<std::size_t>(z));
  for (int k = 0; k <= steps; ++k) {
    const auto kk = static_cast<std::size_t>(k);
    trajectory.psi[kk] = 2.0 * std::numbers::pi * k / steps;
    trajectory.centre[kk] = path.block<2, 1>(0, k);
    for (int i = 0; i < z; ++i) {
      const auto slot = kk * static_cast<std::size_t>(z) + static_cast<std::size_t>(i);
      trajectory.travel[slot] = path(2 + i, k);
      trajectory.contact_force[slot] = path(2 + z + i, k);
      if (trajectory.status == Status::kOk && path(2 + z + i, k) <= 0.0) {
        trajectory.status = Status::kLiftOff;
        trajectory.failure_angle = trajectory.psi[kk];
        trajectory.message = "roller " + scene.rollers[static_cast<std::size_t>(i)].name +
                             "'s linearised contact force turns tensile";
      }
    }
  }
  return trajectory;
}

}  // namespace ringtol::solvers
