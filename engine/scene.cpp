#include "engine/scene.h"
#include "engine/units.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace ringtol::engine {

double RadialPositionError(const Scene& scene, int i) {
  const Roller& roller = scene.rollers[static_cast<std::size_t>(i)];
  const double series = scene.roller_positions.Evaluate(roller.angle).r - scene.roller_positions.radius();
  return roller.radial_offset + series;
}

Eigen::Vector2d RollerCentre(const Scene& scene, int i) {
  const Roller& roller = scene.rollers[static_cast<std::size_t>(i)];
  return (roller.centre_radius + RadialPositionError(scene, i)) * Direction(roller.angle) +
         roller.tangential_offset * Direction(roller.angle + std::numbers::pi / 2.0);
}

double SpinRatio(const Scene& scene, int i) {
  return scene.ring.inner.radius() / scene.rollers[static_cast<std::size_t>(i)].outline.radius();
}

double RollerBodyAngle(const Scene& scene, int i, double psi) {
  const Roller& roller = scene.rollers[static_cast<std::size_t>(i)];
  const double reference = roller.phase_reference == ShapePhaseReference::kRadial ? roller.angle : 0.0;
  return reference + roller.spin_phase + SpinRatio(scene, i) * psi;
}

Eigen::Vector2d SpringAxis(const Scene& scene, int i) {
  return Direction(scene.rollers[static_cast<std::size_t>(i)].spring.axis_angle);
}

int SpringRollerCount(const Scene& scene) {
  return static_cast<int>(std::count_if(scene.rollers.begin(), scene.rollers.end(),
                                        [](const Roller& r) { return r.mount == RollerMount::kSpring; }));
}

int FixedRollerCount(const Scene& scene) {
  return static_cast<int>(scene.rollers.size()) - SpringRollerCount(scene);
}

Scene WithoutErrors(const Scene& scene) {
  Scene perfect = scene;
  perfect.ring.inner = PolarProfile(scene.ring.inner.radius(), 0.0, {});
  perfect.roller_positions = PolarProfile(scene.roller_positions.radius(), 0.0, {});
  for (Roller& roller : perfect.rollers) {
    roller.outline = PolarProfile(roller.outline.radius(), 0.0, {});
    roller.radial_offset = 0.0;
    roller.tangential_offset = 0.0;
  }
  return perfect;
}

double FastestHarmonicRate(const Scene& scene) {
  double rate = scene.ring.inner.max_order();
  for (int i = 0; i < static_cast<int>(scene.rollers.size()); ++i) {
    rate = std::max(rate, scene.rollers[static_cast<std::size_t>(i)].outline.max_order() * SpinRatio(scene, i));
  }
  return rate;
}

namespace {
std::string Millimetres(double metres) {
  std::ostringstream out;
  out.precision(6);
  out << metres * units::kMillimetresPerMetre << " mm";
  return out.str();
}
}  // namespace

GeometryCheck CheckGeometry(const Scene& scene) {
  // Fit first: a roller that does not fit is an input error, whatever else is wrong. The
  // profiles' bounds on their extremes settle a roller that fits with room to spare (the
  // sums below only grow with reach and shrink with bore, rounding included); the exact
  // extremes decide the rest.
  const double bore_bound = scene.ring.inner.ExtremesBounds().min_radius;
  for (int i = 0; i < static_cast<int>(scene.rollers.size()); ++i) {
    const Roller& roller = scene.rollers[static_cast<std::size_t>(i)];
    const double centre = RollerCentre(scene, i).norm();
    const double reach_bound = roller.outline.ExtremesBounds().max_radius;
    if (reach_bound < bore_bound && centre + reach_bound - bore_bound <= roller.outline.radius()) continue;
    const double bore = scene.ring.inner.MinRadius();
    const double reach = roller.outline.MaxRadius();
    const double interference = centre + reach - bore;
    if (reach >= bore || interference > roller.outline.radius()) {
      return {GeometryIssue::kRollerDoesNotFit, i,
              "roller " + roller.name + " does not fit in the ring: it reaches " + Millimetres(centre + reach) +
                  " from the ring's centre against a bore of " + Millimetres(bore) +
                  " (overlap may not exceed the roller's radius " + Millimetres(roller.outline.radius()) + ")"};
    }
  }
  if (!scene.ring.inner.IsConvex()) {
    return {GeometryIssue::kRingNotConvex, -1,
            "the ring's inner profile is not convex (its curvature reaches " +
                std::to_string(scene.ring.inner.MinCurvature()) +
                " 1/m): an inward bump makes contact ambiguous; reduce the amplitude of high orders "
                "(a single harmonic is convex while C_n < R / (n^2 + 1))"};
  }
  for (int i = 0; i < static_cast<int>(scene.rollers.size()); ++i) {
    const Roller& roller = scene.rollers[static_cast<std::size_t>(i)];
    if (!roller.outline.IsConvex()) {
      return {GeometryIssue::kRollerNotConvex, i,
              "roller " + roller.name + "'s outline is not convex: reduce its high-order amplitudes"};
    }
  }
  return {};
}

}  // namespace ringtol::engine
