// PolarProfile against references built here from the definition alone:
//   r(theta) = R + mean + sum_n C_n cos(n theta + phi_n),
// evaluated term by term in long double; the support function by brute force over a dense
// sampling of the outline; the curvature by the textbook polar formula; and the exact
// convexity limit of a single harmonic (derived below).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

#include <boost/math/tools/minima.hpp>

#include "engine/profile.h"

namespace ringtol::engine {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kLongEps = std::numeric_limits<long double>::epsilon();

// ---------------------------------------------------------------------------------------
// Test profiles as compile-time data (template arguments), so that every tolerance below
// is a constexpr derived from the profile it applies to.

constexpr int kMaxTerms = 6;

struct Spec {
  double radius = 0.0;  // [m]
  double mean = 0.0;    // [m]
  int count = 0;        // harmonics used
  std::array<Harmonic, kMaxTerms> terms{};
};

PolarProfile Make(const Spec& spec) {
  return PolarProfile(spec.radius, spec.mean, {spec.terms.begin(), spec.terms.begin() + spec.count});
}

// sum_n n^power C_n [m]
constexpr double Moment(const Spec& spec, int power) {
  double sum = 0.0;
  for (int i = 0; i < spec.count; ++i) {
    double weight = 1.0;
    for (int k = 0; k < power; ++k) weight *= spec.terms[static_cast<std::size_t>(i)].order;
    sum += weight * spec.terms[static_cast<std::size_t>(i)].amplitude;
  }
  return sum;
}

constexpr double Power(double x, int k) {
  double p = 1.0;
  for (int i = 0; i < k; ++i) p *= x;
  return p;
}

constexpr int MaxOrder(const Spec& spec) {
  int n = 0;
  for (int i = 0; i < spec.count; ++i) n = std::max(n, spec.terms[static_cast<std::size_t>(i)].order);
  return n;
}

constexpr double MaxReach(const Spec& spec) { return spec.radius + spec.mean + Moment(spec, 0); }  // [m]
constexpr double MinReach(const Spec& spec) { return spec.radius + spec.mean - Moment(spec, 0); }  // [m]
// |x'| = sqrt(r^2 + r'^2) <= r_max + r'_max [m/rad]
constexpr double MaxSpeed(const Spec& spec) { return MaxReach(spec) + Moment(spec, 1); }

// |kappa| = |r^2 + 2 r'^2 - r r''| / (r^2 + r'^2)^(3/2) <= (r_max^2 + 2 r'_max^2 + r_max r''_max) / r_min^3.
constexpr double CurvatureBound(const Spec& spec) {
  const double r = MaxReach(spec);
  const double dr = Moment(spec, 1);
  const double r_min = MinReach(spec);
  return (r * r + 2.0 * dr * dr + r * Moment(spec, 2)) / (r_min * r_min * r_min);
}

// |dkappa/dtheta| [1/(m rad)]: kappa = N / q^(3/2) with N = r^2 + 2 r'^2 - r r'',
// q = r^2 + r'^2, so |kappa'| <= |N'| / r_min^3 + 1.5 |N| |q'| / r_min^5 with
// |N'| <= 2 r r' + 5 r' r'' + r r''' and |q'| <= 2 r r' + 2 r' r'' at their bounds.
constexpr double CurvatureSlopeBound(const Spec& spec) {
  const double r = MaxReach(spec);
  const double r1 = Moment(spec, 1);
  const double r2 = Moment(spec, 2);
  const double r3 = Moment(spec, 3);
  const double r_min = MinReach(spec);
  const double n_max = r * r + 2.0 * r1 * r1 + r * r2;
  const double dn_max = 2.0 * r * r1 + 5.0 * r1 * r2 + r * r3;
  const double dq_max = 2.0 * r * r1 + 2.0 * r1 * r2;
  return dn_max / Power(r_min, 3) + 1.5 * n_max * dq_max / Power(r_min, 5);
}

// Bound of the k-th theta derivative of the curvature [1/m]: kappa is a ratio of
// trigonometric polynomials of degree <= 2 n_max; Bernstein's inequality bounds a
// polynomial's k-th derivative by degree^k times its size; a factor 4 covers the ratio.
constexpr double CurvatureDerivativeBound(const Spec& spec, int k) {
  return 4.0 * Power(2.0 * MaxOrder(spec), k) * CurvatureBound(spec);
}

// Exact smallest curvature of a single harmonic r = R + C cos(n theta + phi): the
// numerator r^2 + 2 r'^2 - r r'' is, in c = cos(n theta + phi),
//   R^2 + (n^2 + 2) R C c + (1 - n^2) C^2 c^2 + 2 n^2 C^2,
// concave in c, so smallest at c = -1 where r' = 0 and it equals (R - C)(R - (n^2 + 1) C):
//   kappa_min = (R - (n^2 + 1) C) / (R - C)^2,   convex iff C < R / (n^2 + 1).
// (The linearised rule (n^2 - 1) C < R is too generous: for n = 1 it misses the limacon's
// dimple at C = R / 2, for n = 5 the limit is R / 26, not R / 24.) At c = +1 the same
// algebra gives kappa = (R + (n^2 + 1) C) / (R + C)^2, the largest curvature.
constexpr double SingleOrderMinCurvature(double radius, int n, double amplitude) {
  return (radius - (n * n + 1) * amplitude) / ((radius - amplitude) * (radius - amplitude));
}
constexpr double SingleOrderMaxCurvature(double radius, int n, double amplitude) {
  return (radius + (n * n + 1) * amplitude) / ((radius + amplitude) * (radius + amplitude));
}

// Lower bound of the curvature [1/m]: exact for a single order; for several orders the
// numerator is >= r_min^2 - r_max r''_max and the denominator <= (r_max + r'_max)^3.
constexpr double MinCurvatureBound(const Spec& spec) {
  if (spec.count == 1) {
    return SingleOrderMinCurvature(spec.radius + spec.mean, spec.terms[0].order, spec.terms[0].amplitude);
  }
  const double r_min = MinReach(spec);
  return (r_min * r_min - MaxReach(spec) * Moment(spec, 2)) / Power(MaxSpeed(spec), 3);
}

// ---------------------------------------------------------------------------------------
// Independent references.

template <typename T>
struct Terms {
  T r = 0, dr = 0, ddr = 0;
};
using Exact = Terms<long double>;

// Term by term; in long double (64-bit mantissa: n theta is exact for n <= 60) for the
// pointwise references, in double for the dense samplings.
template <typename T>
Terms<T> DirectSumAs(const Spec& spec, T theta) {
  Terms<T> e{static_cast<T>(spec.radius) + static_cast<T>(spec.mean), 0, 0};
  for (int i = 0; i < spec.count; ++i) {
    const Harmonic& h = spec.terms[static_cast<std::size_t>(i)];
    const T n = static_cast<T>(h.order);
    const T arg = n * theta + static_cast<T>(h.phase);
    const T c = std::cos(arg);
    e.r += static_cast<T>(h.amplitude) * c;
    e.dr -= n * static_cast<T>(h.amplitude) * std::sin(arg);
    e.ddr -= n * n * static_cast<T>(h.amplitude) * c;
  }
  return e;
}
Exact DirectSum(const Spec& spec, long double theta) { return DirectSumAs<long double>(spec, theta); }

template <typename T>
T PolarCurvature(const Terms<T>& e) {
  const T q = e.r * e.r + e.dr * e.dr;
  return (e.r * e.r + 2 * e.dr * e.dr - e.r * e.ddr) / (q * std::sqrt(q));
}

// d/dtheta of x(theta) . n(phi): r' cos(theta - phi) - r sin(theta - phi).
long double SupportSlope(const Spec& spec, long double theta, long double phi) {
  const Exact e = DirectSum(spec, theta);
  return e.dr * std::cos(theta - phi) - e.r * std::sin(theta - phi);
}

constexpr int kOutlinePoints = 200000;
constexpr double kOutlineStep = 2.0 * kPi / kOutlinePoints;  // [rad]

// The outline sampled at kOutlinePoints equally spaced body angles.
struct Outline {
  std::vector<double> theta, x, y;
};

Outline SampleOutline(const Spec& spec) {
  Outline o;
  for (int j = 0; j < kOutlinePoints; ++j) {
    const double theta = j * kOutlineStep;
    const double r = DirectSumAs<double>(spec, theta).r;
    o.theta.push_back(theta);
    o.x.push_back(r * std::cos(theta));
    o.y.push_back(r * std::sin(theta));
  }
  return o;
}

// One sampling per profile, shared by the tests that use it.
template <Spec kSpec>
const Outline& OutlineOf() {
  static const Outline outline = SampleOutline(kSpec);
  return outline;
}

struct BruteSupport {
  double h = 0.0;      // [m] max over the samples of x . n(phi)
  double theta = 0.0;  // [rad] body angle of the best sample
};

BruteSupport BruteForceSupport(const Outline& o, double phi) {
  const double c = std::cos(phi);
  const double s = std::sin(phi);
  BruteSupport best{-std::numeric_limits<double>::infinity(), 0.0};
  for (std::size_t j = 0; j < o.x.size(); ++j) {
    const double value = o.x[j] * c + o.y[j] * s;
    if (value > best.h) best = {value, o.theta[j]};
  }
  return best;
}

// The brute force refined to full precision: the best sample's neighbours bracket the
// touching point, where x . n(phi) has its single maximum, and bisection on the long double
// slope of x . n(phi) finds it.
struct RefinedSupport {
  long double theta = 0.0L, h = 0.0L, dh = 0.0L;
  double kappa = 0.0;  // [1/m] polar curvature at theta
};

RefinedSupport ReferenceSupport(const Spec& spec, const Outline& o, long double phi) {
  const BruteSupport brute = BruteForceSupport(o, static_cast<double>(phi));
  long double lo = static_cast<long double>(brute.theta) - kOutlineStep;
  long double hi = static_cast<long double>(brute.theta) + kOutlineStep;
  EXPECT_GT(SupportSlope(spec, lo, phi), 0.0L) << "brute force bracket lost at phi " << static_cast<double>(phi);
  EXPECT_LT(SupportSlope(spec, hi, phi), 0.0L) << "brute force bracket lost at phi " << static_cast<double>(phi);
  for (int k = 0; k < 80; ++k) {
    const long double mid = 0.5L * (lo + hi);
    (SupportSlope(spec, mid, phi) > 0.0L ? lo : hi) = mid;
  }
  RefinedSupport ref;
  ref.theta = 0.5L * (lo + hi);
  const Exact e = DirectSum(spec, ref.theta);
  ref.h = e.r * std::cos(ref.theta - phi);
  ref.dh = e.r * std::sin(ref.theta - phi);
  ref.kappa = static_cast<double>(PolarCurvature(e));
  return ref;
}

double WrapAngle(double a) { return std::remainder(a, 2.0 * kPi); }

double Uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

// `count` body angles drawn uniformly over several turns either way [rad].
std::vector<double> RandomAngles(std::uint64_t seed, int count) {
  std::mt19937_64 rng(seed);
  std::vector<double> thetas;
  for (int k = 0; k < count; ++k) thetas.push_back(Uniform(rng, -20.0, 20.0));
  return thetas;
}

// ---------------------------------------------------------------------------------------
// The profiles.

constexpr double kR = 0.302;  // [m] the article's ring bore

// Six orders up to 60 with amplitudes spread over three decades.
constexpr Spec kMixed{kR, 2.0e-5, 6,
                      {{{1, 2.0e-4, 0.3}, {2, 1.4e-4, 0.785}, {5, 3.0e-5, -1.1}, {13, 8.0e-6, 2.0},
                        {31, 1.0e-6, -2.7}, {60, 2.0e-7, 0.9}}}};
// The paper's study orders at moderate size.
constexpr Spec kRingLike{kR, 0.0, 5,
                         {{{2, 1.4e-4, 0.785}, {3, 5.0e-5, 1.0}, {7, 3.0e-5, -2.0}, {12, 1.0e-5, 0.3},
                           {20, 5.0e-6, 2.5}}}};
// A single order 2 at 10 % of the radius: far from small, far from the convexity limit.
constexpr Spec kOvalModerate{kR, 0.0, 1, {{{2, 0.10 * kR, 0.4}}}};
// Order 2 at 19 % of the radius: 95 % of its exact convexity limit R / 5.
constexpr Spec kOvalLarge{kR, 0.0, 1, {{{2, 0.19 * kR, -0.7}}}};
// Order 5 at 99 % of its exact convexity limit R / 26.
constexpr Spec kFiveNearLimit{kR, 0.0, 1, {{{5, 0.99 * kR / 26.0, 1.3}}}};
// Order 40 at small amplitude: (n^2 + 1) C = 0.053 R.
constexpr Spec kOrderForty{kR, 0.0, 1, {{{40, 1.0e-5, 0.2}}}};
// Not convex: order 6 at 5 % of R, (n^2 + 1) C = 1.85 R.
constexpr Spec kDented{kR, 0.0, 2, {{{6, 0.05 * kR, 0.3}, {2, 2.0e-3, 1.0}}}};

static_assert(MinCurvatureBound(kRingLike) > 0.0 && MinCurvatureBound(kMixed) > 0.0);

// ---------------------------------------------------------------------------------------
// Evaluate

// The engine's angle-addition recurrence for cos(n theta), sin(n theta) drifts by about
// one rounding per order, so term n carries ~n eps relative error: 4 n_max eps times the
// matching moment, plus 4 roundings of the constant part.
struct DerivativeTolerances {
  double r = 0.0;    // [m]
  double dr = 0.0;   // [m/rad]
  double ddr = 0.0;  // [m/rad^2]
};

// `evaluate(profile, theta)` against the long-double direct sum at every theta.
template <Spec kSpec, typename Evaluate>
void ExpectNearDirectSum(Evaluate evaluate, const std::vector<double>& thetas, const DerivativeTolerances& tolerance) {
  const PolarProfile profile = Make(kSpec);
  for (const double theta : thetas) {
    const RadiusDerivatives d = evaluate(profile, theta);
    const Exact e = DirectSum(kSpec, theta);
    EXPECT_NEAR(d.r, static_cast<double>(e.r), tolerance.r) << "theta " << theta;
    EXPECT_NEAR(d.dr, static_cast<double>(e.dr), tolerance.dr) << "theta " << theta;
    EXPECT_NEAR(d.ddr, static_cast<double>(e.ddr), tolerance.ddr) << "theta " << theta;
  }
}

template <Spec kSpec>
constexpr double kRecurrence = 4.0 * MaxOrder(kSpec) * kEps;

template <Spec kSpec>
constexpr DerivativeTolerances kSummed{kRecurrence<kSpec> * Moment(kSpec, 0) + 4.0 * kEps * MaxReach(kSpec),
                                        kRecurrence<kSpec> * Moment(kSpec, 1), kRecurrence<kSpec> * Moment(kSpec, 2)};

template <Spec kSpec>
void ExpectEvaluateMatchesDirectSum(const std::vector<double>& thetas) {
  ExpectNearDirectSum<kSpec>([](const PolarProfile& p, double theta) { return p.Evaluate(theta); }, thetas,
                             kSummed<kSpec>);
}

TEST(PolarProfile, EvaluateMatchesDirectSumOfHarmonicsAndTheirDerivatives) {
  const std::vector<double> thetas = RandomAngles(20250101, 2000);
  ExpectEvaluateMatchesDirectSum<kMixed>(thetas);
  ExpectEvaluateMatchesDirectSum<kOrderForty>(thetas);
  ExpectEvaluateMatchesDirectSum<kOvalLarge>(thetas);
}

// Profiles with kSampledOrders harmonic orders and more evaluate by interpolating their
// samples. The table's step h is at most the one its bound allows,
// h_max = (46080 tol / S6)^(1/6) with S6 = sum n^6 C_n, and the quintic Hermite error
// f^(6)/720 * w(t) h^6, w = t^3 (1 - t)^3, bounds r by tol; differentiated once and
// twice, max |w'| = 0.048 and max |w''| = 0.375 bound r' and r'' by 0.048 h^5 S6 / 720
// and 0.375 h^4 S6 / 720, to leading order: a factor 8 covers the next order (the
// dependence of f^(6) on where it is taken).
template <Spec kSpec>
void ExpectSampledEvaluationWithinItsBound(const std::vector<double>& thetas) {
  constexpr double kSixth = Moment(kSpec, 6);  // [m/rad^6] S6
  const double step = std::pow(46080.0 * PolarProfile::kSampleTolerance / kSixth, 1.0 / 6.0);  // [rad] h_max
  // The bound, plus the direct sum's own round-off (above).
  const DerivativeTolerances tolerance{PolarProfile::kSampleTolerance + kSummed<kSpec>.r,
                                       8.0 * 0.048 * std::pow(step, 5) * kSixth / 720.0 + kSummed<kSpec>.dr,
                                       8.0 * 0.375 * std::pow(step, 4) * kSixth / 720.0 + kSummed<kSpec>.ddr};
  ASSERT_TRUE(Make(kSpec).sampled());
  ExpectNearDirectSum<kSpec>(
      [](const PolarProfile& p, double theta) { return p.EvaluateAt(theta, std::cos(theta), std::sin(theta)); }, thetas,
      tolerance);
}

TEST(PolarProfile, SampledEvaluationStaysWithinItsInterpolationBound) {
  const std::vector<double> thetas = RandomAngles(20261124, 4000);
  ExpectSampledEvaluationWithinItsBound<kMixed>(thetas);
  ExpectSampledEvaluationWithinItsBound<kRingLike>(thetas);
  ExpectSampledEvaluationWithinItsBound<kOrderForty>(thetas);
  // Few orders are summed: there the sampled path is the summed one.
  const PolarProfile oval = Make(kOvalLarge);
  EXPECT_FALSE(oval.sampled());
  const RadiusDerivatives summed = oval.EvaluateAt(0.3, std::cos(0.3), std::sin(0.3));
  EXPECT_EQ(summed.r, oval.EvaluateAt(std::cos(0.3), std::sin(0.3)).r);
}

// The four-lane evaluation the contact steps use does the arithmetic of EvaluateAt lane
// by lane, so it must give the same bits.
TEST(PolarProfile, FourAnglesAtOnceGiveExactlyWhatFourEvaluationsGive) {
  const PolarProfile profile = Make(kMixed);
  std::mt19937_64 rng(20261124);
  for (int trial = 0; trial < 100; ++trial) {
    double cos_theta[4];
    double sin_theta[4];
    for (int k = 0; k < 4; ++k) {
      const double theta = Uniform(rng, -20.0, 20.0);
      cos_theta[k] = std::cos(theta);
      sin_theta[k] = std::sin(theta);
    }
    RadiusDerivatives four[4];
    profile.EvaluateFourAt(cos_theta, sin_theta, four);
    for (int k = 0; k < 4; ++k) {
      const RadiusDerivatives one = profile.EvaluateAt(cos_theta[k], sin_theta[k]);
      EXPECT_EQ(four[k].r, one.r);
      EXPECT_EQ(four[k].dr, one.dr);
      EXPECT_EQ(four[k].ddr, one.ddr);
    }
  }
}

// The contact steps take cos and sin of every moving angle from a Taylor series about a
// reference: across the whole reach the series must be as good as libm. A series cut
// one term short at this reach would miss by ~1e-15, several ulps.
TEST(NearbyAngle, MatchesLibmToRoundOffAcrossItsReachAndAlongAWalk) {
  constexpr double kRoundOff = 3.0 * kEps;
  for (int k = -1000; k <= 1000; ++k) {
    const double delta = NearbyAngle::kReach * k / 1000.0;
    double c;
    double s;
    CosSinOfSmallAngle(delta, c, s);
    EXPECT_NEAR(c, static_cast<double>(std::cos(static_cast<long double>(delta))), kRoundOff) << delta;
    EXPECT_NEAR(s, static_cast<double>(std::sin(static_cast<long double>(delta))), kRoundOff) << delta;
  }
  // Steps of a contact along a revolution, both ways, and a jump beyond the reach.
  NearbyAngle angle;
  double theta = 0.3;
  std::mt19937_64 rng(20261124);
  for (int step = 0; step < 20000; ++step) {
    theta += step == 10000 ? 2.5 : Uniform(rng, -0.004, 0.012);
    double c;
    double s;
    angle.Evaluate(theta, c, s);
    EXPECT_NEAR(c, static_cast<double>(std::cos(static_cast<long double>(theta))), kRoundOff) << theta;
    EXPECT_NEAR(s, static_cast<double>(std::sin(static_cast<long double>(theta))), kRoundOff) << theta;
  }
}

TEST(PolarProfile, HarmonicsOfEqualOrderAddUp) {
  // Two order-3 terms and two order-7 terms; the phasor sums give the coefficients.
  constexpr Spec kDuplicated{kR, -1.0e-5, 5,
                             {{{3, 4.0e-5, 0.5}, {7, 1.0e-5, -1.0}, {3, 2.5e-5, 2.2}, {7, 3.0e-6, 0.1},
                               {2, 6.0e-5, 0.0}}}};
  const PolarProfile profile = Make(kDuplicated);
  EXPECT_EQ(profile.max_order(), 7);
  // A coefficient sums two products of size <= 4e-5 m: 4 roundings.
  constexpr double kCoefficientTolerance = 4.0 * kEps * 4.0e-5;  // [m]
  EXPECT_NEAR(profile.cos_coefficient(3), 4.0e-5 * std::cos(0.5) + 2.5e-5 * std::cos(2.2), kCoefficientTolerance);
  EXPECT_NEAR(profile.sin_coefficient(3), 4.0e-5 * std::sin(0.5) + 2.5e-5 * std::sin(2.2), kCoefficientTolerance);
  EXPECT_NEAR(profile.cos_coefficient(7), 1.0e-5 * std::cos(-1.0) + 3.0e-6 * std::cos(0.1), kCoefficientTolerance);
  EXPECT_NEAR(profile.sin_coefficient(7), 1.0e-5 * std::sin(-1.0) + 3.0e-6 * std::sin(0.1), kCoefficientTolerance);
  EXPECT_NEAR(profile.cos_coefficient(2), 6.0e-5, kCoefficientTolerance);
  EXPECT_EQ(profile.sin_coefficient(2), 0.0);
  EXPECT_EQ(profile.cos_coefficient(4), 0.0);
  EXPECT_EQ(profile.cos_coefficient(8), 0.0);
  EXPECT_EQ(profile.sin_coefficient(60), 0.0);
  EXPECT_EQ(profile.cos_coefficient(-1), 0.0);

  std::vector<double> thetas;
  for (int k = 0; k < 97; ++k) thetas.push_back(-7.0 + 0.15 * k);
  ExpectEvaluateMatchesDirectSum<kDuplicated>(thetas);
}

TEST(PolarProfile, ZeroAmplitudesLeaveACircle) {
  const PolarProfile profile(kR, 3.0e-5, {{4, 0.0, 1.0}, {9, 0.0, -0.5}});
  EXPECT_TRUE(profile.is_circle());
  EXPECT_EQ(profile.max_order(), 0);
  const RadiusDerivatives d = profile.Evaluate(1.234);
  EXPECT_EQ(d.r, kR + 3.0e-5);
  EXPECT_EQ(d.dr, 0.0);
  EXPECT_EQ(d.ddr, 0.0);
  const SupportPoint s = profile.Support(0.7, -2.0);
  EXPECT_EQ(s.h, kR + 3.0e-5);
  EXPECT_EQ(s.dh, 0.0);
  EXPECT_EQ(s.curvature_radius, kR + 3.0e-5);
  EXPECT_EQ(WrapAngle(s.theta - 0.7), 0.0);
}

TEST(PolarProfile, ConstructorRejectsNonPositiveRadiusAndOrdersBelowOne) {
  EXPECT_THROW(PolarProfile(0.0, 0.0, {}), std::invalid_argument);
  EXPECT_THROW(PolarProfile(-0.302, 0.0, {}), std::invalid_argument);
  EXPECT_THROW(PolarProfile(-1e-300, 0.0, {{2, 1e-4, 0.0}}), std::invalid_argument);
  EXPECT_THROW(PolarProfile(kR, 0.0, {{0, 1e-4, 0.0}}), std::invalid_argument);
  EXPECT_THROW(PolarProfile(kR, 0.0, {{2, 1e-4, 0.0}, {-3, 1e-4, 0.0}}), std::invalid_argument);
  EXPECT_THROW(PolarProfile(kR, 0.0, {{0, 0.0, 0.0}}), std::invalid_argument);  // even when inert
  EXPECT_NO_THROW(PolarProfile(1e-9, 0.0, {{1, 1e-10, 0.0}}));
  EXPECT_NO_THROW(PolarProfile(kR, -1e-3, {}));
}

// ---------------------------------------------------------------------------------------
// Support

// Support's stopping rule (engine/profile.cpp): Newton stops once its step, or the step
// after it as the harmonics' bound on f'' predicts, is below 1e-14 rad, and returns the
// angle before that step or after it (taken by series); doubled for margin. Rounding of the
// slope f = r' cos - r sin (~8 eps r) over its derivative kappa (r^2 + r'^2) >=
// kappa_min r_min^2 adds the rest [rad].
template <Spec kSpec>
constexpr double kThetaTolerance =
    2e-14 + 8.0 * kEps * MaxReach(kSpec) / (MinCurvatureBound(kSpec) * MinReach(kSpec) * MinReach(kSpec));

// Checks Support(phi) at 36 directions against the brute force:
//  - h lies between the best sample and the best sample plus its sagitta, and equals the
//    refined brute force up to rounding;
//  - theta is within one sample step of the best sample and within the engine's stopping
//    tolerance of the refined touching point;
//  - dh and the curvature match their values at the refined touching point.
template <Spec kSpec>
void ExpectSupportMatchesBruteForce() {
  SCOPED_TRACE(::testing::Message() << "profile with max order " << MaxOrder(kSpec));
  // The best sample misses the support by at most the sagitta of half a sample step,
  // |x'|^2 (dtheta / 2)^2 kappa / 2 [m].
  constexpr double kSagitta = MaxSpeed(kSpec) * MaxSpeed(kSpec) * kOutlineStep * kOutlineStep * CurvatureBound(kSpec) / 8.0;
  constexpr double kHRounding = 16.0 * kEps * MaxReach(kSpec);  // [m] products and sums at the reach
  constexpr double kTheta = kThetaTolerance<kSpec>;             // [rad]
  // dh = r sin(theta - phi) moves by at most |x'| per radian of theta [m].
  constexpr double kDhTolerance = MaxSpeed(kSpec) * kTheta + kHRounding;
  // Curvature: 32 roundings of its bound plus its drift over the theta tolerance, plus what
  // a last step taken by series leaves out of r'', at most 1e-14 r by the stopping rule,
  // which moves the curvature by that over r^2 [1/m].
  constexpr double kCurvatureTolerance = 32.0 * kEps * CurvatureBound(kSpec) + CurvatureSlopeBound(kSpec) * kTheta +
                                         1e-14 / MinReach(kSpec);

  const PolarProfile profile = Make(kSpec);
  ASSERT_TRUE(profile.IsConvex());
  const Outline& outline = OutlineOf<kSpec>();
  for (int k = 0; k < 36; ++k) {
    const double phi = -kPi + (k + 0.37) * (2.0 * kPi / 36.0);
    const SupportPoint s = profile.Support(phi, phi);
    const BruteSupport brute = BruteForceSupport(outline, phi);
    const RefinedSupport ref = ReferenceSupport(kSpec, outline, phi);
    EXPECT_LE(brute.h - s.h, kHRounding) << "phi " << phi << ": a sample reaches further than h";
    EXPECT_LE(s.h - brute.h, kSagitta + kHRounding) << "phi " << phi;
    EXPECT_NEAR(s.h, static_cast<double>(ref.h), kHRounding) << "phi " << phi;
    EXPECT_LE(std::abs(WrapAngle(s.theta - brute.theta)), kOutlineStep) << "phi " << phi;
    EXPECT_NEAR(WrapAngle(s.theta - static_cast<double>(ref.theta)), 0.0, kTheta) << "phi " << phi;
    EXPECT_NEAR(s.dh, static_cast<double>(ref.dh), kDhTolerance) << "phi " << phi;
    EXPECT_NEAR(1.0 / s.curvature_radius, ref.kappa, kCurvatureTolerance) << "phi " << phi;
  }
}

TEST(PolarProfileSupport, MatchesBruteForceForMixedOrders) { ExpectSupportMatchesBruteForce<kRingLike>(); }

TEST(PolarProfileSupport, MatchesBruteForceForOrdersUpToSixty) { ExpectSupportMatchesBruteForce<kMixed>(); }

TEST(PolarProfileSupport, MatchesBruteForceForOrderFortyAtSmallAmplitude) {
  ExpectSupportMatchesBruteForce<kOrderForty>();
}

TEST(PolarProfileSupport, MatchesBruteForceForAnOvalOfTenPercent) { ExpectSupportMatchesBruteForce<kOvalModerate>(); }

TEST(PolarProfileSupport, MatchesBruteForceForAnOvalAtNinetyFivePercentOfTheConvexityLimit) {
  ExpectSupportMatchesBruteForce<kOvalLarge>();
}

TEST(PolarProfileSupport, MatchesBruteForceForOrderFiveJustInsideTheConvexityLimit) {
  ExpectSupportMatchesBruteForce<kFiveNearLimit>();
}

// dh/dphi and h + h'' against central differences of the refined brute-force support.
template <Spec kSpec>
void ExpectSupportDerivativesMatchFiniteDifferences() {
  SCOPED_TRACE(::testing::Message() << "profile with max order " << MaxOrder(kSpec));
  constexpr double kStep = 1e-5;  // [rad]
  // To second order in C the support function is r(phi) + r'(phi)^2 / (2 r): its k-th
  // derivative is bounded by sum n^k C_n plus (2 n_max)^k r'_max^2 / r_min (Bernstein on
  // the degree-2 n_max square); double that for the higher orders [m/rad^k].
  constexpr auto kDerivativeBound = [](int k) {
    return 2.0 * (Moment(kSpec, k) + Power(2.0 * MaxOrder(kSpec), k) * Moment(kSpec, 1) * Moment(kSpec, 1) / MinReach(kSpec));
  };
  // The refined reference carries ~4 long double roundings of the reach [m].
  constexpr double kReferenceError = 4.0 * kLongEps * MaxReach(kSpec);
  // Central first difference: h''' step^2 / 6 + 2 e / (2 step) [m].
  constexpr double kSlopeFd = kDerivativeBound(3) * kStep * kStep / 6.0 + kReferenceError / kStep;
  // The engine's dh moves by |x'| per radian of its theta tolerance [m].
  constexpr double kDhTolerance = kSlopeFd + MaxSpeed(kSpec) * kThetaTolerance<kSpec>;
  // Central second difference: h'''' step^2 / 12 + 4 e / step^2; plus 32 roundings of the
  // engine's curvature radius rho <= 1 / kappa_min, and its drift rho^2 |kappa'| over the
  // theta tolerance [m].
  constexpr double kRhoMax = 1.0 / MinCurvatureBound(kSpec);
  constexpr double kRhoTolerance = kDerivativeBound(4) * kStep * kStep / 12.0 +
                                   4.0 * kReferenceError / (kStep * kStep) + 32.0 * kEps * kRhoMax +
                                   kRhoMax * kRhoMax * CurvatureSlopeBound(kSpec) * kThetaTolerance<kSpec>;
  const PolarProfile profile = Make(kSpec);
  const Outline& outline = OutlineOf<kSpec>();
  for (int k = 0; k < 24; ++k) {
    const long double phi = -kPi + (k + 0.61) * (2.0 * kPi / 24.0);
    const SupportPoint s = profile.Support(static_cast<double>(phi), static_cast<double>(phi) + 0.3);
    const long double h0 = ReferenceSupport(kSpec, outline, phi).h;
    const long double h_plus = ReferenceSupport(kSpec, outline, phi + kStep).h;
    const long double h_minus = ReferenceSupport(kSpec, outline, phi - kStep).h;
    const auto slope = static_cast<double>((h_plus - h_minus) / (2.0L * kStep));
    const auto second = static_cast<double>((h_plus - 2.0L * h0 + h_minus) / (static_cast<long double>(kStep) * kStep));
    EXPECT_NEAR(s.dh, slope, kDhTolerance) << "phi " << static_cast<double>(phi);
    EXPECT_NEAR(s.curvature_radius, static_cast<double>(h0) + second, kRhoTolerance) << "phi " << static_cast<double>(phi);
  }
}

TEST(PolarProfileSupport, SlopeAndCurvatureRadiusMatchFiniteDifferencesForMixedOrders) {
  ExpectSupportDerivativesMatchFiniteDifferences<kRingLike>();
}

TEST(PolarProfileSupport, SlopeAndCurvatureRadiusMatchFiniteDifferencesForOrderForty) {
  ExpectSupportDerivativesMatchFiniteDifferences<kOrderForty>();
}

TEST(PolarProfileSupport, SlopeAndCurvatureRadiusMatchFiniteDifferencesForOrdersUpToSixty) {
  ExpectSupportDerivativesMatchFiniteDifferences<kMixed>();
}

TEST(PolarProfileSupport, AnswerDoesNotDependOnThetaGuess) {
  constexpr double kTheta = kThetaTolerance<kRingLike>;         // [rad]
  constexpr double kHTolerance = 16.0 * kEps * MaxReach(kRingLike);  // [m] rounding at the reach
  constexpr double kDhTolerance = MaxSpeed(kRingLike) * kTheta + kHTolerance;  // [m] |x'| per radian
  const PolarProfile profile = Make(kRingLike);
  const Outline& outline = OutlineOf<kRingLike>();
  std::mt19937_64 rng(77);
  for (int k = 0; k < 8; ++k) {
    const double phi = Uniform(rng, -2.0 * kPi, 2.0 * kPi);
    const RefinedSupport ref = ReferenceSupport(kRingLike, outline, phi);
    const auto nominal = static_cast<double>(ref.theta);
    std::vector<double> guesses = {phi,
                                   nominal,
                                   nominal + 2.0 * kPi,
                                   nominal - 6.0 * kPi,
                                   nominal + 200.0 * kPi,
                                   phi + kPi,
                                   phi - kPi / 2.0,
                                   phi + kPi / 2.0,
                                   phi + 1.5,
                                   phi - 3.0,
                                   -1e6,
                                   std::numeric_limits<double>::infinity(),
                                   std::numeric_limits<double>::quiet_NaN()};
    for (int g = 0; g < 8; ++g) guesses.push_back(Uniform(rng, -100.0, 100.0));
    for (const double guess : guesses) {
      const SupportPoint s = profile.Support(phi, guess);
      EXPECT_NEAR(s.h, static_cast<double>(ref.h), kHTolerance) << "phi " << phi << " guess " << guess;
      EXPECT_NEAR(WrapAngle(s.theta - nominal), 0.0, kTheta) << "phi " << phi << " guess " << guess;
      EXPECT_NEAR(s.dh, static_cast<double>(ref.dh), kDhTolerance) << "phi " << phi << " guess " << guess;
    }
  }
}

// A Normal-class roller (5 mm, lobes of a few um), whose body angle reaches hundreds of
// radians in one ring revolution: R / r_b ~ 60 turns.
constexpr Spec kRollerLike{5.0e-3, -1.0e-6, 6,
                           {{{1, 3.0e-6, 0.2}, {2, 1.0e-6, -1.0}, {3, 8.0e-7, 2.1}, {4, 5.0e-7, 0.7},
                             {6, 3.0e-7, -2.4}, {8, 4.0e-7, 1.6}}}};

// The search works on the touching point's offset from the normal, so how far the body has
// turned changes neither the answer nor the cost. Searching on the body angle itself, a
// version stopped only at its iteration limit beyond a few turns, where the tolerance
// 1e-14 rad is below one ulp, and spent 30 evaluations per contact on average.
template <Spec kSpec>
void ExpectSupportIndependentOfTurns() {
  SCOPED_TRACE(::testing::Message() << "profile of radius " << kSpec.radius);
  constexpr double kTheta = kThetaTolerance<kSpec>;              // [rad]
  constexpr double kHTolerance = 16.0 * kEps * MaxReach(kSpec);  // [m]
  // Newton from the normal itself: the offset is below (r'/r)_max ~ 1e-3 rad here, and
  // quadratic convergence reaches 1e-14 rad in three updates plus the confirming one.
  constexpr int kColdEvaluations = 5;
  // From the offset of a nearby direction (a warm start along a trajectory).
  constexpr int kWarmEvaluations = 3;
  const PolarProfile profile = Make(kSpec);
  const Outline& outline = OutlineOf<kSpec>();
  for (int k = 0; k < 12; ++k) {
    const double phi = -kPi + (k + 0.29) * (2.0 * kPi / 12.0);
    const RefinedSupport ref = ReferenceSupport(kSpec, outline, phi);
    const double offset = WrapAngle(static_cast<double>(ref.theta) - phi);
    for (const double turns : {0.0, 1.0, 7.0, 60.0, 1000.0}) {
      const double turned = phi + 2.0 * kPi * turns;
      const SupportPoint cold = profile.Support(turned, turned);
      const SupportPoint warm = profile.Support(turned, turned + offset + 1e-6);
      for (const SupportPoint& s : {cold, warm}) {
        EXPECT_NEAR(s.h, static_cast<double>(ref.h), kHTolerance) << "phi " << phi << " turns " << turns;
        // theta carries the rounding of the turned angle itself.
        EXPECT_NEAR(s.theta - turned, offset, kTheta + 4.0 * kEps * std::abs(turned))
            << "phi " << phi << " turns " << turns;
      }
      EXPECT_LE(cold.evaluations, kColdEvaluations) << "phi " << phi << " turns " << turns;
      EXPECT_LE(warm.evaluations, kWarmEvaluations) << "phi " << phi << " turns " << turns;
    }
  }
}

TEST(PolarProfileSupport, NeitherAnswerNorCostDependsOnHowFarARollerHasTurned) {
  ExpectSupportIndependentOfTurns<kRollerLike>();
}

TEST(PolarProfileSupport, NeitherAnswerNorCostDependsOnHowFarARingHasTurned) {
  ExpectSupportIndependentOfTurns<kRingLike>();
}

TEST(PolarProfileSupport, TowardAGivenNormalVectorIsTheSameSearch) {
  // The two start from guesses that differ by the rounding of phi + guess - phi, so each
  // answer is held to the stopping tolerance, as in AnswerDoesNotDependOnThetaGuess.
  constexpr double kTheta = kThetaTolerance<kMixed>;                      // [rad]
  constexpr double kHTolerance = 16.0 * kEps * MaxReach(kMixed);          // [m]
  constexpr double kDhTolerance = MaxSpeed(kMixed) * kTheta + kHTolerance;  // [m]
  const PolarProfile profile = Make(kMixed);
  std::mt19937_64 rng(91);
  for (int k = 0; k < 32; ++k) {
    const double phi = Uniform(rng, -kPi, kPi);
    const double guess = Uniform(rng, -0.5, 0.5);
    const SupportPoint by_angle = profile.Support(phi, phi + guess);
    const SupportPoint by_vector = profile.SupportToward(std::cos(phi), std::sin(phi), guess);
    EXPECT_NEAR(by_vector.h, by_angle.h, kHTolerance) << "phi " << phi;
    EXPECT_NEAR(by_vector.dh, by_angle.dh, kDhTolerance) << "phi " << phi;
    EXPECT_NEAR(by_vector.theta, WrapAngle(by_angle.theta - phi), kTheta) << "phi " << phi;
  }
}

// The nearly-round series takes one evaluation where its error bound is within the
// tolerance asked, and then answers like the full search to that tolerance: theta to it,
// dh = r sin(offset) to r times it, h (stationary in theta) to rounding, the curvature
// to its drift over it and what its series leaves out. An outline far out of round
// (kOvalModerate, 10 %) mostly falls back to the full search, to its 1e-14 rad.
TEST(PolarProfileSupport, NearlyRoundSeriesAnswersLikeTheSearchToTheToleranceAsked) {
  constexpr double kAsked = 1e-12;  // [rad] what the quasistatic rung asks (solvers/equilibrium.cpp)
  const PolarProfile roller = Make(kRollerLike);
  const PolarProfile oval = Make(kOvalModerate);
  std::mt19937_64 rng(7);
  int series_answers = 0;
  int oval_searches = 0;
  for (int k = 0; k < 200; ++k) {
    const double phi = Uniform(rng, -kPi, kPi);
    for (const PolarProfile* profile : {&roller, &oval}) {
      const bool nearly_round = profile == &roller;
      const double theta = nearly_round ? kAsked + kThetaTolerance<kRollerLike> : kThetaTolerance<kOvalModerate>;
      const double reach = nearly_round ? MaxReach(kRollerLike) : MaxReach(kOvalModerate);
      const double h_rounding = 16.0 * kEps * reach;
      const SupportPoint series = profile->SupportTowardNearlyRound(std::cos(phi), std::sin(phi), kAsked);
      // The series' r'' leaves out r^(5) delta^3 / 6, which moves the curvature by that
      // over r^2.
      const double left_out = Moment(kRollerLike, 5) * std::pow(std::abs(series.theta), 3) / 6.0 /
                              (MinReach(kRollerLike) * MinReach(kRollerLike));
      const double curvature = nearly_round ? 32.0 * kEps * CurvatureBound(kRollerLike) +
                                                  CurvatureSlopeBound(kRollerLike) * theta + left_out
                                            : 32.0 * kEps * CurvatureBound(kOvalModerate) +
                                                  CurvatureSlopeBound(kOvalModerate) * theta;
      const SupportPoint search = profile->SupportToward(std::cos(phi), std::sin(phi), 0.0);
      if (nearly_round) series_answers += series.evaluations == 1;
      EXPECT_NEAR(series.theta, search.theta, theta) << "phi " << phi;
      EXPECT_NEAR(series.h, search.h, h_rounding) << "phi " << phi;
      EXPECT_NEAR(series.dh, search.dh, reach * theta + h_rounding) << "phi " << phi;
      EXPECT_NEAR(1.0 / series.curvature_radius, 1.0 / search.curvature_radius, curvature) << "phi " << phi;
      if (!nearly_round) oval_searches += series.evaluations > 1;
    }
  }
  EXPECT_EQ(series_answers, 200) << "the roller is nearly round: the series should answer every direction";
  // Except near its axes, where its touching point lies on the normal, the oval is too far
  // out of round for the series.
  EXPECT_GT(oval_searches, 150);
}

// ---------------------------------------------------------------------------------------
// Convexity and extremes

TEST(PolarProfileConvexity, SingleOrderClearlyAboveTheLimitIsNotConvex) {
  EXPECT_FALSE(Make(kDented).IsConvex());
  // Order 6 at 5 % of R alone, and among small terms.
  EXPECT_FALSE(PolarProfile(kR, 0.0, {{6, 0.05 * kR, 0.3}}).IsConvex());
  EXPECT_FALSE(PolarProfile(kR, 0.0, {{2, 1e-4, 0.0}, {6, 0.05 * kR, 0.3}, {9, 1e-6, 1.0}}).IsConvex());
  // Order 6 at 2 % of R: (n^2 + 1) C = 0.74 R.
  EXPECT_TRUE(PolarProfile(kR, 0.0, {{6, 0.02 * kR, 0.3}}).IsConvex());
}

TEST(PolarProfileConvexity, SingleOrderLimitIsRadiusOverNSquaredPlusOne) {
  for (const int n : {1, 2, 3, 5, 8, 20}) {
    const double limit = kR / (n * n + 1);
    EXPECT_TRUE(PolarProfile(kR, 0.0, {{n, 0.98 * limit, 0.6}}).IsConvex()) << "order " << n;
    EXPECT_FALSE(PolarProfile(kR, 0.0, {{n, 1.02 * limit, 0.6}}).IsConvex()) << "order " << n;
  }
  // Just under the linearised limit R / (n^2 - 1) = R / 24 the order-5 outline already has
  // a dent: IsConvex must not implement the linearised rule.
  EXPECT_FALSE(PolarProfile(kR, 0.0, {{5, 0.99 * kR / 24.0, 0.0}}).IsConvex());
}

// Smallest and largest of f over kOutlinePoints equally spaced body angles.
template <typename F>
std::pair<double, double> DenseExtremes(F f) {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (int j = 0; j < kOutlinePoints; ++j) {
    const double value = f(j * kOutlineStep);
    lo = std::min(lo, value);
    hi = std::max(hi, value);
  }
  return {lo, hi};
}

// The engine's extremes [min, max] against the grid's [lo, hi]: at least as far out as the
// grid up to `rounding`, and no further out than the grid can miss between its points
// (`sampling`).
void ExpectExtremesMatchTheGrid(double min, double max, double lo, double hi, double sampling, double rounding) {
  EXPECT_LE(min, lo + rounding);
  EXPECT_GE(min, lo - sampling - rounding);
  EXPECT_GE(max, hi - rounding);
  EXPECT_LE(max, hi + sampling + rounding);
}

template <Spec kSpec>
void ExpectCurvatureExtremesMatchDenseSampling() {
  SCOPED_TRACE(::testing::Message() << "profile with max order " << MaxOrder(kSpec));
  // The grid misses an extreme by at most |kappa''| (dtheta / 2)^2 / 2 [1/m].
  constexpr double kSampling = CurvatureDerivativeBound(kSpec, 2) * kOutlineStep * kOutlineStep / 8.0;
  constexpr double kRounding = 32.0 * kEps * CurvatureBound(kSpec);  // [1/m]
  const PolarProfile profile = Make(kSpec);
  const auto [lo, hi] =
      DenseExtremes([](double t) { return PolarCurvature(DirectSumAs<double>(kSpec, t)); });
  ExpectExtremesMatchTheGrid(profile.MinCurvature(), profile.MaxCurvature(), lo, hi, kSampling, kRounding);
}

TEST(PolarProfileConvexity, CurvatureExtremesMatchDenseSamplingOfThePolarFormula) {
  ExpectCurvatureExtremesMatchDenseSampling<kMixed>();
  ExpectCurvatureExtremesMatchDenseSampling<kRingLike>();
  ExpectCurvatureExtremesMatchDenseSampling<kOvalModerate>();
  ExpectCurvatureExtremesMatchDenseSampling<kOvalLarge>();
  ExpectCurvatureExtremesMatchDenseSampling<kFiveNearLimit>();
  ExpectCurvatureExtremesMatchDenseSampling<kOrderForty>();
  ExpectCurvatureExtremesMatchDenseSampling<kDented>();
}

template <Spec kSpec>
void ExpectSingleOrderExtremesMatchClosedForm() {
  static_assert(kSpec.count == 1 && kSpec.mean == 0.0);
  SCOPED_TRACE(::testing::Message() << "order " << kSpec.terms[0].order);
  constexpr int kN = kSpec.terms[0].order;
  constexpr double kC = kSpec.terms[0].amplitude;
  // The engine's golden section stops within 1e-10 rad of the extreme, where the error is
  // |kappa''| (1e-10)^2 / 2; plus 64 roundings of the curvature bound [1/m].
  constexpr double kCurvatureTolerance =
      CurvatureDerivativeBound(kSpec, 2) * 1e-20 / 2.0 + 64.0 * kEps * CurvatureBound(kSpec);
  // r at an extreme: n^2 C (1e-10)^2 / 2 plus 4 roundings of the reach [m].
  constexpr double kRadiusTolerance = kN * kN * kC * 1e-20 / 2.0 + 4.0 * kEps * MaxReach(kSpec);
  const PolarProfile profile = Make(kSpec);
  EXPECT_NEAR(profile.MinCurvature(), SingleOrderMinCurvature(kR, kN, kC), kCurvatureTolerance);
  EXPECT_NEAR(profile.MaxCurvature(), SingleOrderMaxCurvature(kR, kN, kC), kCurvatureTolerance);
  EXPECT_NEAR(profile.MinRadius(), kR - kC, kRadiusTolerance);
  EXPECT_NEAR(profile.MaxRadius(), kR + kC, kRadiusTolerance);
}

TEST(PolarProfileConvexity, SingleOrderCurvatureExtremesMatchTheClosedForm) {
  ExpectSingleOrderExtremesMatchClosedForm<kOvalModerate>();
  ExpectSingleOrderExtremesMatchClosedForm<kOvalLarge>();
  ExpectSingleOrderExtremesMatchClosedForm<kFiveNearLimit>();
  ExpectSingleOrderExtremesMatchClosedForm<kOrderForty>();
}

template <Spec kSpec>
void ExpectRadiusExtremesMatchDenseSampling() {
  SCOPED_TRACE(::testing::Message() << "profile with max order " << MaxOrder(kSpec));
  // The grid misses an extreme by at most |r''| (dtheta / 2)^2 / 2, |r''| <= sum n^2 C [m].
  constexpr double kSampling = Moment(kSpec, 2) * kOutlineStep * kOutlineStep / 8.0;
  constexpr double kRounding = 8.0 * kEps * MaxReach(kSpec);  // [m]
  const PolarProfile profile = Make(kSpec);
  const auto [lo, hi] = DenseExtremes([](double t) { return DirectSumAs<double>(kSpec, t).r; });
  ExpectExtremesMatchTheGrid(profile.MinRadius(), profile.MaxRadius(), lo, hi, kSampling, kRounding);
}

TEST(PolarProfileConvexity, RadiusExtremesMatchDenseSampling) {
  ExpectRadiusExtremesMatchDenseSampling<kMixed>();
  ExpectRadiusExtremesMatchDenseSampling<kRingLike>();
  ExpectRadiusExtremesMatchDenseSampling<kOvalLarge>();
  ExpectRadiusExtremesMatchDenseSampling<kOrderForty>();
  ExpectRadiusExtremesMatchDenseSampling<kDented>();
}

// The extremes' scan (64 samples per undulation of the highest order, the best sample of
// each quantity refined by Brent's method between its neighbours) takes a summed
// profile's samples four at a time, at cosines and sines kept per thread and order, and a
// sampled profile's from its table. That is the arithmetic of evaluating every scan angle
// alone, so the extremes must be, bit for bit, those of the scan written out here one
// angle at a time; profiles of several highest orders are made in turn, so kept angles
// of one order must never serve another.
std::array<double, 4> ExtremesScannedOneAngleAtATime(const PolarProfile& profile) {
  const int samples = 64 * profile.max_order();
  const double step = 2.0 * kPi / samples;
  const auto value = [&](const RadiusDerivatives& d, int quantity) {
    const double sign = quantity % 2 == 0 ? 1.0 : -1.0;  // min, max, min, max
    return sign * (quantity < 2 ? Curvature(d) : d.r);
  };
  std::array<double, 4> extremes{};
  for (int quantity = 0; quantity < 4; ++quantity) {
    int best = 0;
    double best_value = 0.0;
    for (int k = 0; k < samples; ++k) {
      const double theta = k * step;
      const double v = value(profile.EvaluateAt(theta, std::cos(theta), std::sin(theta)), quantity);
      if (k == 0 || v < best_value) {
        best_value = v;
        best = k;
      }
    }
    const auto refined = boost::math::tools::brent_find_minima(
        [&](double t) { return value(profile.Evaluate(t), quantity); }, (best - 1) * step, (best + 1) * step,
        std::numeric_limits<double>::digits);
    extremes[static_cast<std::size_t>(quantity)] = (quantity % 2 == 0 ? 1.0 : -1.0) * std::min(best_value, refined.second);
  }
  return extremes;
}

TEST(PolarProfileConvexity, ExtremesAreThoseOfTheScanOneAngleAtATime) {
  for (const Spec& spec : {kFiveNearLimit, kRingLike, kOvalLarge, kMixed, kDented, kFiveNearLimit, kOrderForty}) {
    const PolarProfile profile = Make(spec);
    SCOPED_TRACE(::testing::Message() << "max order " << profile.max_order() << (profile.sampled() ? ", sampled" : ""));
    const std::array<double, 4> expected = ExtremesScannedOneAngleAtATime(profile);
    EXPECT_EQ(profile.MinCurvature(), expected[0]);
    EXPECT_EQ(profile.MaxCurvature(), expected[1]);
    EXPECT_EQ(profile.MinRadius(), expected[2]);
    EXPECT_EQ(profile.MaxRadius(), expected[3]);
  }
}

// ---------------------------------------------------------------------------------------
// State built on demand: the sampled table and the exact extremes

// A random profile of the kinds a campaign draws and beyond: a radius from a roller's to a
// ring's, 1 to 60 orders with amplitudes falling as n^-a, a mean deviation. Half are
// nearly round (sum (n^2 + 1) C_n log-uniform in 1e-6 R .. R), half reach past the
// single-order convexity limit sum (n^2 + 1) C_n < R (0.5 R .. 1.8 R, so some are not
// convex); sum C_n <= 0.9 R keeps r > 0.
PolarProfile RandomProfile(std::mt19937_64& rng) {
  const double radius = std::exp(Uniform(rng, std::log(2e-3), std::log(0.6)));  // [m]
  const int orders = 1 + static_cast<int>(Uniform(rng, 0.0, 60.0));
  const int first = 1 + static_cast<int>(Uniform(rng, 0.0, 3.0));
  const double exponent = Uniform(rng, 0.5, 2.5);
  const double spread = Uniform(rng, 0.0, 1.0) < 0.5 ? std::exp(Uniform(rng, std::log(1e-6), 0.0))
                                                     : Uniform(rng, 0.5, 1.8);  // [-] of R
  double weight = 0.0;  // sum (n^2 + 1) n^-a
  for (int n = first; n < first + orders; ++n) weight += (n * n + 1.0) * std::pow(n, -exponent);
  const double scale = radius * spread / weight;  // [m]
  std::vector<Harmonic> harmonics;
  for (int n = first; n < first + orders; ++n) {
    harmonics.push_back({n, scale * std::pow(n, -exponent) * Uniform(rng, 0.5, 1.0), Uniform(rng, -kPi, kPi)});
  }
  return PolarProfile(radius, Uniform(rng, -1e-3, 1e-3) * radius, std::move(harmonics));
}

PolarProfile Remade(const PolarProfile& p) { return PolarProfile(p.radius(), p.mean_deviation(), p.harmonics()); }

// Every answer a profile gives, as bits, in a fixed order: evaluations (the table's among
// them) before the extremes.
std::vector<double> Answers(const PolarProfile& p) {
  std::vector<double> out{p.radius(), p.mean_deviation(), static_cast<double>(p.max_order()),
                          static_cast<double>(p.is_circle()), static_cast<double>(p.sampled())};
  for (int n = -1; n <= p.max_order() + 1; ++n) {
    out.push_back(p.cos_coefficient(n));
    out.push_back(p.sin_coefficient(n));
  }
  const auto push = [&out](const RadiusDerivatives& d) { out.insert(out.end(), {d.r, d.dr, d.ddr, d.cos_theta, d.sin_theta}); };
  double cos_theta[4];
  double sin_theta[4];
  for (int k = 0; k < 4; ++k) {
    const double theta = -7.0 + 3.7 * k;
    cos_theta[k] = std::cos(theta);
    sin_theta[k] = std::sin(theta);
    push(p.Evaluate(theta));
    push(p.EvaluateAt(cos_theta[k], sin_theta[k]));
    push(p.EvaluateAt(theta, cos_theta[k], sin_theta[k]));
  }
  RadiusDerivatives four[4];
  p.EvaluateFourAt(cos_theta, sin_theta, four);
  for (const RadiusDerivatives& d : four) push(d);
  const OutlineExtremes& bounds = p.ExtremesBounds();
  out.insert(out.end(), {bounds.min_curvature, bounds.max_curvature, bounds.min_radius, bounds.max_radius});
  out.push_back(static_cast<double>(p.IsConvex()));
  if (p.IsConvex()) {
    for (const double phi : {0.3, 2.0, -1.1}) {
      for (const SupportPoint& s : {p.Support(phi, phi + 0.1), p.SupportToward(std::cos(phi), std::sin(phi), 0.05),
                                    p.SupportTowardNearlyRound(std::cos(phi), std::sin(phi), 1e-12)}) {
        out.insert(out.end(), {s.theta, s.h, s.dh, s.curvature_radius, static_cast<double>(s.evaluations)});
      }
    }
  }
  out.insert(out.end(), {p.MinCurvature(), p.MaxCurvature(), p.MinRadius(), p.MaxRadius()});
  return out;
}

// What each first question builds: the extremes alone (and, sampled, the table under
// them), the table alone, nothing but a convexity the bounds may settle, or nothing.
enum class FirstQuestion { kNone, kExtremes, kTable, kConvexity, kCount };

void Ask(const PolarProfile& p, FirstQuestion question) {
  switch (question) {
    case FirstQuestion::kExtremes: static_cast<void>(p.MaxRadius()); break;
    case FirstQuestion::kTable: static_cast<void>(p.EvaluateAt(0.1, std::cos(0.1), std::sin(0.1))); break;
    case FirstQuestion::kConvexity: static_cast<void>(p.IsConvex()); break;
    case FirstQuestion::kNone:
    case FirstQuestion::kCount: break;
  }
}

// The bits compared with EXPECT_EQ on the doubles' representations, NaN included.
void ExpectSameBits(const std::vector<double>& a, const std::vector<double>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(a[k]), std::bit_cast<std::uint64_t>(b[k])) << "answer " << k;
  }
}

TEST(PolarProfileOnDemand, AnswersAreTheSameBitsWhicheverQuestionBuildsItsState) {
  std::mt19937_64 rng(20261126);
  std::vector<PolarProfile> profiles = {PolarProfile(kR, 1e-5, {}), Make(kMixed), Make(kRingLike), Make(kDented),
                                        Make(kOrderForty)};
  for (int k = 0; k < 40; ++k) profiles.push_back(RandomProfile(rng));
  for (const PolarProfile& original : profiles) {
    SCOPED_TRACE(::testing::Message() << "max order " << original.max_order() << (original.sampled() ? ", sampled" : ""));
    const std::vector<double> reference = Answers(Remade(original));
    for (int q = 0; q < static_cast<int>(FirstQuestion::kCount); ++q) {
      const PolarProfile fresh = Remade(original);
      const PolarProfile copied_before = fresh;
      Ask(fresh, static_cast<FirstQuestion>(q));
      const PolarProfile copied_after = fresh;
      EXPECT_TRUE(fresh == original);
      ExpectSameBits(Answers(fresh), reference);
      ExpectSameBits(Answers(copied_before), reference);
      ExpectSameBits(Answers(copied_after), reference);
    }
  }
}

// Four threads ask one fresh profile (and one copy each) at once, each starting with a
// different question; their answers must be the bits one thread alone gets. (Built with
// RINGTOL_SANITIZE this also exercises the publication under ASan; ThreadSanitizer would
// check the ordering itself.)
TEST(PolarProfileOnDemand, StateBuiltFromSeveralThreadsAtOnceIsTheSameAsFromOne) {
  std::mt19937_64 rng(20261127);
  std::vector<PolarProfile> profiles = {Make(kRingLike), Make(kOrderForty), Make(kMixed)};
  for (int k = 0; k < 6; ++k) profiles.push_back(RandomProfile(rng));
  constexpr int kThreads = 4;
  for (const PolarProfile& original : profiles) {
    const std::vector<double> reference = Answers(Remade(original));
    for (int round = 0; round < 5; ++round) {
      const PolarProfile shared = Remade(original);
      std::atomic<int> ready{0};
      std::vector<std::vector<double>> answers(kThreads);
      std::vector<std::thread> threads;
      for (int t = 0; t < kThreads; ++t) {
        threads.emplace_back([&, t] {
          const PolarProfile& mine = shared;
          const PolarProfile copy = shared;
          ready.fetch_add(1);
          while (ready.load() < kThreads) std::this_thread::yield();
          Ask(t % 2 == 0 ? mine : copy, static_cast<FirstQuestion>((t + round) % static_cast<int>(FirstQuestion::kCount)));
          answers[static_cast<std::size_t>(t)] = Answers(t % 2 == 0 ? mine : copy);
        });
      }
      for (std::thread& thread : threads) thread.join();
      for (const std::vector<double>& a : answers) ExpectSameBits(a, reference);
    }
  }
}

// The bounds hold for what the exact accessors return (the tables' interpolation and
// every rounding included), so IsConvex is MinCurvature() > 0 whichever answers it; and
// they settle a nearly round part: rho - sum (n^2 + 1) C_n > 1 % of rho leaves a positive
// curvature bound (the bound's own margins are round-off and the table's error, far below).
TEST(PolarProfileBounds, HoldForTheExactExtremesOfRandomProfiles) {
  std::mt19937_64 rng(20261128);
  int convex = 0;
  int settled = 0;
  for (int k = 0; k < 400; ++k) {
    const PolarProfile p = RandomProfile(rng);
    SCOPED_TRACE(::testing::Message() << "profile " << k << ", max order " << p.max_order());
    const OutlineExtremes& bounds = p.ExtremesBounds();
    EXPECT_LE(bounds.min_radius, p.MinRadius());
    EXPECT_GE(bounds.max_radius, p.MaxRadius());
    EXPECT_LE(bounds.min_curvature, p.MinCurvature());
    EXPECT_GE(bounds.max_curvature, p.MaxCurvature());
    EXPECT_EQ(p.IsConvex(), p.MinCurvature() > 0.0);
    double spread = 0.0;  // sum (n^2 + 1) C_n [m]
    for (const Harmonic& h : p.harmonics()) spread += (h.order * h.order + 1.0) * h.amplitude;
    const double rho = p.radius() + p.mean_deviation();
    if (spread < 0.99 * rho) {
      EXPECT_GT(bounds.min_curvature, 0.0);
      ++settled;
    }
    convex += p.IsConvex() ? 1 : 0;
  }
  // The draws span both sides of the convexity limit, and half are nearly round.
  EXPECT_GT(convex, 100);
  EXPECT_LT(convex, 400);
  EXPECT_GT(settled, 150);
}

TEST(PolarProfileBounds, AreTheExtremesThemselvesForACircle) {
  const PolarProfile circle(kR, -2e-5, {{3, 0.0, 1.0}});
  const OutlineExtremes exact{circle.MinCurvature(), circle.MaxCurvature(), circle.MinRadius(), circle.MaxRadius()};
  EXPECT_EQ(circle.ExtremesBounds(), exact);
  EXPECT_EQ(exact.min_radius, kR - 2e-5);
  EXPECT_EQ(exact.max_curvature, 1.0 / (kR - 2e-5));
}

}  // namespace
}  // namespace ringtol::engine
