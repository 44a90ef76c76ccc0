#include "engine/enclosing_circle.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

namespace ringtol::engine {
namespace {

using Point = Eigen::Vector2d;
using Points = std::vector<Point>;

constexpr double kEps = std::numeric_limits<double>::epsilon();

// Radius agreement, relative to the coordinate scale max |coordinate|: the engine accepts
// points up to 256 eps (radius + extent) outside, with radius <= sqrt(2) scale and extent
// <= 2 scale, so < 875 eps scale, plus a few eps of translation and circumcentre rounding.
constexpr double kRelativeRadiusTolerance = 1024.0 * kEps;

// Exact results (midpoints, a known circle) only carry the rounding of a few sums.
constexpr double kRelativeRoundingTolerance = 8.0 * kEps;

double CoordinateScale(const Points& points) {
  double scale = 0.0;
  for (const Point& p : points) scale = std::max(scale, p.cwiseAbs().maxCoeff());
  return scale;
}

double FarthestDistance(const Points& points, const Point& centre) {
  double farthest = 0.0;
  for (const Point& p : points) farthest = std::max(farthest, (p - centre).norm());
  return farthest;
}

// Reference by exhaustion: the MEC is either the diameter circle of a pair or the
// circumcircle of a triple, so the best of those candidate centres, each scored by its
// farthest point, is the MEC up to the rounding of that candidate centre. Scoring by the
// farthest point needs no containment tolerance and can never undercut the true radius.
Circle BruteForceCircle(const Points& points) {
  Circle best{points.front(), FarthestDistance(points, points.front())};
  auto consider = [&](const Point& centre) {
    const double radius = FarthestDistance(points, centre);
    if (radius < best.radius) best = {centre, radius};
  };
  const std::size_t n = points.size();
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      consider(0.5 * (points[i] + points[j]));
      for (std::size_t k = j + 1; k < n; ++k) {
        const Point u = points[j] - points[i];
        const Point v = points[k] - points[i];
        const double cross = u.x() * v.y() - u.y() * v.x();
        if (cross == 0.0) continue;
        const double uu = u.squaredNorm();
        const double vv = v.squaredNorm();
        consider(points[i] + Point(v.y() * uu - u.y() * vv, u.x() * vv - v.x() * uu) / (2.0 * cross));
      }
    }
  }
  return best;
}

// Widest angular gap, seen from the circle's centre, between consecutive points that lie
// within boundary_tolerance of its boundary; 2 pi when fewer than two do.
double WidestBoundaryGap(const Points& points, const Circle& circle, double boundary_tolerance) {
  std::vector<double> angles;
  for (const Point& p : points) {
    const Point d = p - circle.centre;
    if (d.norm() >= circle.radius - boundary_tolerance) angles.push_back(std::atan2(d.y(), d.x()));
  }
  if (angles.size() < 2) return 2.0 * std::numbers::pi;
  std::sort(angles.begin(), angles.end());
  double widest = angles.front() + 2.0 * std::numbers::pi - angles.back();
  for (std::size_t i = 1; i < angles.size(); ++i) widest = std::max(widest, angles[i] - angles[i - 1]);
  return widest;
}

// How far the centre of any circle containing every point, with radius within t of
// reference.radius, can be from reference.centre. Moving the centre by e away from the
// reference's boundary points (within t of its boundary, no gap wider than g <= pi) takes
// one of them out to >= rho + e cos(g/2), and to >= sqrt(rho^2 + e^2), rho >= r - t: so
// e <= 2t / cos(g/2) and e <= sqrt((r + t)^2 - (r - t)^2) = 2 sqrt(r t).
double CentreTolerance(const Points& points, const Circle& reference, double t) {
  const double gap = WidestBoundaryGap(points, reference, t);
  const double without_gap = 2.0 * std::sqrt(reference.radius * t);
  if (gap >= std::numbers::pi) return without_gap;
  return std::min(without_gap, 2.0 * t / std::cos(0.5 * gap));
}

// Optimality certificate of a minimum enclosing circle: it contains every point, and the
// points on its boundary (within boundary_tolerance) are at least two and lie in no open
// half circle, i.e. no angular gap between consecutive boundary points exceeds pi (plus
// angle_tolerance for antipodal pairs that are antipodal only up to rounding).
::testing::AssertionResult IsCertifiedMinimum(const Points& points, const Circle& circle,
                                              double boundary_tolerance, double angle_tolerance) {
  for (const Point& p : points) {
    if ((p - circle.centre).norm() > circle.radius) {
      return ::testing::AssertionFailure() << "point (" << p.x() << ", " << p.y() << ") is outside";
    }
  }
  const double gap = WidestBoundaryGap(points, circle, boundary_tolerance);
  if (gap > std::numbers::pi + angle_tolerance) {
    return ::testing::AssertionFailure()
           << "the boundary points are fewer than two or fit in an open half circle (gap " << gap
           << " rad)";
  }
  return ::testing::AssertionSuccess();
}

enum class Distribution { kUniformSquare, kGaussian, kTinyRing };

Points RandomPoints(Distribution distribution, std::size_t n, unsigned seed) {
  std::mt19937_64 engine(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * std::numbers::pi);
  std::uniform_real_distribution<double> radial_noise(-1e-6, 1e-6);
  Points points;
  for (std::size_t i = 0; i < n; ++i) {
    switch (distribution) {
      case Distribution::kUniformSquare:
        points.emplace_back(uniform(engine), uniform(engine));
        break;
      case Distribution::kGaussian:
        points.emplace_back(gaussian(engine), gaussian(engine));
        break;
      case Distribution::kTinyRing: {
        // A ring-centre path in metres: radius 1e-4 about (0.3, -0.2) with micrometre noise.
        const double t = angle(engine);
        const double r = 1e-4 + radial_noise(engine);
        points.emplace_back(0.3 + r * std::cos(t), -0.2 + r * std::sin(t));
        break;
      }
    }
  }
  return points;
}

bool AllInside(const Points& points, const Circle& circle) {
  return std::all_of(points.begin(), points.end(),
                     [&](const Point& p) { return (p - circle.centre).norm() <= circle.radius; });
}

// `circle` is the one with diameter [a, b], within `tolerance`, and holds every point.
void ExpectDiameterCircle(const Points& points, const Circle& circle, const Point& a, const Point& b,
                          double tolerance) {
  EXPECT_NEAR(circle.centre.x(), 0.5 * (a.x() + b.x()), tolerance);
  EXPECT_NEAR(circle.centre.y(), 0.5 * (a.y() + b.y()), tolerance);
  EXPECT_NEAR(circle.radius, 0.5 * (b - a).norm(), tolerance);
  EXPECT_TRUE(AllInside(points, circle));
}

// The engine's circle against the brute-force reference: the radius within
// kRelativeRadiusTolerance of the coordinate scale, the centre within what that radius
// tolerance allows (CentreTolerance). Returns the engine's circle for further checks.
Circle ExpectMatchesBruteForce(const Points& points) {
  const Circle expected = BruteForceCircle(points);
  const Circle actual = MinimumEnclosingCircle(points);
  const double radius_tolerance = kRelativeRadiusTolerance * CoordinateScale(points);
  const double centre_tolerance = CentreTolerance(points, expected, radius_tolerance);
  EXPECT_NEAR(actual.radius, expected.radius, radius_tolerance);
  EXPECT_NEAR(actual.centre.x(), expected.centre.x(), centre_tolerance);
  EXPECT_NEAR(actual.centre.y(), expected.centre.y(), centre_tolerance);
  return actual;
}

TEST(MinimumEnclosingCircle, MatchesBruteForceOnRandomPoints) {
  for (Distribution distribution :
       {Distribution::kUniformSquare, Distribution::kGaussian, Distribution::kTinyRing}) {
    for (std::size_t n : {1U, 2U, 3U, 4U, 5U, 7U, 10U, 16U, 25U, 40U}) {
      for (unsigned seed = 1; seed <= 6; ++seed) {
        SCOPED_TRACE(::testing::Message() << "distribution " << static_cast<int>(distribution)
                                          << ", n " << n << ", seed " << seed);
        ExpectMatchesBruteForce(RandomPoints(distribution, n, seed));
      }
    }
  }
}

TEST(MinimumEnclosingCircle, ContainsEveryPointWithoutTolerance) {
  for (Distribution distribution :
       {Distribution::kUniformSquare, Distribution::kGaussian, Distribution::kTinyRing}) {
    for (unsigned seed = 1; seed <= 5; ++seed) {
      const Points points = RandomPoints(distribution, 500, seed);
      EXPECT_TRUE(AllInside(points, MinimumEnclosingCircle(points)));
    }
  }
}

TEST(MinimumEnclosingCircle, CollinearPointsGiveTheDiameterCircleOfTheExtremes) {
  // Unsorted, with duplicates, on a sloped line that is not exactly representable.
  const Point start(0.3, -0.2);
  const Point step(1e-5, 3e-5);
  Points points;
  for (double t : {0.4, -1.7, 2.5, 0.4, 0.0, 2.5, -1.7, 1.1, -0.3, 2.0}) points.push_back(start + t * step);
  const Point low = start - 1.7 * step;
  const Point high = start + 2.5 * step;

  const Circle circle = MinimumEnclosingCircle(points);
  const double tolerance = kRelativeRoundingTolerance * CoordinateScale(points);
  ExpectDiameterCircle(points, circle, low, high, tolerance);
}

TEST(MinimumEnclosingCircle, ManyCollinearPointsGiveTheDiameterCircleOfTheExtremes) {
  Points points;
  std::mt19937_64 engine(7);
  std::uniform_real_distribution<double> t(-1.0, 1.0);
  double t_low = 0.0;
  double t_high = 0.0;
  for (int i = 0; i < 2000; ++i) {
    const double ti = t(engine);
    t_low = std::min(t_low, ti);
    t_high = std::max(t_high, ti);
    points.emplace_back(-0.1 + 0.7 * ti, 0.05 - 0.3 * ti);
  }
  const Point low(-0.1 + 0.7 * t_low, 0.05 - 0.3 * t_low);
  const Point high(-0.1 + 0.7 * t_high, 0.05 - 0.3 * t_high);

  const Circle circle = MinimumEnclosingCircle(points);
  // The engine may settle on a point within its inside slack of an extreme, so the radius
  // tolerance rather than plain rounding; a circumcircle would be off by far more.
  const double tolerance = kRelativeRadiusTolerance * CoordinateScale(points);
  ExpectDiameterCircle(points, circle, low, high, tolerance);
}

TEST(MinimumEnclosingCircle, NearlyCollinearPointsMatchBruteForce) {
  // Perpendicular offsets from 1e-14 to 1e-6 of the segment length: from rounding-level
  // noise, where every circumcircle is meaningless, to a genuinely thin triangle.
  for (double offset : {1e-14, 1e-12, 1e-10, 1e-8, 1e-6}) {
    for (unsigned seed = 1; seed <= 4; ++seed) {
      SCOPED_TRACE(::testing::Message() << "offset " << offset << ", seed " << seed);
      std::mt19937_64 engine(seed);
      std::uniform_real_distribution<double> along(-1.0, 1.0);
      std::uniform_real_distribution<double> across(-offset, offset);
      const Point origin(0.3, -0.2);
      const Point direction(0.8, 0.6);
      const Point normal(-0.6, 0.8);
      Points points;
      for (int i = 0; i < 30; ++i) {
        points.push_back(origin + 2e-4 * (along(engine) * direction + across(engine) * normal));
      }
      EXPECT_TRUE(AllInside(points, ExpectMatchesBruteForce(points)));
    }
  }
}

Points OnCircle(const Point& centre, double radius, const std::vector<double>& angles_deg) {
  Points points;
  for (double deg : angles_deg) {
    const double t = deg * std::numbers::pi / 180.0;
    points.push_back(centre + radius * Point(std::cos(t), std::sin(t)));
  }
  return points;
}

TEST(MinimumEnclosingCircle, CoCircularPointsSpanningMoreThanASemicircleGiveThatCircle) {
  const Point centre(0.1, -0.05);
  const double radius = 0.25;
  // Largest angular gap 55 deg, so the circle is the MEC of these points.
  const Points points = OnCircle(
      centre, radius, {3.0, 17.5, 61.0, 95.0, 131.0, 150.0, 171.0, 213.0, 250.0, 288.0, 311.0, 340.0});

  const Circle circle = MinimumEnclosingCircle(points);
  const double radius_tolerance = kRelativeRadiusTolerance * CoordinateScale(points);
  // The support points leave no angular gap wider than 55 deg, so a centre offset e
  // pushes some point out by >= e cos(27.5 deg) > e / 2: the centre is held to twice the
  // radius tolerance (the points' own rounding is included in that tolerance).
  const double centre_tolerance = 2.0 * radius_tolerance;
  EXPECT_NEAR(circle.radius, radius, radius_tolerance);
  EXPECT_NEAR(circle.centre.x(), centre.x(), centre_tolerance);
  EXPECT_NEAR(circle.centre.y(), centre.y(), centre_tolerance);
  EXPECT_TRUE(AllInside(points, circle));
}

TEST(MinimumEnclosingCircle, NearlyCoCircularPointsMatchBruteForce) {
  // Radial noise from 1e-12 to 1e-8 of the radius puts points just inside and just outside
  // the circles through the others: a larger acceptance slack in the engine would return
  // one of those circles instead of the minimum.
  for (double noise : {1e-12, 1e-10, 1e-8}) {
    for (unsigned seed = 1; seed <= 4; ++seed) {
      SCOPED_TRACE(::testing::Message() << "noise " << noise << ", seed " << seed);
      std::mt19937_64 engine(seed);
      std::uniform_real_distribution<double> angle(0.0, 2.0 * std::numbers::pi);
      std::uniform_real_distribution<double> radial(-noise, noise);
      Points points;
      for (int i = 0; i < 30; ++i) {
        const double t = angle(engine);
        points.push_back(Point(0.1, -0.05) + 0.25 * (1.0 + radial(engine)) * Point(std::cos(t), std::sin(t)));
      }
      ExpectMatchesBruteForce(points);
    }
  }
}

TEST(MinimumEnclosingCircle, CoCircularPointsWithinLessThanASemicircleGiveTheArcEndsDiameterCircle) {
  const Points points = OnCircle(Point(0.1, -0.05), 0.25, {20.0, 37.0, 41.0, 88.0, 102.0, 150.0, 171.0, 180.0});
  const Point first = points.front();
  const Point last = points.back();

  const Circle circle = MinimumEnclosingCircle(points);
  const double tolerance = kRelativeRoundingTolerance * CoordinateScale(points);
  ExpectDiameterCircle(points, circle, first, last, tolerance);
}

TEST(MinimumEnclosingCircle, SinglePointIsACircleOfRadiusZero) {
  const Points points = {Point(0.3, -0.2)};
  const Circle circle = MinimumEnclosingCircle(points);
  EXPECT_EQ(circle.centre, points.front());
  EXPECT_EQ(circle.radius, 0.0);
}

TEST(MinimumEnclosingCircle, TwoPointsGiveTheirDiameterCircle) {
  const Points points = {Point(0.3, -0.2), Point(0.3002, -0.1997)};
  const Circle circle = MinimumEnclosingCircle(points);
  const double tolerance = kRelativeRoundingTolerance * CoordinateScale(points);
  EXPECT_NEAR(circle.centre.x(), 0.3001, tolerance);
  EXPECT_NEAR(circle.centre.y(), -0.19985, tolerance);
  EXPECT_NEAR(circle.radius, 0.5 * (points[1] - points[0]).norm(), tolerance);
  EXPECT_TRUE(AllInside(points, circle));
}

TEST(MinimumEnclosingCircle, IdenticalPointsGiveACircleOfRadiusZero) {
  const Points points(50, Point(-0.7, 1e-3));
  const Circle circle = MinimumEnclosingCircle(points);
  EXPECT_EQ(circle.centre, points.front());
  EXPECT_EQ(circle.radius, 0.0);
}

TEST(MinimumEnclosingCircle, EmptyInputThrows) {
  EXPECT_THROW(MinimumEnclosingCircle(Points{}), std::invalid_argument);
}

TEST(MinimumEnclosingCircle, NonFiniteInputThrows) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(MinimumEnclosingCircle(Points{Point(0.0, 0.0), Point(nan, 1.0)}), std::invalid_argument);
  EXPECT_THROW(MinimumEnclosingCircle(Points{Point(0.0, nan)}), std::invalid_argument);
  EXPECT_THROW(MinimumEnclosingCircle(Points{Point(1.0, 0.0), Point(0.0, inf)}), std::invalid_argument);
}

TEST(MinimumEnclosingCircle, ShufflingTheInputGivesTheSameCircle) {
  for (Distribution distribution :
       {Distribution::kUniformSquare, Distribution::kGaussian, Distribution::kTinyRing}) {
    Points points = RandomPoints(distribution, 300, 11);
    const Circle reference = MinimumEnclosingCircle(points);
    const double radius_tolerance = kRelativeRadiusTolerance * CoordinateScale(points);
    const double centre_tolerance = CentreTolerance(points, reference, radius_tolerance);
    std::mt19937 engine(3);
    for (int trial = 0; trial < 5; ++trial) {
      std::shuffle(points.begin(), points.end(), engine);
      const Circle shuffled = MinimumEnclosingCircle(points);
      EXPECT_NEAR(shuffled.radius, reference.radius, radius_tolerance);
      EXPECT_NEAR(shuffled.centre.x(), reference.centre.x(), centre_tolerance);
      EXPECT_NEAR(shuffled.centre.y(), reference.centre.y(), centre_tolerance);
    }
  }
}

TEST(MinimumEnclosingCircle, LargeLissajousPathIsCertifiedOptimal) {
  Points points;
  const std::size_t n = 20000;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = 2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n);
    points.emplace_back(0.3 + 1.2e-4 * std::sin(3.0 * t + 0.7) + 2e-5 * std::cos(7.0 * t),
                        -0.2 + 0.9e-4 * std::sin(4.0 * t) + 1.5e-5 * std::sin(5.0 * t + 0.2));
  }
  const Circle circle = MinimumEnclosingCircle(points);
  const double boundary_tolerance = kRelativeRadiusTolerance * CoordinateScale(points);
  // An antipodal support pair is antipodal up to the boundary tolerance over the radius.
  const double angle_tolerance = 2.0 * boundary_tolerance / circle.radius;
  EXPECT_TRUE(IsCertifiedMinimum(points, circle, boundary_tolerance, angle_tolerance));
}

TEST(MinimumEnclosingCircle, CertificateRejectsANonMinimalCircle) {
  const Points points = OnCircle(Point(0.0, 0.0), 1.0, {0.0, 120.0, 240.0});
  // Centred off the MEC centre and just large enough: two boundary points, on one side.
  const Point off_centre(0.2, 0.0);
  const Circle too_big{off_centre, FarthestDistance(points, off_centre)};
  // Radius 1, so the same relative tolerance serves for lengths and angles.
  const double tolerance = kRelativeRadiusTolerance * CoordinateScale(points);
  EXPECT_FALSE(IsCertifiedMinimum(points, too_big, tolerance, tolerance));
  const Circle minimal = MinimumEnclosingCircle(points);
  EXPECT_TRUE(IsCertifiedMinimum(points, minimal, tolerance, tolerance));
}

}  // namespace
}  // namespace ringtol::engine
