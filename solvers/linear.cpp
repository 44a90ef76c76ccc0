#include "solvers/linear.h"

#include <algorithm>
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

// Outputs y at psi_k = 2 pi k / steps for k = 0 .. samples - 1, handed to
// sink(k, y) one angle at a time. Angles go in chunks through one small matrix product
// each: whole-revolution temporaries of ~150 KB cost more in heap traffic (glibc returns
// them to the kernel on free) than the arithmetic.
template <typename Sink>
void EvaluatePath(const Linearisation& lin, int steps, int samples, Sink sink) {
  constexpr int kChunk = 256;
  const auto terms = lin.phasors.cols();
  const Eigen::MatrixXd real = lin.phasors.real();
  const Eigen::MatrixXd imag = lin.phasors.imag();
  const double dpsi = 2.0 * std::numbers::pi / steps;
  // Rotate a unit phasor per term by a fixed increment: one complex product per angle;
  // the accumulated round-off after 1e5 steps is ~1e-11 relative.
  std::vector<Complex> phasor(static_cast<std::size_t>(terms), Complex(1.0, 0.0));
  std::vector<Complex> increment;
  for (const double rate : lin.rates) increment.push_back(std::polar(1.0, -rate * dpsi));
  Eigen::MatrixXd cosines(terms, kChunk);
  Eigen::MatrixXd sines(terms, kChunk);
  Eigen::MatrixXd chunk(lin.offset.size(), kChunk);
  for (int first = 0; first < samples; first += kChunk) {
    const int count = std::min(kChunk, samples - first);
    for (Eigen::Index p = 0; p < terms; ++p) {
      // Written out: std::complex's product carries Inf/NaN recovery that costs more
      // than the product itself, and these phasors are unit-modulus and finite.
      double re = phasor[static_cast<std::size_t>(p)].real();
      double im = phasor[static_cast<std::size_t>(p)].imag();
      const double step_re = increment[static_cast<std::size_t>(p)].real();
      const double step_im = increment[static_cast<std::size_t>(p)].imag();
      for (int k = 0; k < count; ++k) {
        cosines(p, k) = re;
        sines(p, k) = im;
        const double next_re = re * step_re - im * step_im;
        im = re * step_im + im * step_re;
        re = next_re;
      }
      phasor[static_cast<std::size_t>(p)] = Complex(re, im);
    }
    chunk.leftCols(count).noalias() = real * cosines.leftCols(count);
    chunk.leftCols(count).noalias() -= imag * sines.leftCols(count);
    chunk.leftCols(count).colwise() += lin.offset;
    for (int k = 0; k < count; ++k) sink(first + k, chunk.col(k));
  }
}

template <typename Column>
void FillEquilibrium(const Linearisation& lin, const Column& y, Equilibrium& e) {
  const int z = lin.rollers;
  e.centre = y.template head<2>();
  e.travel.resize(static_cast<std::size_t>(z));
  e.contact_force.resize(static_cast<std::size_t>(z));
  for (int i = 0; i < z; ++i) {
    e.travel[static_cast<std::size_t>(i)] = y(2 + i);
    e.contact_force[static_cast<std::size_t>(i)] = y(2 + z + i);
  }
}

}  // namespace

Equilibrium LinearSolver::SolveStatic(const Scene& scene) const {
  const Linearisation lin = Linearise(scene, options_.nominal);
  if (lin.nominal.status != Status::kOk) return lin.nominal;
  Equilibrium e;
  EvaluatePath(lin, 1, 1, [&](int, const auto& y) { FillEquilibrium(lin, y, e); });
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
  const int z = lin.rollers;
  const auto n = static_cast<std::size_t>(steps) + 1;
  trajectory.psi.resize(n);
  trajectory.centre.resize(n);
  trajectory.travel.resize(n * static_cast<std::size_t>(z));
  trajectory.contact_force.resize(n * static_cast<std::size_t>(z));
  EvaluatePath(lin, steps, steps + 1, [&](int k, const auto& y) {
    const auto kk = static_cast<std::size_t>(k);
    if (k == 0) FillEquilibrium(lin, y, trajectory.initial);
    trajectory.psi[kk] = 2.0 * std::numbers::pi * k / steps;
    trajectory.centre[kk] = y.template head<2>();
    for (int i = 0; i < z; ++i) {
      const auto slot = kk * static_cast<std::size_t>(z) + static_cast<std::size_t>(i);
      trajectory.travel[slot] = y(2 + i);
      trajectory.contact_force[slot] = y(2 + z + i);
      if (trajectory.status == Status::kOk && y(2 + z + i) <= 0.0) {
        trajectory.status = Status::kLiftOff;
        trajectory.failure_angle = trajectory.psi[kk];
        trajectory.message = "roller " + scene.rollers[static_cast<std::size_t>(i)].name +
                             "'s linearised contact force turns tensile";
      }
    }
  });
  return trajectory;
}

}  // namespace ringtol::solvers
