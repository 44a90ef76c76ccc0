#include "jobs/inputs/scene_file.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <optional>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "jobs/inputs/input_error.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

using ringtol::testing::ReadText;
using ringtol::testing::ReplaceOnce;
using ringtol::testing::WriteText;

using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr double kDeg = std::numbers::pi / 180.0;
// Masses and inertias are a few products and a difference of squares: ~10 ulp of
// relative rounding whatever the order of operations, far below this.
constexpr double kRoundingRelative = 1e-12;
// docs/model.md quotes the paper ring's mass as "about 1.24 kg"; 1.236 kg is given to 4 digits.
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
  return ringtol::testing::MessageOf<InputError>([&] { ParseScene(text, "bad.toml"); });
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

std::string MinimalSceneWith(const std::string& tables) { return std::string(kMinimalScene) + "\n" + tables; }

// The paper scene's stated law, which a scene of one's own leaves out.
constexpr std::string_view kPaperLaw =
    "stiffness_N_per_m_e = 1.0e7       # k in F = k delta^e, units N/m^e\nexponent = 1.5\n";

// k [N/m^(10/9)] of Palmgren's steel-on-steel fit delta = 3.84e-5 Q^0.9 / l^0.8 (mm, N),
// written through the contact modulus (docs/model.md §4): for bodies of E* [Pa] touching
// over `length` [m].
double PalmgrenStiffness(double contact_modulus, double length) {
  const double steel_mpa = 207e3 / (2.0 * (1.0 - 0.3 * 0.3));  // E* of Palmgren's steel [N/mm^2]
  const double c = 3.84e-5 * std::pow(steel_mpa, 0.9);
  return contact_modulus * std::pow(length, 8.0 / 9.0) / std::pow(c, 10.0 / 9.0);
}

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
  // Steel on steel over the rollers' 4 mm (the ring is 5 mm thick): the law of the materials.
  EXPECT_EQ(scene.ring.material, engine::Material({210e9, 0.3}));
  EXPECT_EQ(scene.rollers[2].material, engine::Material({210e9, 0.3}));
  const double steel = 210e9 / (2.0 * (1.0 - 0.3 * 0.3));
  EXPECT_NEAR(scene.contact.stiffness, PalmgrenStiffness(steel, 0.004), kRoundingRelative * scene.contact.stiffness);
  EXPECT_DOUBLE_EQ(scene.contact.exponent, 10.0 / 9.0);
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

TEST(SceneFile, KeepsTheLawAFileStates) {
  const engine::Scene scene = ParseScene(PaperSceneText(), "scene.toml");
  EXPECT_EQ(scene.ring.material, engine::Material({70e9, 0.33}));
  EXPECT_DOUBLE_EQ(scene.contact.stiffness, 1e7);
  EXPECT_DOUBLE_EQ(scene.contact.exponent, 1.5);
}

TEST(SceneFile, DerivesTheLawOfTheMaterialsWhenTheFileStatesNone) {
  // The paper's aluminium ring on steel rollers, touching over the rollers' 4 mm.
  const engine::Scene scene = ParseScene(PaperSceneWith(kPaperLaw, ""), "scene.toml");
  const double aluminium_on_steel = 1.0 / ((1.0 - 0.33 * 0.33) / 70e9 + (1.0 - 0.3 * 0.3) / 210e9);
  const double expected = PalmgrenStiffness(aluminium_on_steel, 0.004);
  EXPECT_NEAR(scene.contact.stiffness, expected, kRoundingRelative * expected);
  EXPECT_DOUBLE_EQ(scene.contact.exponent, 10.0 / 9.0);
  EXPECT_DOUBLE_EQ(scene.contact.max_damping, 1e5);

  // A roller of another material or narrower than the others: the softest contact sets the law.
  const engine::Scene softer = ParseScene(
      ReplaceOnce(PaperSceneWith(kPaperLaw, ""), kFixedA,
                  ReplaceOnce(std::string(kFixedA), "width_mm = 4.0\n", "width_mm = 2.0\nyoungs_modulus_GPa = 70\n")),
      "scene.toml");
  EXPECT_EQ(softer.rollers[1].material, engine::Material({70e9, 0.3}));
  const double aluminium_on_aluminium = 1.0 / ((1.0 - 0.33 * 0.33) / 70e9 + (1.0 - 0.3 * 0.3) / 70e9);
  const double softest = PalmgrenStiffness(aluminium_on_aluminium, 0.002);
  EXPECT_NEAR(softer.contact.stiffness, softest, kRoundingRelative * softest);
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

// ---- [motion] and [dynamics]

engine::Scene SceneWith(const std::string& tables) { return ParseScene(MinimalSceneWith(tables), "bad.toml"); }

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

// ---- [life]

TEST(SceneFile, ReadsWhetherTheRollersArePhaseLocked) {
  EXPECT_FALSE(ParseScene(PaperSceneText(), "scene.toml").phase_locked_rollers);
  EXPECT_FALSE(SceneWith("[life]\n").phase_locked_rollers);
  EXPECT_TRUE(SceneWith("[life]\nphase_locked_rollers = true\n").phase_locked_rollers);
}

// ---- bad input: one key or value
//
// Each case is a scene with one thing wrong, and the pieces its InputError must contain:
// the file, the key with its value, what is wrong and what is allowed. One table, so that a
// new check of the reader is one row, and a case that stops naming a piece fails by name.

std::string PaperSceneWithTwoRollers() {
  const std::string text = PaperSceneText();
  const std::size_t third = text.rfind("[[rollers]]");
  const std::size_t contact = text.find("[contact]");
  return text.substr(0, third) + text.substr(contact);
}

struct BadScene {
  std::string name;                   // the case's name in the test's name
  std::function<std::string()> text;  // built when the case runs, as the paper scene is read from disk
  std::vector<std::string> message_pieces;
};

void PrintTo(const BadScene& scene, std::ostream* out) { *out << scene.name; }

const std::vector<BadScene> kBadScenes = {
    // keys
    {"AMissingRequiredKey", [] { return PaperSceneWith("thickness_mm = 6.0\n", ""); },
     {"bad.toml:", "ring.thickness_mm", "missing required key", "allowed: > 0"}},
    {"ARenamedRingTable", [] { return ReplaceOnce(kMinimalScene, "[ring]", "[wheel]"); },
     {"bad.toml", "unknown key 'wheel'"}},
    {"AMissingRingTable",
     [] { return std::string(kMinimalScene).substr(std::string(kMinimalScene).find("[[rollers]]")); },
     {"bad.toml: ring: missing required key", "allowed: a table [ring]"}},
    {"AnUnknownTopLevelKey", [] { return "colour = \"red\"\n" + PaperSceneText(); },
     {"bad.toml:1:1: unknown key 'colour'",
      "valid keys here: ring, roller_positions, rollers, contact, friction, sensor"}},
    {"AnUnknownKeyInTheRing",
     [] { return PaperSceneWith("thickness_mm = 6.0\n", "thickness_mm = 6.0\ncolour = \"red\"\n"); },
     {"bad.toml:", "unknown key 'ring.colour'", "valid keys here: inner_radius_mm, outer_radius_mm, thickness_mm"}},
    {"AnUnknownKeyInARoller",
     [] { return PaperSceneWith("name = \"fixed_a\"\n", "name = \"fixed_a\"\ndiameter_mm = 10.0\n"); },
     {"bad.toml:", "unknown key 'rollers[1].diameter_mm'", "name, angle_deg, radius_mm"}},
    {"AnUnknownKeyInAHarmonic",
     [] { return PaperSceneWith(kRingHarmonics, "harmonics = [{ order = 3, amplitude_mm = 0.14, phase = 45.0 }] #"); },
     {"bad.toml:", "unknown key 'ring.harmonics[0].phase'", "valid keys here: order, amplitude_mm, phase_deg"}},
    {"SpringKeysOnAFixedRoller",
     [] { return PaperSceneWith("name = \"fixed_a\"\n", "name = \"fixed_a\"\nspring_preload_N = 19.3\n"); },
     {"bad.toml:", "rollers[1].spring_preload_N = 19.3", "allowed: only when mount = \"spring\""}},
    {"ASpringRollerWithoutPreload", [] { return PaperSceneWith("spring_preload_N = 19.3\n", ""); },
     {"bad.toml:", "rollers[0].spring_preload_N", "missing required key (needed when mount = \"spring\")",
      "allowed: > 0"}},
    {"BothDensityAndMass",
     [] { return PaperSceneWith("thickness_mm = 6.0\n", "thickness_mm = 6.0\nmass_kg = 1.2\n"); },
     {"bad.toml:", "ring.mass_kg = 1.2", "allowed: exactly one of density_kg_per_m3 and mass_kg"}},
    {"NeitherDensityNorMass", [] { return FixedAWith("density_kg_per_m3 = 7850.0\n", ""); },
     {"bad.toml:", "rollers[1].density_kg_per_m3 or mass_kg", "missing required key", "exactly one of"}},

    // masses beyond what ringtol models: given, or implied by the dimensions
    {"AnOuterRadiusThatImpliesNoFiniteMass",
     [] { return PaperSceneWith("outer_radius_mm = 339.85", "outer_radius_mm = 1e308"); },
     {"bad.toml:", "ring.density_kg_per_m3 = 2700, outer_radius_mm = 1e+308, inner_radius_mm = 302, thickness_mm = 6",
      "imply a mass of inf kg", "allowed: a mass >= 1e-07 and <= 100000 kg"}},
    {"AnOuterRadiusThatImpliesNoFiniteSpinInertia",
     [] {
       return ReplaceOnce(PaperSceneWith("outer_radius_mm = 339.85", "outer_radius_mm = 1e150"),
                          "density_kg_per_m3 = 2700.0", "mass_kg = 1.2");
     },
     {"bad.toml:", "ring.mass_kg = 1.2, outer_radius_mm = 1e+150, inner_radius_mm = 302",
      "imply a spin inertia of 6e+293 kg m^2", "allowed: a spin inertia >= 1e-15 and <= 10000000 kg m^2"}},
    {"ADensityInGramsPerCubicCentimetre",
     [] { return PaperSceneWith("density_kg_per_m3 = 2700.0", "density_kg_per_m3 = 2.7"); },
     {"bad.toml:", "ring.density_kg_per_m3 = 2.7", "out of range", "allowed: >= 100 and <= 30000"}},
    {"ARollerWidthThatImpliesNoFiniteMass", [] { return FixedAWith("width_mm = 4.0", "width_mm = 1e300"); },
     {"bad.toml:", "rollers[1].density_kg_per_m3 = 7850, radius_mm = 5, width_mm = 1e+300", "imply a mass of ",
      "allowed: a mass >= 1e-07 and <= 100000 kg"}},
    {"ARollerMassBeyondWhatRingtolModels",
     [] { return FixedAWith("density_kg_per_m3 = 7850.0", "mass_kg = 1e6"); },
     {"bad.toml:", "rollers[1].mass_kg = 1000000", "out of range", "allowed: >= 1e-07 and <= 100000"}},

    // text a reader cannot see, shown escaped
    {"AValueWithANoBreakSpace", [] { return FixedAWith("mount = \"fixed\"", "mount = \"fixed\xC2\xA0\""); },
     {"bad.toml:", "rollers[1].mount = \"fixed\\u00A0\": unknown value", "allowed: \"fixed\", \"spring\""}},
    {"AKeyWithAZeroWidthSpace",
     [] { return FixedAWith("width_mm = 4.0", "\"width_mm\xE2\x80\x8B\" = 4.0"); },
     {"bad.toml:", "unknown key 'rollers[1].width_mm\\u200B'"}},

    // types and values
    {"AStringWhereANumberIsExpected", [] { return FixedAWith("radius_mm = 5.0", "radius_mm = \"5\""); },
     {"bad.toml:", "rollers[1].radius_mm = \"5\"", "wrong type: expected a number, found string", "allowed: > 0"}},
    {"AFractionalHarmonicOrder",
     [] { return PaperSceneWith(kRingHarmonics, "harmonics = [{ order = 2.5, amplitude_mm = 0.14 }] #"); },
     {"bad.toml:", "ring.harmonics[0].order = 2.5", "expected an integer, found float", ">= 1 and <= 1000"}},
    {"HarmonicOrderZero",
     [] { return PaperSceneWith(kRingHarmonics, "harmonics = [{ order = 0, amplitude_mm = 0.14 }] #"); },
     {"bad.toml:", "ring.harmonics[0].order = 0", "out of range", "allowed: an integer >= 1 and <= 1000"}},
    {"ANegativeRollerRadius", [] { return FixedAWith("radius_mm = 5.0", "radius_mm = -5.0"); },
     {"bad.toml:", "rollers[1].radius_mm = -5", "out of range", "allowed: > 0"}},
    {"AZeroRollerRadius", [] { return FixedAWith("radius_mm = 5.0", "radius_mm = 0"); },
     {"bad.toml:", "rollers[1].radius_mm = 0", "allowed: > 0"}},
    {"ANanValue", [] { return PaperSceneWith("thickness_mm = 6.0", "thickness_mm = nan"); },
     {"bad.toml:", "ring.thickness_mm = nan", "not a finite number", "allowed: > 0"}},
    {"AnInfiniteValue", [] { return PaperSceneWith("angle_deg = 90.0", "angle_deg = inf"); },
     {"bad.toml:", "rollers[0].angle_deg = inf", "not a finite number", "allowed: any finite number"}},
    {"AnOuterRadiusNotAboveTheInnerRadius",
     [] { return PaperSceneWith("outer_radius_mm = 339.85", "outer_radius_mm = 300"); },
     {"bad.toml:", "ring.outer_radius_mm = 300", "allowed: > 302 (ring.inner_radius_mm)"}},
    {"AnExponentAboveThree", [] { return PaperSceneWith("exponent = 1.5", "exponent = 3.5"); },
     {"bad.toml:", "contact.exponent = 3.5", "allowed: >= 1 and <= 3"}},
    {"AStiffnessWithoutAnExponent", [] { return PaperSceneWith("exponent = 1.5\n", ""); },
     {"bad.toml:", "contact.stiffness_N_per_m_e = 10000000", "given without contact.exponent",
      "allowed: both stiffness_N_per_m_e and exponent, or neither for the law of the ring's and rollers' materials"}},
    {"AnExponentWithoutAStiffness", [] { return MinimalSceneWith("[contact]\nexponent = 1.5\n"); },
     {"bad.toml:", "contact.exponent = 1.5", "given without contact.stiffness_N_per_m_e", "or neither"}},
    {"AYoungsModulusInMegapascals",
     [] { return PaperSceneWith("youngs_modulus_GPa = 70.0", "youngs_modulus_GPa = 70000"); },
     {"bad.toml:", "ring.youngs_modulus_GPa = 70000", "out of range", "allowed: > 0 and <= 1500"}},
    {"APoissonRatioAboveAHalf", [] { return FixedAWith("width_mm = 4.0\n", "width_mm = 4.0\npoisson_ratio = 0.6\n"); },
     {"bad.toml:", "rollers[1].poisson_ratio = 0.6", "allowed: >= 0 and <= 0.5"}},
    {"ARollerLargerThanTheRing", [] { return FixedAWith("radius_mm = 5.0", "radius_mm = 400"); },
     {"bad.toml:", "rollers[1].radius_mm = 400", "not smaller than the ring's inner radius",
      "allowed: > 0 and < 302"}},
    {"ARollerCentreOutsideTheRing",
     [] { return PaperSceneWith("name = \"fixed_a\"\n", "name = \"fixed_a\"\ncentre_radius_mm = 400.0\n"); },
     {"bad.toml:", "rollers[1].centre_radius_mm = 400", "fixed_a does not fit in the ring",
      "centre_radius_mm + radial position error <= ring.inner_radius_mm = 302"}},
    // 1 degree apart at a centre radius of 297 mm, 5 mm rollers' centres are 5.18 mm apart.
    {"ARollerOneDegreeFromAnother", [] { return FixedAWith("angle_deg = 210.0", "angle_deg = 91.0"); },
     {"bad.toml:", "rollers[1].angle_deg = 91", "rollers spring and fixed_a overlap by 4.81", "mm apart",
      "allowed: every two rollers' centres at least their largest radii's sum apart"}},
    // Three 95 mm rollers in a 100 mm bore stand 5 mm from its centre: each crosses the others.
    {"ThreeRollersAsLargeAsTheBore",
     [] {
       std::string text = kMinimalScene;
       for (std::size_t at = text.find("radius_mm = 5\n"); at != std::string::npos; at = text.find("radius_mm = 5\n")) {
         text.replace(at, std::string_view("radius_mm = 5").size(), "radius_mm = 95");
       }
       return text;
     },
     {"bad.toml:", "rollers[1].angle_deg = 210", "rollers roller1 and roller2 overlap by 181.3"}},
    {"RingAmplitudesLargerThanTheRadius",
     [] {
       return PaperSceneWith(kRingHarmonics,
                             "harmonics = [{ order = 2, amplitude_mm = 200 }, { order = 3, amplitude_mm = 150 }] #");
     },
     {"bad.toml:", "ring.harmonics", "amplitude_mm = 350", "amplitudes larger than the radius",
      "allowed: < 302 (ring.inner_radius_mm)"}},
    {"RollerAmplitudesLargerThanTheRadius",
     [] {
       return FixedAWith("harmonics = []", "mean_deviation_mm = 1.0\nharmonics = [{ order = 2, amplitude_mm = 4.5 }]");
     },
     {"bad.toml:", "rollers[1].harmonics", "amplitude_mm = 5.5", "amplitudes larger than the radius",
      "allowed: < 5 (rollers[1].radius_mm)"}},
    {"FewerThanThreeRollers", PaperSceneWithTwoRollers,
     {"bad.toml:", "rollers (2 entries): too few", "allowed: at least 3 [[rollers]] tables"}},
    {"AnUnknownMount", [] { return PaperSceneWith("mount = \"spring\"", "mount = \"sliding\""); },
     {"bad.toml:", "rollers[0].mount = \"sliding\"", "unknown value", "allowed: \"fixed\", \"spring\""}},
    {"AnUnknownContactLaw", [] { return PaperSceneWith("law = \"penalty\"", "law = \"hertz\""); },
     {"bad.toml:", "contact.law = \"hertz\"", "allowed: \"rigid\", \"penalty\""}},
    {"AnUnknownShapePhaseReference",
     [] { return PaperSceneWith("shape_phase_reference = \"radial\"", "shape_phase_reference = \"body\""); },
     {"bad.toml:", "rollers[0].shape_phase_reference = \"body\"", "allowed: \"radial\", \"global\""}},
    {"DuplicatedRollerNames", [] { return PaperSceneWith("name = \"fixed_b\"", "name = \"fixed_a\""); },
     {"bad.toml:", "rollers[2].name = \"fixed_a\"", "the same name as rollers[1]",
      "allowed: a name no other roller has"}},
    {"ADefaultNameTakenByAnotherRoller",
     [] { return ReplaceOnce(kMinimalScene, "angle_deg = 90", "name = \"roller2\"\nangle_deg = 90"); },
     {"bad.toml:", "rollers[1].name = \"roller2\"", "the same name as rollers[0]"}},
    {"ATransitionVelocityBelowTheStictionVelocity",
     [] { return PaperSceneWith("transition_velocity_mm_per_s = 50.0", "transition_velocity_mm_per_s = 5.0"); },
     {"bad.toml:", "friction.transition_velocity_mm_per_s = 5", "not above the stiction velocity",
      "allowed: > stiction_velocity_mm_per_s = 10"}},
    {"AStictionVelocityAboveTheDefaultTransitionVelocity",
     [] { return MinimalSceneWith("[friction]\nstiction_velocity_mm_per_s = 60\n"); },
     {"bad.toml:", "friction.transition_velocity_mm_per_s = 50 (default)",
      "allowed: > stiction_velocity_mm_per_s = 60"}},
    {"ATableWhereANumberIsExpected", [] { return PaperSceneWith("angle_deg = 0.0 ", "angle_deg = { value = 0 } "); },
     {"bad.toml:", "sensor.angle_deg = { value = 0 }", "expected a number, found table"}},

    {"ANegativeErrorMotionCutoff", [] { return MinimalSceneWith("[sensor]\nerror_motion_cutoff_upr = -1\n"); },
     {"bad.toml:", "sensor.error_motion_cutoff_upr = -1", "allowed: >= 0 and <= 100000"}},

    // [motion] and [dynamics]
    {"ARateForTheTestBenchLaw",
     [] { return MinimalSceneWith("[motion]\nlaw = \"test_bench\"\nrate_deg_per_s = 100\n"); },
     {"bad.toml:", "motion.rate_deg_per_s = 100", "only when law = \"article\""}},
    {"SegmentsForTheArticleLaw", [] { return MinimalSceneWith("[motion]\nsegments = [{ duration_s = 1 }]\n"); },
     {"motion.segments", "only when law = \"piecewise\""}},
    {"AnUnknownMotionLaw", [] { return MinimalSceneWith("[motion]\nlaw = \"spline\"\n"); },
     {"motion.law = \"spline\"", "\"article\", \"test_bench\", \"piecewise\""}},
    {"AZeroRate", [] { return MinimalSceneWith("[motion]\nrate_deg_per_s = 0\n"); },
     {"motion.rate_deg_per_s = 0", "non-zero"}},
    {"ANegativeSettlingTime", [] { return MinimalSceneWith("[motion]\nsettle_s = -1\n"); },
     {"motion.settle_s = -1", ">= 0"}},
    {"ZeroRevolutions", [] { return MinimalSceneWith("[motion]\nrevolutions = 0\n"); },
     {"motion.revolutions = 0", "> 0"}},
    {"APiecewiseLawWithoutSegments", [] { return MinimalSceneWith("[motion]\nlaw = \"piecewise\"\n"); },
     {"motion.segments", "missing"}},
    {"APiecewiseLawWithNoSegment", [] { return MinimalSceneWith("[motion]\nlaw = \"piecewise\"\nsegments = []\n"); },
     {"motion.segments"}},
    {"ASegmentOfZeroDuration",
     [] { return MinimalSceneWith("[motion]\nlaw = \"piecewise\"\nsegments = [{ duration_s = 0 }]\n"); },
     {"motion.segments[0].duration_s = 0", "> 0"}},
    {"AnUnknownKeyInASegment",
     [] { return MinimalSceneWith("[motion]\nlaw = \"piecewise\"\nsegments = [{ duration_s = 1, jerk = 2 }]\n"); },
     {"unknown key 'motion.segments[0].jerk'"}},
    {"AStringForADynamicsSwitch", [] { return MinimalSceneWith("[dynamics]\nfriction = \"yes\"\n"); },
     {"dynamics.friction = \"yes\"", "true or false"}},
    {"AnUnknownDynamicsSwitch", [] { return MinimalSceneWith("[dynamics]\ninertia = false\n"); },
     {"unknown key 'dynamics.inertia'"}},

    // [life]
    {"ANumberForPhaseLockedRollers", [] { return MinimalSceneWith("[life]\nphase_locked_rollers = 1\n"); },
     {"bad.toml:", "life.phase_locked_rollers = 1", "true or false"}},
    {"AnUnknownLifeKey", [] { return MinimalSceneWith("[life]\nphase_locked = true\n"); },
     {"unknown key 'life.phase_locked'"}},
    // Values in range whose law still overflows a double: refused as input, not thrown
    // from the engine or passed on as infinities.
    {"ARateSoSlowTheLawOverflows", [] { return MinimalSceneWith("[motion]\nrate_deg_per_s = 1e-320\n"); },
     {"bad.toml:", "motion"}},
    {"ASegmentWhoseRateOverflows",
     [] {
       return MinimalSceneWith(
           "[motion]\nlaw = \"piecewise\"\nsegments = [{ duration_s = 1e300, acceleration_deg_per_s2 = 1e300 }]\n");
     },
     {"bad.toml:", "overflows"}},
};

class SceneFileRejects : public ::testing::TestWithParam<BadScene> {};

TEST_P(SceneFileRejects, WithAMessageNamingWhatIsWrongAndWhere) {
  std::vector<::testing::Matcher<std::string>> pieces;
  for (const std::string& piece : GetParam().message_pieces) pieces.push_back(HasSubstr(piece));
  EXPECT_THAT(ErrorFor(GetParam().text()), ::testing::AllOfArray(pieces));
}

INSTANTIATE_TEST_SUITE_P(OneBadKey, SceneFileRejects, ::testing::ValuesIn(kBadScenes),
                         [](const ::testing::TestParamInfo<BadScene>& row) { return row.param.name; });

// ---- ring.measured_profile

std::filesystem::path MeasuredFolder() { return ringtol::testing::FreshTestFolder("scene_file_test"); }

constexpr double kBoreRadius = 0.302;  // [m] of the paper scene
// A set-up eccentricity (order 1) and form errors, as a roundness tester sees them.
const std::vector<engine::Harmonic> kMeasuredForm = {
    {1, 4e-6, -0.6}, {2, 30e-6, 0.3}, {3, 12e-6, 2.0}, {5, 6e-6, -2.2}};
constexpr int kMeasuredOrders = 6;  // above every order of kMeasuredForm: 4 and 6 must come out zero
constexpr double kEps = 0x1p-52;    // DBL_EPSILON
// Noise-free readings are rounded twice (17 digits in the file, times the unit on
// reading): <= 2 eps R each. Least squares amplifies that by the condition number (< 10
// for a reading per degree, a 30 degree gap and 6 orders; fit_command_test asserts it for
// 8) and rounds once per unknown: (2 x 6 + 1) x 2 eps x 10 x R.
constexpr double kFitRoundOff = (2 * kMeasuredOrders + 1) * 2.0 * kEps * 10.0 * kBoreRadius;  // [m], 1.7e-14

// A roundness tester's export of `mean + harmonics` [m] in `column`'s unit (metres per
// unit): a reading per degree, none strictly between 100 and 130 degrees.
std::string MeasuredCsv(std::string_view column, double unit, double mean,
                        const std::vector<engine::Harmonic>& harmonics) {
  std::ostringstream text;
  text.precision(17);
  text << "# measured by scene_file_test\nangle_deg, " << column << "\n";
  for (int degree = 0; degree < 360; ++degree) {
    if (degree > 100 && degree < 130) continue;
    double value = mean;
    for (const engine::Harmonic& h : harmonics) value += h.amplitude * std::cos(h.order * degree * kDeg + h.phase);
    text << degree << ", " << value / unit << "\n";
  }
  return text.str();
}

std::string MeasuredRadii(double mean = kBoreRadius) { return MeasuredCsv("radius_mm", 1e-3, mean, kMeasuredForm); }

// a_n and b_n of r = ... + sum_n (a_n cos n theta - b_n sin n theta) for `harmonics` [m], as
// PolarProfile sums harmonics of equal order.
double CosCoefficient(const std::vector<engine::Harmonic>& harmonics, int n) {
  return engine::PolarProfile(1.0, 0.0, harmonics).cos_coefficient(n);
}
double SinCoefficient(const std::vector<engine::Harmonic>& harmonics, int n) {
  return engine::PolarProfile(1.0, 0.0, harmonics).sin_coefficient(n);
}

// The paper scene whose ring has `harmonics_line` and measured_profile = `measured`.
std::string PaperSceneMeasuring(std::string_view measured, std::string_view harmonics_line = "harmonics = []") {
  return PaperSceneWith(kRingHarmonics, std::string(harmonics_line) + "\nmeasured_profile = " + std::string(measured) +
                                            "\n#");
}

// ReadScene's message for the paper scene with measured_profile = `measured`, written as
// scene.toml in `folder`.
std::string MeasuredErrorFor(const std::filesystem::path& folder, std::string_view measured) {
  WriteText(folder / "scene.toml", PaperSceneMeasuring(measured));
  return ringtol::testing::MessageOf<InputError>([&] { ReadScene(folder / "scene.toml"); });
}

TEST(SceneFile, MeasuredProfileGivesTheRingTheFittedHarmonics) {
  const std::filesystem::path folder = MeasuredFolder();
  WriteText(folder / "ring.csv", MeasuredRadii());
  for (const bool keep : {false, true}) {
    SCOPED_TRACE(keep ? "keep_eccentricity = true" : "keep_eccentricity = false");
    WriteText(folder / "scene.toml", PaperSceneMeasuring("{ file = \"ring.csv\", orders = 6, keep_eccentricity = " +
                                                             std::string(keep ? "true" : "false") + " }"));
    const engine::PolarProfile& bore = ReadScene(folder / "scene.toml").ring.inner;
    EXPECT_EQ(bore.radius(), kBoreRadius);
    // The export's mean radius is the nominal radius: no mean deviation.
    EXPECT_NEAR(bore.mean_deviation(), 0.0, kFitRoundOff);
    const int first = keep ? 1 : 2;
    ASSERT_EQ(bore.harmonics().size(), static_cast<std::size_t>(kMeasuredOrders - first + 1));
    EXPECT_EQ(bore.harmonics().front().order, first);
    EXPECT_EQ(bore.harmonics().back().order, kMeasuredOrders);
    for (int n = 1; n <= kMeasuredOrders; ++n) {
      SCOPED_TRACE("order " + std::to_string(n));
      const bool kept = n >= first;
      EXPECT_NEAR(bore.cos_coefficient(n), kept ? CosCoefficient(kMeasuredForm, n) : 0.0, kFitRoundOff);
      EXPECT_NEAR(bore.sin_coefficient(n), kept ? SinCoefficient(kMeasuredForm, n) : 0.0, kFitRoundOff);
    }
  }
}

// rollers[].measured_profile: a roller's export, fitted as the ring's is and held to the
// roller's radius: its form becomes the outline's harmonics, its size (reference "nominal")
// the outline's mean deviation; an export of another roller's size is refused naming the
// roller's radius key.
TEST(SceneFile, ARollersMeasuredProfileGivesItsOutlineTheFittedSizeAndForm) {
  const std::filesystem::path folder = MeasuredFolder();
  constexpr double kRollerRadius = 5e-3;  // [m] fixed_a's
  constexpr double kSize = -2e-6;         // [m] its export's mean radius less 5 mm
  const std::vector<engine::Harmonic> form = {{2, 1.5e-6, 0.3}, {3, 2e-6, -1.0}, {5, 0.8e-6, 1.7}};
  WriteText(folder / "roller.csv", MeasuredCsv("radius_mm", 1e-3, kRollerRadius + kSize, form));
  WriteText(folder / "scene.toml", FixedAWith("harmonics = []\n", "harmonics = []\nmeasured_profile = { file = \"roller.csv\", orders = 6 }\n"));
  const engine::Scene scene = ReadScene(folder / "scene.toml");
  const engine::PolarProfile& outline = scene.rollers[1].outline;
  EXPECT_EQ(outline.radius(), kRollerRadius);
  const double round_off = (2 * 6 + 1) * 2.0 * kEps * 10.0 * kRollerRadius;
  EXPECT_NEAR(outline.mean_deviation(), kSize, round_off);
  for (int n = 1; n <= 6; ++n) {
    SCOPED_TRACE("order " + std::to_string(n));
    EXPECT_NEAR(outline.cos_coefficient(n), CosCoefficient(form, n), round_off);
    EXPECT_NEAR(outline.sin_coefficient(n), SinCoefficient(form, n), round_off);
  }
  WriteText(folder / "other.csv", MeasuredCsv("radius_mm", 1e-3, 5.2e-3, form));
  WriteText(folder / "scene.toml", FixedAWith("harmonics = []\n", "harmonics = []\nmeasured_profile = { file = \"other.csv\", orders = 6 }\n"));
  const std::string error = ringtol::testing::MessageOf<InputError>([&] { ReadScene(folder / "scene.toml"); });
  EXPECT_THAT(error, AllOf(HasSubstr("rollers[1].measured_profile"), HasSubstr("from rollers[1].radius_mm = 5 mm"),
                           HasSubstr("a profile of another roller"), HasSubstr("own_mean")));
}

TEST(SceneFile, MeasuredProfileAddsToTheRingsOwnHarmonicsAndMeanDeviation) {
  const std::filesystem::path folder = MeasuredFolder();
  constexpr std::string_view kOwnKeys = "mean_deviation_mm = 0.0\nharmonics = []                    # e.g.";
  constexpr std::string_view kOwnHarmonic = "{ order = 3, amplitude_mm = 0.01, phase_deg = 90 }";
  const engine::Harmonic own{3, 1e-5, std::numbers::pi / 2.0};
  constexpr double kOwnMeanDeviation = 2e-6;   // [m], mean_deviation_mm = 0.002
  constexpr double kMeasuredOffset = 1.5e-6;   // [m] the export's mean deviation, or its radius above 302 mm
  const std::vector<std::pair<std::string, std::string>> exports = {
      {"deviations", MeasuredCsv("deviation_um", 1e-6, kMeasuredOffset, kMeasuredForm)},
      {"radii", MeasuredRadii(kBoreRadius + kMeasuredOffset)}};
  for (const auto& [name, csv] : exports) {
    SCOPED_TRACE(name);
    WriteText(folder / "ring.csv", csv);
    WriteText(folder / "scene.toml",
                  PaperSceneWith(kOwnKeys, "mean_deviation_mm = 0.002\nharmonics = [" + std::string(kOwnHarmonic) +
                                               "]\nmeasured_profile = { file = \"ring.csv\", orders = 6 } #"));
    const engine::PolarProfile& bore = ReadScene(folder / "scene.toml").ring.inner;
    // 2 um + 1.5 um: the explicit key's rounding (eps x 2 um) vanishes in the fit's.
    EXPECT_NEAR(bore.mean_deviation(), kOwnMeanDeviation + kMeasuredOffset, kFitRoundOff);
    // The ring's own harmonic first, as written, then the fitted orders 2..6.
    ASSERT_EQ(bore.harmonics().size(), static_cast<std::size_t>(1 + kMeasuredOrders - 1));
    EXPECT_EQ(bore.harmonics().front(), own);
    EXPECT_EQ(bore.harmonics()[1].order, 2);
    // Equal orders add up: order 3 is the own harmonic plus the fitted one.
    EXPECT_NEAR(bore.cos_coefficient(3), own.amplitude * std::cos(own.phase) + CosCoefficient(kMeasuredForm, 3),
                kFitRoundOff);
    EXPECT_NEAR(bore.sin_coefficient(3), own.amplitude * std::sin(own.phase) + SinCoefficient(kMeasuredForm, 3),
                kFitRoundOff);
  }
}

TEST(SceneFile, MeasuredProfileIsFoundRelativeToTheSceneFilesFolder) {
  const std::filesystem::path folder = MeasuredFolder();
  std::filesystem::create_directories(folder / "scenes" / "profiles");
  WriteText(folder / "scenes" / "profiles" / "ring.csv", MeasuredRadii());
  const std::string text = PaperSceneMeasuring("{ file = \"profiles/ring.csv\", orders = 6 }");
  WriteText(folder / "scenes" / "scene.toml", text);
  const engine::Scene scene = ReadScene(folder / "scenes" / "scene.toml");
  EXPECT_EQ(scene.ring.inner.harmonics().size(), static_cast<std::size_t>(kMeasuredOrders - 1));

  // Text without a file resolves against the current directory, which has no profiles/.
  EXPECT_THAT(ErrorFor(text), AllOf(HasSubstr("ring.measured_profile.file = \"profiles/ring.csv\""),
                                    HasSubstr("no such file: profiles/ring.csv")));
  // An absolute path is taken as it is.
  const std::string absolute = (folder / "scenes" / "profiles" / "ring.csv").string();
  const engine::Scene parsed =
      ParseScene(PaperSceneMeasuring("{ file = \"" + absolute + "\", orders = 6 }"), "text.toml");
  EXPECT_EQ(parsed.ring.inner.harmonics(), scene.ring.inner.harmonics());
}

TEST(SceneFile, RejectsAMissingMeasuredProfileNamingKeyValueAndPath) {
  const std::filesystem::path folder = MeasuredFolder();
  const std::string scene = (folder / "scene.toml").string();
  EXPECT_THAT(MeasuredErrorFor(folder, "{ file = \"missing.csv\", orders = 6 }"),
              AllOf(HasSubstr(scene + ":"), HasSubstr("ring.measured_profile.file = \"missing.csv\": no such file: " +
                                                      (folder / "missing.csv").string()),
                    HasSubstr("allowed: the path of an existing CSV file")));
  std::filesystem::create_directories(folder / "profiles");
  EXPECT_THAT(MeasuredErrorFor(folder, "{ file = \"profiles\", orders = 6 }"),
              HasSubstr("ring.measured_profile.file = \"profiles\": not a file"));
}

// A profile measured on a 302 mm ring, named by a 150 mm design: by default its size
// counts and the mismatch is named as such; with reference = "own_mean" its form alone
// goes onto the 150 mm ring, the harmonics the same as on the 302 mm one.
TEST(SceneFile, AProfileOfAnotherRingSizeIsRefusedAsSuchOrTakenAsItsFormAlone) {
  const std::filesystem::path folder = MeasuredFolder();
  WriteText(folder / "ring.csv", MeasuredRadii());
  constexpr double kSmallBore = 0.150;  // [m]
  std::string text = PaperSceneMeasuring("{ file = \"ring.csv\", orders = 6 }");
  const auto small = [&](std::string scene) {
    const std::string from = "inner_radius_mm = 302.0", to = "inner_radius_mm = 150.0";
    scene.replace(scene.find(from), from.size(), to);
    return scene;
  };
  WriteText(folder / "scene.toml", small(text));
  EXPECT_THAT(ringtol::testing::MessageOf<InputError>([&] { ReadScene(folder / "scene.toml"); }),
              AllOf(HasSubstr("ring.measured_profile"), HasSubstr("its mean radius 302"),
                    HasSubstr("from ring.inner_radius_mm = 150 mm"), HasSubstr("a profile of another ring"),
                    HasSubstr("reference = \"own_mean\"")));
  WriteText(folder / "scene.toml", small(PaperSceneMeasuring("{ file = \"ring.csv\", orders = 6, reference = \"own_mean\" }")));
  const engine::PolarProfile& bore = ReadScene(folder / "scene.toml").ring.inner;
  EXPECT_EQ(bore.radius(), kSmallBore);
  EXPECT_NEAR(bore.mean_deviation(), 0.0, kFitRoundOff);
  for (int n = 2; n <= kMeasuredOrders; ++n) {
    EXPECT_NEAR(bore.cos_coefficient(n), CosCoefficient(kMeasuredForm, n), kFitRoundOff) << n;
    EXPECT_NEAR(bore.sin_coefficient(n), SinCoefficient(kMeasuredForm, n), kFitRoundOff) << n;
  }
  // On the ring it was measured on, own_mean drops the export's size and keeps its form.
  WriteText(folder / "ring.csv", MeasuredRadii(kBoreRadius + 20e-6));
  WriteText(folder / "scene.toml", PaperSceneMeasuring("{ file = \"ring.csv\", orders = 6, reference = \"own_mean\" }"));
  EXPECT_NEAR(ReadScene(folder / "scene.toml").ring.inner.mean_deviation(), 0.0, kFitRoundOff);
  WriteText(folder / "scene.toml", PaperSceneMeasuring("{ file = \"ring.csv\", orders = 6 }"));
  EXPECT_NEAR(ReadScene(folder / "scene.toml").ring.inner.mean_deviation(), 20e-6, kFitRoundOff);
}

// Micrometres under a deviation_mm column make a form a thousand times too large: named,
// with the column that was meant. A deviation export's form is held to 1 mm, and to 1 % of
// the ring where that is less.
TEST(SceneFile, AFormTooLargeForTheRingNamesTheColumnsUnit) {
  const std::filesystem::path folder = MeasuredFolder();
  std::vector<engine::Harmonic> in_micrometres = kMeasuredForm;
  for (engine::Harmonic& h : in_micrometres) h.amplitude *= 1e3;  // 30 um written as 30 "mm"
  WriteText(folder / "ring.csv", MeasuredCsv("deviation_mm", 1e-3, 0.0, in_micrometres));
  EXPECT_THAT(MeasuredErrorFor(folder, "{ file = \"ring.csv\", orders = 6 }"),
              AllOf(HasSubstr("ring.measured_profile"), HasSubstr("deviation_mm: a form of 48 mm"),
                    HasSubstr("more than 1 mm"), HasSubstr("deviation_um for micrometres")));
  // On a 50 mm ring, 1 % of the radius is the tighter bound: 0.6 mm of form written in
  // millimetres on a 50 mm ring is named against that ring.
  for (engine::Harmonic& h : in_micrometres) h.amplitude /= 80.0;
  WriteText(folder / "ring.csv", MeasuredCsv("deviation_mm", 1e-3, 0.0, in_micrometres));
  WriteText(folder / "scene.toml", ReplaceOnce(PaperSceneMeasuring("{ file = \"ring.csv\", orders = 6 }"),
                                               "inner_radius_mm = 302.0", "inner_radius_mm = 50.0"));
  EXPECT_THAT(ringtol::testing::MessageOf<InputError>([&] { ReadScene(folder / "scene.toml"); }),
              AllOf(HasSubstr("a form of 0.6 mm"), HasSubstr("more than 1 % of a ring of 50 mm")));
}

// The issue's export: degrees under angle_rad, whose fit keeps a runout of 5.8 um of a
// ring's 135.8 um. Refused, naming the export, the fit's R^2 and the likely cause.
TEST(SceneFile, AMeasuredProfileWithDegreesUnderAngleRadIsRefused) {
  const std::filesystem::path folder = MeasuredFolder();
  WriteText(folder / "ring.csv", ReplaceOnce(MeasuredRadii(), "angle_deg", "angle_rad"));
  EXPECT_THAT(MeasuredErrorFor(folder, "{ file = \"ring.csv\", orders = 6 }"),
              AllOf(HasSubstr("ring.measured_profile: " + (folder / "ring.csv").string() + ": a fit of orders 0..6 with R^2 = "),
                    HasSubstr("degrees under angle_rad?")));
}

// UTF-16 ("Unicode text") is named before toml++ quotes its bytes.
TEST(SceneFile, RefusesUtf16TextNamingTheEncoding) {
  std::string utf16 = "\xFF\xFE";
  for (const char c : PaperSceneText()) utf16 += std::string{c, '\0'};
  EXPECT_THAT(ErrorFor(utf16), AllOf(HasSubstr("bad.toml: UTF-16 (little-endian) text"), HasSubstr("save the file as UTF-8")));
  // A UTF-8 byte-order mark, as Windows tools write it, is read past.
  EXPECT_EQ(ParseScene("\xEF\xBB\xBF" + PaperSceneText(), "bom.toml").rollers.size(), 3u);
}

TEST(SceneFile, RejectsMeasuredProfileOrdersOutOfRange) {
  const std::filesystem::path folder = MeasuredFolder();
  WriteText(folder / "ring.csv", MeasuredRadii());
  EXPECT_THAT(MeasuredErrorFor(folder, "{ file = \"ring.csv\", orders = 0 }"),
              AllOf(HasSubstr((folder / "scene.toml").string() + ":"),
                    HasSubstr("ring.measured_profile.orders = 0: out of range; allowed: an integer >= 1 and <= 1000")));
  EXPECT_THAT(MeasuredErrorFor(folder, "{ file = \"ring.csv\", orders = 1001 }"),
              HasSubstr("ring.measured_profile.orders = 1001: out of range"));
  EXPECT_THAT(MeasuredErrorFor(folder, "{ file = \"ring.csv\", orders = 6.5 }"),
              HasSubstr("ring.measured_profile.orders = 6.5: wrong type: expected an integer, found float"));
}

TEST(SceneFile, RejectsUnknownMissingAndMistypedKeysOfTheMeasuredProfile) {
  const std::filesystem::path folder = MeasuredFolder();
  WriteText(folder / "ring.csv", MeasuredRadii());
  EXPECT_THAT(MeasuredErrorFor(folder, "{ file = \"ring.csv\", order = 6 }"),
              HasSubstr("unknown key 'ring.measured_profile.order'; valid keys here: file, orders, keep_eccentricity, "
                        "reference"));
  EXPECT_THAT(MeasuredErrorFor(folder, "{ file = \"ring.csv\" }"),
              AllOf(HasSubstr("ring.measured_profile.orders: missing required key"),
                    HasSubstr("allowed: an integer >= 1 and <= 1000")));
  EXPECT_THAT(MeasuredErrorFor(folder, "{ file = \"ring.csv\", orders = 6, keep_eccentricity = 1 }"),
              HasSubstr("ring.measured_profile.keep_eccentricity = 1: wrong type: expected a boolean"));
  EXPECT_THAT(MeasuredErrorFor(folder, "\"ring.csv\""),
              AllOf(HasSubstr("ring.measured_profile = \"ring.csv\": wrong type: expected a table"),
                    HasSubstr("allowed: a table { file = \"profile.csv\", orders = integer 1..1000")));
}

TEST(SceneFile, PassesCsvAndFitErrorsThroughAfterTheKeyPath) {
  const std::filesystem::path folder = MeasuredFolder();
  const std::string csv = (folder / "ring.csv").string();
  // measured_profile is on the line of the paper scene's ring harmonics, plus one.
  const std::string text = PaperSceneText();
  const std::size_t line = 2 + static_cast<std::size_t>(std::count(
                                   text.begin(), text.begin() + static_cast<std::ptrdiff_t>(text.find(kRingHarmonics)),
                                   '\n'));
  const std::string where = (folder / "scene.toml").string() + ":" + std::to_string(line) + ":";

  WriteText(folder / "ring.csv", "angle_deg,radius_mm\n0,1\n1,1\n2,1\n3,1\n4,1\n5,abc\n");
  EXPECT_THAT(MeasuredErrorFor(folder, "{ file = \"ring.csv\", orders = 2 }"),
              AllOf(::testing::StartsWith(where),
                    HasSubstr(": ring.measured_profile: " + csv +
                              ":7: radius_mm = abc: not a number; allowed: a finite number > 0")));

  WriteText(folder / "ring.csv", "angle_deg,radius_mm\n0,302\n72,302.01\n144,302\n216,301.99\n288,302\n");
  EXPECT_THAT(MeasuredErrorFor(folder, "{ file = \"ring.csv\", orders = 6 }"),
              AllOf(::testing::StartsWith(where),
                    HasSubstr(": ring.measured_profile: " + csv +
                              ": fitting orders up to 6 needs at least 2*6+1 = 13 points at distinct angles; got 5")));
}

TEST(SceneFile, BlamesTheMeasuredProfileForAmplitudesLargerThanTheRadius) {
  // 60 orders across the example's 30 degree gap: well enough conditioned to be fitted,
  // but the 1 um noise comes out amplified to amplitudes that add up to more than the radius.
  const std::string example = RINGTOL_SOURCE_DIR "/examples/measured/ring_profile.csv";
  EXPECT_THAT(ErrorFor(PaperSceneMeasuring("{ file = \"" + example + "\", orders = 60 }")),
              AllOf(HasSubstr("bad.toml:"),
                    HasSubstr("ring.measured_profile (|mean_deviation_mm| + sum of amplitude_mm"),
                    HasSubstr("amplitudes larger than the radius (`ringtol fit` shows the fit: fewer orders?)"),
                    HasSubstr("allowed: < 302 (ring.inner_radius_mm)")));
}

}  // namespace
}  // namespace ringtol::jobs

namespace ringtol::jobs {
namespace {

// The examples' comments quote the rollers' centre circle the position classes are graded
// at (sampling/catalogue.h): every such number must be the diameter of the article's
// scene's centre circle, which every example builds on.
TEST(Examples, CommentsQuoteTheCentreCircleTheSceneHas) {
  const engine::Scene scene = ReadScene(std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/paper/scene.toml");
  const double diameter_mm = 2.0 * scene.rollers.front().centre_radius * 1e3;
  // The number before each " mm centre circle" (std::regex trips GCC 12's
  // maybe-uninitialized warning under the sanitizers).
  const std::string quoted = " mm centre circle";
  int found = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples")) {
    if (entry.path().extension() != ".toml") continue;
    std::ifstream in(entry.path());
    std::string line;
    while (std::getline(in, line)) {
      for (std::size_t at = line.find(quoted); at != std::string::npos; at = line.find(quoted, at + 1)) {
        const std::size_t start = line.find_last_of(' ', at - 1) + 1;
        EXPECT_NEAR(std::stod(line.substr(start, at - start)), diameter_mm, 0.5) << entry.path() << ": " << line;
        ++found;
      }
    }
  }
  EXPECT_GE(found, 3) << "the examples no longer quote the centre circle: the test shows nothing";
}

}  // namespace
}  // namespace ringtol::jobs
