// ReadSensor against a brute-force ray/outline intersection and a closed form; the runout's
// total and swing against signals whose extremes are known by construction, against the
// swing's definition evaluated by brute force on random signals, and for continuity; the
// Gaussian filter against its ISO transmission.
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
// MeasureRunout and Swing

// Independent reference, straight from the definition: every arc of the periodic signal of
// at most one revolution (start i, n + 1 samples at most), each rise charged the excess of
// its largest inner fall over the resolution, each fall likewise.
double ReferenceSwing(const std::vector<double>& signal, double resolution) {
  const std::size_t n = signal.size();
  double swing = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    double top = signal[i];
    double bottom = signal[i];
    double drawdown = 0.0;  // largest fall inside the arc so far
    double drawup = 0.0;    // largest rise inside the arc so far
    for (std::size_t length = 0; length <= n; ++length) {
      const double value = signal[(i + length) % n];
      drawdown = std::max(drawdown, top - value);
      drawup = std::max(drawup, value - bottom);
      top = std::max(top, value);
      bottom = std::min(bottom, value);
      swing = std::max(swing, value - signal[i] - std::max(0.0, drawdown - resolution));
      swing = std::max(swing, signal[i] - value - std::max(0.0, drawup - resolution));
    }
  }
  return swing;
}

std::vector<double> Rotated(const std::vector<double>& signal, std::size_t by) {
  std::vector<double> out(signal.size());
  for (std::size_t i = 0; i < signal.size(); ++i) out[i] = signal[(i + by) % signal.size()];
  return out;
}

// Every value below is a small multiple of 1/8: differences are exact, so comparisons are.
void ExpectSwingInEveryRotation(const std::vector<double>& signal, double resolution, double swing) {
  for (std::size_t by = 0; by < signal.size(); ++by) {
    EXPECT_EQ(Swing(Rotated(signal, by), resolution), swing) << "rotated by " << by;
  }
}

TEST(MeasureRunout, PureSineGivesTwiceItsAmplitudeUpToTheSamplingMissAsTotalAndSwing) {
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
    // One peak and one valley: the swing is the whole range.
    EXPECT_EQ(runout.swing, runout.total) << "phase " << phase;
  }
}

TEST(Swing, ChargesARiseTheExcessOfItsLargestInnerFallOverTheResolution) {
  // Extremes 2, 9, 4, 6, 1, 3 joined by ramps; max - min = 8. Unresolved (resolution 0):
  // the fall 9 -> 1 passes the rise 4 -> 6 (charged 2): 6; the rise 1 -> 9, wrapping round
  // the end, passes the fall 3 -> 2 (charged 1): 7; no other arc does better.
  const std::vector<double> signal = {2.0, 4.5, 7.0, 9.0, 7.5, 5.0, 4.0, 5.0, 6.0, 5.5,
                                      3.0, 1.0, 2.0, 3.0, 2.5};
  ExpectSwingInEveryRotation(signal, 0.0, 7.0);
  // At resolution 1 the fall 3 -> 2 is free: the rise 1 -> 9 counts whole.
  ExpectSwingInEveryRotation(signal, 1.0, 8.0);
  // At resolution 2 the rise 4 -> 6 is free too: the fall 9 -> 1 counts whole as well.
  ExpectSwingInEveryRotation(signal, 2.0, 8.0);
}

TEST(Swing, RepeatedPatternGivesItsLargestNetStep) {
  // 0, 5, 1, 3 repeated: the rise 0 -> 5 is clean; 5 -> 0 passes the rise 1 -> 3.
  std::vector<double> signal;
  for (int k = 0; k < 4; ++k) signal.insert(signal.end(), {0.0, 5.0, 1.0, 3.0});
  ExpectSwingInEveryRotation(signal, 0.0, 5.0);
  ExpectSwingInEveryRotation(signal, 3.0, 5.0);
}

TEST(Swing, PlateausAndRepeatedExtremesChangeNothing) {
  const std::vector<double> signal = {9.0, 9.0, 9.0, 5.0, 2.0, 2.0, 2.0, 4.0, 7.0, 7.0, 7.0, 7.0,
                                      3.0, 0.0, 0.0, 0.0, 2.0, 5.0, 5.0, 4.0, 3.0, 3.0, 6.0, 9.0};
  for (const double resolution : {0.0, 1.0, 2.5, 5.0, 10.0}) {
    ExpectSwingInEveryRotation(signal, resolution, ReferenceSwing(signal, resolution));
  }
  ExpectSwingInEveryRotation({5.0, 0.0, 5.0, 1.0, 5.0, 0.0}, 0.0, 5.0);
}

TEST(Swing, ConstantShortAndEmptySignalsGiveTheirRange) {
  EXPECT_EQ(Swing(std::vector<double>{}, 0.0), 0.0);
  EXPECT_EQ(Swing(std::vector<double>{4.2}, 0.0), 0.0);
  EXPECT_EQ(Swing(std::vector<double>(720, 1.5e-4), 0.1e-6), 0.0);
  EXPECT_EQ(Swing(std::vector<double>{1.0, 3.5}, 0.0), 2.5);
  // A range within the resolution is still the swing: nothing is charged.
  EXPECT_EQ(Swing(std::vector<double>{1.0, 3.5, 2.0}, 4.0), 2.5);
}

TEST(Swing, MatchesTheDefinitionOnRandomSignalsWithPlateaus) {
  std::mt19937_64 rng(271828);
  for (int trial = 0; trial < 3000; ++trial) {
    // Short signals with few levels (plenty of plateaus and equal extremes), and long ones
    // with many extremes, where the walk stops early once no arc can beat the best.
    const bool long_signal = trial % 10 == 0;
    const auto size = static_cast<std::size_t>(long_signal ? 200 + rng() % 400 : 1 + rng() % 40);
    const auto levels = long_signal ? 64 + rng() % 64 : 2 + rng() % 8;
    std::vector<double> signal;
    for (std::size_t i = 0; i < size; ++i) signal.push_back(0.125 * static_cast<double>(rng() % levels));
    const double resolution = 0.125 * static_cast<double>(rng() % 4);
    ASSERT_EQ(Swing(signal, resolution), ReferenceSwing(signal, resolution))
        << "trial " << trial << ", resolution " << resolution;
    const Runout runout = MeasureRunout(signal, {resolution, 0.0});
    const auto [lo, hi] = std::minmax_element(signal.begin(), signal.end());
    ASSERT_EQ(runout.total, *hi - *lo) << "trial " << trial;
  }
}

// The property the old "peak to nearest valley" lacked: a ripple that appears or grows can
// move the swing only by what it moves the signal. A rise and its inner fall each move by
// at most 2 max|delta|, so the swing by at most 4 max|delta|.
TEST(Swing, MovesByAtMostFourTimesTheLargestChangeOfTheSignal) {
  std::mt19937_64 rng(314159);
  constexpr double kLipschitz = 4.0;
  for (int trial = 0; trial < 2000; ++trial) {
    const auto size = static_cast<std::size_t>(2 + rng() % 60);
    std::vector<double> signal;
    for (std::size_t i = 0; i < size; ++i) signal.push_back(Uniform(rng, -1.0, 1.0));
    const double change = Uniform(rng, 0.0, 0.2);
    std::vector<double> moved = signal;
    for (double& x : moved) x += Uniform(rng, -change, change);
    const double resolution = Uniform(rng, 0.0, 0.5);
    // Rounding: each swing is a few additions of values of size 2 [-].
    constexpr double kRounding = 16.0 * kEps;
    ASSERT_LE(std::abs(Swing(moved, resolution) - Swing(signal, resolution)), kLipschitz * change + kRounding)
        << "trial " << trial;
  }
}

TEST(Swing, IgnoresARippleWithinTheResolutionAndIsContinuousAsItGrows) {
  // A two-lobed signal with a fast ripple of depth 2 a: within the resolution the ripple is
  // free and the swing is the whole range; beyond it the ripple is charged only its
  // excess, so sweeping a through the resolution moves the swing smoothly.
  constexpr int kSamples = 4096;
  constexpr double kResolution = 0.1e-6;  // [m]
  constexpr double kSlow = 50e-6;         // [m]
  double previous = -1.0;
  for (int step = 0; step <= 40; ++step) {
    const double ripple = 0.0025e-6 * step;  // [m] 0 .. 0.1 um, depth 0 .. 0.2 um
    std::vector<double> signal;
    for (int k = 0; k < kSamples; ++k) {
      const double angle = 2.0 * kPi * k / kSamples;
      signal.push_back(kSlow * std::cos(2.0 * angle) + ripple * std::cos(421.0 * angle));
    }
    const Runout runout = MeasureRunout(signal, {kResolution, 0.0});
    if (2.0 * ripple <= kResolution) {
      EXPECT_EQ(runout.swing, runout.total) << "ripple " << ripple;
    }
    if (previous >= 0.0) {
      // One sweep step changes the signal by at most 0.0025 um anywhere.
      EXPECT_LE(std::abs(runout.swing - previous), 4.0 * 0.0025e-6 + 1e-15) << "ripple " << ripple;
    }
    previous = runout.swing;
  }
}

TEST(GaussianFilterClosed, PassesEachHarmonicByTheIsoTransmission) {
  // ISO 16610-21: a(k) = exp(-pi (alpha k / k_c)^2), alpha = sqrt(ln 2 / pi): 50 % at the
  // cutoff, 2^-9 at three times it. An FFT's roundings add up like a random walk, to
  // about eps sqrt(n) log2(n) of a unit amplitude per sample; twice that for the round trip.
  constexpr int kSamples = 1000;
  constexpr double kCutoff = 50.0;
  const double tolerance = 2.0 * kEps * std::sqrt(kSamples) * std::log2(kSamples);
  const double alpha = std::sqrt(std::log(2.0) / kPi);
  for (const int order : {0, 1, 15, 50, 150, 499}) {
    std::vector<double> signal;
    for (int k = 0; k < kSamples; ++k) signal.push_back(std::cos(2.0 * kPi * order * k / kSamples + 0.7));
    const std::vector<double> filtered = GaussianFilterClosed(signal, kCutoff);
    const double ratio = alpha * order / kCutoff;
    const double transmission = std::exp(-kPi * ratio * ratio);
    for (int k = 0; k < kSamples; ++k) {
      ASSERT_NEAR(filtered[static_cast<std::size_t>(k)], transmission * signal[static_cast<std::size_t>(k)], tolerance)
          << "order " << order << ", sample " << k;
    }
  }
  EXPECT_NEAR(std::exp(-kPi * std::pow(alpha, 2)), 0.5, kEps);
}

TEST(MeasureRunout, FilterRemovesFastRippleFromTheSwingButNotFromTheTotal) {
  // Two lobes of 50 um under a 20 um ripple at 400 undulations: unfiltered, the ripple's
  // falls (40 um) are charged; at a 50 upr cutoff the ripple passes by e^-(pi (8 alpha)^2)
  // = 2^-64 and the lobes by 2^-(2/50)^2 ~ 0.9989.
  constexpr int kSamples = 4000;
  std::vector<double> signal;
  for (int k = 0; k <= kSamples; ++k) {
    const double angle = 2.0 * kPi * k / kSamples;
    signal.push_back(50e-6 * std::cos(2.0 * angle) + 20e-6 * std::cos(400.0 * angle));
  }
  const Runout raw = MeasureRunout(signal, {0.1e-6, 0.0});
  const Runout filtered = MeasureRunout(signal, {0.1e-6, 50.0});
  EXPECT_EQ(raw.total, filtered.total);
  EXPECT_GT(raw.total, 2.0 * 50e-6);
  const double lobes = 2.0 * 50e-6 * std::pow(2.0, -std::pow(2.0 / 50.0, 2));
  // The filtered extremes fall between samples by at most 50 um (1 - cos(2 pi / 4000)).
  const double sampling = 2.0 * 50e-6 * (1.0 - std::cos(2.0 * kPi / kSamples));
  EXPECT_NEAR(filtered.swing, lobes, sampling + 1e-15);
}

}  // namespace
}  // namespace ringtol::engine
