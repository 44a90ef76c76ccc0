// ReadSensor against a brute-force ray/outline intersection and a closed form; MeasureRunout
// against signals whose extremes are known by construction and against an independent
// reference implementation on random signals.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "engine/contact.h"
#include "engine/profile.h"
#include "engine/sensor.h"

namespace ringtol::engine {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kDeg = kPi / 180.0;
constexpr double kR = 0.302;  // [m]

double WrapAngle(double a) { return std::remainder(a, 2.0 * kPi); }

double Uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

// ---------------------------------------------------------------------------------------
// ReadSensor

struct RingSpec {
  int count = 0;
  std::array<Harmonic, 3> terms{};
};

constexpr std::array<RingSpec, 4> kRings{{
    {1, {{{2, 0.14e-3, 45.0 * kDeg}}}},
    {1, {{{20, 0.14e-3, 45.0 * kDeg}}}},
    {3, {{{3, 0.14e-3, 45.0 * kDeg}, {5, 0.14e-3, 45.0 * kDeg}, {12, 0.05e-3, 1.0}}}},
    {3, {{{15, 0.14e-3, 0.3}, {6, 0.07e-3, -1.0}, {1, 0.3e-3, 2.0}}}},
}};
// Largest r' over the rings: 20 x 0.14 mm [m/rad].
constexpr double kMaxSlope = 20 * 0.14e-3;
constexpr double kMaxOffset = 0.5e-3;  // [m] ring centre offsets used below

PolarProfile Make(const RingSpec& spec) { return PolarProfile(kR, 0.0, {spec.terms.begin(), spec.terms.begin() + spec.count}); }

long double RadiusOf(const RingSpec& spec, long double theta) {
  long double r = kR;
  for (int i = 0; i < spec.count; ++i) {
    const Harmonic& h = spec.terms[static_cast<std::size_t>(i)];
    r += h.amplitude * std::cos(h.order * theta + h.phase);
  }
  return r;
}

struct Hit {
  double distance = 0.0;  // [m] from the origin along the ray
  double theta = 0.0;     // [rad] ring body angle
};

// The outline sampled every 2 pi / 100000 over the body angles within 0.05 rad of the ray
// (the hit lies within offset / R + r' / R < 0.012 rad of it); the sample pair whose offsets
// from the ray change sign brackets the hit, and bisection on the exact long double
// outline finds it.
Hit BruteForceHit(const RingSpec& spec, const BodyPose& pose, double sensor_angle) {
  const long double cs = std::cos(static_cast<long double>(sensor_angle));
  const long double ss = std::sin(static_cast<long double>(sensor_angle));
  // Signed offset of the outline point at body angle theta from the ray, and its reach along it.
  const auto point = [&](long double theta) {
    const long double r = RadiusOf(spec, theta);
    const long double x = pose.centre.x() + r * std::cos(theta + pose.angle);
    const long double y = pose.centre.y() + r * std::sin(theta + pose.angle);
    return std::array<long double, 2>{cs * y - ss * x, cs * x + ss * y};
  };
  constexpr int kPoints = 100000;
  constexpr long double kStep = 2.0L * std::numbers::pi_v<long double> / kPoints;
  const long double aim = sensor_angle - pose.angle;
  const auto first = static_cast<long>(std::floor((aim - 0.05L) / kStep));
  long double lo = 0.0L;
  long double hi = 0.0L;
  int brackets = 0;
  for (long j = first; j < first + static_cast<long>(0.1L / kStep) + 2; ++j) {
    const long double a = static_cast<long double>(j) * kStep;
    const long double b = a + kStep;
    if (point(a)[0] < 0.0L && point(b)[0] >= 0.0L && point(a)[1] > 0.0L) {
      lo = a;
      hi = b;
      ++brackets;
    }
  }
  EXPECT_EQ(brackets, 1) << "the ray must cross the sampled outline once";
  for (int k = 0; k < 80; ++k) {
    const long double mid = 0.5L * (lo + hi);
    (point(mid)[0] < 0.0L ? lo : hi) = mid;
  }
  const long double theta = 0.5L * (lo + hi);
  return {static_cast<double>(point(theta)[1]), static_cast<double>(theta)};
}

// The engine's Newton iteration stops at a step of 1e-14 rad and applies it, so its angle
// carries rounding only: its residual (~4 eps r) over the slope (~r) plus the stop [rad].
constexpr double kThetaTolerance = 1e-14 + 8.0 * kEps;
// The reading moves with theta by e_s . x'(theta) = r' cos - r sin(theta - aim), at most
// r'_max + offset_max; plus 8 roundings of 0.31 m [m].
constexpr double kDistanceTolerance = (kMaxSlope + kMaxOffset) * kThetaTolerance + 8.0 * kEps * 0.31;

TEST(ReadSensor, MatchesBruteForceRayIntersectionForOffsetAndTurnedRings) {
  std::mt19937_64 rng(31337);
  for (std::size_t i = 0; i < kRings.size(); ++i) {
    const PolarProfile ring = Make(kRings[i]);
    for (int k = 0; k < 12; ++k) {
      BodyPose pose;
      pose.centre = Uniform(rng, 0.0, kMaxOffset) * Eigen::Vector2d(std::cos(k * 1.1), std::sin(k * 1.1));
      pose.angle = Uniform(rng, -20.0, 20.0);
      const double sensor_angle = Uniform(rng, -kPi, kPi);
      const Hit expected = BruteForceHit(kRings[i], pose, sensor_angle);
      const SensorReading reading = ReadSensor(ring, pose, sensor_angle, sensor_angle - pose.angle);
      SCOPED_TRACE(::testing::Message() << "ring " << i << " pose angle " << pose.angle << " sensor " << sensor_angle);
      EXPECT_NEAR(reading.distance, expected.distance, kDistanceTolerance);
      EXPECT_NEAR(WrapAngle(reading.ring_theta - expected.theta), 0.0, kThetaTolerance);
    }
  }
}

TEST(ReadSensor, MatchesTheClosedFormForAnOffsetCircle) {
  // Ray from the origin along e meets the circle |x - c| = R at c . e + sqrt(R^2 - (c x e)^2).
  const PolarProfile circle(kR, 0.0, {});
  // 8 roundings of the reach [m].
  constexpr double kTolerance = 8.0 * kEps * 0.31;
  for (int k = 0; k < 36; ++k) {
    const double sensor_angle = -kPi + (k + 0.5) * kPi / 18.0;
    BodyPose pose{Eigen::Vector2d(3e-4, -4e-4), 0.1 * k};
    const Eigen::Vector2d e(std::cos(sensor_angle), std::sin(sensor_angle));
    const double cross = pose.centre.x() * e.y() - pose.centre.y() * e.x();
    const double expected = pose.centre.dot(e) + std::sqrt(kR * kR - cross * cross);
    EXPECT_NEAR(ReadSensor(circle, pose, sensor_angle, 0.0).distance, expected, kTolerance) << "sensor " << sensor_angle;
  }
}

TEST(ReadSensor, AnswerDoesNotDependOnThetaGuess) {
  const RingSpec& spec = kRings[1];
  const PolarProfile ring = Make(spec);
  const BodyPose pose{Eigen::Vector2d(-2e-4, 3.5e-4), 2.7};
  for (const double sensor_angle : {0.0, 1.9, -2.5}) {
    const Hit expected = BruteForceHit(spec, pose, sensor_angle);
    const double aim = sensor_angle - pose.angle;
    for (const double guess : {aim, aim + 1.4, aim - 1.5, aim + 2.0 * kPi, aim - 40.0 * kPi, aim + kPi, 1e6, -3.0,
                               std::numeric_limits<double>::quiet_NaN()}) {
      const SensorReading reading = ReadSensor(ring, pose, sensor_angle, guess);
      EXPECT_NEAR(reading.distance, expected.distance, kDistanceTolerance) << "sensor " << sensor_angle << " guess " << guess;
      EXPECT_NEAR(WrapAngle(reading.ring_theta - expected.theta), 0.0, kThetaTolerance)
          << "sensor " << sensor_angle << " guess " << guess;
    }
  }
}

// Along a trajectory the readings share one SensorTrack (cached trigonometry, warm
// starts a step apart). Each must still match the brute-force intersection, as a reading
// taken alone does.
TEST(ReadSensor, ReadingsAlongATrajectoryWithASharedTrackMatchBruteForce) {
  const RingSpec& spec = kRings[1];
  const PolarProfile ring = Make(spec);
  constexpr double kSensorAngle = 0.3;
  constexpr int kSteps = 720;
  SensorTrack track;
  double theta = kSensorAngle;
  for (int k = 0; k <= kSteps; k += 1) {
    const double psi = 2.0 * kPi * k / kSteps;
    const BodyPose pose{Eigen::Vector2d(2e-4 * std::cos(3.0 * psi), -1e-4 * std::sin(2.0 * psi)), psi};
    const SensorReading reading = ReadSensor(ring, pose, kSensorAngle, theta, &track);
    if (k % 24 == 0) {
      const Hit expected = BruteForceHit(spec, pose, kSensorAngle);
      EXPECT_NEAR(reading.distance, expected.distance, kDistanceTolerance) << "step " << k;
      EXPECT_NEAR(WrapAngle(reading.ring_theta - expected.theta), 0.0, kThetaTolerance) << "step " << k;
    }
    EXPECT_NEAR(reading.distance, ReadSensor(ring, pose, kSensorAngle, theta).distance, 4.0 * kEps * kR) << "step " << k;
    theta = reading.ring_theta - 2.0 * kPi / kSteps;
  }
}

// ---------------------------------------------------------------------------------------
// MeasureRunout

// Independent reference: collapse repeats (cyclically), keep the points whose two cyclic
// neighbours are both lower or both higher, take the largest difference between cyclically
// neighbouring extremes.
double ReferencePeakToNearestValley(const std::vector<double>& signal) {
  std::vector<double> v;
  for (const double x : signal) {
    if (v.empty() || x != v.back()) v.push_back(x);
  }
  while (v.size() > 1 && v.front() == v.back()) v.pop_back();
  if (v.size() < 2) return 0.0;
  std::vector<double> extremes;
  const std::size_t m = v.size();
  for (std::size_t i = 0; i < m; ++i) {
    const double prev = v[(i + m - 1) % m];
    const double next = v[(i + 1) % m];
    if ((v[i] > prev) == (v[i] > next)) extremes.push_back(v[i]);
  }
  double largest = 0.0;
  for (std::size_t i = 0; i < extremes.size(); ++i) {
    largest = std::max(largest, std::abs(extremes[i] - extremes[(i + 1) % extremes.size()]));
  }
  return largest;
}

std::vector<double> Rotated(const std::vector<double>& signal, std::size_t by) {
  std::vector<double> out(signal.size());
  for (std::size_t i = 0; i < signal.size(); ++i) out[i] = signal[(i + by) % signal.size()];
  return out;
}

// Every value below is a small multiple of 1/8: differences are exact, so comparisons are.
void ExpectRunoutInEveryRotation(const std::vector<double>& signal, double peak_to_nearest_valley, double total) {
  for (std::size_t by = 0; by < signal.size(); ++by) {
    const Runout runout = MeasureRunout(Rotated(signal, by));
    EXPECT_EQ(runout.peak_to_nearest_valley, peak_to_nearest_valley) << "rotated by " << by;
    EXPECT_EQ(runout.total, total) << "rotated by " << by;
  }
}

TEST(MeasureRunout, PureSineGivesTwiceItsAmplitudeUpToTheSamplingMiss) {
  constexpr double kAmplitude = 75e-6;  // [m]
  constexpr int kSamples = 720;
  // The nearest sample to a crest is within half a step, pi / 720, of it: each extreme
  // reads low by at most A (1 - cos(pi / 720)); plus 4 roundings of A [m].
  const double peak_miss = kAmplitude * (1.0 - std::cos(kPi / kSamples));
  constexpr double kRounding = 4.0 * kEps * kAmplitude;
  for (const double phase : {0.0, 0.3, kPi / kSamples, 1.0, -2.0}) {
    std::vector<double> signal;
    for (int k = 0; k < kSamples; ++k) signal.push_back(kAmplitude * std::sin(2.0 * kPi * k / kSamples + phase));
    const Runout runout = MeasureRunout(signal);
    EXPECT_LE(runout.total, 2.0 * kAmplitude + kRounding) << "phase " << phase;
    EXPECT_GE(runout.total, 2.0 * kAmplitude - 2.0 * peak_miss - kRounding) << "phase " << phase;
    // One peak and one valley: the only neighbouring pair is the global max and min.
    EXPECT_EQ(runout.peak_to_nearest_valley, runout.total) << "phase " << phase;
  }
}

TEST(MeasureRunout, RepeatedPatternGivesItsLargestNeighbouringStep) {
  // 0, 5, 1, 3 repeated: steps 5, 4, 2, 3.
  std::vector<double> signal;
  for (int k = 0; k < 4; ++k) signal.insert(signal.end(), {0.0, 5.0, 1.0, 3.0});
  ExpectRunoutInEveryRotation(signal, 5.0, 5.0);
}

TEST(MeasureRunout, LargestNeighbouringStepCanBeSmallerThanTheTotal) {
  // Extremes 2, 9, 4, 6, 1, 3 joined by ramps: steps 7, 5, 2, 5, 2, 1; max - min = 8.
  const std::vector<double> signal = {2.0, 4.5, 7.0, 9.0, 7.5, 5.0, 4.0, 5.0, 6.0, 5.5,
                                      3.0, 1.0, 2.0, 3.0, 2.5};
  ExpectRunoutInEveryRotation(signal, 7.0, 8.0);
}

TEST(MeasureRunout, LargestStepAcrossTheEndOfTheArrayCounts) {
  // Extremes 10, 6, 8, 0, 3, 1.5 with the rise 1.5 -> 4 -> 7 -> 10 wrapping round the end:
  // steps 4, 2, 8, 3, 1.5, 8.5.
  const std::vector<double> signal = {4.0, 7.0, 10.0, 6.0, 8.0, 0.0, 3.0, 1.5};
  const Runout runout = MeasureRunout(signal);
  EXPECT_EQ(runout.peak_to_nearest_valley, 8.5);
  EXPECT_EQ(runout.total, 10.0);
  ExpectRunoutInEveryRotation(signal, 8.5, 10.0);
}

TEST(MeasureRunout, PlateausCountAsOneExtreme) {
  // Extremes 9, 2, 7, 0, 5, 3, all but the last held over several samples, the rise from
  // the 3-plateau to 9 ending on a plateau: steps 7, 5, 7, 5, 2, 6; max - min = 9.
  const std::vector<double> signal = {9.0, 9.0, 9.0, 5.0, 2.0, 2.0, 2.0, 4.0, 7.0, 7.0, 7.0, 7.0,
                                      3.0, 0.0, 0.0, 0.0, 2.0, 5.0, 5.0, 4.0, 3.0, 3.0, 6.0, 9.0};
  ExpectRunoutInEveryRotation(signal, 7.0, 9.0);
  // A plateau inside a ramp is no extreme: 0, 2, 2, 2, 4 rises by 4.
  ExpectRunoutInEveryRotation({0.0, 2.0, 2.0, 2.0, 4.0, 4.0, 1.0}, 4.0, 4.0);
  // Two equal global maxima and two equal global minima.
  ExpectRunoutInEveryRotation({5.0, 0.0, 5.0, 1.0, 5.0, 0.0}, 5.0, 5.0);
}

TEST(MeasureRunout, ClosingSampleEqualToTheFirstChangesNothing) {
  const std::vector<double> open = {4.0, 7.0, 10.0, 6.0, 8.0, 0.0, 3.0, 1.5};
  std::vector<double> closed = open;
  closed.push_back(open.front());
  const Runout a = MeasureRunout(open);
  const Runout b = MeasureRunout(closed);
  EXPECT_EQ(a.peak_to_nearest_valley, b.peak_to_nearest_valley);
  EXPECT_EQ(a.total, b.total);
}

TEST(MeasureRunout, ConstantShortAndEmptySignalsGiveZeros) {
  for (const std::vector<double>& signal : {std::vector<double>{}, std::vector<double>{4.2},
                                            std::vector<double>(720, 1.5e-4)}) {
    const Runout runout = MeasureRunout(signal);
    EXPECT_EQ(runout.peak_to_nearest_valley, 0.0) << "size " << signal.size();
    EXPECT_EQ(runout.total, 0.0) << "size " << signal.size();
  }
  const Runout two = MeasureRunout(std::vector<double>{1.0, 3.5});
  EXPECT_EQ(two.peak_to_nearest_valley, 2.5);
  EXPECT_EQ(two.total, 2.5);
}

TEST(MeasureRunout, MatchesReferenceOnRandomSignalsWithPlateaus) {
  std::mt19937_64 rng(271828);
  for (int trial = 0; trial < 3000; ++trial) {
    const auto size = static_cast<std::size_t>(1 + rng() % 40);
    const auto levels = 2 + rng() % 6;  // few levels: plenty of plateaus and equal extremes
    std::vector<double> signal;
    for (std::size_t i = 0; i < size; ++i) signal.push_back(0.125 * static_cast<double>(rng() % levels));
    const Runout runout = MeasureRunout(signal);
    const auto [lo, hi] = std::minmax_element(signal.begin(), signal.end());
    ASSERT_EQ(runout.total, *hi - *lo) << "trial " << trial;
    ASSERT_EQ(runout.peak_to_nearest_valley, ReferencePeakToNearestValley(signal)) << "trial " << trial;
  }
}

}  // namespace
}  // namespace ringtol::engine
