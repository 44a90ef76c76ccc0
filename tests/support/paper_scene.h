// The article's nominal assembly (docs/model.md §1, examples/paper/scene.toml) built in code,
// so physics tests do not depend on the input reader.
#pragma once

#include <array>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "engine/scene.h"

namespace ringtol::testing {

constexpr double kDeg = std::numbers::pi / 180.0;

inline engine::Roller PaperRoller(const char* name, double angle_deg, bool spring) {
  engine::Roller r;
  r.name = name;
  r.angle = angle_deg * kDeg;
  r.outline = engine::PolarProfile(0.005, 0.0, {});
  r.centre_radius = 0.302 - 0.005;
  r.mass = 2.47e-3;
  r.spin_inertia = 3.08e-8;
  if (spring) {
    r.mount = engine::RollerMount::kSpring;
    r.spring = {1334.0, 19.3, r.angle, 0.005};
  }
  return r;
}

// Spring roller at 90 deg, fixed rollers at 210 and 330 deg, sensor at 0 deg.
inline engine::Scene PaperScene(engine::ContactLaw::Model law = engine::ContactLaw::Model::kPenalty) {
  engine::Scene scene;
  scene.ring.inner = engine::PolarProfile(0.302, 0.0, {});
  scene.ring.outer_radius = 0.33985;
  scene.ring.thickness = 0.006;
  scene.ring.mass = 1.236;
  scene.ring.spin_inertia = 0.1277;
  scene.rollers = {PaperRoller("spring", 90.0, true), PaperRoller("fixed_a", 210.0, false),
                   PaperRoller("fixed_b", 330.0, false)};
  scene.contact.model = law;
  return scene;
}

inline void SetRing(engine::Scene& scene, std::vector<engine::Harmonic> harmonics) {
  scene.ring.inner = engine::PolarProfile(scene.ring.inner.radius(), 0.0, std::move(harmonics));
}

inline void SetRollerShapes(engine::Scene& scene, const std::vector<engine::Harmonic>& harmonics) {
  for (engine::Roller& r : scene.rollers) r.outline = engine::PolarProfile(r.outline.radius(), 0.0, harmonics);
}

inline void SetRollerPositions(engine::Scene& scene, std::vector<engine::Harmonic> harmonics) {
  scene.roller_positions = engine::PolarProfile(1.0, 0.0, std::move(harmonics));
}

// A scene shaped like a draw of the default campaign (examples/campaigns/default.toml): a
// waterjet ring with orders 2..50 falling as 1/n, Normal-class rollers with 8 lobe orders
// of a few um, roller position errors of a few um.
inline engine::Scene CampaignLikeScene() {
  engine::Scene scene = PaperScene(engine::ContactLaw::Model::kPenalty);
  std::vector<engine::Harmonic> ring = {{2, 60e-6, 0.5}};
  for (int n = 3; n <= 50; ++n) ring.push_back({n, 10e-6 / n, 0.7 * n});
  SetRing(scene, std::move(ring));
  for (std::size_t i = 0; i < scene.rollers.size(); ++i) {
    engine::Roller& roller = scene.rollers[i];
    std::vector<engine::Harmonic> lobes;
    for (int k = 1; k <= 8; ++k) lobes.push_back({k, 2e-6 / k, 1.3 * k + static_cast<double>(i)});
    roller.outline = engine::PolarProfile(roller.outline.radius(), -1.5e-6, std::move(lobes));
    roller.radial_offset = 3e-6 * (static_cast<double>(i) - 1.0);
    roller.tangential_offset = 2e-6;
  }
  return scene;
}

// A draw shaped like the default campaign's (CampaignLikeScene), its phases and amplitudes
// scattered: the ring's form up to 3x, the rollers' lobes up to `lobe_scale` times, the
// roller positions within +-3 um.
inline engine::Scene RandomCampaignLikeScene(std::mt19937_64& random, double lobe_scale) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  engine::Scene scene = PaperScene(engine::ContactLaw::Model::kPenalty);
  std::vector<engine::Harmonic> ring = {{2, 60e-6 * 3.0 * unit(random), 6.3 * unit(random)}};
  for (int n = 3; n <= 50; ++n) ring.push_back({n, 10e-6 / n * 3.0 * unit(random), 6.3 * unit(random)});
  SetRing(scene, std::move(ring));
  for (std::size_t i = 0; i < scene.rollers.size(); ++i) {
    engine::Roller& roller = scene.rollers[i];
    std::vector<engine::Harmonic> lobes;
    for (int k = 1; k <= 8; ++k) lobes.push_back({k, lobe_scale * unit(random) * 2e-6 / k, 6.3 * unit(random)});
    roller.outline = engine::PolarProfile(roller.outline.radius(), -1.5e-6, std::move(lobes));
    roller.radial_offset = 6e-6 * (unit(random) - 0.5);
    roller.tangential_offset = 6e-6 * (unit(random) - 0.5);
  }
  return scene;
}

// `scene` with spring rollers added until it has `count` (at most 9): copies of its first
// roller (the spring at 90 deg, lobes and offsets included) at 30, 150, 60, 120, 10 and
// 170 deg, each pushing along its own radius, so the assembly still rests on the two fixed
// rollers below.
inline engine::Scene WithSpringRollers(engine::Scene scene, std::size_t count) {
  constexpr std::array<double, 6> kAnglesDeg = {30.0, 150.0, 60.0, 120.0, 10.0, 170.0};
  const engine::Roller model = scene.rollers.front();
  for (std::size_t j = 0; scene.rollers.size() < count; ++j) {
    engine::Roller roller = model;
    roller.name = "spring_" + std::to_string(j);
    roller.angle = kAnglesDeg.at(j) * kDeg;
    roller.spring.axis_angle = roller.angle;
    scene.rollers.push_back(std::move(roller));
  }
  return scene;
}

// `rollers` rollers of the article's size, equally spaced from 90 deg, `springs` of them
// (spread out: the first, and with two, also the one half-way round) on the article's
// spring pushing along their own radii and the others fixed with their centres
// `interference` [m] beyond a plain fit, so that every contact carries load however many
// rollers there are: the fixed rollers surround the centre. The contact law is linear
// (exponent 1, `stiffness` [N/m]): its linearisation is that stiffness at any load, which
// is what makes the centre's first-order path a closed form
// (tests/validation/roller_count_test.cpp).
inline engine::Scene EquallySpacedScene(int rollers, int springs, double interference, double stiffness) {
  engine::Scene scene = PaperScene(engine::ContactLaw::Model::kPenalty);
  scene.rollers.clear();
  for (int i = 0; i < rollers; ++i) {
    bool spring = false;
    for (int j = 0; j < springs; ++j) spring = spring || i == j * rollers / springs;
    engine::Roller roller = PaperRoller("", 90.0 + 360.0 * i / rollers, spring);
    roller.name = (spring ? "spring_" : "fixed_") + std::to_string(i);
    if (!spring) roller.centre_radius += interference;
    scene.rollers.push_back(std::move(roller));
  }
  scene.contact.exponent = 1.0;
  scene.contact.stiffness = stiffness;
  return scene;
}

// The article's assembly on `rollers` rollers, `springs` of them (1 or 2) on its spring: one
// spring at 90 deg or two at 60 and 120 deg, the fixed rollers spread evenly from 210 to
// 330 deg, under the springs' push, so each carries load at the article's contact law; the
// ring and the rollers' lobes and offsets as CampaignLikeScene's.
inline engine::Scene CampaignLikeStage(int rollers, int springs) {
  engine::Scene scene = CampaignLikeScene();
  const engine::Roller spring = scene.rollers[0];
  const engine::Roller fixed = scene.rollers[1];
  const int fixed_count = rollers - springs;
  scene.rollers.clear();
  for (int i = 0; i < rollers; ++i) {
    engine::Roller roller = i < springs ? spring : fixed;
    const double angle_deg = i < springs ? 90.0 + 30.0 * (2 * i + 1 - springs) : 210.0 + 120.0 * (i - springs) / (fixed_count - 1);
    roller.name = (i < springs ? "spring_" : "fixed_") + std::to_string(i);
    roller.angle = angle_deg * kDeg;
    roller.spring.axis_angle = roller.angle;
    std::vector<engine::Harmonic> lobes = roller.outline.harmonics();
    for (engine::Harmonic& lobe : lobes) lobe.phase += 0.9 * i;
    roller.outline = engine::PolarProfile(roller.outline.radius(), roller.outline.mean_deviation(), std::move(lobes));
    roller.radial_offset = 3e-6 * std::sin(1.7 * i);
    scene.rollers.push_back(std::move(roller));
  }
  return scene;
}

// RandomCampaignLikeScene with a weak spring and a large third-order ring lobe: the
// assembly lifts off for some draws, at angles a coarse grid need not contain.
inline engine::Scene LiftingCampaignLikeScene(std::mt19937_64& random, int draw) {
  engine::Scene scene = RandomCampaignLikeScene(random, 1.0);
  scene.rollers[0].spring.preload = 0.2;
  SetRing(scene, {{3, 150e-6, 0.3 * draw}, {40, 4e-6, 0.1 * draw}});
  return scene;
}

// Roller lobes fast enough that the path's and the sensor signal's extremes fall between
// every eighth angle of the step rule's grid.
inline engine::Scene FastLobeScene() {
  engine::Scene scene = PaperScene(engine::ContactLaw::Model::kPenalty);
  SetRing(scene, {{2, 20e-6, 0.0}});
  for (engine::Roller& roller : scene.rollers) {
    roller.outline = engine::PolarProfile(roller.outline.radius(), 0.0, {{7, 3e-6, 0.4}});
  }
  return scene;
}

}  // namespace ringtol::testing
