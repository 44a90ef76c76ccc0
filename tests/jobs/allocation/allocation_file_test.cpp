// Allocation files: the example reads into its candidates, their costs and characteristic
// tolerances (known exactly from the catalogue), and every refusal names the file, the key
// and what is allowed.
#include "jobs/allocation/allocation_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "jobs/inputs/input_error.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using testing::ReplaceOnce;

const std::filesystem::path kExample = std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/allocation/default.toml";

// The example with its scene found from anywhere, so that variants can live in a
// temporary directory.
std::string ExampleText() {
  return ReplaceOnce(testing::ReadText(kExample), "scene = \"../paper/scene.toml\"",
                     "scene = \"" + (std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/paper/scene.toml").string() +
                         "\"");
}

// A file of this test's own (ctest runs tests in parallel), removed at the end.
class TempFile {
 public:
  explicit TempFile(const std::string& text) {
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string("ringtol_") + test->test_suite_name() + "_" + test->name() + ".toml";
    for (char& c : name) {
      if (c == '/') c = '_';
    }
    path_ = std::filesystem::temp_directory_path() / name;
    testing::WriteText(path_, text);
  }
  ~TempFile() { std::filesystem::remove(path_); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// Costs from a table are the file's numbers; from a model, a few operations on them.
constexpr double kModelCostTolerance = 1e-12;  // relative: a division and a power, ~ 4 eps

TEST(AllocationFile, TheExampleHasItsCandidatesCostsAndCurrentDesign) {
  const AllocationPlan plan = ReadAllocationFile(kExample);
  ASSERT_EQ(plan.components.size(), 4u);
  const std::vector<AllocatedComponent> order{AllocatedComponent::kRing, AllocatedComponent::kRollers,
                                              AllocatedComponent::kRollerPositions, AllocatedComponent::kSprings};
  std::size_t candidates = 1;
  for (std::size_t c = 0; c < order.size(); ++c) {
    EXPECT_EQ(plan.components[c].component, order[c]);
    candidates *= plan.components[c].options.size();
  }
  EXPECT_EQ(candidates, 5u * 4u * 4u * 2u);
  EXPECT_EQ(plan.search.kind, analysis::SearchKind::kExhaustive);  // 160 <= max_exhaustive 256
  EXPECT_EQ(plan.screen, solvers::Rung::kLinear);
  EXPECT_EQ(plan.first_samples, 256);
  EXPECT_EQ(plan.campaign.sampling.samples, 2048);
  EXPECT_EQ(plan.campaign.solver.rung, solvers::Rung::kAuto);
  ASSERT_EQ(plan.constraints.size(), 2u);
  EXPECT_EQ(plan.constraints[0].output, "d_trajectory_mm");
  EXPECT_EQ(plan.constraints[0].kind, analysis::ConstraintKind::kQuantile);
  EXPECT_EQ(plan.constraints[0].level, 0.99);
  EXPECT_EQ(plan.constraints[1].output, "static_offset_mm");

  // waterjet, Normal (inspected), IT7, pm10: options 0, 0, 2, 0 in radix (5, 4, 4, 2),
  // the last component fastest.
  ASSERT_TRUE(plan.current.has_value());
  EXPECT_EQ(*plan.current, ((0 * 4 + 0) * 4 + 2) * 2 + 0);

  // Table costs as written.
  EXPECT_EQ(plan.components[0].options[2].cost, 3.0);
  EXPECT_EQ(plan.components[1].options[3].cost, 1.5);
  EXPECT_FALSE(plan.components[0].cost_model.has_value());
  // Model costs: b / t with b = 70 and t the zone diameter in um.
  ASSERT_TRUE(plan.components[2].cost_model.has_value());
  for (const AllocationOption& option : plan.components[2].options)
    EXPECT_NEAR(option.cost, 70.0 / option.tolerance, kModelCostTolerance * option.cost) << option.class_name;
}

// The characteristic tolerances are the catalogue's numbers at the paper scene's
// diameters: bore 604 mm, rollers 10 mm, centre circle 594 mm (jobs/inputs/catalogue.toml).
TEST(AllocationFile, CharacteristicTolerancesAreTheCatalogueValuesAtThePartsDiameters) {
  const AllocationPlan plan = ReadAllocationFile(kExample);
  const std::vector<std::vector<double>> expected{
      {200, 100, 35, 22, 16},  // ring RONt [um], rows over 500 up to 630 mm
      {15, 8, 5, 3},           // roller Kea [um], rows over 6 up to 18 mm
      {175, 110, 70, 44},      // position zone [um], IT9..IT6 over 500 up to 630 mm
      {10, 5},                 // spring stiffness [%]
  };
  // The catalogue's mm and um converted to m and back: a product and a quotient.
  constexpr double kConversionTolerance = 1e-12;  // [um or %], ~ 4 eps x 200
  for (std::size_t c = 0; c < expected.size(); ++c) {
    ASSERT_EQ(plan.components[c].options.size(), expected[c].size());
    for (std::size_t o = 0; o < expected[c].size(); ++o)
      EXPECT_NEAR(plan.components[c].options[o].tolerance, expected[c][o], kConversionTolerance)
          << plan.components[c].options[o].class_name;
  }
  EXPECT_EQ(plan.components[1].options[2].mode, sampling::ToleranceMode::kInspected);  // inherited
  EXPECT_EQ(plan.components[0].options[2].mode, sampling::ToleranceMode::kProcess);
}

TEST(AllocationFile, ACandidatesTolerancesReplaceEachAllocatedComponentOfTheCurrentDesign) {
  const AllocationPlan plan = ReadAllocationFile(kExample);
  const sampling::AssemblyTolerances current = plan.Tolerances(*plan.current);
  const sampling::AssemblyTolerances& file = plan.campaign.sampling.tolerances;
  EXPECT_EQ(current.ring->circularity, file.ring->circularity);
  EXPECT_EQ(current.ring->spectrum, file.ring->spectrum);
  ASSERT_EQ(current.roller_shapes.size(), file.roller_shapes.size());
  EXPECT_EQ(current.roller_shapes[1]->kea, file.roller_shapes[1]->kea);
  EXPECT_EQ(current.roller_positions[2]->zone_diameter, file.roller_positions[2]->zone_diameter);

  // The tightest candidate: IT5/2, class 4 (still inspected), IT6, pm5.
  const std::int64_t tightest = 5 * 4 * 4 * 2 - 1;
  const sampling::AssemblyTolerances t = plan.Tolerances(tightest);
  EXPECT_EQ(t.ring->class_name, "IT5/2");
  EXPECT_EQ(t.ring->spectrum, file.ring->spectrum);
  for (const auto& roller : t.roller_shapes) {
    EXPECT_EQ(roller->class_name, "4");
    EXPECT_EQ(roller->capability.mode, sampling::ToleranceMode::kInspected);
  }
  for (const auto& position : t.roller_positions) EXPECT_EQ(position->class_name, "IT6");
  // Springs only on the spring roller (the paper scene's first).
  ASSERT_EQ(t.springs.size(), 3u);
  EXPECT_EQ(t.springs[0]->class_name, "pm5");
  EXPECT_FALSE(t.springs[1].has_value());
}

TEST(AllocationFile, AComponentWithoutATableTakesTheDefaultsAndNoCurrentCandidateExists) {
  std::string text = ReplaceOnce(ExampleText(), "[tolerances.springs]\nclass = \"pm10\"\n", "");
  text = ReplaceOnce(text, "reference = \"current\"", "reference = \"loosest\"");
  const TempFile file(text);
  const AllocationPlan plan = ReadAllocationFile(file.path());
  EXPECT_FALSE(plan.current.has_value());
  EXPECT_EQ(plan.components[3].options[1].tolerances.springs[0]->capability.mode, sampling::ToleranceMode::kProcess);
}

TEST(AllocationFile, AnInlineOptionSetsItsModeAndAnAliasIsTheCurrentClass) {
  std::string text = ReplaceOnce(ExampleText(), "options = [\"Normal\", \"6\", \"5\", \"4\"]",
                                 "options = [\"P0\", \"6\", { class = \"6\", mode = \"inspected\" }]");
  text = ReplaceOnce(text, "[tolerances.rollers]\nclass = \"Normal\"\nmode = \"inspected\"\n",
                     "[tolerances.rollers]\nclass = \"Normal\"\n");
  text = ReplaceOnce(text, "cost = [0.3, 0.45, 0.8, 1.5]", "cost = [0.3, 0.45, 0.5]");
  const TempFile file(text);
  const AllocationPlan plan = ReadAllocationFile(file.path());
  const ComponentChoice& rollers = plan.components[1];
  EXPECT_EQ(rollers.options[1].mode, sampling::ToleranceMode::kProcess);
  EXPECT_EQ(rollers.options[2].mode, sampling::ToleranceMode::kInspected);
  // "P0" is Normal's alias; the file's rollers are Normal in process mode: option 0.
  ASSERT_TRUE(plan.current.has_value());
  EXPECT_EQ(*plan.current, ((0 * 3 + 0) * 4 + 2) * 2 + 0);
}

// ISO 492 class 6 at 6 < D <= 18 mm: VDsp 9 um in diameter series 9, 5 um in series 2-4
// (jobs/inputs/catalogue.toml); an option is looked up in its table's series.
TEST(AllocationFile, RollerOptionsAreLookedUpInTheTablesDiameterSeries) {
  const TempFile file(ReplaceOnce(ExampleText(), "mode = \"inspected\"\n", "mode = \"inspected\"\ndiameter_series = \"2\"\n"));
  const AllocationPlan plan = ReadAllocationFile(file.path());
  constexpr double kVdspSeries2 = 5e-6;  // [m], the catalogue's number, converted exactly enough
  constexpr double kConversionTolerance = 1e-18;  // [m], ~ eps x 5e-6
  for (const auto& roller : plan.components[1].options[1].tolerances.roller_shapes)
    EXPECT_NEAR(roller->vdsp, kVdspSeries2, kConversionTolerance);
}

TEST(AllocationFile, BranchAndBoundIsChosenAboveMaxExhaustiveCandidates) {
  const TempFile file(ReplaceOnce(ExampleText(), "search = \"auto\"", "search = \"auto\"\nmax_exhaustive = 100"));
  EXPECT_EQ(ReadAllocationFile(file.path()).search.kind, analysis::SearchKind::kBranchAndBound);
}

TEST(AllocationFile, AFileWithoutConstraintsIsRefused) {
  std::string text = ExampleText();
  const std::size_t from = text.find("[[allocation.constraint]]");
  const std::size_t to = text.find("# Relative costs");
  ASSERT_LT(from, to);
  const TempFile file(text.erase(from, to - from));
  std::string message = "no error";
  try {
    ReadAllocationFile(file.path());
  } catch (const InputError& e) {
    message = e.what();
  }
  EXPECT_THAT(message, AllOf(HasSubstr(file.path().string()), HasSubstr("allocation.constraint"),
                             HasSubstr("at least 1 [[constraint]]")));
}

// One refused variant of the example: what to replace, and what the message must name
// besides the file.
struct Refusal {
  std::string name;
  std::string from;
  std::string to;
  std::vector<std::string> names;  // the key path, the value, what is allowed
};

void PrintTo(const Refusal& refusal, std::ostream* out) { *out << refusal.name; }

class AllocationFileRefusal : public ::testing::TestWithParam<Refusal> {};

TEST_P(AllocationFileRefusal, NamesTheFileTheKeyAndWhatIsAllowed) {
  const Refusal& refusal = GetParam();
  const TempFile file(ReplaceOnce(ExampleText(), refusal.from, refusal.to));
  std::string message = "no error";
  try {
    ReadAllocationFile(file.path());
  } catch (const InputError& e) {
    message = e.what();
  }
  EXPECT_THAT(message, HasSubstr(file.path().string()));
  for (const std::string& expected : refusal.names) EXPECT_THAT(message, HasSubstr(expected));
}

const std::string kRingOptions = "options = [\"waterjet\", \"precise\", \"IT7/2\", \"IT6/2\", \"IT5/2\"]";
const std::string kRingCost = "cost = [1.0, 1.6, 3.0, 4.5, 7.0]";
const std::string kQuantile = "output = \"d_trajectory_mm\"\nquantile = 0.99\nupper_mm = 0.053";

INSTANTIATE_TEST_SUITE_P(
    EveryRule, AllocationFileRefusal,
    ::testing::Values(
        // The rollers' lobes to order 8 pass 8 x 302 / 5 = 483.2 times a revolution.
        Refusal{"StepsTooFewForTheRollersLobes", "path_tolerance_um = 1.0\n", "path_tolerance_um = 1.0\nsteps = 966\n",
                {"solver.steps = 966", "too few", ">= 967", "order 8, 483.2 per revolution"}},
        Refusal{"UnknownClass", "\"IT6/2\", \"IT5/2\"]", "\"IT6/2\", \"IT4/2\"]",
                {"allocation.components.ring.options[4]", "IT4/2", "\"waterjet\", \"precise\""}},
        Refusal{"UnknownMode", "\"6\", \"5\", \"4\"]", "\"6\", \"5\", { class = \"4\", mode = \"sorted\" }]",
                {"allocation.components.rollers.options[3].mode", "sorted", "\"process\", \"inspected\""}},
        Refusal{"NegativeCost", kRingCost, "cost = [-1.0, 1.6, 3.0, 4.5, 7.0]",
                {"allocation.components.ring.cost[0]", "-1", ">= 0"}},
        Refusal{"CostFalling", kRingCost, "cost = [1.0, 1.6, 1.5, 4.5, 7.0]",
                {"allocation.components.ring.cost[2]", "1.5", ">= 1.6"}},
        Refusal{"CostCountWrong", kRingCost, "cost = [1.0, 1.6]",
                {"allocation.components.ring.cost", "5 numbers >= 0"}},
        Refusal{"OptionsOutOfOrder", kRingOptions, "options = [\"waterjet\", \"IT7/2\", \"precise\", \"IT6/2\", \"IT5/2\"]",
                {"allocation.components.ring.options[2]", "precise", "loosest first", "<= 35 µm"}},
        Refusal{"InspectedBeforeProcess", "options = [\"pm10\", \"pm5\"]",
                "options = [{ class = \"pm10\", mode = \"inspected\" }, \"pm10\"]",
                {"allocation.components.springs.options[1]", "process before inspected"}},
        Refusal{"EmptyOptions", kRingOptions, "options = []",
                {"allocation.components.ring.options", "non-empty array"}},
        Refusal{"OutputThatDoesNotExist", "output = \"static_offset_mm\"", "output = \"wobble_mm\"",
                {"allocation.constraint[1].output", "wobble_mm", "\"static_offset_mm\"", "\"runout_mm\""}},
        Refusal{"NeitherQuantileNorYield", kQuantile, "output = \"d_trajectory_mm\"\nupper_mm = 0.053",
                {"allocation.constraint[0]", "quantile", "yield", "exactly one"}},
        Refusal{"BothQuantileAndYield", kQuantile, "output = \"d_trajectory_mm\"\nquantile = 0.99\nyield = 0.9\nupper_mm = 0.053",
                {"allocation.constraint[0].yield", "exactly one"}},
        Refusal{"YieldOutOfRange", kQuantile, "output = \"d_trajectory_mm\"\nyield = 1.0\nupper_mm = 0.053",
                {"allocation.constraint[0].yield", "> 0 and < 1"}},
        Refusal{"WrongUpperUnit", kQuantile, "output = \"d_trajectory_mm\"\nquantile = 0.99\nupper_N = 0.053",
                {"allocation.constraint[0].upper_N", "upper_mm > 0"}},
        Refusal{"DesignWhosePrefixesAreNotIndependentDraws", "kind = \"sobol\"", "kind = \"latin_hypercube\"",
                {"design.kind", "latin_hypercube", "\"monte_carlo\""}},
        Refusal{"ScreenForARungItsBoundIsNotKnownAgainst", "name = \"auto\"", "name = \"dynamic\"",
                {"allocation.screen", "dynamic", "\"none\""}},
        Refusal{"SpecPresent", "[allocation]\n", "[spec]\nd_trajectory_mm = 0.3\n\n[allocation]\n",
                {"spec", "[[allocation.constraint]]"}},
        Refusal{"ReferenceCurrentWithoutACurrentCandidate", "options = [\"IT9\", \"IT8\", \"IT7\", \"IT6\"]",
                "options = [\"IT9\", \"IT8\", \"IT6\"]",
                {"allocation.reference", "[tolerances.roller_positions] class \"IT7\"", "\"loosest\""}},
        Refusal{"UnknownComponent", "[allocation.components.springs]", "[allocation.components.bearings]",
                {"unknown key 'allocation.components.bearings'", "ring", "roller_positions", "springs"}},
        Refusal{"UnknownSearch", "search = \"auto\"", "search = \"genetic\"",
                {"allocation.search", "genetic", "\"auto\", \"exhaustive\", \"branch_and_bound\""}},
        Refusal{"UnknownScreen", "screen = \"linear\"", "screen = \"dynamic\"",
                {"allocation.screen", "dynamic", "\"linear\", \"none\""}},
        Refusal{"BatchOutOfRange", "first_samples = 256", "first_samples = 256\nbatch = 0",
                {"allocation.batch", ">= 1 and <= 4096"}},
        Refusal{"FirstSamplesAboveTheDesign", "first_samples = 256", "first_samples = 4096",
                {"allocation.first_samples", "4096", "design.samples"}},
        Refusal{"ConfidenceOutOfRange", "confidence = 0.95", "confidence = 1.5",
                {"allocation.confidence", "1.5", "> 0 and < 1"}},
        Refusal{"ModelParameterOutOfRange", "b = 70.0", "b = 0.0",
                {"allocation.components.roller_positions.cost_model.b", "> 0"}},
        Refusal{"CostAndCostModel", "cost = [0.1, 0.2]", "cost = [0.1, 0.2]\ncost_model = { b = 1.0 }",
                {"allocation.components.springs.cost_model", "either cost or cost_model"}},
        // A spring class without a preload tolerance leaves the preload input out.
        Refusal{"OptionsDrawingOtherInputs", "options = [\"pm10\", \"pm5\"]\ncost = [0.1, 0.2]",
                "options = [\"pm10\", \"stiff_only\"]\ncost = [0.1, 0.2]\n\n[[catalogue.spring]]\n"
                "name = \"stiff_only\"\nrows = [{ stiffness_percent = 2, preload_percent = 0, source = \"test\" }]",
                {"allocation.components.springs.options[1]", "stiff_only", "common random numbers"}}),
    [](const ::testing::TestParamInfo<Refusal>& refusal) { return refusal.param.name; });

}  // namespace
}  // namespace ringtol::jobs
