#include "solvers/second_order.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>

#include <boost/container/small_vector.hpp>

namespace ringtol::solvers {

// The second-order correction (docs/model.md §7, "The linear rung's second order"). The
// first-order path drops, per contact i, changes gamma_i of its gap that the first-order
// response carries to every output like any other gap change:
//  - a profile's support function is h = r + dr + dr'^2 / (2 (r + dr - dr'')) to second
//    order (the touching point slides along the surface by dr' / (r + dr - dr'')): from
//    the bore +a_i^2 / (2 (R - q_i)), from the roller -b_i^2 / (2 (r_i + p_i)), a_i, b_i
//    the slopes and q_i, p_i the curvatures their harmonics give the gap at the nominal
//    normal (dr, second order there, is left to the bound);
//  - the normal turns by -g'_i / g''_i, which lowers the gap by g'_i^2 / (2 g''_i), with
//    g'_i = a_i + b_i + (dc - dc_roller_i) . t_i + the support terms' slopes
//    (a_i q_i / (R - q_i) - b_i p_i / (r_i + p_i)) and g''_i the nominal one plus q_i + p_i
//    minus (dc - dc_roller_i) . n_i (two circles' g'' is minus their relative centre along n);
//  - the penalty law's curvature: F(delta + d) = F + F' d + F'' d^2 / 2, an extra force
//    that acts as a gap change of -(e - 1) d^2 / (2 delta), d = dF_i / F' the linearised
//    change of penetration (so the force rows come out right to second order too);
// and, in the force balance, each contact force turning with its normal: along n_i it
// loses F phi^2 / 2, along t_i it has F phi instead of the linear F0 phi_linear (phi the
// normal's turn with the terms above, phi_linear the one the response followed), extra
// forces whose response the nominal solve gives too. Keeping the curvatures and slopes that
// are known at the angle (they are products of first-order terms) leaves a remainder of
// third order in what is not known there; At bounds it term by term below.

namespace {

// The kernel below runs on one angle (Lane = double: At) or on two side by side (Lane =
// Pair: AtEach), a GCC vector of two doubles, an SSE2 register on every x86-64. Each lane
// of a Pair operation is the IEEE operation a double would do (the file is compiled without
// contraction into fused multiply-adds, solvers/CMakeLists.txt), so both give the same bits.
using Pair = double __attribute__((vector_size(16)));
using PairMask = long long __attribute__((vector_size(16)));  // a comparison's lanes: all ones or zero

template <class Lane>
struct LaneOps;

template <>
struct LaneOps<double> {
  using Mask = bool;
  static double Splat(double x) { return x; }
  static double Abs(double x) { return std::abs(x); }
  static double Sqrt(double x) { return std::sqrt(x); }
  static double Select(bool m, double a, double b) { return m ? a : b; }
  static bool And(bool a, bool b) { return a && b; }
  static bool Any(bool m) { return m; }
  template <class F>
  static double EachLane(double x, F f) { return f(x); }
};

template <>
struct LaneOps<Pair> {
  using Mask = PairMask;
  static Pair Splat(double x) { return Pair{x, x}; }
  static Pair Abs(Pair x) {
    constexpr long long kMagnitude = 0x7fffffffffffffffLL;  // every bit but the sign
    return std::bit_cast<Pair>(std::bit_cast<PairMask>(x) & PairMask{kMagnitude, kMagnitude});
  }
  static Pair Sqrt(Pair x) { return Pair{std::sqrt(x[0]), std::sqrt(x[1])}; }
  static Pair Select(PairMask m, Pair a, Pair b) { return m ? a : b; }
  static PairMask And(PairMask a, PairMask b) { return a & b; }
  static bool Any(PairMask m) { return m[0] != 0 || m[1] != 0; }
  template <class F>
  static Pair EachLane(Pair x, F f) { return Pair{f(x[0]), f(x[1])}; }
};

// x^(e - 3) [m^(e-3)], the penalty law's third derivative's factor, at x > 0. For the
// article's e = 1.5 it is 1 / (x sqrt(x)): three correctly rounded operations against pow's
// one, within a few ulp of it (tests/solvers/second_order_test.cpp), and it vectorises,
// where pow was a sixth of At's time.
template <class Lane>
Lane LawPower(Lane x, double e) {
  using Ops = LaneOps<Lane>;
  if (e == 1.5) return 1.0 / (x * Ops::Sqrt(x));
  return Ops::EachLane(x, [e](double w) { return std::pow(w, e - 3.0); });
}

// Remainder term 1 of SecondOrderTerms::At (the support functions), shared with Over: per
// outline its slope's and curvature's magnitudes at the contact, its reach (R - q, r + p)
// and allowance (the reach less U >= |dr|, > 0), U and J >= |dr'''|. The operations and
// their order are At's own from before Over existed, so its results keep their bits.
template <class Lane>
struct OutlineAtContact {
  Lane slope;              // [m/rad] |a| or |b|
  Lane curvature;          // [m/rad^2] |q| or |p|
  Lane reach;              // [m]
  Lane allowance;          // [m]
  double value = 0.0;      // [m] U
  double jerk = 0.0;       // [m] J
};
template <class Lane>
struct SupportRemainder {
  Lane value;      // [m] of the gap
  Lane slope;      // [m/rad]
  Lane curvature;  // [m/rad^2]
};
template <class Lane>
SupportRemainder<Lane> SupportRemainderOf(const OutlineAtContact<Lane>& ring, const OutlineAtContact<Lane>& roller) {
  const Lane a = ring.slope, q = ring.curvature, b = roller.slope, p = roller.curvature;
  const Lane ring_slide = a / ring.allowance;
  const Lane roller_slide = b / roller.allowance;
  const Lane ring_cubic = ring.jerk + 3.0 * a;
  const Lane roller_cubic = roller.jerk + 3.0 * b;
  SupportRemainder<Lane> out;
  out.value = a * a * ring.value / (2.0 * ring.allowance * ring.reach) + ring_cubic * ring_slide * ring_slide * ring_slide / 3.0 +
              b * b * roller.value / (2.0 * roller.allowance * roller.reach) +
              roller_cubic * roller_slide * roller_slide * roller_slide / 3.0;
  out.slope = a * q * ring.value / (ring.allowance * ring.reach) + ring_cubic * ring_slide * ring_slide / 2.0 +
              b * p * roller.value / (roller.allowance * roller.reach) + roller_cubic * roller_slide * roller_slide / 2.0;
  out.curvature = (q * q + a * ring.jerk) / ring.allowance + (p * p + b * roller.jerk) / roller.allowance;
  return out;
}

// Remainder term 5 of one contact, taken contact by contact (SecondOrderKernel's comment),
// shared with Over: the contact's stiffness drifting by `law_drift` (relative) and turning
// by `phi` [rad], its geometric entry F / g'' changing by `force_change` [N] and turning
// with `force` [N], each acting on the correction's displacement at the contact along its
// normal and tangent [m] and carried to the centre by its gains. The operations and their
// order are At's own, so its results keep their bits.
template <class Lane>
Lane ContactDrift(const SecondOrderScene::Contact& k, Lane law_drift, Lane phi, Lane force, Lane force_change,
                  Lane along_n, Lane along_t) {
  const double kc = k.force_stiffness;
  const Lane bending = force * phi / k.gap_curvature;  // the geometric entry's turn [N/m]
  return kc * (law_drift * along_n * k.normal_force_gain +
               phi * (along_n * k.tangent_force_gain + along_t * k.normal_force_gain)) +
         force_change / k.gap_curvature * along_t * k.tangent_force_gain +
         bending * (along_t * k.normal_force_gain + along_n * k.tangent_force_gain);
}

// Per contact, what the kernel carries from one pass over the contacts to the next: gamma,
// the turn g'_i with its known second-order slopes, the gap's curvature, the penetration
// change d_i, the first-order turn's slope, the correction's own turn, and the corrections
// of the roller's travel and contact force.
template <class Lane>
struct ContactLanes {
  Lane gamma, slope, curvature, penetration_change, linear_slope, feedback, travel, force;
};

// One angle's (Lane = double) or two angles' (Pair) second order: At's computation, written
// once for both. `first` gives the lanes of FirstOrderAngle's fields: centre(0 or 1),
// travel(i), force(i), slope(r), curvature(r) (r < 2Z, the bore's then the roller's).
// Writes each contact's corrections to per[i], the centre's to centre[0, 1], and the
// remainder, infinite in every lane where a premise of the expansion or of its bound fails.
template <class Lane, class Input>
void SecondOrderKernel(const SecondOrderScene& scene, const Input& first, ContactLanes<Lane>* per, Lane* centre,
                       Lane& remainder_out) {
  using Ops = LaneOps<Lane>;
  using Mask = typename Ops::Mask;
  const std::vector<SecondOrderScene::Contact>& contacts = scene.contacts;
  const std::size_t zs = contacts.size();
  const Lane zero = Ops::Splat(0.0);
  Mask bounded = zero == zero;  // true in every lane
  const Lane moved_x = first.centre(0) - scene.centre0.x();
  const Lane moved_y = first.centre(1) - scene.centre0.y();
  const double ring_radius = scene.ring_radius;
  for (std::size_t i = 0; i < zs; ++i) {
    const SecondOrderScene::Contact& k = contacts[i];
    ContactLanes<Lane>& c = per[i];
    const Lane a = first.slope(i);
    const Lane b = first.slope(zs + i);
    const Lane q = first.curvature(i);
    const Lane p = first.curvature(zs + i);
    Lane relative_x = moved_x - k.shift.x();
    Lane relative_y = moved_y - k.shift.y();
    if (k.spring) {
      const Lane travel = first.travel(i) - k.travel0;
      relative_x = relative_x - travel * k.axis.x();
      relative_y = relative_y - travel * k.axis.y();
    }
    const Lane ring_reach = ring_radius - q;  // r + dr - dr'' of the bore, dr left out
    const Lane roller_reach = k.roller_radius + p;
    c.linear_slope = a + b + (relative_x * k.tangent.x() + relative_y * k.tangent.y());
    const Lane curvature = k.gap_curvature + q + p - (relative_x * k.normal.x() + relative_y * k.normal.y());
    const Mask expands = Ops::And(Ops::And(ring_reach > zero, roller_reach > zero), curvature > zero);
    bounded = Ops::And(bounded, expands);
    // Beyond any expansion the first-order curvatures stand in.
    c.slope = Ops::Select(expands, c.linear_slope + a * q / ring_reach - b * p / roller_reach, c.linear_slope);
    c.curvature = Ops::Select(expands, curvature, Ops::Splat(k.gap_curvature));
    c.gamma = Ops::Select(expands, a * a / (2.0 * ring_reach) - b * b / (2.0 * roller_reach),
                          a * a / (2.0 * ring_radius) - b * b / (2.0 * k.roller_radius));
    c.gamma = c.gamma - c.slope * c.slope / (2.0 * c.curvature);
    c.penetration_change = zero;
    if (k.penetration > 0.0) {
      c.penetration_change = (first.force(i) - k.force0) / k.force_stiffness;
      c.gamma = c.gamma - (scene.exponent - 1.0) * c.penetration_change * c.penetration_change / (2.0 * k.penetration);
    }
    c.travel = zero;
    c.force = zero;
  }
  centre[0] = zero;
  centre[1] = zero;
  const Eigen::MatrixXd& response = scene.response;
  const auto add = [&](Lane weight, Eigen::Index column) {
    centre[0] = centre[0] + weight * response(0, column);
    centre[1] = centre[1] + weight * response(1, column);
    for (std::size_t j = 0; j < zs; ++j) {
      const auto row = static_cast<Eigen::Index>(2 + j);
      if (contacts[j].spring) per[j].travel = per[j].travel + weight * response(row, column);
      per[j].force = per[j].force + weight * response(row + static_cast<Eigen::Index>(zs), column);
    }
  };
  for (std::size_t i = 0; i < zs; ++i) add(per[i].gamma, static_cast<Eigen::Index>(i));
  // The turn the correction itself gives each normal, which the response followed.
  for (std::size_t i = 0; i < zs; ++i) {
    const SecondOrderScene::Contact& k = contacts[i];
    Lane moved_correction_x = centre[0];
    Lane moved_correction_y = centre[1];
    if (k.spring) {
      moved_correction_x = moved_correction_x - per[i].travel * k.axis.x();
      moved_correction_y = moved_correction_y - per[i].travel * k.axis.y();
    }
    per[i].feedback = moved_correction_x * k.tangent.x() + moved_correction_y * k.tangent.y();
  }
  Lane correction = zero;  // the correction's size at the centre, each term by its gain
  for (std::size_t i = 0; i < zs; ++i) {
    const SecondOrderScene::Contact& k = contacts[i];
    const ContactLanes<Lane>& c = per[i];
    const Lane force = first.force(i);
    const Lane turn = -(c.slope + c.feedback) / c.curvature;
    const Lane linear_turn = -(c.linear_slope + c.feedback) / k.gap_curvature;
    const Lane normal_force = -force * turn * turn / 2.0;
    const Lane tangent_force = force * turn - k.force0 * linear_turn;
    add(normal_force, static_cast<Eigen::Index>(zs + i));
    add(tangent_force, static_cast<Eigen::Index>(2 * zs + i));
    correction = correction + (k.gap_gain * Ops::Abs(c.gamma) + k.normal_force_gain * Ops::Abs(normal_force) +
                               k.tangent_force_gain * Ops::Abs(tangent_force));
  }
  const Lane infinite = Ops::Splat(std::numeric_limits<double>::infinity());
  if (!Ops::Any(bounded)) {
    remainder_out = infinite;
    return;
  }

  // The remainder, per contact as a gap change [m] (times its gain to the centre) and as
  // extra contact forces [N] along the normal and the tangent (times theirs). With, of the
  // bore and of roller i, U >= |dr| (|dr0| + sum |C_n|) and J >= |dr'''| (sum n^3 |C_n|),
  // and A = R - q - U (r_i + p - U) <= r + dr - dr'':
  //  1. the support functions: dr left out of r + dr - dr'' changes the quadratic term by
  //     at most a^2 U / (2 A (R - q)); the cubic term (dr''' - 3 dr') t^3 / 6 at the slide
  //     t <= |a| / A takes at most twice its value at t (the maximum moves by less than t).
  //     Their slopes are known up to |a q| U / (A (R - q)) + (J + 3 |a|) t^2 / 2, their
  //     curvatures ((dr''^2 + dr' dr''') / A, left out) up to (q^2 + |a| J) / A;
  //  2. the turn: the gap function's minimum is g - g'^2 / (2 g'') + g''' phi^3 / 6 + ...;
  //     its slope is known up to s = |dturn_i| (the correction's own turn: the turn term
  //     was evaluated at the first-order configuration) + the slopes' share of 1, its
  //     curvature up to K' = the curvatures' share of 1, and |g'''| <= J_ring + J_i + |g'|
  //     (two circles' g''' is -g'); with g^ = |g'_i| + s and phi^ = g^ / (g'' - K') (a
  //     bound of the normal's exact turn) the term errs by at most
  //       g^^2 / (2 (g'' - K')) - g'_i^2 / (2 g'') + 2 (J_ring + J_i + g^) phi^^3 / 6;
  //  3. the penalty law: its curvature term at the corrected penetration change d^ =
  //     |d| + |dd| instead of d, and its cubic term F''' d^3 / 6, F''' at the worst point
  //     of [delta - d^, delta + d^];
  //  4. the forces' turn: the force's second-order change dF times phi^, and the force
  //     times the turn's error phi^ - |turn| along t_i, and (phi^^2 - turn^2) / 2 along
  //     n_i, plus the sine's and cosine's next terms phi^3 / 6 and phi^4 / 24;
  //  5. the responses were taken at the error-free assembly: over the path the entries
  //     that carry a gap change to the centre (n n^T k_c of each contact) move by at most
  //     2 phi^ + (e - 1) d^ / (delta - d^) relative (F t t^T / g'' by |dF| / (g'' k_c) of
  //     k_c), and so does their product with the correction. Under the penalty law, contact
  //     by contact too: the correction x (centre and travels) is K^-1 f, the exact one
  //     K'^-1 f, and they differ by K^-1 dK x to this order, dK the sum over the contacts of
  //     k_c's change (e - 1) d^ / (delta - d^) times k_c along n n^T, k_c's turn by phi^
  //     (k_c phi^ (n.x along t and t.x along n)), and the geometric F / g'' t t^T's change
  //     (|dF| / g'' t.x along t) and turn (F phi^ / g'' (t.x along n and n.x along t)),
  //     each force carried to the centre by its gain, n.x and t.x the correction's own
  //     displacement at the contact. That sum is smaller where one contact's drift, the
  //     largest, is not the whole correction's: the lesser of the two counts.
  // Each term is bounded by its magnitude and carried to the centre by the norm of its
  // response, so their sum bounds |exact - corrected| up to terms of fourth order and
  // products of the bounds (docs/model.md §7). A lane where a premise fails computes on
  // (its numbers are not used) and ends infinite.
  Lane remainder = zero;
  Lane drift = zero;  // the largest relative change of the response's entries
  // Term 5 contact by contact (penalty law), where light redundant contacts can make it the
  // lesser: beyond three rollers. On three, every contact carries the spring's push and on
  // the default campaign's 2,048 draws the sum never came below the other, at 2 % of a
  // sample's time.
  Lane drift_by_contact = zero;
  bool by_contact = zs > 3;
  for (std::size_t i = 0; i < zs; ++i) {
    const SecondOrderScene::Contact& k = contacts[i];
    const ContactLanes<Lane>& c = per[i];
    const Lane a = Ops::Abs(first.slope(i));
    const Lane b = Ops::Abs(first.slope(zs + i));
    const Lane q = Ops::Abs(first.curvature(i));
    const Lane p = Ops::Abs(first.curvature(zs + i));
    const Lane ring_reach = ring_radius - first.curvature(i);
    const Lane roller_reach = k.roller_radius + first.curvature(zs + i);
    const Lane ring_allowance = ring_reach - scene.ring_value;
    const Lane roller_allowance = roller_reach - k.roller_value;
    bounded = Ops::And(bounded, Ops::And(ring_allowance > zero, roller_allowance > zero));
    // 1. The support functions.
    const SupportRemainder<Lane> support =
        SupportRemainderOf<Lane>({a, q, ring_reach, ring_allowance, scene.ring_value, scene.ring_jerk},
                                 {b, p, roller_reach, roller_allowance, k.roller_value, k.roller_jerk});
    // 2. The turn.
    const Lane curvature_allowance = c.curvature - support.curvature;
    bounded = Ops::And(bounded, curvature_allowance > zero);
    const Lane g1 = Ops::Abs(c.slope);
    const Lane bound_slope = g1 + Ops::Abs(c.feedback) + support.slope;
    const Lane phi = bound_slope / curvature_allowance;
    const Lane turning = bound_slope * bound_slope / (2.0 * curvature_allowance) - g1 * g1 / (2.0 * c.curvature) +
                         (scene.ring_jerk + k.roller_jerk + bound_slope) * phi * phi * phi / 3.0;
    // 3. The penalty law.
    Lane law = zero;
    Lane law_drift = zero;
    if (k.penetration > 0.0) {
      const double e = scene.exponent;
      const double delta = k.penetration;
      const Lane d = Ops::Abs(c.penetration_change);
      const Lane reach = d + Ops::Abs(c.force / k.force_stiffness);
      const Lane lowest = delta - reach;
      bounded = Ops::And(bounded, lowest > zero);
      // x^(e - 3) is monotone, so its largest over [lowest, delta + reach] sits at one end:
      // one power per contact and angle instead of three.
      const Lane worst_point = e < 3.0 ? lowest : delta + reach;
      const Lane third = (e - 1.0) * std::abs(e - 2.0) * LawPower(worst_point, e) / k.law_scale;
      law = (e - 1.0) * (reach * reach - d * d) / (2.0 * delta) + third * reach * reach * reach / 6.0;
      law_drift = (e - 1.0) * reach / lowest;
    }
    // 4. The forces' turn.
    const Lane force = Ops::Abs(first.force(i)) + Ops::Abs(c.force);
    const Lane turn = Ops::Abs(c.slope + c.feedback) / c.curvature;
    const Lane phi2 = phi * phi;
    const Lane normal_force = Ops::Abs(c.force) * phi2 / 2.0 + force * ((phi2 - turn * turn) / 2.0 + phi2 * phi2 / 24.0);
    const Lane tangent_force = Ops::Abs(c.force) * phi + force * (phi - turn + phi2 * phi / 6.0);
    remainder = remainder + (k.gap_gain * (support.value + turning + law) + k.normal_force_gain * normal_force +
                             k.tangent_force_gain * tangent_force);
    // 5. The response's drift.
    const Lane force_change = Ops::Abs(first.force(i) - k.force0) + Ops::Abs(c.force);
    const Lane geometric = k.force_stiffness > 0.0 ? force_change / (k.gap_curvature * k.force_stiffness) : zero;
    const Lane growth = 2.0 * phi + law_drift + geometric;
    drift = Ops::Select(drift < growth, growth, drift);  // std::max's rule, lane by lane
    by_contact = by_contact && k.penetration > 0.0;
    if (by_contact) {
      Lane shift_x = centre[0];  // the correction's displacement at the contact
      Lane shift_y = centre[1];
      if (k.spring) {
        shift_x = shift_x - per[i].travel * k.axis.x();
        shift_y = shift_y - per[i].travel * k.axis.y();
      }
      const Lane along_n = Ops::Abs(shift_x * k.normal.x() + shift_y * k.normal.y());
      const Lane along_t = Ops::Abs(shift_x * k.tangent.x() + shift_y * k.tangent.y());
      drift_by_contact =
          drift_by_contact + ContactDrift<Lane>(k, law_drift, phi, force, force_change, along_n, along_t);
    }
  }
  Lane drifted = drift * correction;
  if (by_contact) drifted = Ops::Select(drift_by_contact < drifted, drift_by_contact, drifted);
  remainder_out = Ops::Select(bounded, remainder + drifted, infinite);
}

// FirstOrderAngle's fields as the kernel reads them, one angle.
struct AngleInput {
  const FirstOrderAngle& angle;
  double centre(int axis) const { return angle.centre[axis]; }
  double travel(std::size_t i) const { return angle.travel[i]; }
  double force(std::size_t i) const { return angle.contact_force[i]; }
  double slope(std::size_t r) const { return angle.slopes[r]; }
  double curvature(std::size_t r) const { return angle.curvatures[r]; }
};

// FirstOrderAngles' rows as the kernel reads them, angles j and j + 1 (j again past the
// block's last angle, so a lane that is not stored computes on real inputs).
struct PairInput {
  const FirstOrderAngles& block;
  std::size_t zs;
  std::size_t j;
  Pair Row(std::size_t row) const {
    const double* at = block.rows + row * block.stride + j;
    return Pair{at[0], j + 1 < block.count ? at[1] : at[0]};
  }
  Pair centre(int axis) const { return Row(static_cast<std::size_t>(axis)); }
  Pair travel(std::size_t i) const { return Row(2 + i); }
  Pair force(std::size_t i) const { return Row(2 + zs + i); }
  Pair slope(std::size_t r) const { return Row(2 + 2 * zs + r); }
  Pair curvature(std::size_t r) const { return Row(2 + 4 * zs + r); }
};

}  // namespace

void SecondOrderTerms::At(const FirstOrderAngle& first, SecondOrderAngle& out) const {
  const std::size_t zs = scene_->contacts.size();
  thread_local std::vector<ContactLanes<double>> per;
  per.resize(zs);
  double centre[2];
  SecondOrderKernel<double>(*scene_, AngleInput{first}, per.data(), centre, out.remainder);
  out.centre = Eigen::Vector2d(centre[0], centre[1]);
  out.travel.resize(zs);
  out.contact_force.resize(zs);
  for (std::size_t i = 0; i < zs; ++i) {
    out.travel[i] = per[i].travel;
    out.contact_force[i] = per[i].force;
  }
}

void SecondOrderTerms::AtEach(const FirstOrderAngles& first, const SecondOrderAngles& out) const {
  const std::size_t zs = scene_->contacts.size();
  thread_local std::vector<ContactLanes<Pair>> per;
  per.resize(zs);
  Pair centre[2];
  Pair remainder;
  for (std::size_t j = 0; j < first.count; j += 2) {
    SecondOrderKernel<Pair>(*scene_, PairInput{first, zs, j}, per.data(), centre, remainder);
    const std::size_t lanes = std::min<std::size_t>(2, first.count - j);
    const auto store = [&](std::size_t row, Pair value) {
      double* at = out.rows + row * out.stride + j;
      for (std::size_t l = 0; l < lanes; ++l) at[l] = value[l];
    };
    store(0, centre[0]);
    store(1, centre[1]);
    for (std::size_t i = 0; i < zs; ++i) {
      store(2 + i, per[i].travel);
      store(2 + zs + i, per[i].force);
    }
    store(2 + 2 * zs, remainder);
  }
}
namespace {

// A closed interval [lo, hi] of reals, for SecondOrderTerms::Over. Its operations enclose
// the exact result of any operands inside their intervals; rounding is not directed, and
// Over widens its results by kRoundingAllowance instead.
struct Interval {
  double lo = 0.0;
  double hi = 0.0;
  static Interval Point(double x) { return {x, x}; }
  double Magnitude() const { return std::max(std::abs(lo), std::abs(hi)); }       // >= |x|
  double Mignitude() const { return lo > 0.0 ? lo : (hi < 0.0 ? -hi : 0.0); }     // <= |x|
};
Interval operator+(Interval x, Interval y) { return {x.lo + y.lo, x.hi + y.hi}; }
Interval operator-(Interval x, Interval y) { return {x.lo - y.hi, x.hi - y.lo}; }
Interval operator*(double w, Interval x) { return w >= 0.0 ? Interval{w * x.lo, w * x.hi} : Interval{w * x.hi, w * x.lo}; }
Interval operator*(Interval x, Interval y) {
  const double a = x.lo * y.lo, b = x.lo * y.hi, c = x.hi * y.lo, d = x.hi * y.hi;
  return {std::min({a, b, c, d}), std::max({a, b, c, d})};
}
// y strictly positive (the caller checks y.lo > 0).
Interval operator/(Interval x, Interval y) { return x * Interval{1.0 / y.hi, 1.0 / y.lo}; }
Interval Square(Interval x) {
  const double m = x.Magnitude();
  const double n = x.Mignitude();
  return {n * n, m * m};
}

// Over's interval operations round to nearest, as At does; At's own results carry the
// rounding of its cancellations (tangent force F turn - F0 turn_linear, phi - turn), about
// 1e-16 of first-order terms that the correction is 1e-5 or more of: ~1e-11 relative.
// Over's bounds are widened by 1e-9 relative to cover both.
constexpr double kRoundingAllowance = 1.0 + 1e-9;

// Per-contact intervals of one Over call, on the stack for up to kInlineRollers rollers
// (Over runs a few hundred times a sample, and a heap vector each was most of its cost);
// a scene with more spills to the heap and gets the same numbers.
constexpr std::size_t kInlineRollers = 8;
using Intervals = boost::container::small_vector<Interval, kInlineRollers>;

// The centre's bound from its projections on kDirections directions
// u_m = (cos, sin)(m pi / kDirections): a vector is within pi / (2 kDirections) of one of
// them or of its opposite, so |v| <= max_m |v . u_m| / cos(pi / (2 kDirections)), where
// the two axes alone would give sqrt(2) where the terms' extremes fall in different
// directions. Computed once, not on every call.
constexpr int kDirections = 16;
const std::array<Eigen::Vector2d, kDirections>& Directions() {
  static const std::array<Eigen::Vector2d, kDirections> directions = [] {
    std::array<Eigen::Vector2d, kDirections> u;
    for (int m = 0; m < kDirections; ++m) {
      const double angle = std::numbers::pi * m / kDirections;
      u[static_cast<std::size_t>(m)] = Eigen::Vector2d(std::cos(angle), std::sin(angle));
    }
    return u;
  }();
  return directions;
}

}  // namespace

// At, mirrored term by term over intervals: every quantity At forms at one angle is
// replaced by an interval holding it at every angle of the range (or by an upper bound of
// its magnitude, where At only uses that), so the results bound At's wherever its inputs lie
// in the range. The first-order terms that At's correction cancels (the tangent force
// F turn - F0 turn_linear, the remainder's phi - turn and its turning term) are rewritten
// as the sums of second-order parts they equal, so that the bound stays of second order
// (of third for the remainder) rather than of first.
void SecondOrderTerms::Over(const FirstOrderRange& range, SecondOrderRange& out) const {
  const SecondOrderScene& scene = *scene_;
  const std::vector<SecondOrderScene::Contact>& contacts = scene.contacts;
  const auto zs = contacts.size();
  const double infinite = std::numeric_limits<double>::infinity();
  out.travel.assign(zs, 0.0);
  out.contact_force.assign(zs, 0.0);
  const auto fail = [&] {
    out.centre = infinite;
    out.remainder = infinite;
    for (std::size_t j = 0; j < zs; ++j) {
      if (contacts[j].spring) out.travel[j] = infinite;
      out.contact_force[j] = infinite;
    }
  };
  // Per contact, as in At: gamma, the slope g'_i with its support terms (linear_slope + its
  // second-order part slope_extra), the curvature's change kappa (curvature = g'' + kappa),
  // the force's change from the nominal, and the reaches.
  Intervals gamma(zs), linear_slope(zs), slope_extra(zs), slope(zs), kappa(zs), curvature(zs), force_change(zs),
      ring_reach(zs), roller_reach(zs);
  const double ring_radius = scene.ring_radius;
  const Eigen::Vector2d moved = range.centre - scene.centre0;
  for (std::size_t i = 0; i < zs; ++i) {
    const SecondOrderScene::Contact& k = contacts[i];
    const Interval a{range.slope_low[i], range.slope_high[i]};
    const Interval b{range.slope_low[zs + i], range.slope_high[zs + i]};
    const Interval q{range.curvature_low[i], range.curvature_high[i]};
    const Interval p{range.curvature_low[zs + i], range.curvature_high[zs + i]};
    // relative . u = (moved - shift) . u - (travel - travel0) axis . u, the centre anywhere
    // within centre_radius of range.centre (|u| = 1 moves the product by at most that).
    const auto relative_along = [&](const Eigen::Vector2d& u) {
      const double middle = (moved - k.shift).dot(u);
      Interval along{middle - range.centre_radius, middle + range.centre_radius};
      if (k.spring) {
        along = along - k.axis.dot(u) * Interval{range.travel_low[i] - k.travel0, range.travel_high[i] - k.travel0};
      }
      return along;
    };
    ring_reach[i] = Interval::Point(ring_radius) - q;
    roller_reach[i] = Interval::Point(k.roller_radius) + p;
    linear_slope[i] = a + b + relative_along(k.tangent);
    kappa[i] = q + p - relative_along(k.normal);
    curvature[i] = Interval::Point(k.gap_curvature) + kappa[i];
    // At's premises: where one may fail, At falls back to first-order curvatures and an
    // infinite remainder, which this does not follow: every bound is infinite.
    if (!(ring_reach[i].lo > 0.0 && roller_reach[i].lo > 0.0 && curvature[i].lo > 0.0)) {
      fail();
      return;
    }
    slope_extra[i] = a * q / ring_reach[i] - b * p / roller_reach[i];
    slope[i] = linear_slope[i] + slope_extra[i];
    gamma[i] = 0.5 * (Square(a) / ring_reach[i]) - 0.5 * (Square(b) / roller_reach[i]) -
               0.5 * (Square(slope[i]) / curvature[i]);
    force_change[i] = Interval{range.force_low[i] - k.force0, range.force_high[i] - k.force0};
    if (k.penetration > 0.0) {
      const Interval d = (1.0 / k.force_stiffness) * force_change[i];
      gamma[i] = gamma[i] - ((scene.exponent - 1.0) / (2.0 * k.penetration)) * Square(d);
    }
  }
  // The outputs' corrections as intervals, summed column by column like At's `add`; the
  // centre's along Directions().
  std::array<Interval, kDirections> centre_along{};
  const std::array<Eigen::Vector2d, kDirections>& directions = Directions();
  Intervals travel(zs), force(zs);
  // The correction's displacement at each contact (centre less travel along the axis),
  // along its normal and its tangent: term 5 of the remainder reads them.
  Intervals shift_n(zs), shift_t(zs);
  const Eigen::MatrixXd& response = scene.response;
  const auto add = [&](Interval weight, Eigen::Index column) {
    const Eigen::Vector2d moves = response.block<2, 1>(0, column);
    for (int m = 0; m < kDirections; ++m) {
      Interval& along = centre_along[static_cast<std::size_t>(m)];
      along = along + moves.dot(directions[static_cast<std::size_t>(m)]) * weight;
    }
    for (std::size_t j = 0; j < zs; ++j) {
      const SecondOrderScene::Contact& c = contacts[j];
      const auto row = static_cast<Eigen::Index>(2 + j);
      const double travels = c.spring ? response(row, column) : 0.0;
      if (c.spring) travel[j] = travel[j] + travels * weight;
      force[j] = force[j] + response(row + static_cast<Eigen::Index>(zs), column) * weight;
      shift_n[j] = shift_n[j] + (moves.dot(c.normal) - travels * c.axis.dot(c.normal)) * weight;
      shift_t[j] = shift_t[j] + (moves.dot(c.tangent) - travels * c.axis.dot(c.tangent)) * weight;
    }
  };
  for (std::size_t i = 0; i < zs; ++i) add(gamma[i], static_cast<Eigen::Index>(i));
  // The feedback of contact i, (centre - travel_i axis_i) . t_i after the gammas, is linear
  // in them: summed gamma by gamma, not from the centre's and travel's intervals, which
  // would forget that one gamma moves both.
  Intervals feedback(zs);
  for (std::size_t i = 0; i < zs; ++i) {
    const Eigen::Vector2d& t = contacts[i].tangent;
    for (std::size_t m = 0; m < zs; ++m) {
      const auto column = static_cast<Eigen::Index>(m);
      double weight = response(0, column) * t.x() + response(1, column) * t.y();
      if (contacts[i].spring) weight -= response(static_cast<Eigen::Index>(2 + i), column) * contacts[i].axis.dot(t);
      feedback[i] = feedback[i] + weight * gamma[m];
    }
  }
  // The forces' turn. At's tangent force F turn - F0 turn_linear is, exactly,
  //   (F - F0) turn + F0 (turn - turn_linear),
  //   turn - turn_linear = (linear_slope + feedback) kappa / (g'' curvature) - slope_extra / curvature,
  // (curvature = g'' + kappa, slope = linear_slope + slope_extra), whose parts are each of
  // second order: bounding F and turn apart would leave a first-order bound.
  Intervals turn(zs), normal_force(zs), tangent_force(zs);
  for (std::size_t i = 0; i < zs; ++i) {
    const SecondOrderScene::Contact& k = contacts[i];
    const Interval force_first{range.force_low[i], range.force_high[i]};
    turn[i] = Interval::Point(0.0) - (slope[i] + feedback[i]) / curvature[i];
    const Interval turn_change = (linear_slope[i] + feedback[i]) * kappa[i] / (k.gap_curvature * curvature[i]) -
                                 slope_extra[i] / curvature[i];
    normal_force[i] = -0.5 * (force_first * Square(turn[i]));
    tangent_force[i] = force_change[i] * turn[i] + k.force0 * turn_change;
  }
  for (std::size_t i = 0; i < zs; ++i) {
    add(normal_force[i], static_cast<Eigen::Index>(zs + i));
    add(tangent_force[i], static_cast<Eigen::Index>(2 * zs + i));
  }
  double centre_along_max = 0.0;
  for (const Interval& along : centre_along) centre_along_max = std::max(centre_along_max, along.Magnitude());
  static const double direction_cosine = std::cos(std::numbers::pi / (2.0 * kDirections));
  out.centre = kRoundingAllowance * centre_along_max / direction_cosine;
  for (std::size_t j = 0; j < zs; ++j) {
    out.travel[j] = kRoundingAllowance * travel[j].Magnitude();
    out.contact_force[j] = kRoundingAllowance * force[j].Magnitude();
  }
  // At's `correction`: each term's magnitude by its gain.
  double correction = 0.0;
  for (std::size_t i = 0; i < zs; ++i) {
    correction += contacts[i].gap_gain * gamma[i].Magnitude() + contacts[i].normal_force_gain * normal_force[i].Magnitude() +
                  contacts[i].tangent_force_gain * tangent_force[i].Magnitude();
  }

  // The remainder, At's five terms. Each is a sum of products and quotients of
  // non-negative quantities, increasing in the magnitudes |a|, |b|, |q|, |p|, |F|, |dF| and
  // decreasing in the denominators (the reaches, allowances, curvature): evaluated at the
  // magnitudes' upper bounds and the denominators' lower bounds, each is at least At's at
  // any angle of the range. Where At subtracts (the turning term, phi - turn, the law's
  // reach^2 - d^2), the difference is rewritten below as a sum of such non-negative parts.
  double remainder = 0.0;
  double drift = 0.0;
  double drift_by_contact = 0.0;  // At's, at the bounds of its increasing factors
  bool by_contact = zs > 3;
  for (std::size_t i = 0; i < zs; ++i) {
    const SecondOrderScene::Contact& k = contacts[i];
    const double a = std::max(std::abs(range.slope_low[i]), std::abs(range.slope_high[i]));
    const double b = std::max(std::abs(range.slope_low[zs + i]), std::abs(range.slope_high[zs + i]));
    const double q = std::max(std::abs(range.curvature_low[i]), std::abs(range.curvature_high[i]));
    const double p = std::max(std::abs(range.curvature_low[zs + i]), std::abs(range.curvature_high[zs + i]));
    const double ring_low = ring_reach[i].lo;      // <= R - q at every angle
    const double roller_low = roller_reach[i].lo;  // <= r + p
    const double ring_allowance = ring_low - scene.ring_value;
    const double roller_allowance = roller_low - k.roller_value;
    if (!(ring_allowance > 0.0 && roller_allowance > 0.0)) {
      out.remainder = infinite;
      return;
    }
    // 1. The support functions: increasing in a, b, q, p, decreasing in the reaches.
    const SupportRemainder<double> support = SupportRemainderOf<double>({a, q, ring_low, ring_allowance, scene.ring_value, scene.ring_jerk},
                                                        {b, p, roller_low, roller_allowance, k.roller_value, k.roller_jerk});
    // 2. The turn. With g1 = |slope|, x = |feedback| + support.slope (At's bound_slope is
    // g1 + x), K' = support.curvature and G = curvature, At's
    //   (g1 + x)^2 / (2 (G - K')) - g1^2 / (2 G)
    //     = (2 g1 x + x^2) / (2 (G - K')) + g1^2 K' / (2 G (G - K')),
    // increasing in g1, x, K' and decreasing in G.
    const double curvature_low = curvature[i].lo;
    const double curvature_allowance = curvature_low - support.curvature;
    if (!(curvature_allowance > 0.0)) {
      out.remainder = infinite;
      return;
    }
    const double g1 = slope[i].Magnitude();
    const double x = feedback[i].Magnitude() + support.slope;
    const double bound_slope = g1 + x;
    const double phi = bound_slope / curvature_allowance;  // >= At's phi
    const double turning = (2.0 * g1 * x + x * x) / (2.0 * curvature_allowance) +
                           g1 * g1 * support.curvature / (2.0 * curvature_low * curvature_allowance) +
                           (scene.ring_jerk + k.roller_jerk + bound_slope) * phi * phi * phi / 3.0;
    // 3. The penalty law. At's reach^2 - d^2 with reach = d + |dd| is 2 d |dd| + dd^2,
    // increasing in d and |dd|; x^(e - 3) is monotone, so its largest over
    // [delta - reach, delta + reach] is at an end, and it grows as reach does.
    const double force_correction = force[i].Magnitude();  // >= |At's out.contact_force|
    double law = 0.0;
    double law_drift = 0.0;
    if (k.penetration > 0.0) {
      const double e = scene.exponent;
      const double delta = k.penetration;
      const double d = force_change[i].Magnitude() / k.force_stiffness;
      const double dd = force_correction / k.force_stiffness;
      const double reach = d + dd;
      const double lowest = delta - reach;
      if (!(lowest > 0.0)) {
        out.remainder = infinite;
        return;
      }
      const double worst_point = e < 3.0 ? lowest : delta + reach;
      const double third = std::abs(e - 1.0) * std::abs(e - 2.0) * std::pow(worst_point, e - 3.0) / k.law_scale;
      law = std::abs(e - 1.0) * (2.0 * d * dd + dd * dd) / (2.0 * delta) + third * reach * reach * reach / 6.0;
      law_drift = std::abs(e - 1.0) * reach / lowest;
    }
    // 4. The forces' turn. With s = slope + feedback, At's phi - |turn| is
    //   (|slope| + |feedback| - |s| + support.slope) / (G - K') + |s| K' / (G (G - K')),
    // where |slope| + |feedback| - |s| is 0 when the two have one sign and at most
    // 2 min(|slope|, |feedback|) otherwise; (phi^2 - turn^2) / 2 = (phi - |turn|)(phi + |turn|) / 2.
    const Interval s = slope[i] + feedback[i];
    const bool one_sign = (slope[i].lo >= 0.0 && feedback[i].lo >= 0.0) || (slope[i].hi <= 0.0 && feedback[i].hi <= 0.0);
    const double sign_loss = one_sign ? 0.0 : 2.0 * std::min(g1, feedback[i].Magnitude());
    const double turn_bound = s.Magnitude() / curvature_low;  // >= At's |turn|
    const double phi_excess = (sign_loss + support.slope) / curvature_allowance +
                              s.Magnitude() * support.curvature / (curvature_low * curvature_allowance);
    const double force_bound = std::max(std::abs(range.force_low[i]), std::abs(range.force_high[i])) + force_correction;
    const double phi2 = phi * phi;
    const double normal = force_correction * phi2 / 2.0 +
                          force_bound * (phi_excess * (phi + turn_bound) / 2.0 + phi2 * phi2 / 24.0);
    const double tangent = force_correction * phi + force_bound * (phi_excess + phi2 * phi / 6.0);
    remainder += k.gap_gain * (support.value + turning + law) + k.normal_force_gain * normal +
                 k.tangent_force_gain * tangent;
    // 5. The response's drift: increasing in phi, reach and the force's change.
    const double change = force_change[i].Magnitude() + force_correction;
    const double geometric =
        k.force_stiffness > 0.0 ? change / (k.gap_curvature * k.force_stiffness) : 0.0;
    drift = std::max(drift, 2.0 * phi + law_drift + geometric);
    by_contact = by_contact && k.penetration > 0.0;
    if (by_contact) {
      const double along_n = kRoundingAllowance * shift_n[i].Magnitude();
      const double along_t = kRoundingAllowance * shift_t[i].Magnitude();
      drift_by_contact += ContactDrift<double>(k, law_drift, phi, force_bound, change, along_n, along_t);
    }
  }
  const double drifted = by_contact ? std::min(drift * correction, drift_by_contact) : drift * correction;
  out.remainder = kRoundingAllowance * (remainder + drifted);
}

double SecondOrderTerms::EstimateFrom(double largest_remainder, double farthest) const {
  // The sensor reads the centre along its ray, plus its tangential offset c_t times the
  // bore's slope over R and c_t^2 / (2 R) (docs/model.md §5): a centre error moves the
  // reading by at most (1 + (|c| + max |dr'|) / R) times itself.
  const double sensor_gain = 1.0 + (farthest + scene_->ring_slope_sum) / scene_->ring_radius;
  return 2.0 * sensor_gain * largest_remainder;
}

SecondOrderTerms::SecondOrderTerms(SecondOrderScene scene)
    : scene_(std::make_shared<const SecondOrderScene>(std::move(scene))) {}

}  // namespace ringtol::solvers
