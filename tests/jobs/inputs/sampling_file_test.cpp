#include "jobs/inputs/sampling_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include "jobs/inputs/catalogue_file.h"
#include "jobs/inputs/input_error.h"
#include "jobs/inputs/profile_csv.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

const std::filesystem::path kExample = std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/tolerances/normal_waterjet.toml";

const std::string kSceneLine =
    "scene = \"" + (std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/paper/scene.toml").string() + "\"\n";

// Writes `text` to a file of this test's own (ctest runs tests in parallel) and reads it.
SamplingPlan ReadVariant(const std::string& text) {
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path file = std::filesystem::temp_directory_path() /
                                     (std::string("ringtol_") + test->test_suite_name() + "_" + test->name() + ".toml");
  std::ofstream(file) << text;
  struct Remove {
    std::filesystem::path f;
    ~Remove() { std::filesystem::remove(f); }
  } remove{file};
  return ReadSamplingFile(file);
}

std::string ErrorOf(const std::string& text) {
  try {
    const SamplingPlan plan = ReadVariant(text);
    MakeSampling(plan, "variant");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ShippedCatalogue, HoldsTheIso492ValuesWithTheirSources) {
  const sampling::ToleranceCatalogue c = ShippedCatalogue();
  EXPECT_FALSE(c.version.empty());
  // docs/tolerances.md §1: D 6-18 mm, Normal: Kea 15, VDsp 10 (series 9), ΔDmp -8 um.
  const sampling::RollerTolerance normal = c.Roller("Normal", 10e-3, sampling::DiameterSeries::kSeries9);
  EXPECT_DOUBLE_EQ(normal.kea, 15e-6);
  EXPECT_DOUBLE_EQ(normal.vdsp, 10e-6);
  EXPECT_DOUBLE_EQ(normal.mean_diameter_lower, -8e-6);
  EXPECT_DOUBLE_EQ(c.Roller("P5", 600e-3, sampling::DiameterSeries::kSeries2To4).vdsp, 21e-6);
  EXPECT_DOUBLE_EQ(c.Ring("waterjet", 604e-3).circularity, 0.2e-3);
  EXPECT_DOUBLE_EQ(c.Position("IT7", 594e-3).zone_diameter, 70e-6);
  for (const auto& k : c.roller_classes)
    for (const auto& row : k.rows) EXPECT_FALSE(row.source.empty()) << k.name;
}

TEST(ShippedCatalogue, MissingClassesAreErrorsNotExtrapolations) {
  const sampling::ToleranceCatalogue c = ShippedCatalogue();
  EXPECT_THAT([&] { c.Roller("P4", 600e-3, sampling::DiameterSeries::kSeries9); },
              ::testing::ThrowsMessage<std::invalid_argument>(
                  AllOf(HasSubstr("no value for diameter 600 mm"), HasSubstr("does not extrapolate"))));
  EXPECT_THAT([&] { c.Ring("polished", 600e-3); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("unknown ring circularity class 'polished'")));
}

TEST(SamplingFile, TheExampleReadsAndSamples) {
  const SamplingPlan plan = ReadSamplingFile(kExample);
  EXPECT_EQ(plan.design.kind, sampling::DesignKind::kSobol);
  ASSERT_TRUE(plan.tolerances.ring);
  EXPECT_DOUBLE_EQ(plan.tolerances.ring->circularity, 0.2e-3);
  ASSERT_EQ(plan.tolerances.roller_shapes.size(), 3u);
  EXPECT_DOUBLE_EQ(plan.tolerances.roller_shapes[0]->kea, 15e-6);
  ASSERT_EQ(plan.tolerances.springs.size(), 3u);
  EXPECT_EQ(static_cast<int>(plan.tolerances.springs[0].has_value()) +
                static_cast<int>(plan.tolerances.springs[1].has_value()) +
                static_cast<int>(plan.tolerances.springs[2].has_value()),
            1);
}

// "IT7" with a zero-width space after it is not the class IT7: both the value and the
// catalogue's message show the difference.
TEST(SamplingFile, AClassNameWithAnInvisibleCharacterIsShownEscaped) {
  const std::string message =
      ErrorOf(kSceneLine + "[tolerances.roller_positions]\nclass = \"IT7\xE2\x80\x8B\"\n");
  EXPECT_THAT(message, AllOf(HasSubstr("tolerances.roller_positions.class = \"IT7\\u200B\""),
                             HasSubstr("unknown roller position class 'IT7\\u200B'; known: "), HasSubstr("IT7")));
  EXPECT_THAT(message, ::testing::Not(HasSubstr("\xE2\x80\x8B")));
}

// The file's seed and --seed share one range (the commands' side: tests/jobs/cli/cli_test.cpp).
TEST(SeedOfText, TakesDecimalIntegersFromZeroToTheLargestTomlInteger) {
  EXPECT_EQ(SeedOfText("0"), std::optional<std::uint64_t>(0));
  EXPECT_EQ(SeedOfText("42"), std::optional<std::uint64_t>(42));
  EXPECT_EQ(SeedOfText("9223372036854775807"), std::optional<std::uint64_t>(kMaxSeed));
  for (const char* text : {"9223372036854775808", "18446744073709551616", "-1", "+1", "0x10", " 1", "1 ", "1e3", ""}) {
    EXPECT_EQ(SeedOfText(text), std::nullopt) << text;
  }
  EXPECT_EQ(SeedAllowed(), "an integer >= 0 and <= 9223372036854775807");
  EXPECT_THAT(ErrorOf(kSceneLine + "seed = -1\n"),
              AllOf(HasSubstr("seed = -1"), HasSubstr("allowed: an integer >= 0 and <= 9223372036854775807")));
}

TEST(SamplingFile, BadFilesNameKeyValueAndAllowedRange) {
  const std::string head = kSceneLine;
  EXPECT_THAT(ErrorOf(head + "[tolerances.ring]\nclass = \"granite\"\n"),
              AllOf(HasSubstr("tolerances.ring.class"), HasSubstr("unknown ring circularity class 'granite'")));
  EXPECT_THAT(ErrorOf(head + "[tolerances.ring]\nclass = \"waterjet\"\ncircularity_mm = 0.1\n"),
              HasSubstr("either class or circularity_mm"));
  EXPECT_THAT(ErrorOf(head + "[tolerances.ring]\ncircularity_mm = -0.1\n"),
              AllOf(HasSubstr("tolerances.ring.circularity_mm = -0.1"), HasSubstr("> 0")));
  EXPECT_THAT(ErrorOf(head + "[tolerances.ring]\ncircularity_mm = 0.1\nmax_order = 1\n"),
              AllOf(HasSubstr("tolerances.ring.max_order = 1"), HasSubstr(">= 2")));
  EXPECT_THAT(ErrorOf(head + "[tolerances.rollers]\nclass = \"P4\"\nmode = \"sorted\"\n"),
              AllOf(HasSubstr("tolerances.rollers.mode"), HasSubstr("\"inspected\"")));
  EXPECT_THAT(ErrorOf(head + "[design]\nkind = \"sobol\"\nsamples = 1000\n[tolerances.roller_positions]\nclass = \"IT7\"\n"),
              AllOf(HasSubstr("design.samples = 1000"), HasSubstr("use 512 or 1024")));
  EXPECT_THAT(ErrorOf(head + "[tolerances]\n"), HasSubstr("nothing is toleranced"));
  EXPECT_THAT(ErrorOf(head + "[tolerances.springs]\nstiffness_percent = 5\n"), HasSubstr("preload_percent"));
  EXPECT_THAT(ErrorOf(head + "[tolerances.ring]\ncircularity_mm = 0.1\ncapability_cp = 2\n"), HasSubstr("<= 1.33"));
  EXPECT_THAT(ErrorOf(head + "colour = 3\n"), HasSubstr("unknown key 'colour'"));
}

// [population.ring]: the exports of a folder (by name) or a list, each fitted, and a line
// per part naming its export and the CRC-32 of its bytes.
TEST(SamplingFile, APopulationOfRingsReadsItsPartsAndWhatIdentifiesThem) {
  // The examples are campaign files: their [spec] is the campaign reader's.
  constexpr std::array<std::string_view, 1> kSpec = {"spec"};
  const std::filesystem::path examples = std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/populations";
  const SamplingPlan resample = ReadSamplingFile(examples / "resample.toml", kSpec);
  ASSERT_TRUE(resample.tolerances.ring_population.has_value());
  const sampling::PartPopulation& rings = *resample.tolerances.ring_population;
  EXPECT_EQ(rings.draw, sampling::PopulationDraw::kResample);
  ASSERT_EQ(rings.parts.size(), 20u);
  EXPECT_EQ(rings.parts.front().name, "ring_01.csv");
  EXPECT_EQ(rings.parts.back().name, "ring_20.csv");
  EXPECT_FALSE(resample.tolerances.ring.has_value());
  // Each part is its export fitted as a scene's measured profile (reference = "nominal").
  const std::filesystem::path first = examples / "rings/ring_01.csv";
  const MeasuredFit fit = FitProfileFile(first, 12, resample.scene.ring.inner.radius());
  EXPECT_EQ(rings.parts.front().harmonics, FormHarmonics(fit.fit, false));
  EXPECT_EQ(rings.parts.front().mean_deviation, MeanDeviation(fit, resample.scene.ring.inner.radius()));
  EXPECT_THAT(resample.population, AllOf(HasSubstr("draw = resample, orders = 12"), HasSubstr("ring_01.csv crc32 "),
                                         HasSubstr("ring_20.csv crc32 ")));
  EXPECT_EQ(std::count(resample.population.begin(), resample.population.end(), '\n'), 21);
  EXPECT_EQ(ReadSamplingFile(examples / "model.toml", kSpec).tolerances.ring_population->draw, sampling::PopulationDraw::kModel);
}

// [population.rollers]: a batch fitted against the scene's roller radius, resampled without
// replacement, and refused beside [tolerances.rollers] or smaller than the scene's rollers.
TEST(SamplingFile, ABatchOfRollersReadsAndIsHeldToTheScenesRollers) {
  constexpr std::array<std::string_view, 1> kSpec = {"spec"};
  const std::filesystem::path examples = std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/populations";
  const SamplingPlan plan = ReadSamplingFile(examples / "roller_batch.toml", kSpec);
  ASSERT_TRUE(plan.tolerances.roller_population.has_value());
  EXPECT_EQ(plan.tolerances.roller_population->parts.size(), 12u);
  EXPECT_THAT(plan.population, AllOf(HasSubstr("population.rollers: draw = resample, orders = 8"),
                                     HasSubstr("roller_12.csv crc32 ")));
  const MeasuredFit fit = FitProfileFile(examples / "rollers/roller_01.csv", 8, 5e-3, "roller");
  EXPECT_EQ(plan.tolerances.roller_population->parts.front().mean_deviation, MeanDeviation(fit, 5e-3));
  const std::string rollers = (examples / "rollers").string();
  const std::string head = kSceneLine + "[population.rollers]\norders = 6\n";
  EXPECT_THAT(ErrorOf(head + "folder = \"" + rollers + "\"\n[tolerances.rollers]\nclass = \"Normal\"\n"),
              AllOf(HasSubstr("population.rollers"),
                    HasSubstr("fills roller \"spring\", and [tolerances.rollers] draws it too")));
  EXPECT_THAT(ErrorOf(head + "profiles = [\"" + rollers + "/roller_01.csv\", \"" + rollers + "/roller_02.csv\"]\n"),
              AllOf(HasSubstr("population.rollers.draw"), HasSubstr("2 parts for 3 rollers")));
  EXPECT_EQ(ErrorOf(head + "folder = \"" + rollers + "\"\n"), "no error");
}

// [population.rollers] rollers: the batch fills the rollers named, so that one measured
// roller (or a class) keeps the others; two parts are then enough for two rollers.
TEST(SamplingFile, ABatchOfRollersCanFillSomeRollersOnly) {
  const std::string rollers = (std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/populations/rollers").string();
  const std::string batch = kSceneLine + "[population.rollers]\norders = 6\nprofiles = [\"" + rollers +
                            "/roller_01.csv\", \"" + rollers + "/roller_02.csv\"]\n";
  const SamplingPlan plan = ReadVariant(batch + "rollers = [\"fixed_b\", \"spring\"]\n");
  EXPECT_EQ(plan.tolerances.batch_rollers, (std::vector<std::size_t>{0, 2}));  // spring, fixed_a, fixed_b
  EXPECT_THAT(plan.population, HasSubstr("reference = nominal, rollers = fixed_b, spring\n"));
  const SamplingPlan beside_a_class = ReadVariant(batch + "rollers = [\"fixed_b\", \"spring\"]\n"
                                                  "[tolerances.rollers]\nclass = \"Normal\"\nrollers = [\"fixed_a\"]\n");
  EXPECT_EQ(beside_a_class.tolerances.roller_shapes[1].has_value(), true);
  EXPECT_THAT(ErrorOf(batch + "rollers = [\"fixed_b\", \"middle\"]\n"),
              AllOf(HasSubstr("population.rollers.rollers"), HasSubstr("names no roller \"middle\"")));
  EXPECT_THAT(ErrorOf(batch), HasSubstr("2 parts for 3 rollers"));
  EXPECT_THAT(ErrorOf(batch + "rollers = [\"fixed_b\", \"spring\"]\n[tolerances.rollers]\nclass = \"Normal\"\n"),
              HasSubstr("fills roller \"spring\", and [tolerances.rollers] draws it too"));
  EXPECT_THAT(ErrorOf(kSceneLine + "[population.ring]\norders = 6\nfolder = \"" + rollers + "\"\nrollers = [\"spring\"]\n"),
              HasSubstr("population.ring.rollers"));
}

// [population.*] class and mode: kept for the report's comparison, looked up at the parts'
// diameter as a [tolerances.*] class is, and never drawn from.
TEST(SamplingFile, APopulationsClassIsKeptForTheReportAndChangesNoDraw) {
  const std::string rollers = (std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/populations/rollers").string();
  const std::string head = kSceneLine + "[population.rollers]\norders = 6\nfolder = \"" + rollers + "\"\n";
  const SamplingPlan unnamed = ReadVariant(head);
  ASSERT_TRUE(unnamed.roller_population.has_value());
  EXPECT_FALSE(unnamed.roller_population->class_name.has_value());
  EXPECT_EQ(unnamed.roller_population->mode, sampling::ToleranceMode::kProcess);
  EXPECT_EQ(unnamed.roller_population->orders, 6);
  EXPECT_FALSE(unnamed.ring_population.has_value());
  const SamplingPlan named = ReadVariant(head + "class = \"P5\"\nmode = \"inspected\"\n");
  EXPECT_EQ(named.roller_population->class_name, "P5");
  EXPECT_EQ(named.roller_population->mode, sampling::ToleranceMode::kInspected);
  EXPECT_TRUE(named.tolerances.roller_shapes.empty());
  EXPECT_EQ(named.population, unnamed.population);
  // A ring class has no row for a 10 mm roller, whose catalogue names the rows there are.
  EXPECT_THAT(ErrorOf(head + "class = \"IT7/2\"\n"), AllOf(HasSubstr("population.rollers.class"), HasSubstr("IT7/2")));
  EXPECT_THAT(ErrorOf(head + "mode = \"sorted\"\n"),
              AllOf(HasSubstr("population.rollers.mode"), HasSubstr("\"process\", \"inspected\"")));
}

// [tolerances.rollers] rollers: the class draws only the rollers named; one left out keeps
// the scene's outline (a measured roller judged alone), in the allocation's classes too.
TEST(SamplingFile, ARollerClassCanLeaveAMeasuredRollerOut) {
  const std::string table = "[tolerances.rollers]\nclass = \"Normal\"\n";
  const SamplingPlan plan = ReadVariant(kSceneLine + table + "rollers = [\"fixed_a\", \"fixed_b\"]\n");
  ASSERT_EQ(plan.tolerances.roller_shapes.size(), 3u);
  EXPECT_FALSE(plan.tolerances.roller_shapes[0].has_value());  // spring
  EXPECT_TRUE(plan.tolerances.roller_shapes[1].has_value());
  EXPECT_TRUE(plan.tolerances.roller_shapes[2].has_value());
  const sampling::AssemblyTolerances classed = ToleranceOfClass(plan, sampling::ErrorSource::kRollerShape, "5",
                                                                sampling::ToleranceMode::kProcess);
  EXPECT_FALSE(classed.roller_shapes[0].has_value());
  EXPECT_TRUE(classed.roller_shapes[1].has_value());
  EXPECT_THAT(ErrorOf(kSceneLine + table + "rollers = [\"fixed_c\"]\n"),
              AllOf(HasSubstr("tolerances.rollers.rollers"), HasSubstr("names no roller \"fixed_c\""),
                    HasSubstr("spring, fixed_a, fixed_b")));
  EXPECT_THAT(ErrorOf(kSceneLine + table + "rollers = [\"fixed_a\", \"fixed_a\"]\n"),
              HasSubstr("names twice \"fixed_a\""));
  EXPECT_THAT(ErrorOf(kSceneLine + table + "rollers = []\n"), HasSubstr("names no roller"));
}

TEST(SamplingFile, ABadPopulationNamesItsKeyAndWhatIsAllowed) {
  const std::string rings = (std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/populations/rings").string();
  const std::string one = "\"" + rings + "/ring_01.csv\"";
  const std::string head = kSceneLine + "[population.ring]\norders = 8\n";
  EXPECT_THAT(ErrorOf(head + "profiles = [" + one + "]\nfolder = \"" + rings + "\"\n"),
              AllOf(HasSubstr("profiles"), HasSubstr("folder")));
  EXPECT_THAT(ErrorOf(head), AllOf(HasSubstr("population.ring"), HasSubstr("folder")));
  EXPECT_THAT(ErrorOf(head + "folder = \"" + rings + "/none\"\n"), HasSubstr("no such folder"));
  EXPECT_THAT(ErrorOf(head + "profiles = []\n"), AllOf(HasSubstr("population.ring.profiles"), HasSubstr("no profiles")));
  EXPECT_THAT(ErrorOf(head + "profiles = [\"missing.csv\"]\n"), HasSubstr("no such file"));
  EXPECT_THAT(ErrorOf(head + "profiles = [" + one + "]\ndraw = \"model\"\n"),
              AllOf(HasSubstr("population.ring.draw"), HasSubstr("at least 2 parts")));
  EXPECT_THAT(ErrorOf(head + "profiles = [" + one + "]\ndraw = \"bootstrap\"\n"),
              AllOf(HasSubstr("population.ring.draw"), HasSubstr("\"resample\", \"model\"")));
  EXPECT_THAT(ErrorOf(head + "profiles = [" + one + "]\n[tolerances.ring]\nclass = \"waterjet\"\n"),
              AllOf(HasSubstr("population.ring"), HasSubstr("[tolerances.ring] draws it too")));
  EXPECT_EQ(ErrorOf(head + "profiles = [" + one + "]\n"), "no error");
}

TEST(SamplingFile, CampaignCataloguesAddClasses) {
  const SamplingPlan plan = ReadVariant(
      kSceneLine + "[tolerances.ring]\nclass = \"lapped\"\n"
      "[[catalogue.ring]]\nname = \"lapped\"\n"
      "rows = [{ diameter_over_mm = 0, diameter_up_to_mm = 1000, circularity_mm = 0.005, source = \"shop\" }]\n");
  EXPECT_DOUBLE_EQ(plan.tolerances.ring->circularity, 5e-6);
}

}  // namespace
}  // namespace ringtol::jobs
