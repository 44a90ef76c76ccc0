#include "jobs/scene_file.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "jobs/input_error.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

using ringtol::testing::ReadText;
using ringtol::testing::ReplaceOnce;

using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr double kDeg = std::numbers::pi / 180.0;
// Masses and inertias are a few products and a difference of squares: ~10 ulp of
// relative rounding whatever the order of operations, far below this.
constexpr double kRoundingRelative = 1e-12;
// model.md quotes the paper ring's mass as "about 1.24 kg"; 1.236 kg is given to 4 digits.
constexpr double kQuotedMassRelative = 1e-3;

constexpr const char* kPaperScenePath = RINGTOL_SOURCE_DIR "/examples/paper/scene.toml";

std::string PaperSceneText() { return ReadText(kPaperScenePath); }

// The paper scene with one edit.
std::string PaperSceneWith(std::string_view from, std::string_view to) {
  return ReplaceOnce(PaperSceneText(), from, to);
}

// The second roller of the paper scene (rollers[1]), whole, so tests can rewrite it.
constexpr std::string_view kFixedA =
    "name = \"fixed_a\"\nangle_deg = 210.0\nradius_mm = 5.0\nmount = \"fixed\"\nwidth_mm = 4.0\n"
    "density_kg_per_m3 = 7850.0\nharmonics = []\n";
constexpr std::string_view kRingHarmonics = "harmonics = []                    # e.g.";

// The paper scene with one edit inside rollers[1].
std::string FixedAWith(std::string_view from, std::string_view to) {
  return PaperSceneWith(kFixedA, ReplaceOnce(std::string(kFixedA), from, to));
}

std::string ErrorFor(const std::string& text) {
  try {
    ParseScene(text, "bad.toml");
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "ParseScene accepted the input";
  return "";
}

// A scene with only the required keys.
constexpr const char* kMinimalScene = R"(
[ring]
inner_radius_mm = 100
outer_radius_mm = 110
thickness_mm = 5
mass_kg = 0.5

[[rollers]]
angle_deg = 90
radius_mm = 5
mount = "spring"
spring_stiffness_N_per_m = 1000
spring_preload_N = 10
width_mm = 4
mass_kg = 0.002

[[rollers]]
angle_deg = 210
radius_mm = 5
mount = "fixed"
width_mm = 4
mass_kg = 0.002

[[rollers]]
angle_deg = 330
radius_mm = 5
mount = "fixed"
width_mm = 4
mass_kg = 0.002
)";

// ---- valid input

TEST(SceneFile, ParsesThePaperSceneInSiUnits) {
  const engine::Scene scene = ParseScene(PaperSceneText(), "scene.toml");
  EXPECT_DOUBLE_EQ(scene.ring.inner.radius(), 0.302);
  EXPECT_DOUBLE_EQ(scene.ring.outer_radius, 0.33985);
  EXPECT_DOUBLE_EQ(scene.ring.thickness, 0.006);
  EXPECT_TRUE(scene.ring.inner.is_circle());
  ASSERT_EQ(scene.rollers.size(), 3u);
  EXPECT_EQ(engine::SpringRollerCount(scene), 1);
  const engine::Roller& spring = scene.rollers[0];
  EXPECT_EQ(spring.name, "spring");
  EXPECT_EQ(spring.mount, engine::RollerMount::kSpring);
  EXPECT_DOUBLE_EQ(spring.spring.preload, 19.3);
  EXPECT_DOUBLE_EQ(spring.spring.stiffness, 1334.0);
  EXPECT_EQ(scene.rollers[1].name, "fixed_a");
  EXPECT_EQ(scene.rollers[2].mount, engine::RollerMount::kFixed);

  const double ro = 0.33985;
  const double ri = 0.302;
  const double annulus_mass = 2700.0 * std::numbers::pi * (ro * ro - ri * ri) * 0.006;
  EXPECT_NEAR(scene.ring.mass, annulus_mass, kRoundingRelative * annulus_mass);
  EXPECT_NEAR(scene.ring.mass, 1.236, kQuotedMassRelative * 1.236);
  const double annulus_inertia = annulus_mass * (ro * ro + ri * ri) / 2.0;
  EXPECT_NEAR(scene.ring.spin_inertia, annulus_inertia, kRoundingRelative * annulus_inertia);
}

TEST(SceneFile, ConvertsDegreesAndMillimetresToRadiansAndMetres) {
  const std::string text =
      PaperSceneWith(kRingHarmonics, "harmonics = [{ order = 3, amplitude_mm = 0.14, phase_deg = 45.0 }] #");
  const engine::Scene scene = ParseScene(text, "scene.toml");
  ASSERT_EQ(scene.ring.inner.harmonics().size(), 1u);
  EXPECT_EQ(scene.ring.inner.harmonics()[0].order, 3);
  EXPECT_DOUBLE_EQ(scene.ring.inner.harmonics()[0].amplitude, 1.4e-4);
  EXPECT_DOUBLE_EQ(scene.ring.inner.harmonics()[0].phase, std::numbers::pi / 4.0);
  EXPECT_DOUBLE_EQ(scene.rollers[0].angle, std::numbers::pi / 2.0);
  EXPECT_DOUBLE_EQ(scene.rollers[1].angle, 210.0 * kDeg);
  EXPECT_DOUBLE_EQ(scene.rollers[2].angle, 330.0 * kDeg);
  EXPECT_DOUBLE_EQ(scene.rollers[1].outline.radius(), 0.005);
  EXPECT_DOUBLE_EQ(scene.contact.full_damping_penetration, 1e-6);
  EXPECT_DOUBLE_EQ(scene.friction.stiction_velocity, 0.010);
  EXPECT_DOUBLE_EQ(scene.friction.transition_velocity, 0.050);
  EXPECT_DOUBLE_EQ(scene.sensor_angle, 0.0);
}

TEST(SceneFile, DerivesRollerDefaultsFromItsRadiusAndAngle) {
  const engine::Scene scene = ParseScene(PaperSceneText(), "scene.toml");
  const engine::Roller& spring = scene.rollers[0];
  EXPECT_DOUBLE_EQ(spring.centre_radius, 0.302 - 0.005);
  EXPECT_DOUBLE_EQ(spring.spring.axis_angle, spring.angle);
  EXPECT_DOUBLE_EQ(spring.spring.travel_limit, 0.005);
  EXPECT_EQ(spring.phase_reference, engine::ShapePhaseReference::kRadial);
  const double cylinder_mass = 7850.0 * std::numbers::pi * 0.005 * 0.005 * 0.004;
  EXPECT_NEAR(spring.mass, cylinder_mass, kRoundingRelative * cylinder_mass);
  const double cylinder_inertia = cylinder_mass * 0.005 * 0.005 / 2.0;
  EXPECT_NEAR(spring.spin_inertia, cylinder_inertia, kRoundingRelative * cylinder_inertia);
}

TEST(SceneFile, UsesMassAndSpinInertiaWhenGivenInsteadOfDensity) {
  const engine::Scene scene = ParseScene(
      PaperSceneWith("density_kg_per_m3 = 2700.0", "mass_kg = 2.0\nspin_inertia_kg_m2 = 0.2"), "scene.toml");
  EXPECT_DOUBLE_EQ(scene.ring.mass, 2.0);
  EXPECT_DOUBLE_EQ(scene.ring.spin_inertia, 0.2);
}

TEST(SceneFile, AcceptsIntegersWhereNumbersAreExpected) {
  const engine::Scene scene = ParseScene(PaperSceneWith("inner_radius_mm = 302.0", "inner_radius_mm = 302"), "s.toml");
  EXPECT_DOUBLE_EQ(scene.ring.inner.radius(), 0.302);
}

TEST(SceneFile, FillsDefaultsForEverythingOptional) {
  const engine::Scene scene = ParseScene(kMinimalScene, "minimal.toml");
  const engine::Scene defaults;
  ASSERT_EQ(scene.rollers.size(), 3u);
  EXPECT_EQ(scene.rollers[0].name, "roller1");
  EXPECT_EQ(scene.rollers[2].name, "roller3");
  EXPECT_DOUBLE_EQ(scene.rollers[1].centre_radius, 0.095);
  EXPECT_DOUBLE_EQ(scene.rollers[1].spin_inertia, 0.002 * 0.005 * 0.005 / 2.0);
  EXPECT_EQ(scene.contact.model, engine::ContactLaw::Model::kPenalty);
  EXPECT_DOUBLE_EQ(scene.contact.stiffness, 1e7);
  EXPECT_DOUBLE_EQ(scene.contact.exponent, 1.5);
  EXPECT_DOUBLE_EQ(scene.contact.max_damping, 1e5);
  EXPECT_DOUBLE_EQ(scene.contact.full_damping_penetration, 1e-6);
  EXPECT_DOUBLE_EQ(scene.friction.static_coefficient, 0.61);
  EXPECT_DOUBLE_EQ(scene.friction.dynamic_coefficient, 0.47);
  EXPECT_DOUBLE_EQ(scene.friction.stiction_velocity, defaults.friction.stiction_velocity);
  EXPECT_DOUBLE_EQ(scene.friction.transition_velocity, defaults.friction.transition_velocity);
  EXPECT_TRUE(scene.roller_positions.is_circle());
  EXPECT_DOUBLE_EQ(scene.sensor_angle, 0.0);
}

TEST(SceneFile, ReadsRollerErrorsAndOptionalSettings) {
  const std::string roller =
      "name = \"fixed_a\"\nangle_deg = 210.0\nradius_mm = 5.0\nmount = \"fixed\"\nwidth_mm = 4.0\n"
      "mass_kg = 0.003\nspin_inertia_kg_m2 = 4e-8\ncentre_radius_mm = 296.5\nradial_offset_mm = 0.01\n"
      "tangential_offset_mm = -0.02\nshape_phase_reference = \"global\"\nspin_phase_deg = 90\n"
      "mean_deviation_mm = -0.001\nharmonics = [{ order = 15, amplitude_mm = 0.014 }]\n";
  std::string text = PaperSceneWith(kFixedA, roller);
  text = ReplaceOnce(text, "[roller_positions]\nmean_deviation_mm = 0.0\nharmonics = []",
                     "[roller_positions]\nmean_deviation_mm = 0.02\nharmonics = [{ order = 7, amplitude_mm = 0.14 }]");
  text = ReplaceOnce(text, "angle_deg = 0.0 ", "angle_deg = 180 ");
  const engine::Scene scene = ParseScene(text, "scene.toml");
  const engine::Roller& r = scene.rollers[1];
  EXPECT_DOUBLE_EQ(r.mass, 0.003);
  EXPECT_DOUBLE_EQ(r.spin_inertia, 4e-8);
  EXPECT_DOUBLE_EQ(r.centre_radius, 0.2965);
  EXPECT_DOUBLE_EQ(r.radial_offset, 1e-5);
  EXPECT_DOUBLE_EQ(r.tangential_offset, -2e-5);
  EXPECT_EQ(r.phase_reference, engine::ShapePhaseReference::kGlobal);
  EXPECT_DOUBLE_EQ(r.spin_phase, std::numbers::pi / 2.0);
  EXPECT_DOUBLE_EQ(r.outline.mean_deviation(), -1e-6);
  ASSERT_EQ(r.outline.harmonics().size(), 1u);
  EXPECT_DOUBLE_EQ(r.outline.harmonics()[0].amplitude, 1.4e-5);
  EXPECT_DOUBLE_EQ(r.outline.harmonics()[0].phase, 0.0);
  EXPECT_DOUBLE_EQ(scene.roller_positions.mean_deviation(), 2e-5);
  ASSERT_EQ(scene.roller_positions.harmonics().size(), 1u);
  EXPECT_EQ(scene.roller_positions.harmonics()[0].order, 7);
  EXPECT_DOUBLE_EQ(scene.sensor_angle, std::numbers::pi);
}

TEST(SceneFile, ReadsTheExampleFileFromDisk) {
  const engine::Scene scene = ReadScene(kPaperScenePath);
  EXPECT_EQ(scene.rollers.size(), 3u);
  EXPECT_DOUBLE_EQ(scene.ring.inner.radius(), 0.302);
}

TEST(SceneFile, LeavesNonConvexProfilesToTheSolvers) {
  // (n^2 - 1) C_n = 399 * 1 mm > R: an inward bump, which is a solver status, not bad input.
  const engine::Scene scene =
      ParseScene(PaperSceneWith(kRingHarmonics, "harmonics = [{ order = 20, amplitude_mm = 1.0 }] #"), "s.toml");
  EXPECT_EQ(engine::CheckGeometry(scene).issue, engine::GeometryIssue::kRingNotConvex);
}

// ---- bad input: file level

TEST(SceneFile, RejectsAMissingFileNamingIt) {
  try {
    ReadScene("/nonexistent/folder/scene.toml");
    FAIL() << "ReadScene accepted a missing file";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), AllOf(HasSubstr("/nonexistent/folder/scene.toml"), HasSubstr("no such file")));
  }
}

TEST(SceneFile, RejectsTextThatIsNotTomlWithThePosition) {
  EXPECT_THAT(ErrorFor("[ring]\ninner_radius_mm = = 3\n"),
              AllOf(HasSubstr("bad.toml:2:"), HasSubstr("not valid TOML")));
}

TEST(SceneFile, ReportsTheLineAndColumnOfTheBadValue) {
  const std::string text = FixedAWith("radius_mm = 5.0", "radius_mm = -5.0");
  const std::size_t at = text.find("radius_mm = -5.0");
  const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n');
  const std::size_t column = std::string_view("radius_mm = ").size() + 1;
  EXPECT_THAT(ErrorFor(text), HasSubstr("bad.toml:" + std::to_string(line) + ":" + std::to_string(column) + ": "));
}

// ---- bad input: keys

TEST(SceneFile, RejectsAMissingRequiredKey) {
  EXPECT_THAT(ErrorFor(PaperSceneWith("thickness_mm = 6.0\n", "")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("ring.thickness_mm"), HasSubstr("missing required key"),
                    HasSubstr("allowed: > 0")));
}

TEST(SceneFile, RejectsAMissingRingTable) {
  EXPECT_THAT(ErrorFor(ReplaceOnce(kMinimalScene, "[ring]", "[wheel]")),
              AllOf(HasSubstr("bad.toml"), HasSubstr("unknown key 'wheel'")));
  const std::string without_ring = std::string(kMinimalScene).substr(std::string(kMinimalScene).find("[[rollers]]"));
  EXPECT_THAT(ErrorFor(without_ring),
              AllOf(HasSubstr("bad.toml: ring: missing required key"), HasSubstr("allowed: a table [ring]")));
}

TEST(SceneFile, RejectsAnUnknownTopLevelKey) {
  EXPECT_THAT(ErrorFor("colour = \"red\"\n" + PaperSceneText()),
              AllOf(HasSubstr("bad.toml:1:1: unknown key 'colour'"),
                    HasSubstr("valid keys here: ring, roller_positions, rollers, contact, friction, sensor")));
}

TEST(SceneFile, RejectsAnUnknownKeyInTheRing) {
  EXPECT_THAT(ErrorFor(PaperSceneWith("thickness_mm = 6.0\n", "thickness_mm = 6.0\ncolour = \"red\"\n")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("unknown key 'ring.colour'"),
                    HasSubstr("valid keys here: inner_radius_mm, outer_radius_mm, thickness_mm")));
}

TEST(SceneFile, RejectsAnUnknownKeyInARoller) {
  EXPECT_THAT(ErrorFor(PaperSceneWith("name = \"fixed_a\"\n", "name = \"fixed_a\"\ndiameter_mm = 10.0\n")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("unknown key 'rollers[1].diameter_mm'"),
                    HasSubstr("name, angle_deg, radius_mm")));
}

TEST(SceneFile, RejectsAnUnknownKeyInAHarmonic) {
  const std::string text =
      PaperSceneWith(kRingHarmonics, "harmonics = [{ order = 3, amplitude_mm = 0.14, phase = 45.0 }] #");
  EXPECT_THAT(ErrorFor(text),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("unknown key 'ring.harmonics[0].phase'"),
                    HasSubstr("valid keys here: order, amplitude_mm, phase_deg")));
}

TEST(SceneFile, RejectsSpringKeysOnAFixedRoller) {
  EXPECT_THAT(ErrorFor(PaperSceneWith("name = \"fixed_a\"\n", "name = \"fixed_a\"\nspring_preload_N = 19.3\n")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("rollers[1].spring_preload_N = 19.3"),
                    HasSubstr("allowed: only when mount = \"spring\"")));
}

TEST(SceneFile, RejectsASpringRollerWithoutPreload) {
  EXPECT_THAT(ErrorFor(PaperSceneWith("spring_preload_N = 19.3\n", "")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("rollers[0].spring_preload_N"),
                    HasSubstr("missing required key (needed when mount = \"spring\")"), HasSubstr("allowed: > 0")));
}

TEST(SceneFile, RejectsBothDensityAndMass) {
  EXPECT_THAT(ErrorFor(PaperSceneWith("thickness_mm = 6.0\n", "thickness_mm = 6.0\nmass_kg = 1.2\n")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("ring.mass_kg = 1.2"),
                    HasSubstr("allowed: exactly one of density_kg_per_m3 > 0 or mass_kg > 0")));
}

TEST(SceneFile, RejectsNeitherDensityNorMass) {
  EXPECT_THAT(ErrorFor(FixedAWith("density_kg_per_m3 = 7850.0\n", "")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("rollers[1].density_kg_per_m3 or mass_kg"),
                    HasSubstr("missing required key"), HasSubstr("exactly one of")));
}

// ---- bad input: types and values

TEST(SceneFile, RejectsAStringWhereANumberIsExpected) {
  EXPECT_THAT(ErrorFor(FixedAWith("radius_mm = 5.0", "radius_mm = \"5\"")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("rollers[1].radius_mm = \"5\""),
                    HasSubstr("wrong type: expected a number, found string"), HasSubstr("allowed: > 0")));
}

TEST(SceneFile, RejectsAFractionalHarmonicOrder) {
  EXPECT_THAT(ErrorFor(PaperSceneWith(kRingHarmonics, "harmonics = [{ order = 2.5, amplitude_mm = 0.14 }] #")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("ring.harmonics[0].order = 2.5"),
                    HasSubstr("expected an integer, found float"), HasSubstr(">= 1 and <= 1000")));
}

TEST(SceneFile, RejectsHarmonicOrderZero) {
  EXPECT_THAT(ErrorFor(PaperSceneWith(kRingHarmonics, "harmonics = [{ order = 0, amplitude_mm = 0.14 }] #")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("ring.harmonics[0].order = 0"), HasSubstr("out of range"),
                    HasSubstr("allowed: an integer >= 1 and <= 1000")));
}

TEST(SceneFile, RejectsANegativeRollerRadius) {
  EXPECT_THAT(ErrorFor(FixedAWith("radius_mm = 5.0", "radius_mm = -5.0")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("rollers[1].radius_mm = -5"), HasSubstr("out of range"),
                    HasSubstr("allowed: > 0")));
}

TEST(SceneFile, RejectsAZeroRollerRadius) {
  EXPECT_THAT(ErrorFor(FixedAWith("radius_mm = 5.0", "radius_mm = 0")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("rollers[1].radius_mm = 0"), HasSubstr("allowed: > 0")));
}

TEST(SceneFile, RejectsANanValue) {
  EXPECT_THAT(ErrorFor(PaperSceneWith("thickness_mm = 6.0", "thickness_mm = nan")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("ring.thickness_mm = nan"), HasSubstr("not a finite number"),
                    HasSubstr("allowed: > 0")));
}

TEST(SceneFile, RejectsAnInfiniteValue) {
  EXPECT_THAT(ErrorFor(PaperSceneWith("angle_deg = 90.0", "angle_deg = inf")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("rollers[0].angle_deg = inf"), HasSubstr("not a finite number"),
                    HasSubstr("allowed: any finite number")));
}

TEST(SceneFile, RejectsAnOuterRadiusNotAboveTheInnerRadius) {
  EXPECT_THAT(ErrorFor(PaperSceneWith("outer_radius_mm = 339.85", "outer_radius_mm = 300")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("ring.outer_radius_mm = 300"),
                    HasSubstr("allowed: > 302 (ring.inner_radius_mm)")));
}

TEST(SceneFile, RejectsAnExponentAboveThree) {
  EXPECT_THAT(ErrorFor(PaperSceneWith("exponent = 1.5", "exponent = 3.5")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("contact.exponent = 3.5"), HasSubstr("allowed: >= 1 and <= 3")));
}

TEST(SceneFile, RejectsARollerLargerThanTheRing) {
  EXPECT_THAT(ErrorFor(FixedAWith("radius_mm = 5.0", "radius_mm = 400")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("rollers[1].radius_mm = 400"),
                    HasSubstr("not smaller than the ring's inner radius"), HasSubstr("allowed: > 0 and < 302")));
}

TEST(SceneFile, RejectsARollerCentreOutsideTheRing) {
  EXPECT_THAT(ErrorFor(PaperSceneWith("name = \"fixed_a\"\n", "name = \"fixed_a\"\ncentre_radius_mm = 400.0\n")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("rollers[1].centre_radius_mm = 400"),
                    HasSubstr("fixed_a does not fit in the ring"),
                    HasSubstr("centre_radius_mm + radial position error <= ring.inner_radius_mm = 302")));
}

TEST(SceneFile, RejectsRingAmplitudesLargerThanTheRadius) {
  EXPECT_THAT(ErrorFor(PaperSceneWith(kRingHarmonics,
                                      "harmonics = [{ order = 2, amplitude_mm = 200 }, { order = 3, "
                                      "amplitude_mm = 150 }] #")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("ring.harmonics"), HasSubstr("amplitude_mm = 350"),
                    HasSubstr("amplitudes larger than the radius"),
                    HasSubstr("allowed: < 302 (ring.inner_radius_mm)")));
}

TEST(SceneFile, RejectsRollerAmplitudesLargerThanTheRadius) {
  EXPECT_THAT(ErrorFor(FixedAWith("harmonics = []",
                                  "mean_deviation_mm = 1.0\nharmonics = [{ order = 2, amplitude_mm = 4.5 }]")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("rollers[1].harmonics"), HasSubstr("amplitude_mm = 5.5"),
                    HasSubstr("amplitudes larger than the radius"), HasSubstr("allowed: < 5 (rollers[1].radius_mm)")));
}

TEST(SceneFile, RejectsFewerThanThreeRollers) {
  const std::string text = PaperSceneText();
  const std::size_t third = text.rfind("[[rollers]]");
  const std::size_t contact = text.find("[contact]");
  const std::string two_rollers = text.substr(0, third) + text.substr(contact);
  EXPECT_THAT(ErrorFor(two_rollers), AllOf(HasSubstr("bad.toml:"), HasSubstr("rollers (2 entries): too few"),
                                           HasSubstr("allowed: at least 3 [[rollers]] tables")));
}

TEST(SceneFile, RejectsAnUnknownMount) {
  EXPECT_THAT(ErrorFor(PaperSceneWith("mount = \"spring\"", "mount = \"sliding\"")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("rollers[0].mount = \"sliding\""), HasSubstr("unknown value"),
                    HasSubstr("allowed: \"fixed\", \"spring\"")));
}

TEST(SceneFile, RejectsAnUnknownContactLaw) {
  EXPECT_THAT(ErrorFor(PaperSceneWith("law = \"penalty\"", "law = \"hertz\"")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("contact.law = \"hertz\""),
                    HasSubstr("allowed: \"rigid\", \"penalty\"")));
}

TEST(SceneFile, RejectsAnUnknownShapePhaseReference) {
  EXPECT_THAT(ErrorFor(PaperSceneWith("shape_phase_reference = \"radial\"", "shape_phase_reference = \"body\"")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("rollers[0].shape_phase_reference = \"body\""),
                    HasSubstr("allowed: \"radial\", \"global\"")));
}

TEST(SceneFile, RejectsDuplicatedRollerNames) {
  EXPECT_THAT(ErrorFor(PaperSceneWith("name = \"fixed_b\"", "name = \"fixed_a\"")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("rollers[2].name = \"fixed_a\""),
                    HasSubstr("the same name as rollers[1]"), HasSubstr("allowed: a name no other roller has")));
}

TEST(SceneFile, RejectsADefaultNameTakenByAnotherRoller) {
  EXPECT_THAT(ErrorFor(ReplaceOnce(kMinimalScene, "angle_deg = 90", "name = \"roller2\"\nangle_deg = 90")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("rollers[1].name = \"roller2\""),
                    HasSubstr("the same name as rollers[0]")));
}

TEST(SceneFile, RejectsATransitionVelocityBelowTheStictionVelocity) {
  EXPECT_THAT(ErrorFor(PaperSceneWith("transition_velocity_mm_per_s = 50.0", "transition_velocity_mm_per_s = 5.0")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("friction.transition_velocity_mm_per_s = 5"),
                    HasSubstr("not above the stiction velocity"),
                    HasSubstr("allowed: > stiction_velocity_mm_per_s = 10")));
}

TEST(SceneFile, RejectsAStictionVelocityAboveTheDefaultTransitionVelocity) {
  EXPECT_THAT(ErrorFor(std::string(kMinimalScene) + "\n[friction]\nstiction_velocity_mm_per_s = 60\n"),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("friction.transition_velocity_mm_per_s = 50 (default)"),
                    HasSubstr("allowed: > stiction_velocity_mm_per_s = 60")));
}

TEST(SceneFile, RejectsATableWhereANumberIsExpected) {
  EXPECT_THAT(ErrorFor(PaperSceneWith("angle_deg = 0.0 ", "angle_deg = { value = 0 } ")),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("sensor.angle_deg = { value = 0 }"),
                    HasSubstr("expected a number, found table")));
}

// ---- [motion] and [dynamics]

engine::Scene SceneWith(const std::string& tables) { return ParseScene(std::string(kMinimalScene) + "\n" + tables, "bad.toml"); }

TEST(SceneFile, DefaultsToTheArticleLawWithEveryStateModelled) {
  const engine::Scene scene = ParseScene(PaperSceneText(), "scene.toml");
  EXPECT_EQ(scene.motion, engine::ArticleLaw());
  EXPECT_EQ(scene.dynamics, engine::DynamicModel{});
}

TEST(SceneFile, ReadsEachKindOfMotionLaw) {
  EXPECT_EQ(SceneWith("[motion]\nsettle_s = 2\nrate_deg_per_s = -90\nrevolutions = 1.5\n").motion,
            engine::ArticleLaw(2.0, -90.0 * kDeg, 1.5));
  EXPECT_EQ(SceneWith("[motion]\nlaw = \"test_bench\"\nsettle_s = 0\n").motion, engine::TestBenchLaw(0.0));
  const engine::MotionLaw piecewise = SceneWith(
      "[motion]\nlaw = \"piecewise\"\nsegments = [{ duration_s = 0.5 }, { duration_s = 1, acceleration_deg_per_s2 = "
      "90 }, { duration_s = 2, start_rate_deg_per_s = -30 }]\n").motion;
  EXPECT_EQ(piecewise, engine::MotionLaw({{.duration = 0.5, .acceleration = 0.0, .start_rate = std::nullopt},
                                          {.duration = 1.0, .acceleration = 90.0 * kDeg, .start_rate = std::nullopt},
                                          {.duration = 2.0, .acceleration = 0.0, .start_rate = -30.0 * kDeg}}));
}

TEST(SceneFile, ReadsTheDynamicModelSwitches) {
  const engine::Scene scene =
      SceneWith("[dynamics]\nfriction = false\nrolling_without_slip = true\nmassless_spring_rollers = true\n");
  EXPECT_FALSE(scene.dynamics.friction);
  EXPECT_TRUE(scene.dynamics.rolling_without_slip);
  EXPECT_TRUE(scene.dynamics.massless_spring_rollers);
}

TEST(SceneFile, RejectsKeysThatDoNotBelongToTheChosenLaw) {
  try {
    SceneWith("[motion]\nlaw = \"test_bench\"\nrate_deg_per_s = 100\n");
    FAIL() << "accepted a rate for the test-bench law";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), AllOf(HasSubstr("bad.toml:"), HasSubstr("motion.rate_deg_per_s = 100"),
                                HasSubstr("only when law = \"article\"")));
  }
  try {
    SceneWith("[motion]\nsegments = [{ duration_s = 1 }]\n");
    FAIL() << "accepted segments for the article law";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), AllOf(HasSubstr("motion.segments"), HasSubstr("only when law = \"piecewise\"")));
  }
}

TEST(SceneFile, RejectsBadMotionValuesNamingKeyAndRange) {
  auto error = [](const std::string& tables) {
    try {
      SceneWith(tables);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_THAT(error("[motion]\nlaw = \"spline\"\n"),
              AllOf(HasSubstr("motion.law = \"spline\""), HasSubstr("\"article\", \"test_bench\", \"piecewise\"")));
  EXPECT_THAT(error("[motion]\nrate_deg_per_s = 0\n"), AllOf(HasSubstr("motion.rate_deg_per_s = 0"), HasSubstr("non-zero")));
  EXPECT_THAT(error("[motion]\nsettle_s = -1\n"), AllOf(HasSubstr("motion.settle_s = -1"), HasSubstr(">= 0")));
  EXPECT_THAT(error("[motion]\nrevolutions = 0\n"), AllOf(HasSubstr("motion.revolutions = 0"), HasSubstr("> 0")));
  EXPECT_THAT(error("[motion]\nlaw = \"piecewise\"\n"), AllOf(HasSubstr("motion.segments"), HasSubstr("missing")));
  EXPECT_THAT(error("[motion]\nlaw = \"piecewise\"\nsegments = []\n"), HasSubstr("motion.segments"));
  EXPECT_THAT(error("[motion]\nlaw = \"piecewise\"\nsegments = [{ duration_s = 0 }]\n"),
              AllOf(HasSubstr("motion.segments[0].duration_s = 0"), HasSubstr("> 0")));
  EXPECT_THAT(error("[motion]\nlaw = \"piecewise\"\nsegments = [{ duration_s = 1, jerk = 2 }]\n"),
              HasSubstr("unknown key 'motion.segments[0].jerk'"));
  EXPECT_THAT(error("[dynamics]\nfriction = \"yes\"\n"),
              AllOf(HasSubstr("dynamics.friction = \"yes\""), HasSubstr("true or false")));
  EXPECT_THAT(error("[dynamics]\ninertia = false\n"), HasSubstr("unknown key 'dynamics.inertia'"));
  // Values in range whose law still overflows a double: refused as input, not thrown
  // from the engine or passed on as infinities.
  EXPECT_THAT(error("[motion]\nrate_deg_per_s = 1e-320\n"), AllOf(HasSubstr("bad.toml:"), HasSubstr("motion")));
  EXPECT_THAT(error("[motion]\nlaw = \"piecewise\"\nsegments = [{ duration_s = 1e300, acceleration_deg_per_s2 = 1e300 }]\n"),
              AllOf(HasSubstr("bad.toml:"), HasSubstr("overflows")));
}

}  // namespace
}  // namespace ringtol::jobs
