#include "engine/scene.h"
#include "engine/units.h"

#include <algorithm>
#include <cmath>
#include <numbers>

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
  const PolarProfile& outline = scene.rollers[static_cast<std::size_t>(i)].outline;
  return (scene.ring.inner.radius() + scene.ring.inner.mean_deviation()) / (outline.radius() + outline.mean_deviation());
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

bool SameWithoutErrors(const Scene& a, const Scene& b) {
  // Structured bindings name every field of Scene, Ring and Roller: one added to them does
  // not compile here until it is sorted into an error (left out, and cleared by
  // WithoutErrors and HasErrors) or a nominal field (compared).
  const auto& [ring_a, rollers_a, positions_a, contact_a, friction_a, sensor_a, swing_a, filter_a, motion_a,
               dynamics_a, locked_a] = a;
  const auto& [ring_b, rollers_b, positions_b, contact_b, friction_b, sensor_b, swing_b, filter_b, motion_b,
               dynamics_b, locked_b] = b;
  const auto& [inner_a, outer_a, thickness_a, mass_a, inertia_a, material_a] = ring_a;
  const auto& [inner_b, outer_b, thickness_b, mass_b, inertia_b, material_b] = ring_b;
  if (!(inner_a.radius() == inner_b.radius() && outer_a == outer_b && thickness_a == thickness_b &&
        mass_a == mass_b && inertia_a == inertia_b && material_a == material_b)) {
    return false;
  }
  if (rollers_a.size() != rollers_b.size()) return false;
  for (std::size_t i = 0; i < rollers_a.size(); ++i) {
    const auto& [name_a, angle_a, centre_a, radial_a, tangential_a, outline_a, reference_a, phase_a, mount_a,
                 spring_a, roller_mass_a, roller_inertia_a, width_a, roller_material_a] = rollers_a[i];
    const auto& [name_b, angle_b, centre_b, radial_b, tangential_b, outline_b, reference_b, phase_b, mount_b,
                 spring_b, roller_mass_b, roller_inertia_b, width_b, roller_material_b] = rollers_b[i];
    // The radial and tangential offsets are errors: not compared.
    if (!(name_a == name_b && angle_a == angle_b && centre_a == centre_b && outline_a.radius() == outline_b.radius() &&
          reference_a == reference_b && phase_a == phase_b && mount_a == mount_b && spring_a == spring_b &&
          roller_mass_a == roller_mass_b && roller_inertia_a == roller_inertia_b && width_a == width_b &&
          roller_material_a == roller_material_b)) {
      return false;
    }
  }
  return positions_a.radius() == positions_b.radius() && contact_a == contact_b && friction_a == friction_b &&
         sensor_a == sensor_b && swing_a == swing_b && filter_a == filter_b && motion_a == motion_b &&
         dynamics_a == dynamics_b &&
         locked_a == locked_b;
}

bool HasErrors(const Scene& scene) {
  // A profile equals the circle of its radius when it has neither a mean deviation nor
  // harmonics (even of zero amplitude: they make it compare unequal).
  const auto round = [](const PolarProfile& p) { return p.mean_deviation() == 0.0 && p.harmonics().empty(); };
  if (!round(scene.ring.inner) || !round(scene.roller_positions)) return true;
  return std::any_of(scene.rollers.begin(), scene.rollers.end(), [&](const Roller& r) {
    return !round(r.outline) || !(r.radial_offset == 0.0) || !(r.tangential_offset == 0.0);
  });
}

FastestHarmonic FindFastestHarmonic(const Scene& scene) {
  const int ring_order = scene.ring.inner.max_order();
  FastestHarmonic fastest{static_cast<double>(ring_order), -1, ring_order};
  for (int i = 0; i < static_cast<int>(scene.rollers.size()); ++i) {
    const int order = scene.rollers[static_cast<std::size_t>(i)].outline.max_order();
    const double rate = order * SpinRatio(scene, i);
    if (rate > fastest.rate) fastest = {rate, i, order};
  }
  return fastest;
}

double FastestHarmonicRate(const Scene& scene) { return FindFastestHarmonic(scene).rate; }

int MinimumSteps(double rate) { return static_cast<int>(std::floor(2.0 * rate)) + 1; }

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
      return {GeometryIssue::kRollerDoesNotFit, i, -1, 0.0,
              "roller " + roller.name + " does not fit in the ring: it reaches " + units::ShowMillimetres(centre + reach) +
                  " mm from the ring's centre against a bore of " + units::ShowMillimetres(bore) +
                  " mm (overlap may not exceed the roller's radius " + units::ShowMillimetres(roller.outline.radius()) +
                  " mm)"};
    }
  }
  // Rollers are bodies in one plane: two that overlap would have to pass through each
  // other, and no solver sees it, since each contact is only between a roller and the bore.
  // Rollers turn, so each one's largest radius faces the other at some point. The
  // profiles' bounds settle pairs with room to spare; the exact extremes decide the rest.
  for (int j = 1; j < static_cast<int>(scene.rollers.size()); ++j) {
    const PolarProfile& outline_j = scene.rollers[static_cast<std::size_t>(j)].outline;
    for (int i = 0; i < j; ++i) {
      const PolarProfile& outline_i = scene.rollers[static_cast<std::size_t>(i)].outline;
      const double distance = (RollerCentre(scene, j) - RollerCentre(scene, i)).norm();
      if (outline_i.ExtremesBounds().max_radius + outline_j.ExtremesBounds().max_radius <= distance) continue;
      const double reach = outline_i.MaxRadius() + outline_j.MaxRadius();
      if (reach <= distance) continue;
      const Roller& a = scene.rollers[static_cast<std::size_t>(i)];
      const Roller& b = scene.rollers[static_cast<std::size_t>(j)];
      return {GeometryIssue::kRollersOverlap, j, i, reach - distance,
              "rollers " + a.name + " and " + b.name + " overlap by " + units::ShowMillimetres(reach - distance) +
                  " mm: their centres are " + units::ShowMillimetres(distance) + " mm apart against radii summing to " +
                  units::ShowMillimetres(reach) + " mm"};
    }
  }
  if (!scene.ring.inner.IsConvex()) {
    return {GeometryIssue::kRingNotConvex, -1, -1, 0.0,
            "the ring's inner profile is not convex (its curvature reaches " +
                std::to_string(scene.ring.inner.MinCurvature()) +
                " 1/m): an inward bump makes contact ambiguous; reduce the amplitude of high orders "
                "(a single harmonic is convex while C_n < R / (n^2 + 1))"};
  }
  for (int i = 0; i < static_cast<int>(scene.rollers.size()); ++i) {
    const Roller& roller = scene.rollers[static_cast<std::size_t>(i)];
    if (!roller.outline.IsConvex()) {
      return {GeometryIssue::kRollerNotConvex, i, -1, 0.0,
              "roller " + roller.name + "'s outline is not convex: reduce its high-order amplitudes"};
    }
  }
  return {};
}

}  // namespace ringtol::engine
