#include "jobs/inputs/sweep_file.h"

#include <cstddef>
#include <filesystem>
#include <numbers>
#include <ostream>
#include <sstream>
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

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

const fs::path kExamples = fs::path(RINGTOL_SOURCE_DIR) / "examples" / "paper";

// Writes `sweep` as sweep.toml next to scene.toml (the paper scene unless given) and
// returns the sweep file's path.
fs::path WriteSweep(const std::string& sweep, const std::string& scene = ReadText(kExamples / "scene.toml")) {
  const fs::path folder = ringtol::testing::FreshTestFolder("sweep_file_test");
  WriteText(folder / "scene.toml", scene);
  WriteText(folder / "sweep.toml", sweep);
  return folder / "sweep.toml";
}

std::string ErrorFor(const fs::path& sweep_file) {
  return ringtol::testing::MessageOf<InputError>([&] { ReadSweep(sweep_file); });
}

std::vector<std::string> Names(const Sweep& sweep) {
  std::vector<std::string> names;
  for (const SweepCase& c : sweep.cases) names.push_back(c.name);
  return names;
}

// One harmonic with the given order and amplitude [m] at the paper's phase of 45 deg.
void ExpectSingleHarmonic(const engine::PolarProfile& profile, int order, double amplitude) {
  ASSERT_EQ(profile.harmonics().size(), 1u);
  EXPECT_EQ(profile.harmonics()[0].order, order);
  EXPECT_DOUBLE_EQ(profile.harmonics()[0].amplitude, amplitude);
  EXPECT_DOUBLE_EQ(profile.harmonics()[0].phase, std::numbers::pi / 4.0);
}

// ---- the article's studies

TEST(SweepFile, ReadsTheOrderStudyAsThirteenRingCases) {
  const Sweep sweep = ReadSweep(kExamples / "orders.toml");
  EXPECT_TRUE(fs::equivalent(sweep.scene_file, kExamples / "scene.toml"));
  const std::vector<int> orders{2, 3, 4, 5, 6, 7, 8, 9, 10, 12, 15, 17, 20};
  ASSERT_EQ(sweep.cases.size(), orders.size());
  EXPECT_EQ(sweep.cases[0].name, "ring n=2 C=0.14mm");
  EXPECT_EQ(sweep.cases[12].name, "ring n=20 C=0.14mm");
  for (std::size_t i = 0; i < orders.size(); ++i) {
    const engine::Scene& scene = sweep.cases[i].scene;
    ExpectSingleHarmonic(scene.ring.inner, orders[i], 1.4e-4);
    EXPECT_TRUE(scene.roller_positions.harmonics().empty());
    for (const engine::Roller& roller : scene.rollers) EXPECT_TRUE(roller.outline.harmonics().empty());
  }
}

TEST(SweepFile, ReadsTheAmplitudeStudyWithOrdersInTheOuterLoop) {
  const Sweep sweep = ReadSweep(kExamples / "amplitudes.toml");
  ASSERT_EQ(sweep.cases.size(), 20u);
  EXPECT_EQ(sweep.cases[0].name, "ring n=2 C=0.07mm");
  EXPECT_EQ(sweep.cases[9].name, "ring n=2 C=0.7mm");
  EXPECT_EQ(sweep.cases[10].name, "ring n=6 C=0.07mm");
  EXPECT_EQ(sweep.cases[19].name, "ring n=6 C=0.7mm");
  for (std::size_t j = 0; j < 10; ++j) {
    const double amplitude = 0.07e-3 * static_cast<double>(j + 1);
    // 0.07 * k written as a decimal in the file against 0.07 * k computed: a few ulp.
    constexpr double kDecimalVersusProduct = 1e-18;  // [m] ~ 10 ulp of 0.7e-3
    EXPECT_NEAR(sweep.cases[j].scene.ring.inner.harmonics()[0].amplitude, amplitude, kDecimalVersusProduct);
    EXPECT_EQ(sweep.cases[10 + j].scene.ring.inner.harmonics()[0].order, 6);
  }
}

TEST(SweepFile, ReadsTheTwelveCombinationCases) {
  const Sweep sweep = ReadSweep(kExamples / "combinations.toml");
  EXPECT_THAT(Names(sweep), ElementsAre("case1", "case2", "case3", "case4", "case5", "case6", "case7", "case8",
                                        "case9", "case10", "case11", "case12"));
  const engine::Scene& case9 = sweep.cases[8].scene;
  ExpectSingleHarmonic(case9.ring.inner, 3, 1.4e-4);
  ExpectSingleHarmonic(case9.roller_positions, 7, 1.4e-4);
  ASSERT_EQ(case9.rollers.size(), 3u);
  for (const engine::Roller& roller : case9.rollers) ExpectSingleHarmonic(roller.outline, 15, 1.4e-5);

  const engine::Scene& case4 = sweep.cases[3].scene;
  EXPECT_TRUE(case4.roller_positions.harmonics().empty());
  for (const engine::Roller& roller : case4.rollers) ExpectSingleHarmonic(roller.outline, 2, 1.4e-5);

  const engine::Scene& case11 = sweep.cases[10].scene;
  ExpectSingleHarmonic(case11.ring.inner, 3, 1.4e-4);
  EXPECT_TRUE(case11.roller_positions.harmonics().empty());
  for (const engine::Roller& roller : case11.rollers) EXPECT_TRUE(roller.outline.harmonics().empty());
}

// ---- semantics

TEST(SweepFile, StudyReplacesTheTargetHarmonicsAndKeepsTheMeanDeviation) {
  std::string scene = ReadText(kExamples / "scene.toml");
  scene = ReplaceOnce(scene, "mean_deviation_mm = 0.0\nharmonics = []                    # e.g.",
                      "mean_deviation_mm = 0.01\nharmonics = [{ order = 4, amplitude_mm = 0.05 }] #");
  const Sweep sweep = ReadSweep(WriteSweep(
      "scene = \"scene.toml\"\n[study]\ntarget = \"ring\"\norders = [2]\namplitudes_mm = [0.14]\nphase_deg = 45\n",
      scene));
  ASSERT_EQ(sweep.cases.size(), 1u);
  ExpectSingleHarmonic(sweep.cases[0].scene.ring.inner, 2, 1.4e-4);
  EXPECT_DOUBLE_EQ(sweep.cases[0].scene.ring.inner.mean_deviation(), 1e-5);
}

TEST(SweepFile, RollerShapeStudyGivesEveryRollerTheSameHarmonic) {
  const Sweep sweep = ReadSweep(WriteSweep(
      "scene = \"scene.toml\"\n[study]\ntarget = \"roller_shape\"\norders = [3, 5]\namplitudes_mm = [0.014]\n"
      "phase_deg = 45\n"));
  ASSERT_EQ(sweep.cases.size(), 2u);
  EXPECT_EQ(sweep.cases[1].name, "roller_shape n=5 C=0.014mm");
  for (const engine::Roller& roller : sweep.cases[1].scene.rollers) ExpectSingleHarmonic(roller.outline, 5, 1.4e-5);
  EXPECT_TRUE(sweep.cases[1].scene.ring.inner.harmonics().empty());
}

TEST(SweepFile, CasesKeepTheBaseHarmonicsOfTargetsTheyDoNotList) {
  std::string scene = ReadText(kExamples / "scene.toml");
  scene = ReplaceOnce(scene, "harmonics = []                    # e.g.",
                      "harmonics = [{ order = 4, amplitude_mm = 0.05, phase_deg = 45 }] #");
  const Sweep sweep = ReadSweep(WriteSweep(
      "scene = \"scene.toml\"\n[[cases]]\nname = \"positions only\"\n"
      "roller_positions = [{ order = 2, amplitude_mm = 0.14, phase_deg = 45 }]\n"
      "[[cases]]\nname = \"clean ring\"\nring = []\n",
      scene));
  ASSERT_EQ(sweep.cases.size(), 2u);
  ExpectSingleHarmonic(sweep.cases[0].scene.ring.inner, 4, 5e-5);
  ExpectSingleHarmonic(sweep.cases[0].scene.roller_positions, 2, 1.4e-4);
  EXPECT_TRUE(sweep.cases[1].scene.ring.inner.harmonics().empty());
}

TEST(SweepFile, ResolvesTheScenePathAgainstTheSweepFolder) {
  const fs::path sweep_file = WriteSweep("scene = \"scene.toml\"\n[[cases]]\nname = \"nominal\"\n");
  const Sweep sweep = ReadSweep(sweep_file);
  EXPECT_EQ(sweep.scene_file, sweep_file.parent_path() / "scene.toml");
  ASSERT_EQ(sweep.cases.size(), 1u);
  EXPECT_TRUE(sweep.cases[0].scene.ring.inner.is_circle());
}

// ---- bad input

TEST(SweepFile, RejectsAMissingSweepFile) {
  const fs::path missing = ringtol::testing::FreshTestFolder("sweep_file_test") / "absent.toml";
  EXPECT_THAT(ErrorFor(missing), AllOf(HasSubstr(missing.string()), HasSubstr("no such file")));
}

TEST(SweepFile, ReportsErrorsInTheSceneAgainstTheSceneFile) {
  const std::string scene = ReplaceOnce(ReadText(kExamples / "scene.toml"), "thickness_mm = 6.0", "thickness_mm = -6");
  const fs::path file = WriteSweep("scene = \"scene.toml\"\n[[cases]]\nname = \"a\"\n", scene);
  EXPECT_THAT(ErrorFor(file), AllOf(HasSubstr((file.parent_path() / "scene.toml").string() + ":"),
                                    HasSubstr("ring.thickness_mm = -6"), HasSubstr("allowed: > 0")));
}

// A sweep file with one thing wrong, beside the paper scene, and the pieces its
// InputError must contain: the sweep file's path followed by `where`, then the key with
// its value, what is wrong and what is allowed.
struct BadSweep {
  std::string name;  // the case's name in the test's name
  std::string text;
  std::string where;
  std::vector<std::string> message_pieces;
};

void PrintTo(const BadSweep& sweep, std::ostream* out) { *out << sweep.name; }

const std::vector<BadSweep> kBadSweeps = {
    {"NoSceneKey", "[[cases]]\nname = \"a\"\n", "",
     {"scene: missing required key", "allowed: the path of a scene file, relative to the sweep file's folder"}},
    {"BothStudyAndCases",
     "scene = \"scene.toml\"\n[study]\ntarget = \"ring\"\norders = [2]\namplitudes_mm = [0.14]\n"
     "[[cases]]\nname = \"a\"\n",
     ":", {"study and cases: both present", "allowed: exactly one of [study] or [[cases]]"}},
    {"NeitherStudyNorCases", "scene = \"scene.toml\"\n", "",
     {"study and cases: neither present", "allowed: exactly one of [study] or [[cases]]"}},
    {"AMissingSceneFile", "scene = \"missing.toml\"\n[[cases]]\nname = \"a\"\n", ":1:",
     {"scene = \"missing.toml\"", "no such file", "allowed: the path of a scene file"}},
    {"OrderZeroInAStudy",
     "scene = \"scene.toml\"\n[study]\ntarget = \"ring\"\norders = [2, 0]\namplitudes_mm = [0.14]\n", ":",
     {"study.orders[1] = 0", "out of range", "allowed: an integer >= 1 and <= 1000"}},
    {"ARepeatedOrderInAStudy",
     "scene = \"scene.toml\"\n[study]\ntarget = \"ring\"\norders = [2, 2]\namplitudes_mm = [0.14]\n", ":",
     {"study.orders[1] = 2", "repeats orders[0]", "allowed: distinct orders"}},
    {"AnEmptyAmplitudeList",
     "scene = \"scene.toml\"\n[study]\ntarget = \"ring\"\norders = [2]\namplitudes_mm = []\n", ":",
     {"study.amplitudes_mm = []", "empty", "allowed: a non-empty array of numbers >= 0"}},
    {"AnUnknownStudyTarget",
     "scene = \"scene.toml\"\n[study]\ntarget = \"pinion\"\norders = [2]\namplitudes_mm = [0.1]\n", ":",
     {"study.target = \"pinion\"", "allowed: \"ring\", \"roller_positions\", \"roller_shape\""}},
    {"AnUnknownKeyInAStudy",
     "scene = \"scene.toml\"\n[study]\ntarget = \"ring\"\norder = [2]\norders = [2]\namplitudes_mm = [0.1]\n",
     ":4:1", {"unknown key 'study.order'", "valid keys here: target, orders, amplitudes_mm, phase_deg"}},
    {"AnUnknownKeyInACaseHarmonic",
     "scene = \"scene.toml\"\n[[cases]]\nname = \"a\"\nring = [{ order = 2, amplitude = 0.1 }]\n", ":4:",
     {"unknown key 'cases[0].ring[0].amplitude'", "valid keys here: order, amplitude_mm, phase_deg"}},
    {"DuplicatedCaseNames", "scene = \"scene.toml\"\n[[cases]]\nname = \"a\"\n[[cases]]\nname = \"a\"\n", ":5:",
     {"cases[1].name = \"a\"", "the same name as cases[0]", "allowed: a name no other case has"}},
    {"AStudyCaseWhoseRollerShapeExceedsTheRollerRadius",
     "scene = \"scene.toml\"\n[study]\ntarget = \"roller_shape\"\norders = [2]\namplitudes_mm = [0.01, 6.0]\n",
     ":5:",
     {"study.amplitudes_mm[1] = 6", "case \"roller_shape n=2 C=6mm\"",
      "amplitudes larger than the radius of roller spring",
      "allowed: < 5 mm (rollers[0].radius_mm in the scene file)"}},
    // Order 2 at phase 0 moves the rollers at 210 and 330 deg outward by half the amplitude.
    {"ACaseWhosePositionErrorsPushARollerOutOfTheRing",
     "scene = \"scene.toml\"\n[[cases]]\nname = \"far\"\nring = []\n"
     "roller_positions = [{ order = 2, amplitude_mm = 20.0 }]\n",
     ":5:",
     {"cases[0].roller_positions = ", "case \"far\"", "does not fit in the ring",
      "centre_radius_mm + radial position error <= ring.inner_radius_mm"}},
};

class SweepFileRejects : public ::testing::TestWithParam<BadSweep> {};

TEST_P(SweepFileRejects, WithAMessageNamingWhatIsWrongAndWhere) {
  const fs::path file = WriteSweep(GetParam().text);
  std::vector<::testing::Matcher<std::string>> pieces = {HasSubstr(file.string() + GetParam().where)};
  for (const std::string& piece : GetParam().message_pieces) pieces.push_back(HasSubstr(piece));
  EXPECT_THAT(ErrorFor(file), ::testing::AllOfArray(pieces));
}

INSTANTIATE_TEST_SUITE_P(OneBadKey, SweepFileRejects, ::testing::ValuesIn(kBadSweeps),
                         [](const ::testing::TestParamInfo<BadSweep>& row) { return row.param.name; });

}  // namespace
}  // namespace ringtol::jobs
