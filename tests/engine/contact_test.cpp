// FindContact, GapAlong and IsSinglePoint against a brute force that knows nothing of
// support functions' derivatives: both outlines are sampled densely as global point sets,
// the support function of a point set is max_j P_j . n(phi), and the gap is the minimum
// over phi of H_ring(phi) - H_roller(phi).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "engine/contact.h"
#include "engine/profile.h"

namespace ringtol::engine {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kEps = std::numeric_limits<double>::epsilon();

// ---------------------------------------------------------------------------------------
// Profiles as compile-time data, so that tolerances derive from them.

constexpr int kMaxTerms = 3;

struct Spec {
  double radius = 0.0;  // [m]
  int count = 0;
  std::array<Harmonic, kMaxTerms> terms{};
};

PolarProfile Make(const Spec& spec) {
  return PolarProfile(spec.radius, 0.0, {spec.terms.begin(), spec.terms.begin() + spec.count});
}

constexpr double Power(double x, int k) {
  double p = 1.0;
  for (int i = 0; i < k; ++i) p *= x;
  return p;
}

constexpr double Sqrt(double x) {  // Newton from above; x > 0
  double y = x > 1.0 ? x : 1.0;
  for (int i = 0; i < 200; ++i) y = 0.5 * (y + x / y);
  return y;
}

// sum_n n^power C_n [m]
constexpr double Moment(const Spec& spec, int power) {
  double sum = 0.0;
  for (int i = 0; i < spec.count; ++i) {
    sum += Power(spec.terms[static_cast<std::size_t>(i)].order, power) * spec.terms[static_cast<std::size_t>(i)].amplitude;
  }
  return sum;
}

constexpr int MaxOrder(const Spec& spec) {
  int n = 0;
  for (int i = 0; i < spec.count; ++i) n = std::max(n, spec.terms[static_cast<std::size_t>(i)].order);
  return n;
}

constexpr double MaxReach(const Spec& spec) { return spec.radius + Moment(spec, 0); }
constexpr double MinReach(const Spec& spec) { return spec.radius - Moment(spec, 0); }
constexpr double MaxSpeed(const Spec& spec) { return MaxReach(spec) + Moment(spec, 1); }  // |x'| [m/rad]

// |kappa| <= (r_max^2 + 2 r'_max^2 + r_max r''_max) / r_min^3 [1/m]
constexpr double CurvatureBound(const Spec& spec) {
  const double r = MaxReach(spec);
  const double dr = Moment(spec, 1);
  return (r * r + 2.0 * dr * dr + r * Moment(spec, 2)) / Power(MinReach(spec), 3);
}

// kappa >= (r_min^2 - r_max r''_max) / (r_max + r'_max)^3 [1/m]
constexpr double MinCurvatureBound(const Spec& spec) {
  const double r_min = MinReach(spec);
  return (r_min * r_min - MaxReach(spec) * Moment(spec, 2)) / Power(MaxSpeed(spec), 3);
}

// k-th derivative of a support function [m/rad^k]: to second order in C it is
// r(phi) + r'(phi)^2 / (2 r), bounded by sum n^k C plus (2 n_max)^k r'_max^2 / r_min
// (Bernstein on the square, a trigonometric polynomial of degree 2 n_max); doubled for
// the higher orders.
constexpr double SupportDerivativeBound(const Spec& spec, int k) {
  return 2.0 * (Moment(spec, k) + Power(2.0 * MaxOrder(spec), k) * Moment(spec, 1) * Moment(spec, 1) / MinReach(spec));
}

constexpr double kR = 0.302;    // [m] ring bore
constexpr double kRb = 0.005;   // [m] roller
constexpr double kDeg = kPi / 180.0;

constexpr std::array<Spec, 4> kRings{{
    {kR, 1, {{{2, 0.14e-3, 45.0 * kDeg}}}},
    {kR, 1, {{{20, 0.14e-3, 45.0 * kDeg}}}},
    {kR, 3, {{{3, 0.14e-3, 45.0 * kDeg}, {5, 0.14e-3, 45.0 * kDeg}, {12, 0.05e-3, 1.0}}}},
    {kR, 3, {{{15, 0.14e-3, 0.3}, {6, 0.07e-3, -1.0}, {1, 0.3e-3, 2.0}}}},
}};
constexpr std::array<Spec, 4> kRollers{{
    {kRb, 0, {}},
    {kRb, 1, {{{2, 14e-6, 0.0}}}},
    {kRb, 1, {{{7, 14e-6, 45.0 * kDeg}}}},
    {kRb, 3, {{{3, 5e-6, 1.0}, {5, 1e-6, -0.5}, {4, 1e-6, 2.0}}}},
}};

template <std::size_t N, typename F>
constexpr double MaxOf(const std::array<Spec, N>& specs, F f) {
  double m = f(specs[0]);
  for (const Spec& s : specs) m = std::max(m, f(s));
  return m;
}
template <std::size_t N, typename F>
constexpr double MinOf(const std::array<Spec, N>& specs, F f) {
  double m = f(specs[0]);
  for (const Spec& s : specs) m = std::min(m, f(s));
  return m;
}

// ---------------------------------------------------------------------------------------
// The brute force.

constexpr int kRingPoints = 400000;   // per revolution
constexpr int kRollerPoints = 20000;  // per revolution
constexpr double kRingStep = 2.0 * kPi / kRingPoints;      // [rad]
constexpr double kRollerStep = 2.0 * kPi / kRollerPoints;  // [rad]

// The best sample misses a support function by at most the sagitta of half a step,
// |x'|^2 (dtheta / 2)^2 kappa / 2 [m].
constexpr double Sagitta(const Spec& spec, double step) {
  return MaxSpeed(spec) * MaxSpeed(spec) * step * step * CurvatureBound(spec) / 8.0;
}
constexpr double kRingSagitta = MaxOf(kRings, [](const Spec& s) { return Sagitta(s, kRingStep); });
constexpr double kRollerSagitta = MaxOf(kRollers, [](const Spec& s) { return Sagitta(s, kRollerStep); });
// Dot products of coordinates up to 0.31 m: 8 roundings [m].
constexpr double kCoordinateRounding = 8.0 * kEps * 0.31;
// Sampled support functions under-read by at most their sagitta, so the brute-force gap
// is within the larger sagitta of the true one; golden section adds rounding [m].
constexpr double kBruteGapError = kRingSagitta + kRollerSagitta + 4.0 * kCoordinateRounding;
// Arc length between neighbouring samples [m].
constexpr double kRingSpacing = MaxOf(kRings, [](const Spec& s) { return MaxSpeed(s); }) * kRingStep;
constexpr double kRollerSpacing = MaxOf(kRollers, [](const Spec& s) { return MaxSpeed(s); }) * kRollerStep;

double RadiusOf(const Spec& spec, double theta) {
  double r = spec.radius;
  for (int i = 0; i < spec.count; ++i) {
    const Harmonic& h = spec.terms[static_cast<std::size_t>(i)];
    r += h.amplitude * std::cos(h.order * theta + h.phase);
  }
  return r;
}

struct PointSet {
  std::vector<double> x, y;
  void Add(const Eigen::Vector2d& p) {
    x.push_back(p.x());
    y.push_back(p.y());
  }
  double Support(double phi) const {
    const double c = std::cos(phi);
    const double s = std::sin(phi);
    double h = -std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < x.size(); ++j) h = std::max(h, x[j] * c + y[j] * s);
    return h;
  }
};

Eigen::Vector2d Dir(double a) { return {std::cos(a), std::sin(a)}; }

// Samples j * step for body angles within `half_width` of `centre` (all when >= pi).
PointSet SampleBody(const Spec& spec, const BodyPose& pose, int points_per_turn, double centre, double half_width) {
  const double step = 2.0 * kPi / points_per_turn;
  PointSet set;
  const auto first = static_cast<long>(std::floor((centre - std::min(half_width, kPi)) / step));
  const long count = half_width >= kPi ? points_per_turn : static_cast<long>(2.0 * half_width / step) + 2;
  for (long j = first; j < first + count; ++j) {
    const double theta = static_cast<double>(j) * step;
    set.Add(pose.centre + RadiusOf(spec, theta) * Dir(theta + pose.angle));
  }
  return set;
}

double GoldenMinimum(const std::function<double(double)>& f, double a, double b, double* argmin) {
  const double inv_phi = (std::sqrt(5.0) - 1.0) / 2.0;
  double x1 = b - inv_phi * (b - a);
  double x2 = a + inv_phi * (b - a);
  double f1 = f(x1);
  double f2 = f(x2);
  while (b - a > 1e-10) {
    if (f1 < f2) {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - inv_phi * (b - a);
      f1 = f(x1);
    } else {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + inv_phi * (b - a);
      f2 = f(x2);
    }
  }
  *argmin = f1 < f2 ? x1 : x2;
  return std::min(f1, f2);
}

double WrapAngle(double a) { return std::remainder(a, 2.0 * kPi); }

double Uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

// ---------------------------------------------------------------------------------------
// The cases: every ring with every roller, clearance or penetration alternating so that
// each ring and each roller meets both signs.

struct Case {
  int ring = 0, roller = 0;
  BodyPose ring_pose, roller_pose;
  bool clearance = true;
  // Brute force
  double gap = 0.0;           // [m]
  double normal_angle = 0.0;  // [rad]
  double point_distance = 0.0;  // [m] min distance between the point sets (clearance only)
  PointSet ring_set, roller_set;
  double BruteGap(double phi) const { return ring_set.Support(phi) - roller_set.Support(phi); }
};

Case MakeCase(int k, std::mt19937_64& rng) {
  Case c;
  c.ring = k % 4;
  c.roller = k / 4;
  c.clearance = (c.ring + c.roller) % 2 == 0;
  const Spec& ring = kRings[static_cast<std::size_t>(c.ring)];
  const Spec& roller = kRollers[static_cast<std::size_t>(c.roller)];
  const double alpha = Uniform(rng, -kPi, kPi);  // direction of the roller from the ring centre
  const double offset = Uniform(rng, 0.0, 0.5e-3);
  c.ring_pose.centre = offset * Dir(Uniform(rng, -kPi, kPi));
  c.ring_pose.angle = Uniform(rng, -kPi, kPi);
  c.roller_pose.angle = Uniform(rng, -50.0, 50.0);
  // Place the roller so the sign of the gap is certain: clearance leaves `move` between the
  // bore point on the ray and the roller's largest reach; penetration pushes its smallest
  // reach `move` past that bore point. The bore's tilt (< 1e-2 rad) changes the distance
  // by a relative 5e-5 only.
  const double bore = RadiusOf(ring, alpha - c.ring_pose.angle);
  const double move = c.clearance ? Uniform(rng, 20e-6, 100e-6) : Uniform(rng, 10e-6, 200e-6);
  const double distance = c.clearance ? bore - MaxReach(roller) - move : bore - MinReach(roller) + move;
  c.roller_pose.centre = c.ring_pose.centre + distance * Dir(alpha);

  // Brute force: ring samples within 0.25 rad of the ray (the touching point is within the
  // bore's tilt, < 0.02 rad, of it), all roller samples.
  c.ring_set = SampleBody(ring, c.ring_pose, kRingPoints, alpha - c.ring_pose.angle, 0.25);
  c.roller_set = SampleBody(roller, c.roller_pose, kRollerPoints, 0.0, kPi);
  constexpr double kGrid = 0.002;  // [rad]
  double best_phi = alpha;
  double best = c.BruteGap(alpha);
  for (int i = -30; i <= 30; ++i) {
    const double phi = alpha + i * kGrid;
    const double g = c.BruteGap(phi);
    if (g < best) {
      best = g;
      best_phi = phi;
    }
  }
  c.gap = GoldenMinimum([&c](double phi) { return c.BruteGap(phi); }, best_phi - kGrid, best_phi + kGrid,
                        &c.normal_angle);
  if (c.clearance) {
    // Closest pair among ring samples within 0.02 rad and roller samples within 0.3 rad of
    // the brute-force normal (the touching points lie within the tilts of it).
    const PointSet ring_near = SampleBody(ring, c.ring_pose, kRingPoints, c.normal_angle - c.ring_pose.angle, 0.02);
    const PointSet roller_near =
        SampleBody(roller, c.roller_pose, kRollerPoints, c.normal_angle - c.roller_pose.angle, 0.3);
    double d2 = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < ring_near.x.size(); ++i) {
      for (std::size_t j = 0; j < roller_near.x.size(); ++j) {
        const double dx = ring_near.x[i] - roller_near.x[j];
        const double dy = ring_near.y[i] - roller_near.y[j];
        d2 = std::min(d2, dx * dx + dy * dy);
      }
    }
    c.point_distance = std::sqrt(d2);
  }
  return c;
}

const std::vector<Case>& Cases() {
  static const std::vector<Case> cases = [] {
    std::mt19937_64 rng(0x5eed'c0de);
    std::vector<Case> v;
    for (int k = 0; k < 16; ++k) v.push_back(MakeCase(k, rng));
    return v;
  }();
  return cases;
}

Contact Solve(const Case& c, const ContactGuess* guess = nullptr) {
  return FindContact(Make(kRings[static_cast<std::size_t>(c.ring)]), c.ring_pose,
                     Make(kRollers[static_cast<std::size_t>(c.roller)]), c.roller_pose, guess);
}

::testing::Message Describe(const Case& c) {
  return ::testing::Message() << "ring " << c.ring << " roller " << c.roller << (c.clearance ? " clearance" : " penetration")
                              << " brute gap " << c.gap;
}

// g'' = rho_ring - rho_roller - g >= 1 / kappa_ring,max - 1 / kappa_roller,min - |g|max [m].
constexpr double kMinGapCurvature = 1.0 / MaxOf(kRings, [](const Spec& s) { return CurvatureBound(s); }) -
                                    1.0 / MinOf(kRollers, [](const Spec& s) { return MinCurvatureBound(s); }) -
                                    0.3e-3;
static_assert(kMinGapCurvature > 0.2);
// g'' <= rho_ring + |g|max <= 1 / kappa_ring,min + |g|max [m].
constexpr double kMaxGapCurvature = 1.0 / MinOf(kRings, [](const Spec& s) { return MinCurvatureBound(s); }) + 0.3e-3;

// FindContact's stopping rule (engine/contact.cpp): |g'| <= 1e-14 m, or a Newton step (or
// the bracket) below 1e-13 rad, the returned angle being the one before that step. At
// return |g'| <= max(1e-14 m, g''_max 1e-13 rad).
constexpr double kEngineGradientStop = 1e-14;  // [m]
constexpr double kEngineStepStop = 1e-13;      // [rad]
constexpr double kEngineGradient = std::max(kEngineGradientStop, kMaxGapCurvature * kEngineStepStop);  // [m]

// ---------------------------------------------------------------------------------------

TEST(FindContact, GapMatchesBruteForceForClearanceAndPenetration) {
  int clearances = 0;
  int penetrations = 0;
  for (const Case& c : Cases()) {
    SCOPED_TRACE(Describe(c));
    ASSERT_EQ(c.gap > 0.0, c.clearance) << "placement did not give the intended sign";
    (c.clearance ? clearances : penetrations)++;
    const Contact contact = Solve(c);
    ASSERT_TRUE(contact.converged);
    EXPECT_NEAR(contact.gap, c.gap, kBruteGapError);
  }
  EXPECT_EQ(clearances, 8);
  EXPECT_EQ(penetrations, 8);
}

TEST(FindContact, ClearanceEqualsClosestDistanceBetweenTheOutlines) {
  // The closest pair of samples is at least the gap apart and at most the gap plus half a
  // sample spacing on each outline (triangle inequality) [m].
  constexpr double kSamplingResolution = (kRingSpacing + kRollerSpacing) / 2.0;
  constexpr double kRounding = 4.0 * kCoordinateRounding;  // [m]
  for (const Case& c : Cases()) {
    if (!c.clearance) continue;
    SCOPED_TRACE(Describe(c));
    const Contact contact = Solve(c);
    EXPECT_LE(contact.gap - c.point_distance, kRounding);
    EXPECT_LE(c.point_distance - contact.gap, kSamplingResolution + kRounding);
  }
}

TEST(FindContact, NormalIsTheBruteForceMinimisingDirection) {
  // If |g_brute - g| <= e everywhere, the brute-force argmin phi_b satisfies
  // g(phi_b) - g(phi*) <= 2 e, so |phi_b - phi*| <= 2 sqrt(e / g''_min) [rad].
  constexpr double kNormalTolerance = 2.0 * Sqrt(kBruteGapError / kMinGapCurvature);
  for (const Case& c : Cases()) {
    SCOPED_TRACE(Describe(c));
    const Contact contact = Solve(c);
    EXPECT_NEAR(WrapAngle(contact.normal_angle - c.normal_angle), 0.0, kNormalTolerance);
    // normal and tangent are the unit vectors at normal_angle (4 roundings).
    constexpr double kUnitRounding = 4.0 * kEps;
    EXPECT_NEAR(contact.normal.x(), std::cos(contact.normal_angle), kUnitRounding);
    EXPECT_NEAR(contact.normal.y(), std::sin(contact.normal_angle), kUnitRounding);
    EXPECT_NEAR(contact.tangent.x(), -std::sin(contact.normal_angle), kUnitRounding);
    EXPECT_NEAR(contact.tangent.y(), std::cos(contact.normal_angle), kUnitRounding);
  }
}

TEST(FindContact, TouchingPointsLieOnTheOutlinesAndSpanTheGapAlongTheNormal) {
  // Points are sums of terms up to 0.31 m (8 roundings each way); their polar angle about
  // a body centre is good to that over the body's smallest radius (r moves by r' < 3e-3 m/rad
  // with it: negligible).
  constexpr double kOnOutline = 2.0 * kCoordinateRounding;                 // [m]
  constexpr double kRingAngle = 2.0 * kCoordinateRounding / (kR - 1e-3);   // [rad]
  constexpr double kRollerAngle = 2.0 * kCoordinateRounding / (kRb - 2e-5);  // [rad]
  // ring_point - roller_point = g n + g' t, |g'| bounded by the stopping rule; plus
  // coordinate rounding [m].
  constexpr double kSeparation = kEngineGradient + 2.0 * kCoordinateRounding;
  for (const Case& c : Cases()) {
    SCOPED_TRACE(Describe(c));
    const Spec& ring = kRings[static_cast<std::size_t>(c.ring)];
    const Spec& roller = kRollers[static_cast<std::size_t>(c.roller)];
    const Contact contact = Solve(c);

    const Eigen::Vector2d on_ring = contact.ring_point - c.ring_pose.centre;
    const double ring_angle = std::atan2(on_ring.y(), on_ring.x()) - c.ring_pose.angle;
    EXPECT_NEAR(on_ring.norm(), RadiusOf(ring, ring_angle), kOnOutline);
    EXPECT_NEAR(WrapAngle(ring_angle - contact.ring_theta), 0.0, kRingAngle);

    const Eigen::Vector2d on_roller = contact.roller_point - c.roller_pose.centre;
    const double roller_angle = std::atan2(on_roller.y(), on_roller.x()) - c.roller_pose.angle;
    EXPECT_NEAR(on_roller.norm(), RadiusOf(roller, roller_angle), kOnOutline);
    EXPECT_NEAR(WrapAngle(roller_angle - contact.roller_theta), 0.0, kRollerAngle);

    const Eigen::Vector2d span = contact.ring_point - contact.roller_point;
    EXPECT_NEAR((span - contact.gap * contact.normal).norm(), 0.0, kSeparation);
    EXPECT_NEAR(span.norm(), std::abs(contact.gap), kSeparation);
  }
}

TEST(GapAlong, MatchesTheBruteForceDifferenceOfSupportFunctions) {
  constexpr double kTolerance = kBruteGapError;  // [m] sagittas of the sampled supports
  for (const Case& c : Cases()) {
    SCOPED_TRACE(Describe(c));
    const PolarProfile ring = Make(kRings[static_cast<std::size_t>(c.ring)]);
    const PolarProfile roller = Make(kRollers[static_cast<std::size_t>(c.roller)]);
    for (const double d : {-0.2, -0.03, 0.0, 0.011, 0.1}) {
      const double phi = c.normal_angle + d;
      EXPECT_NEAR(GapAlong(ring, c.ring_pose, roller, c.roller_pose, phi), c.BruteGap(phi), kTolerance) << "phi " << phi;
    }
  }
}

TEST(FindContact, GapCurvatureMatchesSecondDifferenceOfGapAlong) {
  constexpr double kStep = 1e-4;  // [rad]
  // g = (ring - roller centre) . n + h_ring - h_roller: |g''''| <= 0.31 m plus both
  // support functions' bounds [m/rad^4].
  constexpr double kFourthDerivative = 0.31 + MaxOf(kRings, [](const Spec& s) { return SupportDerivativeBound(s, 4); }) +
                                       MaxOf(kRollers, [](const Spec& s) { return SupportDerivativeBound(s, 4); });
  // Second difference: g'''' step^2 / 12 + 4 e / step^2 with e = rounding of GapAlong [m].
  constexpr double kTolerance = kFourthDerivative * kStep * kStep / 12.0 + 4.0 * kCoordinateRounding / (kStep * kStep);
  for (const Case& c : Cases()) {
    SCOPED_TRACE(Describe(c));
    const PolarProfile ring = Make(kRings[static_cast<std::size_t>(c.ring)]);
    const PolarProfile roller = Make(kRollers[static_cast<std::size_t>(c.roller)]);
    const Contact contact = Solve(c);
    const auto g = [&](double phi) { return GapAlong(ring, c.ring_pose, roller, c.roller_pose, phi); };
    const double phi = contact.normal_angle;
    const double second = (g(phi + kStep) - 2.0 * g(phi) + g(phi - kStep)) / (kStep * kStep);
    EXPECT_NEAR(contact.gap_curvature, second, kTolerance);
    EXPECT_GT(contact.gap_curvature, kMinGapCurvature);
  }
}

// Two converged answers to the same problem differ by the stopping rules only: normal
// angles by twice the larger of the step rule and the gradient rule over g''_min [rad] ...
constexpr double kSameAngle =
    2.0 * std::max(kEngineStepStop, (kEngineGradientStop + kCoordinateRounding) / kMinGapCurvature);
// ... gaps by g'' dphi^2 / 2 (negligible) plus rounding [m], points by the lever 0.31 m
// times the angle difference plus rounding [m].
constexpr double kSameGap = 2.0 * kCoordinateRounding;
constexpr double kSamePoint = 0.31 * kSameAngle + 2.0 * kCoordinateRounding;

void ExpectSameContact(const Contact& a, const Contact& b) {
  ASSERT_TRUE(a.converged);
  ASSERT_TRUE(b.converged);
  EXPECT_NEAR(WrapAngle(a.normal_angle - b.normal_angle), 0.0, kSameAngle);
  EXPECT_NEAR(a.gap, b.gap, kSameGap);
  EXPECT_NEAR((a.ring_point - b.ring_point).norm(), 0.0, kSamePoint);
  EXPECT_NEAR((a.roller_point - b.roller_point).norm(), 0.0, kSamePoint);
}

TEST(FindContact, WarmStartFromThePreviousStepGivesTheColdStartAnswer) {
  for (const Case& c : Cases()) {
    SCOPED_TRACE(Describe(c));
    const PolarProfile ring = Make(kRings[static_cast<std::size_t>(c.ring)]);
    const PolarProfile roller = Make(kRollers[static_cast<std::size_t>(c.roller)]);
    const Contact previous = Solve(c);
    // One step along a rolling trajectory: ring turns 1 mrad, roller spins R / r_b as much,
    // the ring centre moves 1 um.
    BodyPose ring_pose = c.ring_pose;
    BodyPose roller_pose = c.roller_pose;
    ring_pose.angle += 1e-3;
    ring_pose.centre += Eigen::Vector2d(1e-6, -0.5e-6);
    roller_pose.angle += 1e-3 * kR / kRb;
    const ContactGuess guess{previous.normal_angle, previous.ring_theta, previous.roller_theta};
    ExpectSameContact(FindContact(ring, ring_pose, roller, roller_pose, &guess),
                      FindContact(ring, ring_pose, roller, roller_pose));
  }
}

TEST(FindContact, PoorGuessHalfARadianAwayGivesTheColdStartAnswer) {
  std::mt19937_64 rng(4242);
  for (const Case& c : Cases()) {
    SCOPED_TRACE(Describe(c));
    const PolarProfile ring = Make(kRings[static_cast<std::size_t>(c.ring)]);
    const PolarProfile roller = Make(kRollers[static_cast<std::size_t>(c.roller)]);
    const Contact cold = FindContact(ring, c.ring_pose, roller, c.roller_pose);
    for (const double away : {-0.5, 0.5}) {
      const double phi = cold.normal_angle + away;
      const ContactGuess consistent{phi, phi - c.ring_pose.angle, phi - c.roller_pose.angle};
      ExpectSameContact(FindContact(ring, c.ring_pose, roller, c.roller_pose, &consistent), cold);
      const ContactGuess scrambled{phi + 2.0 * kPi, Uniform(rng, -10.0, 10.0), Uniform(rng, -10.0, 10.0)};
      ExpectSameContact(FindContact(ring, c.ring_pose, roller, c.roller_pose, &scrambled), cold);
    }
  }
}

TEST(IsSinglePoint, OrdinaryRollerContactIsSinglePoint) {
  for (const Case& c : Cases()) {
    SCOPED_TRACE(Describe(c));
    const PolarProfile ring = Make(kRings[static_cast<std::size_t>(c.ring)]);
    const PolarProfile roller = Make(kRollers[static_cast<std::size_t>(c.roller)]);
    const Contact contact = FindContact(ring, c.ring_pose, roller, c.roller_pose);
    for (const double touching : {1e-5, 1e-6, 1e-9}) {
      EXPECT_TRUE(IsSinglePoint(ring, c.ring_pose, roller, c.roller_pose, contact, touching)) << touching;
    }
  }
}

// ---------------------------------------------------------------------------------------
// A constructed two-point contact.
//
// Ring: R = 0.302 m with an order-2 lobe C = 0.02 m, so its ends (body angle 0 and pi)
// have the smallest curvature radius (R + C)^2 / (R + 5 C) = 0.2579 m. A circular roller
// centred on the long axis at x0 from the ring centre has the gap function
//   g(phi) = h_ring(phi - psi) - x0 cos(phi - psi) - rho,
// even about psi. Its second derivative at psi is rho_end - rho - g(psi) = 0.2579 - 0.322 + x0:
// for x0 < 0.0641 m the end is a local maximum of g, with a minimum on each side. x0 =
// 0.06 m puts them about 0.53 rad either side, within the +-90 deg that IsSinglePoint
// scans. The roller radius is then chosen so both minima are a 1 um clearance: it exceeds
// the end's curvature radius, so the roller bridges the end and touches both flanks.
constexpr Spec kOval{kR, 1, {{{2, 0.02, 0.0}}}};
constexpr int kOvalPoints = 200000;  // per revolution
// The oval's brute-force support under-reads by at most its sagitta; plus rounding [m].
constexpr double kOvalReachError = Sagitta(kOval, 2.0 * kPi / kOvalPoints) + 4.0 * kCoordinateRounding;
// IsSinglePoint's notion of touching for these tests: 10 um [m].
constexpr double kTouching = 1e-5;

struct TwoPointSetup {
  explicit TwoPointSetup(double x0) : roller_centre(ring_pose.centre + x0 * Dir(ring_pose.angle)) {}
  BodyPose ring_pose{Eigen::Vector2d(1e-4, -2e-4), 0.4};
  Eigen::Vector2d roller_centre;
  // Ring samples whose normals can face psi +- pi/2: body angles within pi/2 plus the
  // largest tilt atan(r'/r) < 0.15 rad.
  PointSet ring_set = SampleBody(kOval, ring_pose, kOvalPoints, 0.0, kPi / 2.0 + 0.15);
  // Brute-force support of the ring minus the roller centre's reach along phi: the gap of
  // a circular roller of radius zero [m].
  double Reach(double phi) const { return ring_set.Support(phi) - roller_centre.dot(Dir(phi)); }
};

// The radius of a circular roller at setup.roller_centre that clears the smallest reach on
// the side psi < phi < psi + pi/2 by `clearance`, by brute force; side_phi is where [m].
double BridgingRollerRadius(const TwoPointSetup& setup, double clearance, double* side_phi) {
  const double psi = setup.ring_pose.angle;
  double grid_best = psi;
  double best = std::numeric_limits<double>::infinity();
  for (int i = 1; i < 100; ++i) {
    const double phi = psi + i * (kPi / 2.0) / 100.0;
    const double reach = setup.Reach(phi);
    if (reach < best) {
      best = reach;
      grid_best = phi;
    }
  }
  const double min_reach = GoldenMinimum([&setup](double phi) { return setup.Reach(phi); }, grid_best - kPi / 200.0,
                                         grid_best + kPi / 200.0, side_phi);
  return min_reach - clearance;
}

TEST(IsSinglePoint, RollerBridgingTheEndOfAnOvalBoreTouchesTwice) {
  const TwoPointSetup setup(0.06);
  const double psi = setup.ring_pose.angle;
  // Construct the roller radius: 1 um less than the smallest reach on one side.
  constexpr double kClearance = 1e-6;  // [m]
  double side_phi = 0.0;
  const double rho = BridgingRollerRadius(setup, kClearance, &side_phi);
  const PolarProfile ring = Make(kOval);
  const PolarProfile roller(rho, 0.0, {});
  const BodyPose roller_pose{setup.roller_centre, 1.0};
  EXPECT_GT(rho, 1.0 / ring.MaxCurvature()) << "the roller must be flatter than the bore's end";

  // Verify with the brute force: exactly two local minima of g over psi +- pi/2, both
  // touching, separated by a maximum far above them.
  constexpr int kScan = 360;
  constexpr double kScanStep = kPi / kScan;  // [rad]
  std::vector<double> phis, gaps;
  for (int i = 0; i <= kScan; ++i) {
    phis.push_back(psi - kPi / 2.0 + i * kScanStep);
    gaps.push_back(setup.Reach(phis.back()) - rho);
  }
  std::vector<std::size_t> minima;
  for (std::size_t i = 1; i + 1 < gaps.size(); ++i) {
    if (gaps[i] < gaps[i - 1] && gaps[i] <= gaps[i + 1]) minima.push_back(i);
  }
  // A scan sample misses its minimum by half a step: g'' (step / 2)^2 / 2 with g'' < 0.4 m;
  // plus the sagitta [m].
  constexpr double kScanError = 0.4 * kScanStep * kScanStep / 8.0 + kOvalReachError;
  ASSERT_EQ(minima.size(), 2u);
  EXPECT_NEAR(gaps[minima[0]], kClearance, kScanError);
  EXPECT_NEAR(gaps[minima[1]], kClearance, kScanError);
  EXPECT_NEAR(WrapAngle(phis[minima[1]] - side_phi), 0.0, kScanStep);
  EXPECT_NEAR(WrapAngle(phis[minima[0]] - psi), -WrapAngle(phis[minima[1]] - psi), kScanStep);
  EXPECT_GT(WrapAngle(phis[minima[1]] - phis[minima[0]]), 0.5) << "the touching points must be far apart";
  const double bump = gaps[static_cast<std::size_t>(kScan / 2)];
  EXPECT_GT(bump - kClearance, 10.0 * kTouching) << "the end must stand clear between the contacts";

  // The engine, started next to either touching point, converges there and reports that the
  // contact is not a single point. The true minima are kClearance up to the sagitta of the
  // construction, and their directions are where the scan put them.
  for (const std::size_t i : minima) {
    const ContactGuess guess{phis[i], phis[i] - psi, phis[i] - roller_pose.angle};
    const Contact contact = FindContact(ring, setup.ring_pose, roller, roller_pose, &guess);
    ASSERT_TRUE(contact.converged);
    EXPECT_NEAR(contact.gap, kClearance, kOvalReachError);
    EXPECT_NEAR(WrapAngle(contact.normal_angle - phis[i]), 0.0, kScanStep);
    EXPECT_FALSE(IsSinglePoint(ring, setup.ring_pose, roller, roller_pose, contact, kTouching));
  }
  // A cold start aims at the end, a local maximum of g: whatever it returns must not be a
  // converged contact there.
  const Contact cold = FindContact(ring, setup.ring_pose, roller, roller_pose);
  if (cold.converged) {
    EXPECT_NEAR(cold.gap, kClearance, kOvalReachError);
    EXPECT_FALSE(IsSinglePoint(ring, setup.ring_pose, roller, roller_pose, cold, kTouching));
  }
}

TEST(IsSinglePoint, EqualSecondTouchingPointCountsHoweverSmallTheTolerance) {
  // The construction above is symmetric about the end: the mirror touching point has the
  // same gap as the contact to rounding, so it is within any tolerance of touching. (A
  // sampled scan that compares its grid values, not refined minima, misses it once the
  // tolerance is below the grid's miss g'' (step / 2)^2 / 2 ~ 1e-7 m.)
  const TwoPointSetup setup(0.06);
  constexpr double kClearance = 1e-6;  // [m]
  double side_phi = 0.0;
  const PolarProfile ring = Make(kOval);
  const PolarProfile roller(BridgingRollerRadius(setup, kClearance, &side_phi), 0.0, {});
  const BodyPose roller_pose{setup.roller_centre, 1.0};
  const ContactGuess guess{side_phi, side_phi - setup.ring_pose.angle, side_phi - roller_pose.angle};
  const Contact contact = FindContact(ring, setup.ring_pose, roller, roller_pose, &guess);
  ASSERT_TRUE(contact.converged);
  const double mirror = 2.0 * setup.ring_pose.angle - contact.normal_angle;
  // Both gaps are the same evaluation mirrored: 4 roundings of 0.32 m [m].
  constexpr double kMirrorRounding = 4.0 * kCoordinateRounding;
  ASSERT_NEAR(GapAlong(ring, setup.ring_pose, roller, roller_pose, mirror), contact.gap, kMirrorRounding);
  for (const double touching : {1e-7, 1e-8, 1e-9}) {
    EXPECT_FALSE(IsSinglePoint(ring, setup.ring_pose, roller, roller_pose, contact, touching))
        << "tolerance " << touching;
  }
}

TEST(IsSinglePoint, RollerCurvedMoreThanTheOvalEndTouchesOnce) {
  // Same ring, roller pushed 10 mm further into the end with a radius below the end's
  // curvature radius: g''(psi) = 0.2579 - rho - g > 0, a single minimum at the end.
  const TwoPointSetup setup(0.07);
  constexpr double kClearance = 1e-6;  // [m]
  const double rho = setup.Reach(setup.ring_pose.angle) - kClearance;
  const PolarProfile ring = Make(kOval);
  const PolarProfile roller(rho, 0.0, {});
  const BodyPose roller_pose{setup.roller_centre, -2.0};
  ASSERT_LT(rho, 1.0 / ring.MaxCurvature());
  const Contact contact = FindContact(ring, setup.ring_pose, roller, roller_pose);
  ASSERT_TRUE(contact.converged);
  EXPECT_NEAR(contact.gap, kClearance, kOvalReachError);
  EXPECT_TRUE(IsSinglePoint(ring, setup.ring_pose, roller, roller_pose, contact, kTouching));
}

}  // namespace
}  // namespace ringtol::engine
