#include "solvers/linear.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <initializer_list>
#include <memory>
#include <numbers>
#include <numeric>
#include <span>

#include <Eigen/LU>
#include <boost/container/vector.hpp>

#include "engine/enclosing_circle.h"
#include "solvers/linear_series.h"
#include "solvers/path_kernels.h"
#include "solvers/validity.h"

namespace ringtol::solvers {
namespace {

using engine::Scene;
using Complex = std::complex<double>;

}  // namespace

// Outputs y = [centre (2); travel per spring roller; contact force per roller (Z)]: the
// travel rows are x's (fixed rollers do not travel, and carry no rows to evaluate). Below
// them, 4Z rows that only the second-order terms read: the slope d(dg_i)/dphi that the
// bore's harmonics (rows first_slope_row + i) and the roller's own (+ Z + i) give contact
// i's gap function at its nominal normal, then its curvature d2(dg_i)/dphi2 from each
// (+ 2Z + i, + 3Z + i).
// Every error term p adds cosine_p cos(rate_p psi) + sine_p sin(rate_p psi), the real
// part of v_p e^{-i rate_p psi} with v_p = cosine_p + i sine_p.
struct Linearisation {
  std::shared_ptr<const NominalResponse> nominal;
  Eigen::VectorXd offset;            // y at psi-independent errors: y0 + Y dg_constant; slopes 0
  Eigen::MatrixXd cosine;            // outputs x terms
  Eigen::MatrixXd sine;              // outputs x terms
  std::vector<double> rates;         // [rad of phase per rad of ring angle]
  std::vector<int> roller;           // per term: the roller whose lobe it is, -1 the bore's
  std::vector<int> order;            // per term: the harmonic's order
  // The same terms as changes of the contacts' gap functions, the only way they reach the
  // outputs: series i < Z the gap value at contact i [m], Z + i the bore's slope there and
  // 2Z + i the roller's [m/rad] (the slope rows above), 3Z + i and 4Z + i their curvatures
  // [m/rad^2]. A term of roller i weighs on three series instead of on every output row,
  // which is what makes EvaluatePath cheap.
  Eigen::MatrixXd series_cosine;     // 5Z x terms
  Eigen::MatrixXd series_sine;       // 5Z x terms
};

// The error-free assembly's response: everything of the linearisation that does not
// depend on the errors, and the costly part (a static solve and a factorisation).
struct NominalResponse {
  engine::Scene perfect;             // the key: the scene without its errors
  Equilibrium equilibrium;           // its static equilibrium, with a status
  int rollers = 0;
  std::vector<int> travel_row;       // row of roller i's travel in y, or -1 (fixed)
  int first_force_row = 0;           // row of roller 0's contact force in y
  int first_slope_row = 0;           // row of contact 0's bore slope (first_force_row + Z)
  std::vector<engine::Contact> contacts;  // at the equilibrium
  Eigen::VectorXd y0;                // outputs at the equilibrium
  // Response of the outputs to each contact's gap value (columns 0..Z-1) and gap slope
  // (Z..2Z-1).
  Eigen::MatrixXd response;
  // The same applied to Linearisation's series: [value, bore slope, roller slope] columns
  // (response's slope columns twice, as both slopes move a contact alike).
  Eigen::MatrixXd series_response;
  // What the second-order terms need of each contact (SecondOrderTerms).
  double ring_radius = 0.0;                 // [m] the bore's
  std::vector<double> roller_radius;        // [m]
  std::vector<double> penetration;          // [m] delta at the equilibrium (penalty law; 0 rigid)
  std::vector<double> force_stiffness;      // [N/m] dF/d delta there (penalty law; 0 rigid)
  double exponent = 1.0;                    // [-] of the penalty law
  // What the second-order remainder bound needs: how far the centre moves [m/N] per unit
  // of extra contact force at contact i along its normal and along its tangent (the force
  // balance's neglected terms act as such forces, with their reaction on a spring roller).
  std::vector<double> normal_force_gain;
  std::vector<double> tangent_force_gain;
  Eigen::MatrixXd force_response;           // outputs x 2Z: to a unit force along n_i, then t_i
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
  nominal->first_slope_row = nominal->first_force_row + z;
  nominal->ring_radius = scene.ring.inner.radius();
  nominal->exponent = scene.contact.exponent;
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
      nominal->penetration.push_back(0.0);
      nominal->force_stiffness.push_back(0.0);
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
      nominal->penetration.push_back(std::max(-c.gap, 0.0));
      nominal->force_stiffness.push_back(stiffness);
    }
    nominal->roller_radius.push_back(scene.rollers[static_cast<std::size_t>(i)].outline.radius());
  }
  // An extra force f at contact i pushes the ring by f and its spring roller back by it;
  // the outputs' response to it along the normal (columns 0..Z-1) and the tangent
  // (Z..2Z-1). A penalty contact's force row is its law's, k delta^e, at the moved gap.
  Eigen::MatrixXd extra = Eigen::MatrixXd::Zero(system.size(), 2 * z);
  for (int i = 0; i < z; ++i) {
    const engine::Contact& c = nominal->contacts[static_cast<std::size_t>(i)];
    const int s = system.travel_index(i);
    extra.block<2, 1>(0, i) = c.normal;
    extra.block<2, 1>(0, z + i) = c.tangent;
    if (s >= 0) {
      extra(s, i) = -c.normal.dot(engine::SpringAxis(scene, i));
      extra(s, z + i) = -c.tangent.dot(engine::SpringAxis(scene, i));
    }
  }
  const Eigen::MatrixXd moved = -lu.solve(extra);
  nominal->force_response = Eigen::MatrixXd::Zero(outputs, 2 * z);
  nominal->force_response.topRows<2>() = moved.topRows<2>();
  for (int i = 0; i < z; ++i) {
    const engine::Contact& c = nominal->contacts[static_cast<std::size_t>(i)];
    const int s = system.travel_index(i);
    if (s >= 0) nominal->force_response.row(s) = moved.row(s);
    const int f = nominal->first_force_row + i;
    if (system.rigid()) {
      nominal->force_response.row(f) = moved.row(system.force_index(i));
    } else {
      Eigen::RowVectorXd gap_gradient = Eigen::RowVectorXd::Zero(system.size());
      gap_gradient.head<2>() = c.normal.transpose();
      if (s >= 0) gap_gradient[s] = -engine::SpringAxis(scene, i).dot(c.normal);
      nominal->force_response.row(f) = -nominal->force_stiffness[static_cast<std::size_t>(i)] * gap_gradient * moved;
    }
    nominal->normal_force_gain.push_back(nominal->force_response.block<2, 1>(0, i).norm());
    nominal->tangent_force_gain.push_back(nominal->force_response.block<2, 1>(0, z + i).norm());
  }
  nominal->series_response.resize(outputs, 5 * z);
  nominal->series_response << response, response.rightCols(z), Eigen::MatrixXd::Zero(outputs, 2 * z);
  return nominal;
}

Linearisation Linearise(const Scene& scene, std::shared_ptr<const NominalResponse> nominal_response) {
  Linearisation lin;
  lin.nominal = std::move(nominal_response);
  const NominalResponse& nominal = *lin.nominal;
  if (nominal.equilibrium.status != Status::kOk) return lin;
  const int z = nominal.rollers;
  const Eigen::MatrixXd& response = nominal.response;
  const engine::PolarProfile& ring = scene.ring.inner;

  Eigen::Index terms = 0;
  for (int n = 1; n <= ring.max_order(); ++n) terms += ring.cos_coefficient(n) != 0.0 || ring.sin_coefficient(n) != 0.0;
  for (const engine::Roller& roller : scene.rollers) {
    for (int m = 1; m <= roller.outline.max_order(); ++m) {
      terms += roller.outline.cos_coefficient(m) != 0.0 || roller.outline.sin_coefficient(m) != 0.0;
    }
  }
  const Eigen::Index rows = nominal.first_slope_row + 4 * z;
  lin.cosine.setZero(rows, terms);
  lin.sine.setZero(rows, terms);
  lin.series_cosine.setZero(5 * z, terms);
  lin.series_sine.setZero(5 * z, terms);
  lin.rates.reserve(static_cast<std::size_t>(terms));

  // Every error term as a change of each contact's gap function near its nominal
  // direction phi_i: a bore harmonic a e^{i n theta} adds Re[a e^{i n (phi - psi)}] to
  // g_i(phi), with slope Re[i n a e^{i n (phi - psi)}] and curvature -n^2 times the value;
  // a roller harmonic subtracts. slope_series: Z + i for the bore's, 2Z + i for the
  // roller's; their curvatures' 2Z further (Linearisation).
  auto add_gap_and_slope = [&](Eigen::Index p, int i, Complex value, double order, Eigen::Index slope_series) {
    const Complex slope = Complex(0.0, order) * value;
    const Complex curvature = -order * order * value;
    const Eigen::Index curvature_series = slope_series + 2 * z;
    const Eigen::Index outputs = response.rows();
    const Eigen::Index slope_row = nominal.first_slope_row + slope_series - z;
    lin.cosine.col(p).head(outputs) += value.real() * response.col(i) + slope.real() * response.col(z + i);
    lin.sine.col(p).head(outputs) += value.imag() * response.col(i) + slope.imag() * response.col(z + i);
    lin.cosine(slope_row, p) += slope.real();
    lin.sine(slope_row, p) += slope.imag();
    lin.cosine(slope_row + 2 * z, p) += curvature.real();
    lin.sine(slope_row + 2 * z, p) += curvature.imag();
    lin.series_cosine(curvature_series, p) += curvature.real();
    lin.series_sine(curvature_series, p) += curvature.imag();
    lin.series_cosine(i, p) += value.real();
    lin.series_sine(i, p) += value.imag();
    lin.series_cosine(slope_series, p) += slope.real();
    lin.series_sine(slope_series, p) += slope.imag();
  };
  Eigen::Index p = 0;
  // e^{i n phi_i} as powers of the nominal normal (cos phi_i, sin phi_i): no libm per order.
  std::vector<Complex> normal(static_cast<std::size_t>(z)), normal_power(static_cast<std::size_t>(z), 1.0);
  for (int i = 0; i < z; ++i) {
    const Eigen::Vector2d& n_i = nominal.contacts[static_cast<std::size_t>(i)].normal;
    normal[static_cast<std::size_t>(i)] = Complex(n_i.x(), n_i.y());
  }
  for (int n = 1; n <= ring.max_order(); ++n) {
    for (std::size_t i = 0; i < normal.size(); ++i) normal_power[i] *= normal[i];
    const Complex a(ring.cos_coefficient(n), ring.sin_coefficient(n));
    if (a == Complex(0.0)) continue;
    for (int i = 0; i < z; ++i) {
      add_gap_and_slope(p, i, a * normal_power[static_cast<std::size_t>(i)], n, z + i);
    }
    lin.rates.push_back(n);
    lin.roller.push_back(-1);
    lin.order.push_back(n);
    ++p;
  }
  Eigen::VectorXd constant(2 * z);
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
      add_gap_and_slope(p, i, -a * std::polar(1.0, m * (c.normal_angle - body0)), m, 2 * z + i);
      lin.rates.push_back(m * engine::SpinRatio(scene, i));
      lin.roller.push_back(i);
      lin.order.push_back(m);
      ++p;
    }
  }
  lin.offset = Eigen::VectorXd::Zero(rows);
  lin.offset.head(response.rows()) = nominal.y0 + response * constant;
  return lin;
}

// Where the path goes: the outputs of angle k (rows as in Linearisation) are stored at
// row[o][k * stride[o]], in the trajectory's own arrays.
struct PathRows {
  std::vector<double*> row;
  std::vector<std::ptrdiff_t> stride;
};

constexpr int kLanes = static_cast<int>(path_kernels::kLanes);

// cos(rate psi_k) and sin(rate psi_k) of a set of terms for consecutive angles
// psi_k = 2 pi k / steps, kLanes at a time: each term's phasor at the first angle of a
// group times its turns by 0 .. kLanes - 1 increments (independent products, which
// vectorise), and then turned by kLanes increments for the next group. The turns are
// powers of one libm phasor, exact to ~kLanes ulp; every kAnchor angles the phasors
// restart from libm, so the recurrence's round-off never grows beyond ~1e-13.
class PhasorRun {
 public:
  static constexpr int kAnchor = 512;  // a multiple of kLanes

  PhasorRun(std::vector<double> rates, int steps, const path_kernels::Kernels& kernels)
      : rates_(std::move(rates)), steps_(steps), kernels_(kernels) {
    const double dpsi = 2.0 * std::numbers::pi / steps;
    const std::size_t t = rates_.size();
    lane_cos_.resize(t * kLanes);
    lane_sin_.resize(t * kLanes);
    for (std::size_t p = 0; p < t; ++p) {
      double* lane_cos = lane_cos_.data() + p * kLanes;
      double* lane_sin = lane_sin_.data() + p * kLanes;
      lane_cos[0] = 1.0;
      lane_sin[0] = 0.0;
      lane_cos[1] = std::cos(rates_[p] * dpsi);
      lane_sin[1] = std::sin(rates_[p] * dpsi);
      for (int l = 2; l < kLanes; ++l) {
        lane_cos[l] = lane_cos[l - 1] * lane_cos[1] - lane_sin[l - 1] * lane_sin[1];
        lane_sin[l] = lane_sin[l - 1] * lane_cos[1] + lane_cos[l - 1] * lane_sin[1];
      }
      group_cos_.push_back(lane_cos[kLanes - 1] * lane_cos[1] - lane_sin[kLanes - 1] * lane_sin[1]);
      group_sin_.push_back(lane_sin[kLanes - 1] * lane_cos[1] + lane_cos[kLanes - 1] * lane_sin[1]);
    }
    cos_.resize(t);
    sin_.resize(t);
  }

  // Fills the table for angles k = first + j, j < count (both multiples of kLanes): term
  // p's cosines at table[2 p count + j], its sines at table[(2 p + 1) count + j].
  void Fill(int first, int count, std::vector<double>& table) {
    const std::size_t t = rates_.size();
    const auto c = static_cast<std::size_t>(count);
    table.resize(2 * t * c);
    const path_kernels::Phasors phasors{t,
                                        lane_cos_.data(),
                                        lane_sin_.data(),
                                        group_cos_.data(),
                                        group_sin_.data(),
                                        cos_.data(),
                                        sin_.data()};
    for (int j = 0; j < count; j += kLanes) {
      const int k = first + j;
      if (k % kAnchor == 0 || k != next_) Anchor(k);
      next_ = k + kLanes;
      kernels_.turn_phasors(phasors, table.data() + j, 2 * c, c);
    }
  }

 private:
  void Anchor(int k) {
    if (k == 0) {
      std::fill(cos_.begin(), cos_.end(), 1.0);
      std::fill(sin_.begin(), sin_.end(), 0.0);
      return;
    }
    for (std::size_t p = 0; p < rates_.size(); ++p) {
      // An integer rate's phase reduced exactly to one turn first: libm is then exact to
      // an ulp of an angle below 2 pi.
      const double rate = rates_[p];
      const double turns = std::floor(rate) == rate && std::abs(rate) < 1e9
                               ? std::fmod(rate * k, static_cast<double>(steps_)) / steps_
                               : rate * k / steps_;
      cos_[p] = std::cos(2.0 * std::numbers::pi * turns);
      sin_[p] = std::sin(2.0 * std::numbers::pi * turns);
    }
  }

  std::vector<double> rates_;
  int steps_;
  const path_kernels::Kernels& kernels_;
  int next_ = -1;  // the angle the phasors stand at
  std::vector<double> lane_cos_, lane_sin_;    // turns by 0 .. kLanes - 1 increments, per term
  std::vector<double> group_cos_, group_sin_;  // turn by kLanes increments, per term
  std::vector<double> cos_, sin_;              // phasors at angle next_
};

// Weights of a set of rows over a set of terms, row-major with the terms contiguous, and
// per row the range of terms [first, last) outside which its weights are zero: a contact's
// series see only the bore's and that one roller's terms.
struct TermGroup {
  std::size_t terms = 0;
  std::vector<double> weights;
  std::vector<std::size_t> first, last;
  path_kernels::WeightedRows View() const {
    return {first.size(), terms, weights.data(), first.data(), last.data()};
  }
};

// The rows of `matrices` (of equal shape) over the given columns, interleaved: term
// q * matrices.size() + m is column q of matrix m, so that a table with each term's cosine
// and sine rows in turn meets cosine and sine weights in one pass.
TermGroup MakeGroup(std::initializer_list<const Eigen::MatrixXd*> matrices, const std::vector<Eigen::Index>& columns) {
  TermGroup group;
  const Eigen::Index rows = (*matrices.begin())->rows();
  group.terms = columns.size() * matrices.size();
  group.weights.reserve(group.terms * static_cast<std::size_t>(rows));
  for (Eigen::Index o = 0; o < rows; ++o) {
    std::size_t first = group.terms, last = 0, q = 0;
    for (Eigen::Index column : columns) {
      for (const Eigen::MatrixXd* matrix : matrices) {
        const double weight = (*matrix)(o, column);
        group.weights.push_back(weight);
        if (weight != 0.0) {
          first = std::min(first, q);
          last = q + 1;
        }
        ++q;
      }
    }
    group.first.push_back(std::min(first, last));
    group.last.push_back(last);
  }
  return group;
}

std::vector<double> RatesOf(const std::vector<Eigen::Index>& columns, const std::vector<double>& rates) {
  std::vector<double> chosen;
  chosen.reserve(columns.size());
  for (Eigen::Index p : columns) chosen.push_back(rates[static_cast<std::size_t>(p)]);
  return chosen;
}

constexpr int kBlock = 64;  // angles per pass, a multiple of kLanes: the tables stay in L1

}  // namespace

namespace internal {

std::size_t PaddedAngles(int steps) { return (static_cast<std::size_t>(steps) + kLanes) / kLanes * kLanes; }

SeriesFold FoldFor(int steps) {
  // At least one lane group of angles past k = 0 in the folded part.
  if (steps % 2 == 0) return steps / 4 >= kLanes ? SeriesFold::kQuarter : SeriesFold::kNone;
  return (steps - 1) / 2 >= kLanes ? SeriesFold::kHalf : SeriesFold::kNone;
}

// The path at psi_k = 2 pi k / steps, k = 0 .. steps, in three passes.
//  1. The 5Z gap series (Linearisation) of the terms of integer rate: such a term takes
//     the same values at psi and 2 pi - psi up to the sign of its sine, and at psi + pi up
//     to (-1)^w. With steps even, the sums of the even and the odd rates' cosines and
//     sines over the first quarter turn give the whole revolution, four angles from each
//     (a real FFT's first two stages, which for a few harmonics beats the whole
//     transform); with steps odd, psi + pi is no angle of the revolution, and the sums
//     over the first half turn give two angles each.
//  2. The series of the other terms (a roller's lobes pass R / r_b times per turn, rarely
//     an integer), summed at every angle: a roller's term adds to two series only.
//  3. The outputs from the series, offset + series_response x series; the slope rows are
//     series themselves.
// Summing series rather than output rows costs 3 x terms + 3Z x rows products an angle
// instead of rows x terms. The inner loops are path_kernels', whose builds agree bit for
// bit; the rest is the same code whichever runs.
// Passes 1 and 2 of EvaluatePath for any series (rows of cosine and sine, series x terms
// at `rates`): series s at angle k lands in series[s * PaddedAngles(steps) + k].
void SumSeries(const Eigen::MatrixXd& series_cosine, const Eigen::MatrixXd& series_sine, const std::vector<double>& rates,
               int steps, const path_kernels::Kernels& kernels, std::vector<double>& series) {
  const auto series_count = static_cast<std::size_t>(series_cosine.rows());
  const std::size_t padded = PaddedAngles(steps);
  thread_local std::vector<double> table, sums;
  series.resize(series_count * padded);
  // The phasors of `run` over the angles k = 0 .. last, block by block into the table;
  // use(first angle, angles, lanes) reads each block.
  const auto each_block = [&](PhasorRun& run, int last, const auto& use) {
    for (int first = 0; first <= last; first += kBlock) {
      const int count = std::min(kBlock, last + 1 - first);
      const auto c = static_cast<std::size_t>((count + kLanes - 1) / kLanes * kLanes);
      run.Fill(first, static_cast<int>(c), table);
      use(first, count, c);
    }
  };
  const SeriesFold fold = FoldFor(steps);
  std::vector<Eigen::Index> even_columns, odd_columns, direct_columns;
  for (std::size_t p = 0; p < rates.size(); ++p) {
    const double rate = rates[p];
    const auto column = static_cast<Eigen::Index>(p);
    if (fold != SeriesFold::kNone && std::floor(rate) == rate && std::abs(rate) < 1e9) {
      (std::fmod(std::abs(rate), 2.0) == 1.0 ? odd_columns : even_columns).push_back(column);
    } else {
      direct_columns.push_back(column);
    }
  }

  const bool folded = !(even_columns.empty() && odd_columns.empty());
  if (!folded) {
    std::fill(series.begin(), series.end(), 0.0);
  } else {
    // The fold sets every angle of every series; only the padding lanes need a value.
    for (std::size_t s = 0; s < series_count; ++s) {
      std::fill(series.begin() + static_cast<std::ptrdiff_t>(s * padded + static_cast<std::size_t>(steps) + 1),
                series.begin() + static_cast<std::ptrdiff_t>((s + 1) * padded), 0.0);
    }
    std::vector<double> folded_rates = RatesOf(even_columns, rates);
    const std::vector<double> odd_rates = RatesOf(odd_columns, rates);
    folded_rates.insert(folded_rates.end(), odd_rates.begin(), odd_rates.end());
    PhasorRun run(std::move(folded_rates), steps, kernels);
    if (fold == SeriesFold::kQuarter) {
      const TermGroup cos_even = MakeGroup({&series_cosine}, even_columns);
      const TermGroup cos_odd = MakeGroup({&series_cosine}, odd_columns);
      const TermGroup sin_even = MakeGroup({&series_sine}, even_columns);
      const TermGroup sin_odd = MakeGroup({&series_sine}, odd_columns);
      const std::size_t even = even_columns.size();
      // With steps = 2 (mod 4) the quarter turn falls between two angles: k <= steps / 4
      // still reach every angle, and steps / 2 twice from k = 0, with the same sums.
      const int quarter = steps / 4;
      const int half = steps / 2;
      each_block(run, quarter, [&](int first, int count, std::size_t c) {
        sums.resize(4 * series_count * c);
        double* cos_even_sum = sums.data();
        double* cos_odd_sum = cos_even_sum + series_count * c;
        double* sin_even_sum = cos_odd_sum + series_count * c;
        double* sin_odd_sum = sin_even_sum + series_count * c;
        const double* odd_table = table.data() + even * 2 * c;
        kernels.sum_rows(cos_even.View(), table.data(), 2 * c, c, cos_even_sum, c);
        kernels.sum_rows(cos_odd.View(), odd_table, 2 * c, c, cos_odd_sum, c);
        kernels.sum_rows(sin_even.View(), table.data() + c, 2 * c, c, sin_even_sum, c);
        kernels.sum_rows(sin_odd.View(), odd_table + c, 2 * c, c, sin_odd_sum, c);
        for (std::size_t s = 0; s < series_count; ++s) {
          double* row = series.data() + s * padded;
          for (std::size_t j = 0; j < static_cast<std::size_t>(count); ++j) {
            const std::size_t at = s * c + j;
            const double cos_at_psi = cos_even_sum[at] + cos_odd_sum[at];
            const double cos_at_psi_plus_pi = cos_even_sum[at] - cos_odd_sum[at];
            const double sin_at_psi = sin_even_sum[at] + sin_odd_sum[at];
            const double sin_at_psi_plus_pi = sin_even_sum[at] - sin_odd_sum[at];
            const int k = first + static_cast<int>(j);
            row[k] = cos_at_psi + sin_at_psi;
            row[steps - k] = cos_at_psi - sin_at_psi;
            row[half + k] = cos_at_psi_plus_pi + sin_at_psi_plus_pi;
            row[half - k] = cos_at_psi_plus_pi - sin_at_psi_plus_pi;
          }
        }
      });
    } else {
      // Both parities alike, as the table holds them: the even rates, then the odd.
      std::vector<Eigen::Index> integer_columns = std::move(even_columns);
      integer_columns.insert(integer_columns.end(), odd_columns.begin(), odd_columns.end());
      const TermGroup cos_integer = MakeGroup({&series_cosine}, integer_columns);
      const TermGroup sin_integer = MakeGroup({&series_sine}, integer_columns);
      const int half = (steps - 1) / 2;
      each_block(run, half, [&](int first, int count, std::size_t c) {
        sums.resize(2 * series_count * c);
        double* cos_sum = sums.data();
        double* sin_sum = cos_sum + series_count * c;
        kernels.sum_rows(cos_integer.View(), table.data(), 2 * c, c, cos_sum, c);
        kernels.sum_rows(sin_integer.View(), table.data() + c, 2 * c, c, sin_sum, c);
        for (std::size_t s = 0; s < series_count; ++s) {
          double* row = series.data() + s * padded;
          for (std::size_t j = 0; j < static_cast<std::size_t>(count); ++j) {
            const std::size_t at = s * c + j;
            const int k = first + static_cast<int>(j);
            row[k] = cos_sum[at] + sin_sum[at];
            row[steps - k] = cos_sum[at] - sin_sum[at];
          }
        }
      });
    }
  }

  if (!direct_columns.empty()) {
    const TermGroup direct = MakeGroup({&series_cosine, &series_sine}, direct_columns);
    PhasorRun run(RatesOf(direct_columns, rates), steps, kernels);
    each_block(run, steps, [&](int first, int, std::size_t c) {
      sums.resize(series_count * c);
      // The table's rows are each term's cosines and sines in turn, as direct's terms.
      kernels.sum_rows(direct.View(), table.data(), c, c, sums.data(), c);
      for (std::size_t s = 0; s < series_count; ++s) {
        double* row = series.data() + s * padded + first;
        const double* sum = sums.data() + s * c;
        for (std::size_t j = 0; j < c; ++j) row[j] += sum[j];
      }
    });
  }
}

}  // namespace internal

using internal::PaddedAngles;
using internal::SumSeries;

namespace {

void EvaluatePath(const Linearisation& lin, int steps, const path_kernels::Kernels& kernels, PathRows& path) {
  const NominalResponse& nominal = *lin.nominal;
  const auto zs = static_cast<std::size_t>(nominal.rollers);
  const std::size_t series_count = 5 * zs;
  const std::size_t padded = PaddedAngles(steps);
  // Per thread, as SolveRevolution's slopes: 120 bytes an angle for three rollers.
  thread_local std::vector<double> series, sums;
  SumSeries(lin.series_cosine, lin.series_sine, lin.rates, steps, kernels, series);

  const auto outputs = static_cast<std::size_t>(nominal.response.rows());
  std::vector<Eigen::Index> every_series(series_count);
  std::iota(every_series.begin(), every_series.end(), Eigen::Index{0});
  const TermGroup response = MakeGroup({&nominal.series_response}, every_series);
  for (int first = 0; first <= steps; first += kBlock) {
    const int count = std::min(kBlock, steps + 1 - first);
    const auto c = static_cast<std::size_t>((count + kLanes - 1) / kLanes * kLanes);
    sums.resize(outputs * c);
    kernels.sum_rows(response.View(), series.data() + first, padded, c, sums.data(), c);
    for (std::size_t o = 0; o < outputs; ++o) {
      const double offset = lin.offset[static_cast<Eigen::Index>(o)];
      double* at = path.row[o] + first * path.stride[o];
      const std::ptrdiff_t stride = path.stride[o];
      const double* sum = sums.data() + o * c;
      for (int j = 0; j < count; ++j) at[j * stride] = offset + sum[j];
    }
    for (std::size_t s = zs; s < series_count; ++s) {
      const std::size_t o = static_cast<std::size_t>(nominal.first_slope_row) + s - zs;
      double* at = path.row[o] + first * path.stride[o];
      const std::ptrdiff_t stride = path.stride[o];
      const double* slope = series.data() + s * padded + first;
      for (int j = 0; j < count; ++j) at[j * stride] = slope[j];
    }
  }
}

// The phase a term of `rate` [rad per rad of ring angle] has turned through after k of
// `steps` increments, as its cosine and sine: an integer rate's reduced exactly to one
// turn first, so libm sees an angle below 2 pi (as PhasorRun's anchors).
Complex PhaseAt(double rate, long long k, int steps) {
  const double turns = std::floor(rate) == rate && std::abs(rate) < 1e9
                           ? std::fmod(rate * static_cast<double>(k), static_cast<double>(steps)) / steps
                           : rate * static_cast<double>(k) / steps;
  return std::polar(1.0, 2.0 * std::numbers::pi * turns);
}

// The outputs of one angle as an Equilibrium.
void FillEquilibrium(const Linearisation& lin, const Eigen::VectorXd& y, Equilibrium& e) {
  const NominalResponse& nominal = *lin.nominal;
  const int z = nominal.rollers;
  e.centre = y.head<2>();
  e.travel.resize(static_cast<std::size_t>(z));
  e.contact_force.resize(static_cast<std::size_t>(z));
  for (int i = 0; i < z; ++i) {
    const int s = nominal.travel_row[static_cast<std::size_t>(i)];
    e.travel[static_cast<std::size_t>(i)] = s >= 0 ? y(s) : 0.0;
    e.contact_force[static_cast<std::size_t>(i)] = y(nominal.first_force_row + i);
  }
}

}  // namespace

SecondOrderTerms LinearSolver::SecondOrderOf(const Scene& scene, std::shared_ptr<const NominalResponse> nominal) {
  if (nominal == nullptr || nominal->equilibrium.status != Status::kOk) return {};
  const int z = nominal->rollers;
  const auto zs = static_cast<std::size_t>(z);
  SecondOrderScene second;
  second.contacts.resize(zs);
  second.centre0 = nominal->y0.head<2>();
  second.ring_radius = nominal->ring_radius;
  second.exponent = nominal->exponent;
  // The nominal's outputs (its travel rows for spring rollers only) in the second order's
  // rows, and its force responses beside the gap responses.
  second.response = Eigen::MatrixXd::Zero(2 + 2 * z, 3 * z);
  const auto copy_rows = [&](Eigen::Index from, Eigen::Index to) {
    second.response.block(to, 0, 1, z) = nominal->response.block(from, 0, 1, z);
    second.response.block(to, z, 1, 2 * z) = nominal->force_response.row(from);
  };
  copy_rows(0, 0);
  copy_rows(1, 1);
  // |dr| <= |dr0| + sum |C_n|, |dr'| <= sum n |C_n|, |dr'''| <= sum n^3 |C_n|.
  const auto moments = [](const engine::PolarProfile& profile, double& value, double& jerk, double& slope) {
    value = std::abs(profile.mean_deviation());
    jerk = 0.0;
    slope = 0.0;
    for (int n = 1; n <= profile.max_order(); ++n) {
      const double amplitude = std::hypot(profile.cos_coefficient(n), profile.sin_coefficient(n));
      const double order = n;
      value += amplitude;
      jerk += order * order * order * amplitude;
      slope += order * amplitude;
    }
  };
  double unused = 0.0;
  moments(scene.ring.inner, second.ring_value, second.ring_jerk, second.ring_slope_sum);
  for (std::size_t i = 0; i < zs; ++i) {
    const int index = static_cast<int>(i);
    const engine::Contact& c = nominal->contacts[i];
    SecondOrderScene::Contact& k = second.contacts[i];
    k.normal = c.normal;
    k.tangent = c.tangent;
    k.gap_curvature = c.gap_curvature;
    k.roller_radius = nominal->roller_radius[i];
    k.spring = nominal->travel_row[i] >= 0;
    if (k.spring) {
      k.travel0 = nominal->y0[nominal->travel_row[i]];
      copy_rows(nominal->travel_row[i], 2 + index);
    }
    k.force0 = nominal->y0[nominal->first_force_row + index];
    copy_rows(nominal->first_force_row + index, 2 + z + index);
    k.penetration = nominal->penetration[i];
    k.force_stiffness = nominal->force_stiffness[i];
    k.law_scale = std::pow(nominal->penetration[i], nominal->exponent - 1.0);
    k.gap_gain = nominal->response.block<2, 1>(0, index).norm();
    k.normal_force_gain = nominal->normal_force_gain[i];
    k.tangent_force_gain = nominal->tangent_force_gain[i];
    k.axis = engine::SpringAxis(scene, index);
    k.shift = engine::RollerCentre(scene, index) - engine::RollerCentre(nominal->perfect, index);
    moments(scene.rollers[i].outline, k.roller_value, k.roller_jerk, unused);
  }
  return SecondOrderTerms(std::move(second));
}

SecondOrderTerms LinearSolver::SecondOrder(const Scene& scene) const { return SecondOrderOf(scene, Nominal(scene)); }

std::shared_ptr<const NominalResponse> LinearSolver::Nominal(const Scene& scene) const {
  return nominal_.Get(scene,
                      [this](engine::Scene perfect) { return ComputeNominal(std::move(perfect), options_.nominal); });
}

Equilibrium LinearSolver::SolveStatic(const Scene& scene) const {
  const Linearisation lin = Linearise(scene, Nominal(scene));
  if (lin.nominal->equilibrium.status != Status::kOk) return lin.nominal->equilibrium;
  // At psi = 0 every cosine is 1 and every sine 0.
  Equilibrium e;
  const Eigen::VectorXd y = lin.offset + lin.cosine.rowwise().sum();
  FillEquilibrium(lin, y, e);
  const NominalResponse& nominal = *lin.nominal;
  const auto zs = static_cast<std::size_t>(nominal.rollers);
  SecondOrderAngle correction;
  SecondOrderOf(scene, lin.nominal)
      .At({e.centre, e.travel, e.contact_force,
           std::span<const double>(y.data() + nominal.first_slope_row, 2 * zs),
           std::span<const double>(y.data() + nominal.first_slope_row + 2 * nominal.rollers, 2 * zs)},
          correction);
  e.centre += correction.centre;
  for (std::size_t i = 0; i < zs; ++i) {
    e.travel[i] += correction.travel[i];
    e.contact_force[i] += correction.contact_force[i];
  }
  ValidityCheck(scene).Check(e);
  return e;
}

ChordStraying LinearSolver::ChordStrayingAt(const Scene& scene, double dpsi) const {
  ChordStraying bounds;
  const Linearisation lin = Linearise(scene, Nominal(scene));
  const NominalResponse& nominal = *lin.nominal;
  if (nominal.equilibrium.status != Status::kOk || !lin.cosine.allFinite() || !lin.sine.allFinite()) return bounds;
  bounds.usable = true;
  const auto zs = static_cast<std::size_t>(nominal.rollers);
  bounds.travel.assign(zs, 0.0);
  bounds.contact_force.assign(zs, 0.0);
  const auto straying = [dpsi](double rate) { return std::min(2.0, rate * rate * dpsi * dpsi / 8.0); };
  const Eigen::Vector2d ray = engine::Direction(scene.sensor_angle);
  for (Eigen::Index p = 0; p < static_cast<Eigen::Index>(lin.rates.size()); ++p) {
    const double s = straying(lin.rates[static_cast<std::size_t>(p)]);
    const auto amplitude = [&](Eigen::Index row) { return std::hypot(lin.cosine(row, p), lin.sine(row, p)); };
    bounds.centre += s * std::hypot(amplitude(0), amplitude(1));
    bounds.signal += s * std::hypot(ray.x() * lin.cosine(0, p) + ray.y() * lin.cosine(1, p),
                                    ray.x() * lin.sine(0, p) + ray.y() * lin.sine(1, p));
    for (std::size_t i = 0; i < zs; ++i) {
      const int travel_row = nominal.travel_row[i];
      if (travel_row >= 0) bounds.travel[i] += s * amplitude(travel_row);
      bounds.contact_force[i] += s * amplitude(nominal.first_force_row + static_cast<Eigen::Index>(i));
    }
  }
  // The bore's own form passes the sensor's ray at rate n.
  const engine::PolarProfile& ring = scene.ring.inner;
  for (int n = 1; n <= ring.max_order(); ++n) {
    bounds.signal += straying(n) * std::hypot(ring.cos_coefficient(n), ring.sin_coefficient(n));
  }
  return bounds;
}

PhasorSum LinearSolver::Phasors(const Scene& scene) const {
  PhasorSum sum;
  Linearisation lin = Linearise(scene, Nominal(scene));
  const NominalResponse& nominal = *lin.nominal;
  if (nominal.equilibrium.status != Status::kOk) return sum;
  sum.usable = true;
  sum.offset = std::move(lin.offset);
  sum.cosine = std::move(lin.cosine);
  sum.sine = std::move(lin.sine);
  sum.rates = std::move(lin.rates);
  sum.roller = std::move(lin.roller);
  sum.order = std::move(lin.order);
  sum.travel_row = nominal.travel_row;
  sum.first_force_row = nominal.first_force_row;
  return sum;
}

// What LinearPath reads beyond the Linearisation: the sensor's two extra series, the sums'
// weights, the phasors kept at the coarse angles and the work buffers.
struct LinearPath::Parts {
  SecondOrderTerms second;
  Eigen::Vector2d ray;             // [-] the sensor's direction e_s
  Eigen::Vector2d across;          // [-] e_s turned a quarter turn: c_t = across . c
  double bore_radius = 0.0;        // [m] R, nominal
  double bore_reach = 0.0;         // [m] R + the bore's mean deviation
  // The gap series (Linearisation::series_*: values, slopes, curvatures) and below them the
  // bore's form at the sensor, its slope and its curvature there [m, m/rad, m/rad^2]: rows
  // 5Z, 5Z + 1 and 5Z + 2.
  Eigen::MatrixXd series_cosine, series_sine;
  TermGroup group;                 // their weights, each term's cosine and sine in turn
  // What StrayingOver reads, set by KeepStretchRows: at the coarse angles, rows 0 .. 2Z + 1
  // the slow terms' d/dpsi of the first-order centre x, y, travels and forces (a term's
  // cosine weight rate x sine, its sine weight -rate x cosine), rows 2Z + 2 .. 4Z + 3 the
  // fast terms' values of the same outputs (row stride coarse_stride), each angle's summed
  // the first time a stretch asks for it (stretch_rows_summed), since few stretches do;
  // and per output the slow terms' Hermite remainders plus the fast terms' amplitudes
  // [m, m, N].
  TermGroup stretch_group;
  std::vector<double> coarse_stretch_rows;
  std::vector<char> stretch_rows_summed;
  double centre_hermite = 0.0;
  std::vector<double> travel_hermite, force_hermite;
  std::vector<double> dense_cos, dense_sin;  // per term: the turn by one angle
  // Buffers whose every element is written before it is read, resized with
  // boost::container::default_init: a sample's new path grows them from nothing, and a
  // std::vector's zero fill of them cost 4 % of a sample.
  using Buffer = boost::container::vector<double>;
  Buffer coarse_table;                       // turn_run's rows at the coarse angles
  std::size_t coarse_stride = 0;             // the coarse table's row stride
  std::vector<double> now_cos, now_sin, turn_cos, turn_sin;
  Buffer table, sums;
  std::vector<int> refined;                  // the angles of a refined stretch
  // FirstOrderAngles' and SecondOrderAngles' rows. AtEach reads two lanes at a time, one
  // past the last angle when their count is odd (and drops what it finds there): the
  // first block keeps std::vector's zero fill, so no lane it reads is indeterminate.
  std::vector<double> first_block;
  Buffer correction_block;
  Eigen::VectorXd values, y;
  path_kernels::Isa kernels = path_kernels::Isa::kBest;

  // Appends the outputs of the table's first `count` lanes (row stride `stride`), which
  // hold the angles `index`.
  void Append(const Linearisation& lin, const double* table_data, std::size_t stride, std::span<const int> index,
              Samples& samples) {
    const NominalResponse& nominal = *lin.nominal;
    const auto zs = static_cast<std::size_t>(nominal.rollers);
    const auto series_count = static_cast<std::size_t>(series_cosine.rows());
    sums.resize(series_count * stride, boost::container::default_init);
    path_kernels::KernelsFor(kernels).sum_rows(group.View(), table_data, stride, stride, sums.data(), stride);
    const Eigen::Index outputs = nominal.response.rows();
    const std::size_t gap_series = 5 * zs;
    const std::size_t count = index.size();
    const std::size_t width = 2 + 6 * zs;  // FirstOrderAngles' rows
    values.resize(static_cast<Eigen::Index>(gap_series));
    // The first-order outputs, angle by angle into At's inputs (the block, and the samples'
    // own angle-major copy); the gap derivatives are series rows Z .. 5Z - 1 as they stand.
    first_block.resize(width * stride);
    for (std::size_t j = 0; j < count; ++j) {
      for (std::size_t s = 0; s < gap_series; ++s) values[static_cast<Eigen::Index>(s)] = sums[s * stride + j];
      y.noalias() = nominal.series_response * values;
      y += lin.offset.head(outputs);
      first_block[j] = y[0];
      first_block[stride + j] = y[1];
      for (std::size_t i = 0; i < zs; ++i) {
        const int row = nominal.travel_row[i];
        first_block[(2 + i) * stride + j] = row >= 0 ? y[row] : 0.0;
        first_block[(2 + zs + i) * stride + j] = y[nominal.first_force_row + static_cast<Eigen::Index>(i)];
      }
    }
    std::copy_n(sums.begin() + static_cast<std::ptrdiff_t>(zs * stride), 4 * zs * stride,
                first_block.begin() + static_cast<std::ptrdiff_t>((2 + 2 * zs) * stride));
    for (std::size_t j = 0; j < count; ++j) {
      for (std::size_t f = 0; f < width; ++f) samples.first_order.push_back(first_block[f * stride + j]);
    }
    // The second order SolveRevolution adds at every angle, for the whole block at once.
    correction_block.resize((3 + 2 * zs) * stride, boost::container::default_init);
    second.AtEach({first_block.data(), stride, count}, {correction_block.data(), stride});
    const auto first = [&](std::size_t f, std::size_t j) { return first_block[f * stride + j]; };
    const auto correction = [&](std::size_t f, std::size_t j) { return correction_block[f * stride + j]; };
    for (std::size_t j = 0; j < count; ++j) {
      const Eigen::Vector2d centre =
          Eigen::Vector2d(first(0, j), first(1, j)) + Eigen::Vector2d(correction(0, j), correction(1, j));
      for (std::size_t i = 0; i < zs; ++i) samples.travel.push_back(first(2 + i, j) + correction(2 + i, j));
      for (std::size_t i = 0; i < zs; ++i) samples.contact_force.push_back(first(2 + zs + i, j) + correction(2 + zs + i, j));
      samples.index.push_back(index[j]);
      samples.centre.push_back(centre);
      samples.remainder.push_back(correction(2 + 2 * zs, j));
      const double form = sums[gap_series * stride + j];
      const double form_slope = sums[(gap_series + 1) * stride + j];
      const double form_curvature = sums[(gap_series + 2) * stride + j];
      // The ray meets the bore where the body angle is theta_s - psi - c_t / r, r the bore's
      // radius there, and the point lies c_t^2 / (2 r) short of r there.
      const double c_t = across.dot(centre);
      const double reach = bore_reach + form;
      const double turn = c_t / reach;
      samples.signal.push_back(ray.dot(centre) + reach - form_slope * turn + 0.5 * form_curvature * turn * turn -
                               c_t * turn / 2.0);
    }
  }
};

void LinearPath::Samples::clear() {
  index.clear();
  centre.clear();
  travel.clear();
  contact_force.clear();
  remainder.clear();
  signal.clear();
  first_order.clear();
}

LinearPath::LinearPath() = default;
LinearPath::LinearPath(LinearPath&&) noexcept = default;
LinearPath& LinearPath::operator=(LinearPath&&) noexcept = default;
LinearPath::~LinearPath() = default;

int LinearPath::rollers() const { return lin_ == nullptr ? 0 : lin_->nominal->rollers; }

void LinearPath::EvaluateCoarse(int stride, Samples& samples) {
  Parts& parts = *parts_;
  stride_ = stride;
  coarse_.clear();
  for (int k = 0; k <= steps_; k += stride) coarse_.push_back(k);
  if (coarse_.back() != steps_) coarse_.push_back(steps_);
  const std::size_t terms = lin_->rates.size();
  const std::size_t count = coarse_.size();
  parts.coarse_stride = (count + kLanes - 1) / kLanes * kLanes;
  // The phasor run fills every lane it is given; the padding lanes, which the sums read too, are
  // zeroed.
  parts.coarse_table.resize(2 * terms * parts.coarse_stride, boost::container::default_init);
  for (std::size_t q = 0; q < 2 * terms; ++q) {
    std::fill_n(parts.coarse_table.begin() + static_cast<std::ptrdiff_t>(q * parts.coarse_stride + count),
                parts.coarse_stride - count, 0.0);
  }
  parts.now_cos.assign(terms, 1.0);
  parts.now_sin.assign(terms, 0.0);
  parts.turn_cos.resize(terms);
  parts.turn_sin.resize(terms);
  // The turn by `stride` angles as a power of the turn by one (a few products, each within
  // an ulp): over the ~400 coarse angles of a revolution the phasors stay within ~1e-13 of
  // libm's, far below what any metric resolves.
  for (std::size_t p = 0; p < terms; ++p) {
    Complex turn(1.0, 0.0);
    Complex power(parts.dense_cos[p], parts.dense_sin[p]);
    for (int e = stride; e > 0; e >>= 1) {
      if (e & 1) turn *= power;
      power *= power;
    }
    parts.turn_cos[p] = turn.real();
    parts.turn_sin[p] = turn.imag();
  }
  // The uniform run k = 0, stride, ...; the revolution's end, when off that run, from libm.
  const int uniform = static_cast<int>(count) - (steps_ % stride == 0 ? 0 : 1);
  path_kernels::KernelsFor(parts.kernels)
      .turn_run(terms, parts.now_cos.data(), parts.now_sin.data(), parts.turn_cos.data(), parts.turn_sin.data(),
                static_cast<std::size_t>(uniform), parts.coarse_table.data(), parts.coarse_stride);
  if (uniform < static_cast<int>(count)) {
    for (std::size_t p = 0; p < terms; ++p) {
      const Complex end = PhaseAt(lin_->rates[p], steps_, steps_);
      parts.coarse_table[2 * p * parts.coarse_stride + count - 1] = end.real();
      parts.coarse_table[(2 * p + 1) * parts.coarse_stride + count - 1] = end.imag();
    }
  }
  parts.Append(*lin_, parts.coarse_table.data(), parts.coarse_stride, coarse_, samples);
}

// A term a cos(w psi + phase) is fast over a stretch dpsi long where w dpsi > 2 sqrt(2): its
// chord bound w^2 dpsi^2 / 8 would exceed its amplitude, which bounds it from zero.
// A slow term less its cubic Hermite interpolant H is at most max|f''''| dpsi^4 / 384 (the
// interpolation remainder f''''(xi) (psi - psi_a)^2 (psi - psi_b)^2 / 4!, whose polynomial
// peaks at dpsi^4 / 16 mid-way), a w^4 dpsi^4 / 384 <= a / 6. For the centre's pair of rows
// each row obeys its own bound, so the pair's, with the pair's amplitude norm(|a_x|, |a_y|),
// which also bounds the pair's value.
void LinearPath::KeepStretchRows() {
  const int stride = stride_;
  Parts& parts = *parts_;
  const Linearisation& lin = *lin_;
  const NominalResponse& nominal = *lin.nominal;
  const int z = nominal.rollers;
  const auto zs = static_cast<std::size_t>(z);
  const auto terms = static_cast<Eigen::Index>(lin.rates.size());
  const double span = stride * 2.0 * std::numbers::pi / steps_;
  const Eigen::Index outputs = 2 + 2 * z;
  // Output r's row in the linearisation, -1 for a fixed roller's travel.
  const auto row_of = [&](Eigen::Index r) -> Eigen::Index {
    if (r < 2) return r;
    if (r < 2 + z) return nominal.travel_row[static_cast<std::size_t>(r - 2)];
    return nominal.first_force_row + r - 2 - z;
  };
  Eigen::MatrixXd cosine = Eigen::MatrixXd::Zero(2 * outputs, terms);
  Eigen::MatrixXd sine = Eigen::MatrixXd::Zero(2 * outputs, terms);
  parts.centre_hermite = 0.0;
  parts.travel_hermite.assign(zs, 0.0);
  parts.force_hermite.assign(zs, 0.0);
  const auto norm = [](double x, double y) { return std::sqrt(x * x + y * y); };
  for (Eigen::Index q = 0; q < terms; ++q) {
    const double rate = lin.rates[static_cast<std::size_t>(q)];
    const double turn = std::abs(rate) * span;
    const bool fast = turn > 2.0 * std::numbers::sqrt2;
    const double weight = fast ? 1.0 : turn * turn * turn * turn / 384.0;
    std::array<double, 2> centre{};
    for (Eigen::Index r = 0; r < outputs; ++r) {
      const Eigen::Index row = row_of(r);
      if (row < 0) continue;
      if (fast) {
        cosine(outputs + r, q) = lin.cosine(row, q);
        sine(outputs + r, q) = lin.sine(row, q);
      } else {
        cosine(r, q) = rate * lin.sine(row, q);
        sine(r, q) = -rate * lin.cosine(row, q);
      }
      const double amplitude = weight * norm(lin.cosine(row, q), lin.sine(row, q));
      if (r < 2) {
        centre[static_cast<std::size_t>(r)] = amplitude;
      } else if (r < 2 + z) {
        parts.travel_hermite[static_cast<std::size_t>(r - 2)] += amplitude;
      } else {
        parts.force_hermite[static_cast<std::size_t>(r - 2 - z)] += amplitude;
      }
    }
    parts.centre_hermite += norm(centre[0], centre[1]);
  }
  std::vector<Eigen::Index> columns(static_cast<std::size_t>(terms));
  std::iota(columns.begin(), columns.end(), Eigen::Index{0});
  parts.stretch_group = MakeGroup({&cosine, &sine}, columns);
  parts.coarse_stretch_rows.resize(static_cast<std::size_t>(2 * outputs) * parts.coarse_stride);
  parts.stretch_rows_summed.assign(coarse_.size(), 0);
}

void LinearPath::Refine(int j, Samples& samples) {
  Parts& parts = *parts_;
  const int first = coarse_[static_cast<std::size_t>(j)] + 1;
  const int count = coarse_[static_cast<std::size_t>(j) + 1] - first;
  if (count <= 0) return;
  const std::size_t terms = lin_->rates.size();
  // The phasors one angle past coarse angle j: its kept phasors turned once.
  for (std::size_t p = 0; p < terms; ++p) {
    const double c = parts.coarse_table[2 * p * parts.coarse_stride + static_cast<std::size_t>(j)];
    const double s = parts.coarse_table[(2 * p + 1) * parts.coarse_stride + static_cast<std::size_t>(j)];
    parts.now_cos[p] = c * parts.dense_cos[p] - s * parts.dense_sin[p];
    parts.now_sin[p] = s * parts.dense_cos[p] + c * parts.dense_sin[p];
  }
  const std::size_t stride = (static_cast<std::size_t>(count) + kLanes - 1) / kLanes * kLanes;
  parts.table.resize(2 * terms * stride, boost::container::default_init);
  // The padding lanes, which the sums read too, are zero: each row's last lane group is
  // zeroed whole (a store of fixed size, where the padding's own size took a call to
  // memset a row) before the run sets its angles.
  for (std::size_t q = 1; q <= 2 * terms; ++q) {
    std::fill_n(parts.table.begin() + static_cast<std::ptrdiff_t>(q * stride - kLanes), kLanes, 0.0);
  }
  path_kernels::KernelsFor(parts.kernels)
      .turn_run(terms, parts.now_cos.data(), parts.now_sin.data(), parts.dense_cos.data(), parts.dense_sin.data(),
                static_cast<std::size_t>(count), parts.table.data(), stride);
  parts.refined.resize(static_cast<std::size_t>(count));
  std::iota(parts.refined.begin(), parts.refined.end(), first);
  parts.Append(*lin_, parts.table.data(), stride, parts.refined, samples);
}

const SecondOrderTerms& LinearPath::second_order() const { return parts_->second; }

double LinearPath::EstimateFrom(double largest_remainder, double farthest) const {
  return parts_->second.EstimateFrom(largest_remainder, farthest);
}

void LinearPath::FirstOrderSignal(std::vector<double>& signal) const {
  const Parts& parts = *parts_;
  const auto zs = static_cast<std::size_t>(lin_->nominal->rollers);
  // One series: e_s . (the centre's terms) + the form at the sensor.
  const Eigen::MatrixXd cosine = parts.ray.transpose() * lin_->cosine.topRows<2>() + parts.series_cosine.row(static_cast<Eigen::Index>(5 * zs));
  const Eigen::MatrixXd sine = parts.ray.transpose() * lin_->sine.topRows<2>() + parts.series_sine.row(static_cast<Eigen::Index>(5 * zs));
  SumSeries(cosine, sine, lin_->rates, steps_, path_kernels::KernelsFor(parts.kernels), signal);
  signal.resize(static_cast<std::size_t>(steps_) + 1);
  const double offset = parts.ray.dot(lin_->offset.head<2>()) + parts.bore_reach;
  for (double& value : signal) value += offset;
}

void LinearPath::FirstOrderWithoutLobes(std::vector<Eigen::Vector2d>& centre, std::vector<double>& signal) const {
  const Parts& parts = *parts_;
  const auto zs = static_cast<std::size_t>(lin_->nominal->rollers);
  std::vector<Eigen::Index> bore;
  for (std::size_t p = 0; p < lin_->rates.size(); ++p) {
    if (lin_->roller[p] < 0) bore.push_back(static_cast<Eigen::Index>(p));
  }
  const auto count = static_cast<Eigen::Index>(bore.size());
  // Rows x, y and the signal (e_s . centre + the form at the sensor) in one series.
  Eigen::MatrixXd cosine(3, count), sine(3, count);
  std::vector<double> rates(bore.size());
  const auto form = static_cast<Eigen::Index>(5 * zs);
  for (Eigen::Index q = 0; q < count; ++q) {
    const Eigen::Index p = bore[static_cast<std::size_t>(q)];
    cosine.col(q).head<2>() = lin_->cosine.col(p).head<2>();
    sine.col(q).head<2>() = lin_->sine.col(p).head<2>();
    cosine(2, q) = parts.ray.dot(lin_->cosine.col(p).head<2>()) + parts.series_cosine(form, p);
    sine(2, q) = parts.ray.dot(lin_->sine.col(p).head<2>()) + parts.series_sine(form, p);
    rates[static_cast<std::size_t>(q)] = lin_->rates[static_cast<std::size_t>(p)];
  }
  thread_local std::vector<double> rows;
  SumSeries(cosine, sine, rates, steps_, path_kernels::KernelsFor(parts.kernels), rows);
  const std::size_t padded = PaddedAngles(steps_);
  const auto angles = static_cast<std::size_t>(steps_) + 1;
  centre.resize(angles);
  signal.resize(angles);
  const double offset = parts.ray.dot(lin_->offset.head<2>()) + parts.bore_reach;
  for (std::size_t k = 0; k < angles; ++k) {
    centre[k] = lin_->offset.head<2>() + Eigen::Vector2d(rows[k], rows[padded + k]);
    signal[k] = offset + rows[2 * padded + k];
  }
}

PhasorSum LinearPath::Phasors() const {
  PhasorSum sum;
  sum.usable = true;
  sum.offset = lin_->offset;
  sum.cosine = lin_->cosine;
  sum.sine = lin_->sine;
  sum.rates = lin_->rates;
  sum.roller = lin_->roller;
  sum.order = lin_->order;
  sum.travel_row = lin_->nominal->travel_row;
  sum.first_force_row = lin_->nominal->first_force_row;
  return sum;
}

LinearPath::Straying LinearPath::StrayingAt(double dpsi) const {
  const Parts& parts = *parts_;
  const Linearisation& lin = *lin_;
  const NominalResponse& nominal = *lin.nominal;
  const auto zs = static_cast<std::size_t>(nominal.rollers);
  const std::size_t terms = lin.rates.size();
  Straying bounds;
  bounds.travel.assign(zs, 0.0);
  bounds.contact_force.assign(zs, 0.0);
  bounds.slopes.assign(2 * zs, 0.0);
  bounds.curvatures.assign(2 * zs, 0.0);
  bounds.slope_reach.assign(2 * zs, 0.0);
  bounds.curvature_reach.assign(2 * zs, 0.0);
  const auto straying = [dpsi](double rate) { return std::min(2.0, rate * rate * dpsi * dpsi / 8.0); };
  // sqrt, not hypot: amplitudes of micrometres and newtons neither overflow nor underflow
  // when squared, and hypot's care costs more than the rest of the bounds.
  const auto norm = [](double x, double y) { return std::sqrt(x * x + y * y); };
  const auto amplitude = [&](const Eigen::MatrixXd& cosine, const Eigen::MatrixXd& sine, Eigen::Index row, Eigen::Index p) {
    return norm(cosine(row, p), sine(row, p));
  };
  // The sensor's rest -r' t + r'' t^2 / 2 - c_t t / 2 (t = c_t / r) strays by at most
  // twice its size, which the sums of its factors' amplitudes bound (r >= R / 2 for any
  // bore that can be simulated).
  double form_slope = 0.0;
  double form_curvature = 0.0;
  double across = std::abs(parts.across.dot(lin.offset.head<2>()));
  const auto form_slope_row = static_cast<Eigen::Index>(5 * zs + 1);
  const auto form_curvature_row = static_cast<Eigen::Index>(5 * zs + 2);
  for (std::size_t q = 0; q < terms; ++q) {
    const auto p = static_cast<Eigen::Index>(q);
    const double s = straying(lin.rates[q]);
    bounds.centre += s * norm(amplitude(lin.cosine, lin.sine, 0, p), amplitude(lin.cosine, lin.sine, 1, p));
    form_slope += amplitude(parts.series_cosine, parts.series_sine, form_slope_row, p);
    form_curvature += amplitude(parts.series_cosine, parts.series_sine, form_curvature_row, p);
    across += norm(parts.across.dot(lin.cosine.col(p).head<2>()), parts.across.dot(lin.sine.col(p).head<2>()));
    for (std::size_t i = 0; i < zs; ++i) {
      const int travel_row = nominal.travel_row[i];
      if (travel_row >= 0) bounds.travel[i] += s * amplitude(lin.cosine, lin.sine, travel_row, p);
      bounds.contact_force[i] += s * amplitude(lin.cosine, lin.sine, nominal.first_force_row + static_cast<Eigen::Index>(i), p);
    }
    // The gap series' slope rows Z .. 3Z - 1 and curvature rows 3Z .. 5Z - 1 (Linearisation).
    for (std::size_t r = 0; r < 2 * zs; ++r) {
      const double slope = amplitude(parts.series_cosine, parts.series_sine, static_cast<Eigen::Index>(zs + r), p);
      const double curvature = amplitude(parts.series_cosine, parts.series_sine, static_cast<Eigen::Index>(3 * zs + r), p);
      bounds.slopes[r] += s * slope;
      bounds.curvatures[r] += s * curvature;
      bounds.slope_reach[r] += slope;
      bounds.curvature_reach[r] += curvature;
    }
  }
  const double turn = across / (0.5 * parts.bore_radius);
  bounds.signal_rest = 2.0 * (form_slope * turn + form_curvature * turn * turn / 2.0 + across * turn / 2.0);
  return bounds;
}

namespace {

// max over t in [0, 1] of |a t (1 - t)^2 + b t^2 (1 - t)|: the polynomial vanishes at both
// ends, so it peaks where its derivative 3 (a - b) t^2 + (2 b - 4 a) t + a vanishes (real
// roots, by Rolle; a discriminant rounded below zero is a double root). The roots are taken
// in the form that does not cancel; a root off by an ulp moves the peak by its square.
double CubicPeak(double a, double b) {
  const auto at = [&](double t) { return std::abs(t * (1.0 - t) * ((1.0 - t) * a + t * b)); };
  const double quadratic = 3.0 * (a - b);
  const double linear = 2.0 * b - 4.0 * a;
  double peak = 0.0;
  const auto consider = [&](double t) {
    if (t > 0.0 && t < 1.0) peak = std::max(peak, at(t));
  };
  const double root = std::sqrt(std::max(0.0, linear * linear - 4.0 * quadratic * a));
  const double half = -0.5 * (linear + std::copysign(root, linear));
  if (half != 0.0) consider(a / half);
  if (quadratic != 0.0) consider(half / quadratic);
  return peak;
}

}  // namespace

// The cubic Hermite bound (docs/model.md §5). Over a stretch of length h the slow part f_S
// (the outputs less the fast part f_F, whose values at the ends the stretch rows hold) has
// ends f0, f1 and slopes m0, m1; the cubic H with those values and slopes less their chord
// L is, at t = (psi - psi_a) / h,
//   H - L = h (t (1 - t)^2 (m0 - d) - t^2 (1 - t) (m1 - d)),   d = (f1 - f0) / h
// (the Hermite basis: H = h00 f0 + h01 f1 + h (h10 m0 + h11 m1), h01 - t = -t (1 - t)
// (1 - 2t) = -(h00 - (1 - t)), h10 = t (1 - t)^2, h11 = -t^2 (1 - t)), so |H - L| <=
// h CubicPeak(m0 - d, d - m1) for one row and h CubicPeak(|m0 - d|, |m1 - d|) for the
// centre's pair. H is linear in the path, so f_S - H is the sum over the slow terms of each
// less its own cubic; with |f_F| <= the fast amplitudes, the outputs lie within
// |H - L| + KeepStretchRows' remainders of L, the chord through the ends less f_F there.
// Where that is not below the chord bound the chord is kept, shifts zero; where the
// remainders alone are not, the cubic's peak is not sought.
void LinearPath::StrayingOver(const Samples& samples, std::size_t j, const Straying& straying,
                              StretchStraying& out) const {
  Parts& parts = *parts_;  // the rows' cache
  const auto zs = static_cast<std::size_t>(rollers());
  const std::size_t width = FirstOrderWidth();
  const std::size_t outputs = 2 + 2 * zs;
  const double h = (coarse_[j + 1] - coarse_[j]) * 2.0 * std::numbers::pi / steps_;
  const double* first_a = samples.first_order.data() + j * width;
  const double* first_b = samples.first_order.data() + (j + 1) * width;
  double* rows = parts.coarse_stretch_rows.data();
  const std::size_t stride = parts.coarse_stride;
  const TermGroup& group = parts.stretch_group;
  for (const std::size_t at : {j, j + 1}) {
    if (parts.stretch_rows_summed[at] != 0) continue;
    parts.stretch_rows_summed[at] = 1;
    for (std::size_t r = 0; r < 2 * outputs; ++r) {
      double sum = 0.0;
      const double* weight = group.weights.data() + r * group.terms;
      for (std::size_t q = group.first[r]; q < group.last[r]; ++q) sum += weight[q] * parts.coarse_table[q * stride + at];
      rows[r * stride + at] = sum;
    }
  }
  const auto slope = [&](std::size_t r, std::size_t at) { return rows[r * stride + at]; };
  const auto fast = [&](std::size_t r, std::size_t at) { return rows[(outputs + r) * stride + at]; };
  // Row r's slow slope less the slow chord's, at each end.
  const auto gaps = [&](std::size_t r) {
    const double chord = ((first_b[r] - fast(r, j + 1)) - (first_a[r] - fast(r, j))) / h;
    return std::pair(slope(r, j) - chord, slope(r, j + 1) - chord);
  };
  const auto norm = [](double x, double y) { return std::sqrt(x * x + y * y); };
  double centre = parts.centre_hermite;
  if (centre < straying.centre) {
    const auto [xa, xb] = gaps(0);
    const auto [ya, yb] = gaps(1);
    centre += h * CubicPeak(norm(xa, ya), norm(xb, yb));
  }
  const bool centre_hermite = centre < straying.centre;
  out.centre = centre_hermite ? centre : straying.centre;
  for (std::size_t end = 0; end < 2; ++end) {
    out.centre_shift[end] = centre_hermite ? Eigen::Vector2d(fast(0, j + end), fast(1, j + end)) : Eigen::Vector2d::Zero();
  }
  out.travel.resize(zs);
  out.contact_force.resize(zs);
  out.travel_shift.resize(2 * zs);
  out.force_shift.resize(2 * zs);
  const auto choose = [&](std::size_t r, double hermite, double chord, double& bound, double* shift) {
    double cubic = hermite;
    if (cubic < chord) {
      const auto [a, b] = gaps(r);
      cubic += h * CubicPeak(a, -b);
    }
    const bool use = cubic < chord;
    bound = use ? cubic : chord;
    shift[0] = use ? fast(r, j) : 0.0;
    shift[zs] = use ? fast(r, j + 1) : 0.0;
  };
  for (std::size_t i = 0; i < zs; ++i) {
    choose(2 + i, parts.travel_hermite[i], straying.travel[i], out.travel[i], out.travel_shift.data() + i);
    choose(2 + zs + i, parts.force_hermite[i], straying.contact_force[i], out.contact_force[i],
           out.force_shift.data() + i);
  }
}

std::size_t LinearPath::FirstOrderWidth() const { return 2 + 6 * static_cast<std::size_t>(rollers()); }

void LinearPath::RangeOver(const Samples& samples, std::size_t first, std::size_t last, const Straying& straying,
                           FirstOrderRange& range) const {
  const auto zs = static_cast<std::size_t>(rollers());
  const std::size_t width = FirstOrderWidth();
  // Every stretch's chord lies inside the circle enclosing the run's centres (a disc is
  // convex), so each stretch's points lie within straying of that circle.
  thread_local std::vector<Eigen::Vector2d> centres;
  centres.clear();
  for (std::size_t k = first; k <= last; ++k) centres.emplace_back(samples.first_order[k * width], samples.first_order[k * width + 1]);
  const engine::Circle circle = engine::MinimumEnclosingCircle(centres);
  range.centre = circle.centre;
  range.centre_radius = circle.radius + straying.centre;
  const auto cover = [&](std::size_t offset, std::size_t count, const std::vector<double>& margin,
                         std::vector<double>& low, std::vector<double>& high) {
    low.assign(count, std::numeric_limits<double>::infinity());
    high.assign(count, -std::numeric_limits<double>::infinity());
    for (std::size_t k = first; k <= last; ++k) {
      const double* at = samples.first_order.data() + k * width + offset;
      for (std::size_t j = 0; j < count; ++j) {
        low[j] = std::min(low[j], at[j]);
        high[j] = std::max(high[j], at[j]);
      }
    }
    for (std::size_t j = 0; j < count; ++j) {
      low[j] -= margin[j];
      high[j] += margin[j];
    }
  };
  cover(2, zs, straying.travel, range.travel_low, range.travel_high);
  cover(2 + zs, zs, straying.contact_force, range.force_low, range.force_high);
  cover(2 + 2 * zs, 2 * zs, straying.slopes, range.slope_low, range.slope_high);
  cover(2 + 4 * zs, 2 * zs, straying.curvatures, range.curvature_low, range.curvature_high);
  // The gap derivatives have no constant term, so they never leave +-their reach.
  for (std::size_t j = 0; j < 2 * zs; ++j) {
    range.slope_low[j] = std::max(range.slope_low[j], -straying.slope_reach[j]);
    range.slope_high[j] = std::min(range.slope_high[j], straying.slope_reach[j]);
    range.curvature_low[j] = std::max(range.curvature_low[j], -straying.curvature_reach[j]);
    range.curvature_high[j] = std::min(range.curvature_high[j], straying.curvature_reach[j]);
  }
}

LinearPath LinearSolver::Path(const Scene& scene, int steps) const {
  LinearPath path;
  path.steps_ = steps;
  auto lin = std::make_unique<Linearisation>(Linearise(scene, Nominal(scene)));
  const NominalResponse& nominal = *lin->nominal;
  if (nominal.equilibrium.status != Status::kOk) {
    path.status_ = nominal.equilibrium.status;
    path.message_ = "the error-free assembly cannot be linearised: " + nominal.equilibrium.message;
    return path;
  }
  if (!lin->offset.allFinite() || !lin->cosine.allFinite() || !lin->sine.allFinite()) {
    path.status_ = Status::kNonFinite;
    path.message_ = "the linearised path is not finite (an error amplitude or the contact law overflows)";
    return path;
  }
  auto parts = std::make_unique<LinearPath::Parts>();
  parts->second = SecondOrderOf(scene, lin->nominal);
  parts->kernels = options_.kernels;
  parts->ray = engine::Direction(scene.sensor_angle);
  parts->across = {-parts->ray.y(), parts->ray.x()};
  const engine::PolarProfile& bore = scene.ring.inner;
  parts->bore_radius = bore.radius();
  parts->bore_reach = bore.radius() + bore.mean_deviation();
  const int z = nominal.rollers;
  const Eigen::Index terms = static_cast<Eigen::Index>(lin->rates.size());
  parts->series_cosine.setZero(5 * z + 3, terms);
  parts->series_sine.setZero(5 * z + 3, terms);
  parts->series_cosine.topRows(5 * z) = lin->series_cosine;
  parts->series_sine.topRows(5 * z) = lin->series_sine;
  // The bore's harmonics are the first terms, in order (Linearise): a e^{i n theta} read
  // at theta_s - psi is Re[(a e^{i n theta_s}) e^{-i n psi}], its slope Re[i n (...)].
  Eigen::Index p = 0;
  for (int n = 1; n <= bore.max_order(); ++n) {
    const Complex a(bore.cos_coefficient(n), bore.sin_coefficient(n));
    if (a == Complex(0.0)) continue;
    const Complex at_sensor = a * std::polar(1.0, n * scene.sensor_angle);
    const Complex slope = Complex(0.0, n) * at_sensor;
    const Complex curvature = Complex(0.0, n) * slope;
    parts->series_cosine(5 * z, p) = at_sensor.real();
    parts->series_sine(5 * z, p) = at_sensor.imag();
    parts->series_cosine(5 * z + 1, p) = slope.real();
    parts->series_sine(5 * z + 1, p) = slope.imag();
    parts->series_cosine(5 * z + 2, p) = curvature.real();
    parts->series_sine(5 * z + 2, p) = curvature.imag();
    ++p;
  }
  std::vector<Eigen::Index> columns(static_cast<std::size_t>(terms));
  std::iota(columns.begin(), columns.end(), Eigen::Index{0});
  parts->group = MakeGroup({&parts->series_cosine, &parts->series_sine}, columns);
  for (const double rate : lin->rates) {
    const Complex turn = PhaseAt(rate, 1, steps);
    parts->dense_cos.push_back(turn.real());
    parts->dense_sin.push_back(turn.imag());
  }
  path.lin_ = std::move(lin);
  path.parts_ = std::move(parts);
  return path;
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
  if (!lin.offset.allFinite() || !lin.cosine.allFinite() || !lin.sine.allFinite()) {
    trajectory.status = Status::kNonFinite;
    trajectory.message = "the linearised path is not finite (an error amplitude or the contact law overflows)";
    trajectory.initial = nominal.equilibrium;
    return trajectory;
  }
  const int z = nominal.rollers;
  const auto zs = static_cast<std::size_t>(z);
  const auto n = static_cast<std::size_t>(steps) + 1;
  trajectory.psi.resize(n);
  trajectory.centre.resize(n);
  trajectory.travel.resize(n * zs);
  trajectory.contact_force.resize(n * zs);
  PathRows path;
  const auto outputs = static_cast<std::size_t>(lin.offset.size());
  path.row.resize(outputs);
  path.stride.assign(outputs, z);
  path.row[0] = trajectory.centre.front().data();
  path.row[1] = path.row[0] + 1;
  path.stride[0] = path.stride[1] = 2;
  // The gap slopes and curvatures, psi-major: slopes[k * 4Z + j] for row first_slope_row + j. Kept
  // per thread: a fresh buffer (96 bytes an angle) lies above malloc's mmap threshold at
  // campaign resolutions, and its page faults would cost more than the estimate.
  thread_local std::vector<double> slopes;
  slopes.resize(n * 4 * zs);
  for (std::size_t i = 0; i < zs; ++i) {
    const int s = nominal.travel_row[i];
    if (s >= 0) path.row[static_cast<std::size_t>(s)] = trajectory.travel.data() + i;
    path.row[static_cast<std::size_t>(nominal.first_force_row) + i] = trajectory.contact_force.data() + i;
  }
  for (std::size_t j = 0; j < 4 * zs; ++j) {
    path.row[static_cast<std::size_t>(nominal.first_slope_row) + j] = slopes.data() + j;
    path.stride[static_cast<std::size_t>(nominal.first_slope_row) + j] = 4 * z;
  }
  EvaluatePath(lin, steps, path_kernels::KernelsFor(options_.kernels), path);
  // The second order at every angle, a block of angles at a time (AtEach, At's bits); what
  // it leaves bounds the estimate.
  const SecondOrderTerms second = SecondOrderOf(scene, lin.nominal);
  constexpr std::size_t kBlock = 64;
  thread_local std::vector<double> first_block, correction_block;
  first_block.resize((2 + 6 * zs) * kBlock);
  correction_block.resize((3 + 2 * zs) * kBlock);
  double largest_remainder = 0.0;
  double farthest = 0.0;
  for (std::size_t from = 0; from < n; from += kBlock) {
    const std::size_t count = std::min(kBlock, n - from);
    for (std::size_t j = 0; j < count; ++j) {
      const std::size_t k = from + j;
      first_block[j] = trajectory.centre[k].x();
      first_block[kBlock + j] = trajectory.centre[k].y();
      for (std::size_t i = 0; i < zs; ++i) {
        first_block[(2 + i) * kBlock + j] = trajectory.travel[k * zs + i];
        first_block[(2 + zs + i) * kBlock + j] = trajectory.contact_force[k * zs + i];
      }
      for (std::size_t r = 0; r < 4 * zs; ++r) first_block[(2 + 2 * zs + r) * kBlock + j] = slopes[k * 4 * zs + r];
    }
    second.AtEach({first_block.data(), kBlock, count}, {correction_block.data(), kBlock});
    const auto correction = [&](std::size_t f, std::size_t j) { return correction_block[f * kBlock + j]; };
    for (std::size_t j = 0; j < count; ++j) {
      const std::size_t k = from + j;
      trajectory.centre[k] += Eigen::Vector2d(correction(0, j), correction(1, j));
      for (std::size_t i = 0; i < zs; ++i) {
        trajectory.travel[k * zs + i] += correction(2 + i, j);
        trajectory.contact_force[k * zs + i] += correction(2 + zs + i, j);
      }
      // max() would drop a NaN: the estimate must carry it.
      const double remainder = correction(2 + 2 * zs, j);
      if (!(remainder <= largest_remainder)) largest_remainder = remainder;
      farthest = std::max(farthest, trajectory.centre[k].norm());
    }
  }
  trajectory.initial.centre = trajectory.centre.front();
  trajectory.initial.travel.assign(trajectory.travel.begin(), trajectory.travel.begin() + z);
  trajectory.initial.contact_force.assign(trajectory.contact_force.begin(), trajectory.contact_force.begin() + z);
  // An int counter lets the division vectorise.
  for (int k = 0; k <= steps; ++k) {
    trajectory.psi[static_cast<std::size_t>(k)] = 2.0 * std::numbers::pi * static_cast<double>(k) / steps;
  }
  trajectory.error_estimate = second.EstimateFrom(largest_remainder, farthest);
  // The domain's limits first, as every rung states them; then the rung's own.
  ValidityCheck(scene).Check(trajectory);
  if (trajectory.status != Status::kOk) return trajectory;
  double reach = 0.0;
  for (const Eigen::Vector2d& centre : trajectory.centre) reach = std::max(reach, (centre - trajectory.centre.front()).norm());
  trajectory.message = LinearRangeRefusal(options_, trajectory.error_estimate, reach);
  if (!trajectory.message.empty()) trajectory.status = Status::kBeyondLinearRange;
  return trajectory;
}

std::string LinearRangeRefusal(const LinearOptions& options, double error_estimate, double reach) {
  const double limit = std::max(options.max_relative_error * reach, options.min_error_limit);
  if (error_estimate <= limit) return {};
  return "the second-order path's remaining error, bounded at " + Micrometres(error_estimate) +
         " of D_trajectory, exceeds its limit of " + Micrometres(limit) + ": use the quasistatic rung";
}

}  // namespace ringtol::solvers
