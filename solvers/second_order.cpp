#include "solvers/second_order.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

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

// Remainder term 1 of SecondOrderTerms::At (the support functions), shared with Over: per
// outline its slope's and curvature's magnitudes at the contact, its reach (R - q, r + p)
// and allowance (the reach less U >= |dr|, > 0), U and J >= |dr'''|. The operations and
// their order are At's own from before Over existed, so its results keep their bits.
struct OutlineAtContact {
  double slope = 0.0;      // [m/rad] |a| or |b|
  double curvature = 0.0;  // [m/rad^2] |q| or |p|
  double reach = 0.0;      // [m]
  double allowance = 0.0;  // [m]
  double value = 0.0;      // [m] U
  double jerk = 0.0;       // [m] J
};
struct SupportRemainder {
  double value = 0.0;      // [m] of the gap
  double slope = 0.0;      // [m/rad]
  double curvature = 0.0;  // [m/rad^2]
};
SupportRemainder SupportRemainderOf(const OutlineAtContact& ring, const OutlineAtContact& roller) {
  const double a = ring.slope, q = ring.curvature, b = roller.slope, p = roller.curvature;
  const double ring_slide = a / ring.allowance;
  const double roller_slide = b / roller.allowance;
  const double ring_cubic = ring.jerk + 3.0 * a;
  const double roller_cubic = roller.jerk + 3.0 * b;
  SupportRemainder out;
  out.value = a * a * ring.value / (2.0 * ring.allowance * ring.reach) + ring_cubic * ring_slide * ring_slide * ring_slide / 3.0 +
              b * b * roller.value / (2.0 * roller.allowance * roller.reach) +
              roller_cubic * roller_slide * roller_slide * roller_slide / 3.0;
  out.slope = a * q * ring.value / (ring.allowance * ring.reach) + ring_cubic * ring_slide * ring_slide / 2.0 +
              b * p * roller.value / (roller.allowance * roller.reach) + roller_cubic * roller_slide * roller_slide / 2.0;
  out.curvature = (q * q + a * ring.jerk) / ring.allowance + (p * p + b * roller.jerk) / roller.allowance;
  return out;
}

}  // namespace

void SecondOrderTerms::At(const FirstOrderAngle& first, SecondOrderAngle& out) const {
  const SecondOrderScene& scene = *scene_;
  const std::vector<SecondOrderScene::Contact>& contacts = scene.contacts;
  const int z = static_cast<int>(contacts.size());
  const auto zs = static_cast<std::size_t>(z);
  const double infinite = std::numeric_limits<double>::infinity();
  out.travel.assign(zs, 0.0);
  out.contact_force.assign(zs, 0.0);
  out.centre.setZero();
  bool bounded = true;
  // Per contact: gamma, the turn g'_i with its known second-order slopes, the gap's
  // curvature, the penetration change d_i, and the first-order turn.
  thread_local std::vector<double> scratch;
  scratch.resize(5 * zs);
  double* gamma = scratch.data();
  double* slope = gamma + zs;
  double* curvature = slope + zs;
  double* penetration_change = curvature + zs;
  double* linear_slope = penetration_change + zs;
  const Eigen::Vector2d moved = first.centre - scene.centre0;
  const double ring_radius = scene.ring_radius;
  for (std::size_t i = 0; i < zs; ++i) {
    const SecondOrderScene::Contact& k = contacts[i];
    const double a = first.slopes[i];
    const double b = first.slopes[zs + i];
    const double q = first.curvatures[i];
    const double p = first.curvatures[zs + i];
    Eigen::Vector2d relative = moved - k.shift;
    if (k.spring) relative -= (first.travel[i] - k.travel0) * k.axis;
    const double ring_reach = ring_radius - q;  // r + dr - dr'' of the bore, dr left out
    const double roller_reach = k.roller_radius + p;
    linear_slope[i] = a + b + relative.dot(k.tangent);
    curvature[i] = k.gap_curvature + q + p - relative.dot(k.normal);
    if (!(ring_reach > 0.0 && roller_reach > 0.0 && curvature[i] > 0.0)) {
      bounded = false;  // beyond any expansion: the first-order curvatures stand in
      slope[i] = linear_slope[i];
      curvature[i] = k.gap_curvature;
      gamma[i] = a * a / (2.0 * ring_radius) - b * b / (2.0 * k.roller_radius);
    } else {
      slope[i] = linear_slope[i] + a * q / ring_reach - b * p / roller_reach;
      gamma[i] = a * a / (2.0 * ring_reach) - b * b / (2.0 * roller_reach);
    }
    gamma[i] -= slope[i] * slope[i] / (2.0 * curvature[i]);
    penetration_change[i] = 0.0;
    if (k.penetration > 0.0) {
      penetration_change[i] = (first.contact_force[i] - k.force0) / k.force_stiffness;
      gamma[i] -= (scene.exponent - 1.0) * penetration_change[i] * penetration_change[i] / (2.0 * k.penetration);
    }
  }
  const Eigen::MatrixXd& response = scene.response;
  const auto add = [&](double weight, Eigen::Index column) {
    out.centre += weight * response.block<2, 1>(0, column);
    for (std::size_t j = 0; j < zs; ++j) {
      const auto row = static_cast<Eigen::Index>(2 + j);
      if (contacts[j].spring) out.travel[j] += weight * response(row, column);
      out.contact_force[j] += weight * response(row + z, column);
    }
  };
  for (std::size_t i = 0; i < zs; ++i) add(gamma[i], static_cast<Eigen::Index>(i));
  // The turn the correction itself gives each normal, which the response followed.
  thread_local std::vector<double> feedback;
  feedback.resize(zs);
  for (std::size_t i = 0; i < zs; ++i) {
    Eigen::Vector2d moved_correction = out.centre;
    if (contacts[i].spring) moved_correction -= out.travel[i] * contacts[i].axis;
    feedback[i] = moved_correction.dot(contacts[i].tangent);
  }
  double correction = 0.0;  // the correction's size at the centre, each term by its gain
  for (std::size_t i = 0; i < zs; ++i) {
    const SecondOrderScene::Contact& k = contacts[i];
    const double force = first.contact_force[i];
    const double turn = -(slope[i] + feedback[i]) / curvature[i];
    const double linear_turn = -(linear_slope[i] + feedback[i]) / k.gap_curvature;
    const double normal_force = -force * turn * turn / 2.0;
    const double tangent_force = force * turn - k.force0 * linear_turn;
    add(normal_force, static_cast<Eigen::Index>(zs + i));
    add(tangent_force, static_cast<Eigen::Index>(2 * zs + i));
    correction += k.gap_gain * std::abs(gamma[i]) + k.normal_force_gain * std::abs(normal_force) +
                  k.tangent_force_gain * std::abs(tangent_force);
  }
  if (!bounded) {
    out.remainder = infinite;
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
  //     k_c), and so does their product with the correction.
  // Each term is bounded by its magnitude and carried to the centre by the norm of its
  // response, so their sum bounds |exact - corrected| up to terms of fourth order and
  // products of the bounds (docs/model.md §7).
  double remainder = 0.0;
  double drift = 0.0;  // the largest relative change of the response's entries
  for (std::size_t i = 0; i < zs; ++i) {
    const SecondOrderScene::Contact& k = contacts[i];
    const double a = std::abs(first.slopes[i]);
    const double b = std::abs(first.slopes[zs + i]);
    const double q = std::abs(first.curvatures[i]);
    const double p = std::abs(first.curvatures[zs + i]);
    const double r = k.roller_radius;
    const double ring_reach = ring_radius - first.curvatures[i];
    const double roller_reach = r + first.curvatures[zs + i];
    const double ring_allowance = ring_reach - scene.ring_value;
    const double roller_allowance = roller_reach - k.roller_value;
    if (!(ring_allowance > 0.0 && roller_allowance > 0.0)) {
      out.remainder = infinite;
      return;
    }
    // 1. The support functions.
    const SupportRemainder support_bound = SupportRemainderOf({a, q, ring_reach, ring_allowance, scene.ring_value, scene.ring_jerk},
                                                              {b, p, roller_reach, roller_allowance, k.roller_value, k.roller_jerk});
    const double support = support_bound.value;
    const double support_slope = support_bound.slope;
    const double support_curvature = support_bound.curvature;
    // 2. The turn.
    const double curvature_allowance = curvature[i] - support_curvature;
    if (!(curvature_allowance > 0.0)) {
      out.remainder = infinite;
      return;
    }
    const double g1 = std::abs(slope[i]);
    const double bound_slope = g1 + std::abs(feedback[i]) + support_slope;
    const double phi = bound_slope / curvature_allowance;
    const double turning = bound_slope * bound_slope / (2.0 * curvature_allowance) - g1 * g1 / (2.0 * curvature[i]) +
                           (scene.ring_jerk + k.roller_jerk + bound_slope) * phi * phi * phi / 3.0;
    // 3. The penalty law.
    double law = 0.0;
    double law_drift = 0.0;
    if (k.penetration > 0.0) {
      const double e = scene.exponent;
      const double delta = k.penetration;
      const double d = std::abs(penetration_change[i]);
      const double reach = d + std::abs(out.contact_force[i] / k.force_stiffness);
      const double lowest = delta - reach;
      if (!(lowest > 0.0)) {
        out.remainder = infinite;
        return;
      }
      // x^(e - 3) is monotone, so its largest over [lowest, delta + reach] sits at one end:
      // one pow per contact and angle instead of three (they were a sixth of a linear sample).
      const double worst_point = e < 3.0 ? lowest : delta + reach;
      const double third = (e - 1.0) * std::abs(e - 2.0) * std::pow(worst_point, e - 3.0) / k.law_scale;
      law = (e - 1.0) * (reach * reach - d * d) / (2.0 * delta) + third * reach * reach * reach / 6.0;
      law_drift = (e - 1.0) * reach / lowest;
    }
    // 4. The forces' turn.
    const double force = std::abs(first.contact_force[i]) + std::abs(out.contact_force[i]);
    const double turn = std::abs(slope[i] + feedback[i]) / curvature[i];
    const double phi2 = phi * phi;
    const double normal_force = std::abs(out.contact_force[i]) * phi2 / 2.0 + force * ((phi2 - turn * turn) / 2.0 + phi2 * phi2 / 24.0);
    const double tangent_force = std::abs(out.contact_force[i]) * phi + force * (phi - turn + phi2 * phi / 6.0);
    remainder += k.gap_gain * (support + turning + law) + k.normal_force_gain * normal_force +
                 k.tangent_force_gain * tangent_force;
    // 5. The response's drift.
    const double force_change = std::abs(first.contact_force[i] - k.force0) + std::abs(out.contact_force[i]);
    const double geometric = k.force_stiffness > 0.0
                                 ? force_change / (k.gap_curvature * k.force_stiffness)
                                 : 0.0;
    drift = std::max(drift, 2.0 * phi + law_drift + geometric);
  }
  out.remainder = remainder + drift * correction;
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
  std::vector<Interval> gamma(zs), linear_slope(zs), slope_extra(zs), slope(zs), kappa(zs), curvature(zs),
      force_change(zs), ring_reach(zs), roller_reach(zs);
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
  // centre's along kDirections directions u_m = (cos, sin)(m pi / kDirections): a vector
  // is within pi / (2 kDirections) of one of them or of its opposite, so
  // |v| <= max_m |v . u_m| / cos(pi / (2 kDirections)), where the two axes alone would
  // give sqrt(2) where the terms' extremes fall in different directions.
  constexpr int kDirections = 16;
  std::array<Interval, kDirections> centre_along{};
  std::array<Eigen::Vector2d, kDirections> directions;
  for (int m = 0; m < kDirections; ++m) {
    const double angle = std::numbers::pi * m / kDirections;
    directions[static_cast<std::size_t>(m)] = Eigen::Vector2d(std::cos(angle), std::sin(angle));
  }
  std::vector<Interval> travel(zs), force(zs);
  const Eigen::MatrixXd& response = scene.response;
  const auto add = [&](Interval weight, Eigen::Index column) {
    const Eigen::Vector2d moves = response.block<2, 1>(0, column);
    for (int m = 0; m < kDirections; ++m) {
      Interval& along = centre_along[static_cast<std::size_t>(m)];
      along = along + moves.dot(directions[static_cast<std::size_t>(m)]) * weight;
    }
    for (std::size_t j = 0; j < zs; ++j) {
      const auto row = static_cast<Eigen::Index>(2 + j);
      if (contacts[j].spring) travel[j] = travel[j] + response(row, column) * weight;
      force[j] = force[j] + response(row + static_cast<Eigen::Index>(zs), column) * weight;
    }
  };
  for (std::size_t i = 0; i < zs; ++i) add(gamma[i], static_cast<Eigen::Index>(i));
  // The feedback of contact i, (centre - travel_i axis_i) . t_i after the gammas, is linear
  // in them: summed gamma by gamma, not from the centre's and travel's intervals, which
  // would forget that one gamma moves both.
  std::vector<Interval> feedback(zs);
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
  std::vector<Interval> turn(zs), normal_force(zs), tangent_force(zs);
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
  out.centre = kRoundingAllowance * centre_along_max / std::cos(std::numbers::pi / (2.0 * kDirections));
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
    const SupportRemainder support = SupportRemainderOf({a, q, ring_low, ring_allowance, scene.ring_value, scene.ring_jerk},
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
  }
  out.remainder = kRoundingAllowance * (remainder + drift * correction);
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
