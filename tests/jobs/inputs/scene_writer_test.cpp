#include "jobs/inputs/scene_writer.h"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <unistd.h>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "jobs/inputs/input_error.h"
#include "jobs/inputs/scene_file.h"
#include "tests/support/paper_scene.h"

namespace ringtol::jobs {
namespace {

using engine::Harmonic;
using engine::PolarProfile;
using ringtol::testing::kDeg;
using ::testing::HasSubstr;

// A number in mm or deg is written as value / unit (one rounding) and read back as
// number * unit (a second): |relative error| <= 2 u = DBL_EPSILON. The article law's span
// goes through rate and revolutions, each converted and multiplied or divided again: six
// roundings, 3 DBL_EPSILON. This bound covers both with a little room.
constexpr double kRoundTripRelative = 4.0 * std::numeric_limits<double>::epsilon();

const std::filesystem::path kPaperFolder = RINGTOL_SOURCE_DIR "/examples/paper";

void ExpectClose(double read, double written, const std::string& where) {
  EXPECT_LE(std::abs(read - written), kRoundTripRelative * std::abs(written))
      << where << ": read back " << fmt::format("{}", read) << ", written " << fmt::format("{}", written);
}

// ReadHarmonics keeps the list as written, in order and without normalising phases, so
// harmonics compare one by one.
void ExpectSameHarmonics(const std::vector<Harmonic>& read, const std::vector<Harmonic>& written,
                         const std::string& where) {
  ASSERT_EQ(read.size(), written.size()) << where;
  for (std::size_t i = 0; i < read.size(); ++i) {
    const std::string at = fmt::format("{}[{}]", where, i);
    EXPECT_EQ(read[i].order, written[i].order) << at;
    ExpectClose(read[i].amplitude, written[i].amplitude, at + ".amplitude");
    ExpectClose(read[i].phase, written[i].phase, at + ".phase");
  }
}

// The radius of roller_positions is unused and not written: compare it only elsewhere.
void ExpectSameProfile(const PolarProfile& read, const PolarProfile& written, const std::string& where,
                       bool with_radius = true) {
  if (with_radius) ExpectClose(read.radius(), written.radius(), where + ".radius");
  ExpectClose(read.mean_deviation(), written.mean_deviation(), where + ".mean_deviation");
  ExpectSameHarmonics(read.harmonics(), written.harmonics(), where + ".harmonics");
}

void ExpectSameMaterial(const engine::Material& read, const engine::Material& written, const std::string& where) {
  ExpectClose(read.youngs_modulus, written.youngs_modulus, where + ".youngs_modulus");
  ExpectClose(read.poisson_ratio, written.poisson_ratio, where + ".poisson_ratio");
}

void ExpectSameRoller(const engine::Roller& read, const engine::Roller& written, const std::string& where) {
  EXPECT_EQ(read.name, written.name) << where;
  ExpectClose(read.angle, written.angle, where + ".angle");
  ExpectClose(read.centre_radius, written.centre_radius, where + ".centre_radius");
  ExpectClose(read.radial_offset, written.radial_offset, where + ".radial_offset");
  ExpectClose(read.tangential_offset, written.tangential_offset, where + ".tangential_offset");
  ExpectSameProfile(read.outline, written.outline, where + ".outline");
  EXPECT_EQ(read.phase_reference, written.phase_reference) << where;
  ExpectClose(read.spin_phase, written.spin_phase, where + ".spin_phase");
  EXPECT_EQ(read.mount, written.mount) << where;
  ExpectClose(read.spring.stiffness, written.spring.stiffness, where + ".spring.stiffness");
  ExpectClose(read.spring.preload, written.spring.preload, where + ".spring.preload");
  ExpectClose(read.spring.axis_angle, written.spring.axis_angle, where + ".spring.axis_angle");
  ExpectClose(read.spring.travel_limit, written.spring.travel_limit, where + ".spring.travel_limit");
  ExpectClose(read.mass, written.mass, where + ".mass");
  ExpectClose(read.spin_inertia, written.spin_inertia, where + ".spin_inertia");
  ExpectSameMaterial(read.material, written.material, where + ".material");
}

void ExpectSameMotion(const engine::MotionLaw& read, const engine::MotionLaw& written) {
  ASSERT_EQ(read.segments().size(), written.segments().size());
  for (std::size_t i = 0; i < read.segments().size(); ++i) {
    const engine::MotionSegment& r = read.segments()[i];
    const engine::MotionSegment& w = written.segments()[i];
    const std::string at = fmt::format("motion.segments[{}]", i);
    ExpectClose(r.duration, w.duration, at + ".duration");
    ExpectClose(r.acceleration, w.acceleration, at + ".acceleration");
    ASSERT_EQ(r.start_rate.has_value(), w.start_rate.has_value()) << at;
    if (r.start_rate) ExpectClose(*r.start_rate, *w.start_rate, at + ".start_rate");
  }
}

// Every field of two scenes: numbers within kRoundTripRelative, the rest exactly.
void ExpectSameScene(const engine::Scene& read, const engine::Scene& written) {
  ExpectSameProfile(read.ring.inner, written.ring.inner, "ring.inner");
  ExpectClose(read.ring.outer_radius, written.ring.outer_radius, "ring.outer_radius");
  ExpectClose(read.ring.thickness, written.ring.thickness, "ring.thickness");
  ExpectClose(read.ring.mass, written.ring.mass, "ring.mass");
  ExpectClose(read.ring.spin_inertia, written.ring.spin_inertia, "ring.spin_inertia");
  ExpectSameMaterial(read.ring.material, written.ring.material, "ring.material");
  ASSERT_EQ(read.rollers.size(), written.rollers.size());
  for (std::size_t i = 0; i < read.rollers.size(); ++i) {
    ExpectSameRoller(read.rollers[i], written.rollers[i], fmt::format("rollers[{}]", i));
  }
  ExpectSameProfile(read.roller_positions, written.roller_positions, "roller_positions", false);
  EXPECT_EQ(read.contact.model, written.contact.model);
  ExpectClose(read.contact.stiffness, written.contact.stiffness, "contact.stiffness");
  ExpectClose(read.contact.exponent, written.contact.exponent, "contact.exponent");
  ExpectClose(read.contact.max_damping, written.contact.max_damping, "contact.max_damping");
  ExpectClose(read.contact.full_damping_penetration, written.contact.full_damping_penetration,
              "contact.full_damping_penetration");
  ExpectClose(read.friction.static_coefficient, written.friction.static_coefficient, "friction.static_coefficient");
  ExpectClose(read.friction.dynamic_coefficient, written.friction.dynamic_coefficient, "friction.dynamic_coefficient");
  ExpectClose(read.friction.stiction_velocity, written.friction.stiction_velocity, "friction.stiction_velocity");
  ExpectClose(read.friction.transition_velocity, written.friction.transition_velocity, "friction.transition_velocity");
  ExpectClose(read.sensor_angle, written.sensor_angle, "sensor_angle");
  ExpectClose(read.sensor_swing.resolution, written.sensor_swing.resolution, "sensor_swing.resolution");
  ExpectClose(read.sensor_swing.cutoff_upr, written.sensor_swing.cutoff_upr, "sensor_swing.cutoff_upr");
  ExpectClose(read.error_motion_filter.cutoff_upr, written.error_motion_filter.cutoff_upr,
              "error_motion_filter.cutoff_upr");
  ExpectSameMotion(read.motion, written.motion);
  EXPECT_EQ(read.dynamics, written.dynamics);
  EXPECT_EQ(read.phase_locked_rollers, written.phase_locked_rollers);
}

engine::Scene ReadBack(const engine::Scene& scene) { return ParseScene(WriteScene(scene), "written.toml"); }

// Everything a sample can vary, at values that are not short decimals in mm or degrees.
engine::Scene ErrorScene() {
  engine::Scene scene = ringtol::testing::PaperScene(engine::ContactLaw::Model::kRigid);
  const double e = std::numbers::e;
  scene.ring.inner = PolarProfile(0.302, 0.0123e-3 * e,
                                  {{3, 0.14e-3, 45.0 * kDeg}, {7, 0.0321e-3 * e, -1234.5 * kDeg}, {3, 1e-5 / e, 0.1}});
  scene.roller_positions = PolarProfile(1.0, -0.004e-3 * e, {{2, 0.05e-3 / e, 30.0 * kDeg}, {5, 0.0, 1.0}});
  engine::Roller& spring = scene.rollers[0];
  spring.spring = {987.65 * e, 12.3 / e, 95.0 * kDeg * e, 2.5e-3 / e};
  spring.radial_offset = -0.002e-3 * e;
  engine::Roller& fixed = scene.rollers[1];
  fixed.name = "fixed \"a\" \\ 1";
  fixed.centre_radius = 0.29695 + 1e-6 / e;
  fixed.radial_offset = 0.011e-3 * e;
  fixed.tangential_offset = -0.007e-3 / e;
  fixed.outline = PolarProfile(0.005 + 1e-7 * e, 0.001e-3 / e, {{2, 0.003e-3 * e, 17.0 * kDeg}, {4, 0.0005e-3, 2.0}});
  fixed.phase_reference = engine::ShapePhaseReference::kGlobal;
  fixed.spin_phase = 33.0 * kDeg / e;
  fixed.mass = 2.47e-3 * e;
  fixed.spin_inertia = 3.08e-8 / e;
  fixed.material = {193e9 * e, 0.29 / e};
  scene.ring.material = {68.9e9 / e, 0.33 * e / 3.0};
  scene.rollers[2].outline = PolarProfile(0.005, 0.0, {{3, 0.002e-3, -0.5}});
  scene.contact = {engine::ContactLaw::Model::kRigid, 2.5e8 * e, 1.3, 1234.5 / e, 2.5e-7 * e};
  scene.friction = {0.3 * e, 0.25 / e, 0.002 * e, 0.02 * e};
  scene.sensor_angle = 37.5 * kDeg * e;
  scene.sensor_swing = {0.07e-6 * e, 40.0 / e};
  scene.error_motion_filter.cutoff_upr = 150.0 / e;
  scene.motion = engine::MotionLaw({{0.25, 0.0, 0.0},
                                    {1.0 / 3.0, 810.0 * kDeg, std::nullopt},
                                    {2.0 * e, 0.0, std::nullopt},
                                    {0.1, -5.0 * e, 3.0 / e}});
  scene.dynamics = {false, true, true};
  scene.phase_locked_rollers = true;
  return scene;
}

// The paper scene with sampled errors, as a Monte Carlo run draws them (fixed seed).
engine::Scene SampledScene(std::mt19937_64& random) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto harmonics = [&](double amplitude) {
    std::vector<Harmonic> list;
    for (int order = 2; order <= 6; ++order) list.push_back({order, amplitude * unit(random), 2.0 * std::numbers::pi * unit(random)});
    return list;
  };
  engine::Scene scene = ringtol::testing::PaperScene();
  scene.ring.inner = PolarProfile(0.302, 0.05e-3 * (unit(random) - 0.5), harmonics(0.1e-3));
  scene.roller_positions = PolarProfile(1.0, 0.02e-3 * (unit(random) - 0.5), harmonics(0.02e-3));
  for (engine::Roller& roller : scene.rollers) {
    roller.radial_offset = 0.02e-3 * (unit(random) - 0.5);
    roller.tangential_offset = 0.02e-3 * (unit(random) - 0.5);
    roller.outline = PolarProfile(0.005, 0.002e-3 * (unit(random) - 0.5), harmonics(0.002e-3));
  }
  scene.rollers[0].spring.stiffness = 1334.0 * (0.9 + 0.2 * unit(random));
  scene.rollers[0].spring.preload = 19.3 * (0.9 + 0.2 * unit(random));
  return scene;
}

std::filesystem::path ScratchPath(const std::string& name) {
  return std::filesystem::temp_directory_path() / fmt::format("ringtol_scene_writer_{}_{}", getpid(), name);
}

TEST(SceneWriter, PaperScenesReadBackEqual) {
  for (const char* file : {"scene.toml", "order3.toml"}) {
    SCOPED_TRACE(file);
    const engine::Scene scene = ReadScene(kPaperFolder / file);
    ExpectSameScene(ReadBack(scene), scene);
  }
}

TEST(SceneWriter, WritesBackTheNumbersOfTheFileItRead) {
  const engine::Scene scene = ReadScene(kPaperFolder / "order3.toml");
  const std::string text = WriteScene(scene);
  for (const char* line : {"inner_radius_mm = 302.0", "outer_radius_mm = 339.85", "angle_deg = 210.0",
                           "amplitude_mm = 0.14, phase_deg = 45.0", "full_damping_penetration_mm = 0.001",
                           "rate_deg_per_s = 270.0", "revolutions = 3.0", "spring_travel_limit_mm = 5.0",
                           "width_mm = 4.0", "youngs_modulus_GPa = 70.0", "poisson_ratio = 0.33"}) {
    EXPECT_THAT(text, HasSubstr(line));
  }
  EXPECT_EQ(ReadBack(scene), scene);
}

TEST(SceneWriter, StatesTheLawOfTheMaterialsSoItReadsBackEqual) {
  // A file without k and e: its law comes from its materials, and the written file states it.
  const engine::Scene scene = ReadScene(RINGTOL_SOURCE_DIR "/examples/rotary_table/scene.toml");
  const std::string text = WriteScene(scene);
  EXPECT_THAT(text, HasSubstr(fmt::format("\nstiffness_N_per_m_e = {}\nexponent = {}\n", scene.contact.stiffness,
                                          scene.contact.exponent)));
  EXPECT_EQ(ReadBack(scene), scene);
}

TEST(SceneWriter, ErrorsOffsetsSpringAndPiecewiseMotionReadBackEqual) {
  const engine::Scene scene = ErrorScene();
  const std::string text = WriteScene(scene);
  EXPECT_THAT(text, HasSubstr("[roller_positions]"));
  EXPECT_THAT(text, HasSubstr("law = \"piecewise\""));
  ExpectSameScene(ReadBack(scene), scene);
}

TEST(SceneWriter, SampledScenesReadBackEqual) {
  std::mt19937_64 random(20250501);
  constexpr int kSamples = 50;
  for (int i = 0; i < kSamples; ++i) {
    SCOPED_TRACE(fmt::format("sample {}", i));
    const engine::Scene scene = SampledScene(random);
    ExpectSameScene(ReadBack(scene), scene);
  }
}

TEST(SceneWriter, KeepsArticleAndTestBenchLawsByName) {
  engine::Scene scene = ringtol::testing::PaperScene();
  scene.motion = engine::ArticleLaw(0.0, -100.0 * kDeg * std::numbers::e, 2.5);
  EXPECT_THAT(WriteScene(scene), HasSubstr("law = \"article\"\nsettle_s = 0.0\n"));
  ExpectSameMotion(ReadBack(scene).motion, scene.motion);
  scene.motion = engine::TestBenchLaw(0.2);
  EXPECT_THAT(WriteScene(scene), HasSubstr("law = \"test_bench\"\nsettle_s = 0.2\n"));
  EXPECT_EQ(ReadBack(scene).motion, scene.motion);
}

TEST(SceneWriter, WritesEveryKeyOfTheFormat) {
  const std::string text = WriteScene(ErrorScene());
  for (const char* key :
       {"inner_radius_mm", "outer_radius_mm", "thickness_mm", "mass_kg", "spin_inertia_kg_m2", "mean_deviation_mm",
        "harmonics", "name", "angle_deg", "radius_mm", "centre_radius_mm", "radial_offset_mm", "tangential_offset_mm",
        "mount", "spring_stiffness_N_per_m", "spring_preload_N", "spring_axis_deg", "spring_travel_limit_mm",
        "width_mm", "shape_phase_reference", "spin_phase_deg", "youngs_modulus_GPa", "poisson_ratio", "law",
        "stiffness_N_per_m_e", "exponent",
        "max_damping_N_s_per_m", "full_damping_penetration_mm", "static_coefficient", "dynamic_coefficient",
        "stiction_velocity_mm_per_s", "transition_velocity_mm_per_s", "segments", "friction",
        "rolling_without_slip", "massless_spring_rollers", "phase_locked_rollers", "resolution_um", "cutoff_upr",
        "error_motion_cutoff_upr"}) {
    EXPECT_THAT(text, HasSubstr(fmt::format("\n{} = ", key)));
  }
  for (const char* key : {"duration_s", "acceleration_deg_per_s2", "start_rate_deg_per_s"}) {
    EXPECT_THAT(text, HasSubstr(fmt::format(" {} = ", key)));
  }
}

TEST(SceneWriter, WrittenFileReadsBackEqual) {
  const std::filesystem::path file = ScratchPath("scene.toml");
  const engine::Scene scene = ErrorScene();
  WriteSceneFile(scene, file);
  ExpectSameScene(ReadScene(file), scene);
  std::filesystem::remove(file);
}

TEST(SceneWriter, RejectsAnUnwritablePathNamingIt) {
  const std::filesystem::path folder = ScratchPath("missing_folder");
  ASSERT_FALSE(std::filesystem::exists(folder));
  for (const std::filesystem::path& file : {folder / "scene.toml", std::filesystem::temp_directory_path()}) {
    try {
      WriteSceneFile(ringtol::testing::PaperScene(), file);
      ADD_FAILURE() << "wrote " << file;
    } catch (const InputError& error) {
      EXPECT_THAT(error.what(), HasSubstr(file.string()));
    }
  }
}

}  // namespace
}  // namespace ringtol::jobs
