#include "solvers/linear.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <numbers>

#include <Eigen/LU>

#include "engine/enclosing_circle.h"
#include "solvers/validity.h"

namespace ringtol::solvers {
namespace {

using engine::Scene;
using Complex = std::complex<double>;

// Outputs y = [centre (2); travel per spring roller; contact force per roller (Z)]: the
// travel rows are x's (fixed rollers do not travel, and carry no rows to evaluate). Below
// them, 2Z rows that only the error estimate reads: the slope d(dg_i)/dphi that the
// bore's harmonics (rows first_slope_row + i) and the roller's own (+ Z + i) give contact
// i's gap function at its nominal normal.
// Every error term p adds cosine_p cos(rate_p psi) + sine_p sin(rate_p psi), the real
// part of v_p e^{-i rate_p psi} with v_p = cosine_p + i sine_p.
struct Linearisation {
  std::shared_ptr<const NominalResponse> nominal;
  Eigen::VectorXd offset;            // y at psi-independent errors: y0 + Y dg_constant; slopes 0
  Eigen::MatrixXd cosine;            // outputs x terms
  Eigen::MatrixXd sine;              // outputs x terms
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
  int first_slope_row = 0;           // row of contact 0's bore slope (first_force_row + Z)
  std::vector<engine::Contact> contacts;  // at the equilibrium
  Eigen::VectorXd y0;                // outputs at the equilibrium
  // Response of the outputs to each contact's gap value (columns 0..Z-1) and gap slope
  // (Z..2Z-1).
  Eigen::MatrixXd response;
  // What the second-order error estimate needs of each contact (ErrorEstimate).
  double ring_radius = 0.0;                 // [m] the bore's
  std::vector<double> roller_radius;        // [m]
  std::vector<double> penetration;          // [m] delta at the equilibrium (penalty law; 0 rigid)
  std::vector<double> force_stiffness;      // [N/m] dF/d delta there (penalty law; 0 rigid)
  double exponent = 1.0;                    // [-] of the penalty law
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
  const Eigen::Index rows = nominal.first_slope_row + 2 * z;
  lin.cosine.setZero(rows, terms);
  lin.sine.setZero(rows, terms);
  lin.rates.reserve(static_cast<std::size_t>(terms));

  // Every error term as a change of each contact's gap function near its nominal
  // direction phi_i: a bore harmonic a e^{i n theta} adds Re[a e^{i n (phi - psi)}] to
  // g_i(phi), with slope Re[i n a e^{i n (phi - psi)}]; a roller harmonic subtracts.
  auto add_gap_and_slope = [&](Eigen::Index p, int i, Complex value, double order, Eigen::Index slope_row) {
    const Complex slope = Complex(0.0, order) * value;
    const Eigen::Index outputs = response.rows();
    lin.cosine.col(p).head(outputs) += value.real() * response.col(i) + slope.real() * response.col(z + i);
    lin.sine.col(p).head(outputs) += value.imag() * response.col(i) + slope.imag() * response.col(z + i);
    lin.cosine(slope_row, p) += slope.real();
    lin.sine(slope_row, p) += slope.imag();
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
      add_gap_and_slope(p, i, a * normal_power[static_cast<std::size_t>(i)], n, nominal.first_slope_row + i);
    }
    lin.rates.push_back(n);
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
      add_gap_and_slope(p, i, -a * std::polar(1.0, m * (c.normal_angle - body0)), m, nominal.first_slope_row + z + i);
      lin.rates.push_back(m * engine::SpinRatio(scene, i));
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

// Angles handled together: independent sums that proceed at the adder's throughput rather
// than its latency (four SSE registers).
constexpr int kLanes = 8;
using Lanes = Eigen::Array<double, kLanes, 1>;

// cos(rate psi_k) and sin(rate psi_k) of a set of terms for consecutive angles
// psi_k = 2 pi k / steps, kLanes at a time: each term's phasor at the first angle of a
// group times its turns by 0 .. kLanes - 1 increments (independent products, which
// vectorise), and then turned by kLanes increments for the next group. The turns are
// powers of one libm phasor, exact to ~kLanes ulp; every kAnchor angles the phasors
// restart from libm, so the recurrence's round-off never grows beyond ~1e-13.
class PhasorRun {
 public:
  static constexpr int kAnchor = 512;  // a multiple of kLanes

  PhasorRun(std::vector<double> rates, int steps) : rates_(std::move(rates)), steps_(steps) {
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

  // Fills cos_table[p * count + j] and sin_table[...] for angles k = first + j, j < count;
  // first and count are multiples of kLanes.
  void Fill(int first, int count, std::vector<double>& cos_table, std::vector<double>& sin_table) {
    const std::size_t t = rates_.size();
    const auto c = static_cast<std::size_t>(count);
    cos_table.resize(t * c);
    sin_table.resize(t * c);
    for (int j = 0; j < count; j += kLanes) {
      const int k = first + j;
      if (k % kAnchor == 0 || k != next_) Anchor(k);
      next_ = k + kLanes;
      for (std::size_t p = 0; p < t; ++p) {
        const double cos_k = cos_[p];
        const double sin_k = sin_[p];
        const Eigen::Map<const Lanes> lane_cos(lane_cos_.data() + p * kLanes);
        const Eigen::Map<const Lanes> lane_sin(lane_sin_.data() + p * kLanes);
        const std::size_t at = p * c + static_cast<std::size_t>(j);
        Eigen::Map<Lanes>(cos_table.data() + at) = cos_k * lane_cos - sin_k * lane_sin;
        Eigen::Map<Lanes>(sin_table.data() + at) = sin_k * lane_cos + cos_k * lane_sin;
        cos_[p] = cos_k * group_cos_[p] - sin_k * group_sin_[p];
        sin_[p] = sin_k * group_cos_[p] + cos_k * group_sin_[p];
      }
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
  int next_ = -1;  // the angle the phasors stand at
  std::vector<double> lane_cos_, lane_sin_;    // turns by 0 .. kLanes - 1 increments, per term
  std::vector<double> group_cos_, group_sin_;  // turn by kLanes increments, per term
  std::vector<double> cos_, sin_;              // phasors at angle next_
};

// A group of terms summed together: their rates, and their weights output-major with the
// terms contiguous (weights[o * size() + q]).
struct TermGroup {
  std::vector<double> rates;
  std::vector<double> weights;
  // Per output, the range of terms [first, last) outside which its weights are zero: a
  // contact's slope rows see only the bore's or only one roller's terms.
  std::vector<std::size_t> first, last;
  std::size_t size() const { return rates.size(); }
};

TermGroup MakeGroup(const Eigen::MatrixXd& matrix, const std::vector<Eigen::Index>& columns,
                    const std::vector<double>& all_rates) {
  TermGroup group;
  group.rates.reserve(columns.size());
  group.weights.reserve(columns.size() * static_cast<std::size_t>(matrix.rows()));
  for (Eigen::Index p : columns) group.rates.push_back(all_rates[static_cast<std::size_t>(p)]);
  for (Eigen::Index o = 0; o < matrix.rows(); ++o) {
    std::size_t first = columns.size(), last = 0;
    for (std::size_t q = 0; q < columns.size(); ++q) {
      const double weight = matrix(o, columns[q]);
      group.weights.push_back(weight);
      if (weight != 0.0) {
        first = std::min(first, q);
        last = q + 1;
      }
    }
    group.first.push_back(std::min(first, last));
    group.last.push_back(last);
  }
  return group;
}

// The sum over the group's terms q of weight(o, q) * table[q * count + j + l], for the
// kLanes angles l of a lane group. The pairs of lanes are spelt out: left to itself the
// compiler vectorises across the terms instead, and shuffles every product.
Lanes SumGroup(const TermGroup& group, std::size_t o, const double* table, std::size_t count, std::size_t j) {
  using Pair = Eigen::Array2d;
  const std::size_t terms = group.size();
  const double* weight = group.weights.data() + o * terms;
  const double* values = table + group.first[o] * count + j;
  Pair a = Pair::Zero(), b = Pair::Zero(), c = Pair::Zero(), d = Pair::Zero();
  for (std::size_t q = group.first[o]; q < group.last[o]; ++q, values += count) {
    const double w = weight[q];
    a += w * Eigen::Map<const Pair>(values);
    b += w * Eigen::Map<const Pair>(values + 2);
    c += w * Eigen::Map<const Pair>(values + 4);
    d += w * Eigen::Map<const Pair>(values + 6);
  }
  Lanes sum;
  sum.segment<2>(0) = a;
  sum.segment<2>(2) = b;
  sum.segment<2>(4) = c;
  sum.segment<2>(6) = d;
  return sum;
}

// The path at psi_k = 2 pi k / steps, k = 0 .. steps. A term of integer rate w takes the
// same values at psi and 2 pi - psi up to the sign of its sine, and at psi + pi up to
// (-1)^w: with steps divisible by four, the sums of the even and the odd rates' cosines
// and sines over the first quarter turn give the whole revolution, four angles from each
// (a real FFT's first two stages, which for a few harmonics beats the whole transform).
// Other rates (a roller's lobes pass R / r_b times per turn, rarely an integer) are
// summed at every angle.
void EvaluatePath(const Linearisation& lin, int steps, PathRows& path) {
  constexpr int kBlock = 64;  // angles per pass, a multiple of kLanes: the tables stay in L1
  const auto outputs = static_cast<std::size_t>(lin.offset.size());
  // A quarter turn of at least one lane group, so that every lane's four angles lie in
  // the revolution.
  const bool fold = steps % 4 == 0 && steps / 4 >= kLanes;
  std::vector<Eigen::Index> even_columns, odd_columns, direct_columns;
  for (std::size_t p = 0; p < lin.rates.size(); ++p) {
    const double rate = lin.rates[p];
    const auto column = static_cast<Eigen::Index>(p);
    if (fold && std::floor(rate) == rate && std::abs(rate) < 1e9) {
      (std::fmod(std::abs(rate), 2.0) == 1.0 ? odd_columns : even_columns).push_back(column);
    } else {
      direct_columns.push_back(column);
    }
  }
  std::vector<double> cos_table, sin_table;

  if (fold) {
    const TermGroup cos_even = MakeGroup(lin.cosine, even_columns, lin.rates);
    const TermGroup cos_odd = MakeGroup(lin.cosine, odd_columns, lin.rates);
    const TermGroup sin_even = MakeGroup(lin.sine, even_columns, lin.rates);
    const TermGroup sin_odd = MakeGroup(lin.sine, odd_columns, lin.rates);
    const int quarter = steps / 4;
    const int half = steps / 2;
    std::vector<double> rates = cos_even.rates;
    rates.insert(rates.end(), cos_odd.rates.begin(), cos_odd.rates.end());
    PhasorRun run(rates, steps);
    const std::size_t even = cos_even.size();
    for (int first = 0; first <= quarter; first += kBlock) {
      const int count = std::min(kBlock, quarter + 1 - first);
      const auto c = static_cast<std::size_t>((count + kLanes - 1) / kLanes * kLanes);
      run.Fill(first, static_cast<int>(c), cos_table, sin_table);
      for (std::size_t o = 0; o < outputs; ++o) {
        const double offset = lin.offset[static_cast<Eigen::Index>(o)];
        double* row = path.row[o];
        const std::ptrdiff_t stride = path.stride[o];
        for (std::size_t j = 0; j < c; j += kLanes) {
          const Lanes cos_even_sum = SumGroup(cos_even, o, cos_table.data(), c, j);
          const Lanes cos_odd_sum = SumGroup(cos_odd, o, cos_table.data() + even * c, c, j);
          const Lanes sin_even_sum = SumGroup(sin_even, o, sin_table.data(), c, j);
          const Lanes sin_odd_sum = SumGroup(sin_odd, o, sin_table.data() + even * c, c, j);
          const Lanes cos_at_psi = offset + cos_even_sum + cos_odd_sum;
          const Lanes cos_at_psi_plus_pi = offset + cos_even_sum - cos_odd_sum;
          const Lanes sin_at_psi = sin_even_sum + sin_odd_sum;
          const Lanes sin_at_psi_plus_pi = sin_even_sum - sin_odd_sum;
          // Angles k .. k + lanes - 1 and their mirrors, which run backwards.
          const int k = first + static_cast<int>(j);
          const int lanes = std::min(kLanes, quarter + 1 - k);
          const Lanes at_psi = cos_at_psi + sin_at_psi;
          const Lanes at_minus_psi = cos_at_psi - sin_at_psi;
          const Lanes at_psi_plus_pi = cos_at_psi_plus_pi + sin_at_psi_plus_pi;
          const Lanes at_pi_minus_psi = cos_at_psi_plus_pi - sin_at_psi_plus_pi;
          double* forward = row + k * stride;
          double* backward = row + (steps - k) * stride;
          double* forward_half = row + (half + k) * stride;
          double* backward_half = row + (half - k) * stride;
          for (int l = 0; l < lanes; ++l) {
            const std::ptrdiff_t step = l * stride;
            forward[step] = at_psi[l];
            backward[-step] = at_minus_psi[l];
            forward_half[step] = at_psi_plus_pi[l];
            backward_half[-step] = at_pi_minus_psi[l];
          }
        }
      }
    }
  } else {
    for (std::size_t o = 0; o < outputs; ++o) {
      for (int k = 0; k <= steps; ++k) path.row[o][k * path.stride[o]] = lin.offset[static_cast<Eigen::Index>(o)];
    }
  }

  if (direct_columns.empty()) return;
  const TermGroup cos_direct = MakeGroup(lin.cosine, direct_columns, lin.rates);
  const TermGroup sin_direct = MakeGroup(lin.sine, direct_columns, lin.rates);
  PhasorRun run(cos_direct.rates, steps);
  for (int first = 0; first <= steps; first += kBlock) {
    const int count = std::min(kBlock, steps + 1 - first);
    const auto c = static_cast<std::size_t>((count + kLanes - 1) / kLanes * kLanes);
    run.Fill(first, static_cast<int>(c), cos_table, sin_table);
    for (std::size_t o = 0; o < outputs; ++o) {
      double* row = path.row[o];
      const std::ptrdiff_t stride = path.stride[o];
      for (std::size_t j = 0; j < c; j += kLanes) {
        const int k = first + static_cast<int>(j);
        const int lanes = std::min(kLanes, steps + 1 - k);
        const Lanes sum = SumGroup(cos_direct, o, cos_table.data(), c, j) + SumGroup(sin_direct, o, sin_table.data(), c, j);
        double* at = row + k * stride;
        for (int l = 0; l < lanes; ++l) at[l * stride] += sum[l];
      }
    }
  }
}

// The neglected second-order terms, as changes gamma_i of each contact's gap that the
// first-order response carries to the centre (docs/model.md §3):
//  - a profile's support function is h = r + dr + dr'^2 / (2 r) to second order (the
//    touching point slides along the surface by dr' / r): +a_i^2 / (2 R) from the bore,
//    -b_i^2 / (2 r_i) from the roller, a_i and b_i their slopes at the nominal normal;
//  - the normal turns by -g'_i / g''_i, which lowers the gap by g'_i^2 / (2 g''_i), with
//    g'_i = a_i + b_i + (dc - dc_roller_i) . t_i the gap function's slope there;
//  - the penalty law's curvature: F(delta + d) = F + F' d + F'' d^2 / 2, an extra force
//    that acts as a gap change of -(e - 1) d^2 / (2 delta), d = dF_i / F' the linearised
//    change of penetration.
// Their centre error dc(psi) = sum_i (dc / dg_i) gamma_i(psi) moves D_trajectory by at
// most twice the radius of the circle enclosing dc over the revolution (a common shift
// leaves D as it is): that is the estimate. Third-order terms (the gap's curvature
// changing with the profiles, the force balance's n_i turning by dphi^2 / 2) are left out.
double ErrorEstimate(const Scene& scene, const NominalResponse& nominal, const Trajectory& trajectory,
                     const std::vector<double>& slopes) {
  const int z = nominal.rollers;
  const auto zs = static_cast<std::size_t>(z);
  const Eigen::Vector2d centre0 = nominal.y0.head<2>();
  std::vector<Eigen::Vector2d> shift(zs), axis(zs);
  std::vector<double> travel0(zs, 0.0);
  for (std::size_t i = 0; i < zs; ++i) {
    const int index = static_cast<int>(i);
    shift[i] = engine::RollerCentre(scene, index) - engine::RollerCentre(nominal.perfect, index);
    axis[i] = engine::SpringAxis(scene, index);
    if (nominal.travel_row[i] >= 0) travel0[i] = nominal.y0[nominal.travel_row[i]];
  }
  const double ring_radius = nominal.ring_radius;
  thread_local std::vector<Eigen::Vector2d> error;  // per thread, as the slopes
  error.assign(trajectory.centre.size(), Eigen::Vector2d::Zero());
  for (std::size_t k = 0; k < trajectory.centre.size(); ++k) {
    const Eigen::Vector2d moved = trajectory.centre[k] - centre0;
    const double* slope = slopes.data() + k * 2 * zs;
    for (std::size_t i = 0; i < zs; ++i) {
      const engine::Contact& c = nominal.contacts[i];
      const double a = slope[i];
      const double b = slope[zs + i];
      Eigen::Vector2d relative = moved - shift[i];
      if (nominal.travel_row[i] >= 0) relative -= (trajectory.travel[k * zs + i] - travel0[i]) * axis[i];
      const double turn = a + b + relative.dot(c.tangent);
      double gamma = a * a / (2.0 * ring_radius) - b * b / (2.0 * nominal.roller_radius[i]) -
                     turn * turn / (2.0 * c.gap_curvature);
      if (nominal.penetration[i] > 0.0) {
        const double d = (trajectory.contact_force[k * zs + i] - nominal.y0[nominal.first_force_row + static_cast<int>(i)]) /
                         nominal.force_stiffness[i];
        gamma -= (nominal.exponent - 1.0) * d * d / (2.0 * nominal.penetration[i]);
      }
      error[k] += gamma * nominal.response.block<2, 1>(0, static_cast<Eigen::Index>(i));
    }
  }
  return 2.0 * engine::MinimumEnclosingCircle(error).radius;
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

std::shared_ptr<const NominalResponse> LinearSolver::Nominal(const Scene& scene) const {
  return nominal_.Get(engine::WithoutErrors(scene),
                      [this](engine::Scene perfect) { return ComputeNominal(std::move(perfect), options_.nominal); });
}

Equilibrium LinearSolver::SolveStatic(const Scene& scene) const {
  const Linearisation lin = Linearise(scene, Nominal(scene));
  if (lin.nominal->equilibrium.status != Status::kOk) return lin.nominal->equilibrium;
  // At psi = 0 every cosine is 1 and every sine 0.
  Equilibrium e;
  FillEquilibrium(lin, lin.offset + lin.cosine.rowwise().sum(), e);
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
  // The gap slopes, psi-major: slopes[k * 2Z + j] for slope row first_slope_row + j. Kept
  // per thread: a fresh buffer (48 bytes an angle) lies above malloc's mmap threshold at
  // campaign resolutions, and its page faults would cost more than the estimate.
  thread_local std::vector<double> slopes;
  slopes.resize(n * 2 * zs);
  for (std::size_t i = 0; i < zs; ++i) {
    const int s = nominal.travel_row[i];
    if (s >= 0) path.row[static_cast<std::size_t>(s)] = trajectory.travel.data() + i;
    path.row[static_cast<std::size_t>(nominal.first_force_row) + i] = trajectory.contact_force.data() + i;
  }
  for (std::size_t j = 0; j < 2 * zs; ++j) {
    path.row[static_cast<std::size_t>(nominal.first_slope_row) + j] = slopes.data() + j;
    path.stride[static_cast<std::size_t>(nominal.first_slope_row) + j] = 2 * z;
  }
  EvaluatePath(lin, steps, path);
  trajectory.initial.centre = trajectory.centre.front();
  trajectory.initial.travel.assign(trajectory.travel.begin(), trajectory.travel.begin() + z);
  trajectory.initial.contact_force.assign(trajectory.contact_force.begin(), trajectory.contact_force.begin() + z);
  // An int counter lets the division vectorise.
  for (int k = 0; k <= steps; ++k) {
    trajectory.psi[static_cast<std::size_t>(k)] = 2.0 * std::numbers::pi * static_cast<double>(k) / steps;
  }
  trajectory.error_estimate = ErrorEstimate(scene, nominal, trajectory, slopes);
  // The domain's limits first, as every rung states them; then the rung's own.
  ValidityCheck(scene).Check(trajectory);
  if (trajectory.status != Status::kOk) return trajectory;
  double reach = 0.0;
  for (const Eigen::Vector2d& centre : trajectory.centre) reach = std::max(reach, (centre - trajectory.centre.front()).norm());
  const double limit = std::max(options_.max_relative_error * reach, options_.min_error_limit);
  if (!(trajectory.error_estimate <= limit)) {
    trajectory.status = Status::kBeyondLinearRange;
    trajectory.message = "the first-order path's second-order error, estimated at " +
                         Micrometres(trajectory.error_estimate) + " of D_trajectory, exceeds its limit of " +
                         Micrometres(limit) + ": use the quasistatic rung";
  }
  return trajectory;
}

}  // namespace ringtol::solvers
