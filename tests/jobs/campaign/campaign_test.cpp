// Campaign files, the evaluation of one sample, the summary, and a campaign rebuilt from
// its results file with the calibrations stored there, in process (the pool and the
// command line are tested through the executable in tests/jobs/mpi/).
#include "jobs/campaign/campaign.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "jobs/report/campaign_summary.h"
#include "jobs/inputs/input_error.h"
#include "jobs/store/campaign_store.h"
#include "tests/support/small_campaign.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

const std::string kSceneLine =
    "scene = \"" + (std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/paper/scene.toml").string() + "\"\n";

// Quick to calibrate and to solve: a low-order ring spectrum, positions and springs.
const std::string kSmallCampaign = ringtol::testing::SmallCampaign(
    (std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/paper/scene.toml").string(), 7, 16,
    "[tolerances.springs]\nclass = \"pm10\"\n");

// A file of this test's own (ctest runs tests in parallel), removed at the end.
class TempFile {
 public:
  TempFile(const std::string& text, const std::string& extension = ".toml") {
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            (std::string("ringtol_") + test->test_suite_name() + "_" + test->name() + extension);
    std::filesystem::remove(path_);
    if (!text.empty()) std::ofstream(path_) << text;
  }
  ~TempFile() { std::filesystem::remove(path_); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

std::string CampaignErrorOf(const std::string& text) {
  const TempFile file(text);
  try {
    Campaign campaign(file.path(), std::nullopt, std::nullopt);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

// The identity a results file of `campaign` at `path` reads back with.
CampaignIdentity StoredIdentityOf(const Campaign& campaign, const std::filesystem::path& path) {
  CampaignStore::Create(path, campaign.identity(), campaign.samples());
  return CampaignReader(path).identity();
}

TEST(CampaignFile, ReadsSolverAndSpecBesideTheSamplingTables) {
  const TempFile file(kSmallCampaign + "[catalogue]\n");
  const CampaignPlan plan = ReadCampaignFile(file.path());
  EXPECT_EQ(plan.solver.rung, solvers::Rung::kQuasistatic);
  EXPECT_EQ(plan.solver.simulation.steps, 0);
  constexpr double kDefaultPathTolerance = 1e-6;  // [m] the documented default, 1 um
  EXPECT_EQ(plan.solver.simulation.path_tolerance, kDefaultPathTolerance);
  ASSERT_EQ(plan.spec.size(), 1u);
  EXPECT_EQ(plan.spec[0].output, "d_trajectory_mm");
  EXPECT_EQ(plan.spec[0].upper, 0.25);
  EXPECT_EQ(plan.sampling.samples, 16);
}

TEST(CampaignFile, TheSolverDefaultsToTheAutoRungAtAOneMicrometreBudget) {
  const TempFile file(testing::ReplaceOnce(kSmallCampaign, "name = \"quasistatic\"\n", ""));
  const CampaignPlan plan = ReadCampaignFile(file.path());
  EXPECT_EQ(plan.solver.rung, solvers::Rung::kAuto);
  constexpr double kDefaultPathTolerance = 1e-6;  // [m] the documented default, 1 um
  EXPECT_EQ(plan.solver.simulation.path_tolerance, kDefaultPathTolerance);
  EXPECT_EQ(plan.solver.rung, CampaignSolverDefaults().rung);
}

TEST(CampaignFile, BadKeysNameTheKeyTheValueAndWhatIsAllowed) {
  using testing::ReplaceOnce;
  EXPECT_THAT(CampaignErrorOf(ReplaceOnce(kSmallCampaign, "name = \"quasistatic\"", "name = \"explicit\"")),
              AllOf(HasSubstr("solver.name"), HasSubstr("explicit"), HasSubstr("\"quasistatic\"")));
  EXPECT_THAT(CampaignErrorOf(ReplaceOnce(kSmallCampaign, "d_trajectory_mm = 0.25", "d_trajectory_mm = -1")),
              AllOf(HasSubstr("spec.d_trajectory_mm"), HasSubstr("-1"), HasSubstr("> 0")));
  EXPECT_THAT(CampaignErrorOf(ReplaceOnce(kSmallCampaign, "d_trajectory_mm = 0.25", "runout_um = 3")),
              AllOf(HasSubstr("unknown key 'spec.runout_um'"), HasSubstr("runout_mm")));
  EXPECT_THAT(CampaignErrorOf(kSmallCampaign + "[output]\n"),
              AllOf(HasSubstr("unknown key 'output'"), HasSubstr("solver"), HasSubstr("spec")));
  EXPECT_THAT(CampaignErrorOf(ReplaceOnce(kSmallCampaign, "[solver]\n", "[solver]\npath_tolerance_um = -2\n")),
              AllOf(HasSubstr("solver.path_tolerance_um"), HasSubstr(">= 0")));
  EXPECT_THAT(CampaignErrorOf(ReplaceOnce(kSmallCampaign, "zone_diameter_mm = 0.05", "class = \"IT99\"")),
              HasSubstr("IT99"));
  // The ring is drawn to order 6: 13 angles sample it more than twice a period.
  EXPECT_THAT(CampaignErrorOf(ReplaceOnce(kSmallCampaign, "[solver]\n", "[solver]\nsteps = 12\n")),
              AllOf(HasSubstr("solver.steps = 12"), HasSubstr("too few"), HasSubstr(">= 13"),
                    HasSubstr("the ring's order 6, 6 per revolution")));
  EXPECT_EQ(CampaignErrorOf(ReplaceOnce(kSmallCampaign, "[solver]\n", "[solver]\nsteps = 13\n")), "no error");
  EXPECT_THAT(CampaignErrorOf(ReplaceOnce(kSmallCampaign, "[solver]\n", "[solver]\nstart = \"at_rest\"\n")),
              AllOf(HasSubstr("solver.start"), HasSubstr("at_rest"), HasSubstr("\"quasistatic_equilibrium\""),
                    HasSubstr("\"article_settle\"")));
}

// The dynamic rung's start is a stated choice: the quasistatic equilibrium unless the file
// says otherwise, and the results file's solver names it.
TEST(CampaignFile, TheDynamicStartDefaultsToTheQuasistaticEquilibriumAndIsRecorded) {
  using testing::ReplaceOnce;
  const std::string dynamic = ReplaceOnce(kSmallCampaign, "name = \"quasistatic\"", "name = \"dynamic\"");
  const TempFile default_start(dynamic);
  EXPECT_EQ(ReadCampaignFile(default_start.path()).solver.dynamic_start, solvers::DynamicStart::kQuasistaticEquilibrium);
  const Campaign campaign(default_start.path(), std::nullopt, std::nullopt);
  EXPECT_EQ(campaign.identity().solver, "dynamic, start quasistatic_equilibrium");
  const TempFile article(ReplaceOnce(dynamic, "[solver]\n", "[solver]\nstart = \"article_settle\"\n"));
  EXPECT_EQ(ReadCampaignFile(article.path()).solver.dynamic_start, solvers::DynamicStart::kArticleSettle);
}

// solver.accuracy: full unless the file says fast; the setting is the campaign's identity,
// named in its solver, stored, and read back.
const std::string kFast = testing::ReplaceOnce(kSmallCampaign, "[solver]\n", "[solver]\naccuracy = \"fast\"\n");

TEST(CampaignFile, TheAccuracyIsFullUnlessSolverAccuracyIsFastAndIsRecorded) {
  const TempFile by_default(kSmallCampaign, "_default.toml");
  const Campaign full(by_default.path(), std::nullopt, std::nullopt);
  EXPECT_EQ(full.simulation().accuracy, solvers::Accuracy::kFull);
  EXPECT_EQ(full.identity().solver, "quasistatic");
  const TempFile fast_file(kFast, "_fast.toml");
  const Campaign fast(fast_file.path(), std::nullopt, std::nullopt);
  EXPECT_EQ(fast.simulation().accuracy, solvers::Accuracy::kFast);
  EXPECT_EQ(fast.identity().solver, "quasistatic, accuracy fast");
  const TempFile results("", ".h5");
  const CampaignIdentity stored = StoredIdentityOf(fast, results.path());
  EXPECT_EQ(stored.accuracy, solvers::Accuracy::kFast);
  EXPECT_EQ(Campaign(stored, fast.samples()).simulation().accuracy, solvers::Accuracy::kFast);
}

TEST(CampaignFile, AnUnknownAccuracyNamesTheFileTheKeyTheValueAndTheSettings) {
  const TempFile file(testing::ReplaceOnce(kSmallCampaign, "[solver]\n", "[solver]\naccuracy = \"rough\"\n"));
  try {
    Campaign campaign(file.path(), std::nullopt, std::nullopt);
    ADD_FAILURE() << "read accuracy = \"rough\"";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), AllOf(HasSubstr(file.path().string()), HasSubstr("solver.accuracy"), HasSubstr("rough"),
                                HasSubstr("\"full\""), HasSubstr("\"fast\"")));
  }
}

TEST(CampaignStore, ResumeRefusesAChangedAccuracyNamingIt) {
  const TempFile full_file(kSmallCampaign, "_full.toml");
  const TempFile fast_file(kFast, "_fast.toml");
  const Campaign full(full_file.path(), std::nullopt, std::nullopt);
  const Campaign fast(fast_file.path(), std::nullopt, std::nullopt);
  for (const auto& [written, resumed, from, to] :
       {std::tuple{&full, &fast, "full", "fast"}, std::tuple{&fast, &full, "fast", "full"}}) {
    const TempFile results("", ".h5");
    CampaignStore::Create(results.path(), written->identity(), written->samples());
    try {
      CampaignStore::Resume(results.path(), resumed->identity(), resumed->samples());
      ADD_FAILURE() << "resumed a file of accuracy " << from << " at accuracy " << to;
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), AllOf(HasSubstr("another campaign"),
                                  HasSubstr(fmt::format("solver.accuracy differs ('{}' in the file, '{}' now)", from, to))));
    }
    EXPECT_NO_THROW(CampaignStore::Resume(results.path(), written->identity(), written->samples()));
  }
}

// [outputs] life: on unless the file says false; the choice is the campaign's identity.
const std::string kLifeOff = kSmallCampaign + "[outputs]\nlife = false\n";

TEST(CampaignFile, TheLifeIsComputedUnlessOutputsLifeIsFalse) {
  const TempFile by_default(kSmallCampaign, "_default.toml");
  EXPECT_TRUE(ReadCampaignFile(by_default.path()).solver.simulation.life);
  const TempFile on(kSmallCampaign + "[outputs]\nlife = true\n", "_on.toml");
  EXPECT_TRUE(ReadCampaignFile(on.path()).solver.simulation.life);
  const TempFile off(kLifeOff);
  EXPECT_FALSE(ReadCampaignFile(off.path()).solver.simulation.life);
  EXPECT_FALSE(Campaign(off.path(), std::nullopt, std::nullopt).identity().life);
  EXPECT_TRUE(Campaign(on.path(), std::nullopt, std::nullopt).identity().life);
}

TEST(CampaignFile, ABadOutputsKeyOrALimitOnAnOutputLeftOutNamesTheKeyTheValueAndWhatIsAllowed) {
  using testing::ReplaceOnce;
  EXPECT_THAT(CampaignErrorOf(kSmallCampaign + "[outputs]\nlife = \"no\"\n"),
              AllOf(HasSubstr("outputs.life = \"no\""), HasSubstr("true or false")));
  EXPECT_THAT(CampaignErrorOf(kSmallCampaign + "[outputs]\nlife = 0\n"),
              AllOf(HasSubstr("outputs.life = 0"), HasSubstr("true or false")));
  EXPECT_THAT(CampaignErrorOf(kSmallCampaign + "[outputs]\nswing = false\n"),
              AllOf(HasSubstr("unknown key 'outputs.swing'"), HasSubstr("life")));
  EXPECT_THAT(CampaignErrorOf("outputs = false\n" + kSmallCampaign),
              AllOf(HasSubstr("outputs = false"), HasSubstr("a table [outputs]")));
  // A limit on a life output the campaign does not compute, whichever table comes first.
  for (const std::string& text :
       {ReplaceOnce(kLifeOff, "d_trajectory_mm = 0.25", "error_motion_total_mm = 0.01"),
        ReplaceOnce(ReplaceOnce(kSmallCampaign, "[solver]\n", "[outputs]\nlife = false\n[solver]\n"),
                    "d_trajectory_mm = 0.25", "life_runout_mm = 0.05")}) {
    const std::string error = CampaignErrorOf(text);
    EXPECT_THAT(error, AllOf(HasSubstr(".toml:"), HasSubstr("spec."), HasSubstr("only when outputs.life = true")));
    EXPECT_THAT(error, ::testing::AnyOf(HasSubstr("spec.error_motion_total_mm = 0.01"),
                                        HasSubstr("spec.life_runout_mm = 0.05")));
  }
  // The one-revolution outputs keep their limits.
  EXPECT_EQ(CampaignErrorOf(ReplaceOnce(kLifeOff, "d_trajectory_mm = 0.25", "runout_mm = 0.05")), "no error");
}

// [disposition]: read in fractions, its confidence 95 % unless stated; a disposition
// without a [spec] limit, at 100 % or below 50 % confidence, is refused naming the key.
TEST(CampaignFile, ADispositionReadsItsRequirementAndNeedsASpecLimit) {
  using testing::ReplaceOnce;
  const TempFile stated(kSmallCampaign + "[disposition]\nrequired_yield_percent = 99.5\nconfidence_percent = 90\n");
  const std::optional<DispositionRule> rule = ReadCampaignFile(stated.path()).disposition;
  ASSERT_TRUE(rule.has_value());
  EXPECT_DOUBLE_EQ(rule->required_yield, 0.995);
  EXPECT_DOUBLE_EQ(rule->confidence, 0.90);
  const TempFile defaulted(kSmallCampaign + "[disposition]\nrequired_yield_percent = 99\n");
  EXPECT_DOUBLE_EQ(ReadCampaignFile(defaulted.path()).disposition->confidence, 0.95);
  EXPECT_FALSE(ReadCampaignFile(TempFile(kSmallCampaign).path()).disposition.has_value());

  const std::string without_spec = ReplaceOnce(kSmallCampaign, "[spec]\nd_trajectory_mm = 0.25\n", "");
  EXPECT_THAT(CampaignErrorOf(without_spec + "[disposition]\nrequired_yield_percent = 99\n"),
              AllOf(HasSubstr(".toml:"), HasSubstr("disposition.required_yield_percent"), HasSubstr("[spec]")));
  EXPECT_THAT(CampaignErrorOf(kSmallCampaign + "[disposition]\nrequired_yield_percent = 100\n"),
              AllOf(HasSubstr("disposition.required_yield_percent = 100"), HasSubstr("> 0 and < 100")));
  EXPECT_THAT(CampaignErrorOf(kSmallCampaign + "[disposition]\nrequired_yield_percent = 99\nconfidence_percent = 40\n"),
              AllOf(HasSubstr("disposition.confidence_percent = 40"), HasSubstr(">= 50 and < 100")));
  EXPECT_THAT(CampaignErrorOf(kSmallCampaign + "[disposition]\nconfidence_percent = 90\n"),
              HasSubstr("disposition.required_yield_percent"));
}

// With the life off the solver never computes it (not merely drops it), the one-revolution
// outputs are the same bits, the results file holds no life column and the summary says
// the life was not computed instead of showing numbers.
TEST(SampleEvaluator, WithTheLifeOffTheSolverSkipsItAndTheSummarySaysItWasNotComputed) {
  const TempFile on_file(kSmallCampaign, "_on.toml");
  const TempFile off_file(kLifeOff, "_off.toml");
  const TempFile results("", ".h5");
  const Campaign on(on_file.path(), std::nullopt, std::nullopt);
  const Campaign off(off_file.path(), std::nullopt, std::nullopt);
  int computed_life = 0;
  EvaluatorFaults watch;
  watch.after_simulate = [&computed_life](std::int64_t, solvers::SimulationResult& result) {
    computed_life += result.life.has_value() ? 1 : 0;
  };
  SampleEvaluator with_life(on);
  SampleEvaluator without_life(off, watch);
  {
    CampaignStore store = CampaignStore::Create(results.path(), off.identity(), off.samples());
    for (std::int64_t i = 0; i < off.samples(); ++i) {
      SampleRecord record = without_life.Evaluate(i);
      const SampleRecord reference = with_life.Evaluate(i);
      ASSERT_EQ(record.status, SampleStatus::kOk) << record.message;
      ASSERT_EQ(reference.status, SampleStatus::kOk) << reference.message;
      for (std::size_t k = 0; k < kOutputCount; ++k) {
        if (!IsLifeOutput(k)) {
          EXPECT_TRUE(SameBits(record.outputs[k], reference.outputs[k])) << kOutputNames[k];
        } else {
          EXPECT_TRUE(std::isnan(record.outputs[k])) << kOutputNames[k];
          EXPECT_TRUE(std::isfinite(reference.outputs[k])) << kOutputNames[k];
        }
      }
      store.Add(std::move(record));
    }
    store.Commit();
  }
  EXPECT_EQ(computed_life, 0);

  const CampaignReader reader(results.path());
  EXPECT_FALSE(reader.identity().life);
  for (std::size_t k = 0; k < kOutputCount; ++k) EXPECT_EQ(reader.HasOutput(kOutputNames[k]), !IsLifeOutput(k)) << k;
  EXPECT_TRUE(CheckResults(results.path()).intact());
  const CampaignSummary summary = Summarise(reader, {});
  EXPECT_EQ(summary.ok, off.samples());
  EXPECT_FALSE(summary.life);
  EXPECT_TRUE(summary.life_gaps.empty());
  EXPECT_FALSE(summary.life_error_motion.has_value());
  for (const OutputSummary& output : summary.outputs) {
    const auto* found = std::find(kOutputNames.begin(), kOutputNames.end(), output.name);
    ASSERT_NE(found, kOutputNames.end()) << output.name;
    EXPECT_FALSE(IsLifeOutput(static_cast<std::size_t>(found - kOutputNames.begin()))) << output.name;
  }
  std::ostringstream printed;
  PrintSummary(printed, summary);
  EXPECT_THAT(printed.str(), HasSubstr("life              " + LifeNotComputed()));
  const nlohmann::json json = SummaryJson(summary);
  EXPECT_EQ(json["life"], nlohmann::json({{"computed", false}}));
  EXPECT_FALSE(json["outputs"].contains("life_d_trajectory_mm"));
}

// Resume compares the choice: a file of the life's outputs is not continued without them,
// nor the other way round, and the refusal names the key.
TEST(CampaignStore, ResumeRefusesAChangedLifeChoiceNamingIt) {
  const TempFile on_file(kSmallCampaign, "_on.toml");
  const TempFile off_file(kLifeOff, "_off.toml");
  const Campaign on(on_file.path(), std::nullopt, std::nullopt);
  const Campaign off(off_file.path(), std::nullopt, std::nullopt);
  for (const auto& [written, resumed] : {std::pair{&on, &off}, std::pair{&off, &on}}) {
    const TempFile results("", ".h5");
    CampaignStore::Create(results.path(), written->identity(), written->samples());
    try {
      CampaignStore::Resume(results.path(), resumed->identity(), resumed->samples());
      ADD_FAILURE() << "resumed a file of life = " << written->identity().life << " with life = "
                    << resumed->identity().life;
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), AllOf(HasSubstr("another campaign"),
                                  HasSubstr(fmt::format("outputs.life differs ('{}' in the file, '{}' now)",
                                                        written->identity().life, resumed->identity().life))));
    }
    EXPECT_NO_THROW(CampaignStore::Resume(results.path(), written->identity(), written->samples()));
  }
}

// A campaign rebuilt from its results file (the report's and `ringtol inputs`'s replays)
// keeps the stored choice.
TEST(Campaign, ACampaignRebuiltFromItsResultsFileKeepsItsLifeChoice) {
  const TempFile off_file(kLifeOff);
  const TempFile results("", ".h5");
  const Campaign off(off_file.path(), std::nullopt, std::nullopt);
  const Campaign rebuilt(StoredIdentityOf(off, results.path()), off.samples());
  EXPECT_FALSE(rebuilt.simulation().life);
  EXPECT_FALSE(rebuilt.identity().life);
}

TEST(SampleEvaluator, ASampleIsTheSameWhereverAndWheneverItIsComputed) {
  const TempFile file(kSmallCampaign);
  const Campaign campaign(file.path(), std::nullopt, std::nullopt);
  SampleEvaluator first(campaign);
  SampleEvaluator second(campaign);
  const SampleRecord late = (first.Evaluate(3), first.Evaluate(9));
  const SampleRecord early = second.Evaluate(9);
  ASSERT_EQ(late.status, SampleStatus::kOk) << late.message;
  EXPECT_EQ(late.u, early.u);
  EXPECT_EQ(late.values, early.values);
  for (std::size_t k = 0; k < kOutputCount; ++k) EXPECT_TRUE(SameBits(late.outputs[k], early.outputs[k])) << k;
}

TEST(SampleEvaluator, TheStoredDesignPointReplaysTheSampleAlone) {
  const TempFile file(kSmallCampaign);
  const Campaign campaign(file.path(), std::nullopt, std::nullopt);
  SampleEvaluator evaluator(campaign);
  const SampleRecord record = evaluator.Evaluate(5);
  ASSERT_EQ(record.status, SampleStatus::kOk) << record.message;
  const sampling::SampledAssembly assembly = campaign.sampling().sampler.Realise(5, record.u);
  const auto solver = campaign.MakeSolver();
  const solvers::SimulationResult replay = solvers::Simulate(assembly.scene, *solver, campaign.simulation());
  constexpr double kMillimetresPerMetre = 1e3;
  EXPECT_TRUE(SameBits(replay.d_trajectory * kMillimetresPerMetre, record.outputs[0]));
  EXPECT_EQ(assembly.values, record.values);
}

TEST(SampleDrawer, DrawsEverySampleAsTheEvaluatorDoesBitForBitInAnyOrder) {
  const TempFile file(kSmallCampaign);
  const Campaign campaign(file.path(), std::nullopt, std::nullopt);
  SampleEvaluator evaluator(campaign);
  SampleDrawer drawer(campaign);
  for (const std::int64_t index : {7, 2, 11, 0}) {
    const SampleRecord evaluated = evaluator.Evaluate(index);
    const SampleRecord drawn = drawer.Draw(index);
    EXPECT_EQ(drawn.index, index);
    EXPECT_EQ(drawn.status, SampleStatus::kPending);
    ASSERT_EQ(drawn.u.size(), evaluated.u.size());
    for (std::size_t j = 0; j < drawn.u.size(); ++j) EXPECT_TRUE(SameBits(drawn.u[j], evaluated.u[j])) << j;
    ASSERT_EQ(drawn.values.size(), evaluated.values.size());
    for (std::size_t j = 0; j < drawn.values.size(); ++j) {
      EXPECT_TRUE(SameBits(drawn.values[j], evaluated.values[j])) << j;
    }
    EXPECT_EQ(drawn.redraws, evaluated.redraws);
    EXPECT_EQ(DrawChecksum(drawn), DrawChecksum(evaluated));
    // Computed where the sample is drawn, so that the writer need not.
    EXPECT_EQ(drawn.draw_checksum, DrawChecksum(drawn));
    EXPECT_EQ(evaluated.draw_checksum, DrawChecksum(evaluated));
  }
}

TEST(DrawChecksum, ChangesWithAnyStoredBitOfTheDrawAndNotBelowTheStoredFloat) {
  const TempFile file(kSmallCampaign);
  const Campaign campaign(file.path(), std::nullopt, std::nullopt);
  SampleDrawer drawer(campaign);
  const SampleRecord drawn = drawer.Draw(4);
  const std::uint32_t checksum = DrawChecksum(drawn);
  SampleRecord changed = drawn;
  changed.u.back() = std::nextafter(changed.u.back(), 2.0);  // the last bit of a double
  EXPECT_NE(DrawChecksum(changed), checksum);
  changed = drawn;
  changed.redraws += 1;
  EXPECT_NE(DrawChecksum(changed), checksum);
  changed = drawn;
  changed.values.front() = std::nextafter(static_cast<float>(changed.values.front()), 1e30F);  // a float32 step
  EXPECT_NE(DrawChecksum(changed), checksum);
  // A value is stored as float32: a change that rounds to the same float is no change.
  changed = drawn;
  const double value = static_cast<float>(drawn.values.front());
  changed.values.front() = value + (std::nextafter(static_cast<float>(value), 1e30F) - value) / 8.0;
  ASSERT_EQ(static_cast<float>(changed.values.front()), static_cast<float>(value));
  SampleRecord rounded = drawn;
  rounded.values.front() = value;
  EXPECT_EQ(DrawChecksum(changed), DrawChecksum(rounded));
}

TEST(SampleEvaluator, AnExceptionOrANanStaysInItsSampleWithItsReason) {
  const TempFile file(kSmallCampaign);
  const Campaign campaign(file.path(), std::nullopt, std::nullopt);
  EvaluatorFaults faults;
  faults.before_simulate = [](std::int64_t index) {
    if (index == 2) throw std::runtime_error("injected fault");
  };
  faults.after_simulate = [](std::int64_t index, solvers::SimulationResult& result) {
    if (index == 4) result.runout = std::nan("");
  };
  SampleEvaluator evaluator(campaign, faults);
  const SampleRecord thrown = evaluator.Evaluate(2);
  EXPECT_EQ(thrown.status, SampleStatus::kException);
  EXPECT_EQ(thrown.message, "injected fault");
  EXPECT_EQ(thrown.u.size(), campaign.identity().inputs.size());
  EXPECT_TRUE(std::isnan(thrown.outputs[0]));
  const SampleRecord spoiled = evaluator.Evaluate(4);
  EXPECT_EQ(spoiled.status, SampleStatus::kNonFiniteOutput);
  EXPECT_TRUE(std::isnan(spoiled.outputs[0]));
  EXPECT_EQ(evaluator.Evaluate(3).status, SampleStatus::kOk);
}

TEST(CampaignSummary, CountsFailuresApartAndTreatsThemAsOutOfSpec) {
  const TempFile file(kSmallCampaign);
  const TempFile results("", ".h5");
  const Campaign campaign(file.path(), std::nullopt, std::nullopt);
  EvaluatorFaults faults;
  faults.before_simulate = [](std::int64_t index) {
    if (index % 5 == 0) throw std::runtime_error("injected fault");
  };
  SampleEvaluator evaluator(campaign, faults);
  std::vector<double> d;
  {
    CampaignStore store = CampaignStore::Create(results.path(), campaign.identity(), campaign.samples());
    for (std::int64_t i = 0; i < campaign.samples(); ++i) {
      SampleRecord record = evaluator.Evaluate(i);
      if (record.status == SampleStatus::kOk) d.push_back(record.outputs[0]);
      store.Add(std::move(record));
    }
    store.Commit();
  }
  const CampaignSummary summary = Summarise(CampaignReader(results.path()), {});
  const std::int64_t failed = 4;  // indices 0, 5, 10, 15 of 16
  EXPECT_EQ(summary.done, campaign.samples());
  EXPECT_EQ(summary.ok, campaign.samples() - failed);
  EXPECT_EQ(summary.failures.at("exception"), failed);
  const OutputSummary& trajectory = summary.outputs[0];
  ASSERT_EQ(trajectory.count, static_cast<std::int64_t>(d.size()));
  std::sort(d.begin(), d.end());
  EXPECT_EQ(trajectory.min, d.front());
  EXPECT_EQ(trajectory.max, d.back());
  const auto good = std::count_if(d.begin(), d.end(), [](double v) { return v <= 0.25; });
  ASSERT_TRUE(summary.in_spec.has_value());
  EXPECT_EQ(summary.in_spec->successes, good);
  EXPECT_EQ(summary.in_spec->trials, campaign.samples());
  EXPECT_EQ(summary.in_spec_ok->trials, campaign.samples() - failed);
  const nlohmann::json json = SummaryJson(summary);
  EXPECT_EQ(json["failures"]["exception"], failed);
  EXPECT_EQ(json["outputs"]["d_trajectory_mm"]["upper_spec_limit"], 0.25);
}

// Both kinds of calibrated spectrum (the ring's RONt, the rollers' VDsp, one class for the
// three rollers) and inspection, so that redraws depend on the scales too.
const std::string kCalibratedCampaign = kSceneLine + R"(seed = 5
[design]
kind = "sobol"
samples = 32
[tolerances.ring]
class = "waterjet"
mode = "inspected"
[tolerances.rollers]
class = "Normal"
mode = "inspected"
[tolerances.roller_positions]
class = "IT7"
[solver]
name = "linear"
)";

bool SameCalibration(const sampling::ComponentScale& a, const sampling::ComponentScale& b) {
  return a.component == b.component && a.measure == b.measure && SameBits(a.tolerance, b.tolerance) &&
         SameBits(a.coverage, b.coverage) && SameBits(a.calibration.scale, b.calibration.scale) &&
         SameBits(a.calibration.unit_quantile, b.calibration.unit_quantile) &&
         SameBits(a.calibration.unit_quantile_low, b.calibration.unit_quantile_low) &&
         SameBits(a.calibration.unit_quantile_high, b.calibration.unit_quantile_high) &&
         a.calibration.draws == b.calibration.draws;
}

void ExpectSameProfile(const engine::PolarProfile& a, const engine::PolarProfile& b) {
  EXPECT_TRUE(SameBits(a.mean_deviation(), b.mean_deviation()));
  ASSERT_EQ(a.harmonics().size(), b.harmonics().size());
  for (std::size_t k = 0; k < a.harmonics().size(); ++k) {
    EXPECT_EQ(a.harmonics()[k].order, b.harmonics()[k].order);
    EXPECT_TRUE(SameBits(a.harmonics()[k].amplitude, b.harmonics()[k].amplitude)) << k;
    EXPECT_TRUE(SameBits(a.harmonics()[k].phase, b.harmonics()[k].phase)) << k;
  }
}

TEST(StoredCalibration, TheResultsFileKeepsEveryCalibrationBitForBit) {
  const TempFile file(kCalibratedCampaign);
  const TempFile results("", ".h5");
  const Campaign campaign(file.path(), std::nullopt, std::nullopt);
  const std::vector<sampling::ComponentScale>& made = campaign.sampling().sampler.scales();
  ASSERT_EQ(made.size(), 4u);  // the ring, and the three rollers' one class
  const CampaignIdentity stored = StoredIdentityOf(campaign, results.path());
  ASSERT_EQ(stored.calibrations.size(), made.size());
  for (std::size_t k = 0; k < made.size(); ++k) EXPECT_TRUE(SameCalibration(stored.calibrations[k], made[k])) << k;
}

TEST(StoredCalibration, ACampaignBuiltFromStoredScalesRealisesTheSameAssembliesAsOneThatCalibrates) {
  const TempFile file(kCalibratedCampaign);
  const TempFile results("", ".h5");
  const Campaign fresh(file.path(), std::nullopt, std::nullopt);
  const CampaignIdentity stored = StoredIdentityOf(fresh, results.path());
  CampaignIdentity older = stored;  // as a file written before calibrations were stored
  older.calibrations.clear();
  const Campaign from_scales(stored, fresh.samples());
  const Campaign calibrating(older, fresh.samples());
  const std::vector<sampling::ComponentScale>& scales = calibrating.sampling().sampler.scales();
  ASSERT_EQ(from_scales.sampling().sampler.scales().size(), scales.size());
  for (std::size_t k = 0; k < scales.size(); ++k)
    EXPECT_TRUE(SameCalibration(from_scales.sampling().sampler.scales()[k], scales[k])) << k;

  const sampling::Design& made = calibrating.sampling().design;
  sampling::Design design(made.dimension(), made.options());
  std::vector<double> u(static_cast<std::size_t>(design.dimension()));
  int redraws = 0;
  for (std::int64_t index = 0; index < fresh.samples(); ++index) {
    SCOPED_TRACE(index);
    design.Point(index, u);
    const sampling::SampledAssembly a = from_scales.sampling().sampler.Realise(index, u);
    const sampling::SampledAssembly b = calibrating.sampling().sampler.Realise(index, u);
    EXPECT_EQ(a.redraws, b.redraws);
    ASSERT_EQ(a.values.size(), b.values.size());
    for (std::size_t k = 0; k < a.values.size(); ++k) EXPECT_TRUE(SameBits(a.values[k], b.values[k])) << k;
    ExpectSameProfile(a.scene.ring.inner, b.scene.ring.inner);
    ASSERT_EQ(a.scene.rollers.size(), b.scene.rollers.size());
    for (std::size_t r = 0; r < a.scene.rollers.size(); ++r) {
      ExpectSameProfile(a.scene.rollers[r].outline, b.scene.rollers[r].outline);
      EXPECT_TRUE(SameBits(a.scene.rollers[r].radial_offset, b.scene.rollers[r].radial_offset));
      EXPECT_TRUE(SameBits(a.scene.rollers[r].tangential_offset, b.scene.rollers[r].tangential_offset));
    }
    redraws += a.redraws;
  }
  EXPECT_GT(redraws, 0);  // inspection judged parts against the scales, not only the draws
}

TEST(StoredCalibration, AStoredScaleIsDrawnWithAsStoredWithoutCalibratingAgain) {
  const TempFile file(kCalibratedCampaign);
  const TempFile results("", ".h5");
  const Campaign fresh(file.path(), std::nullopt, std::nullopt);
  CampaignIdentity stored = StoredIdentityOf(fresh, results.path());
  ASSERT_EQ(stored.calibrations.front().component, "ring");
  // Twice the scale: no calibration gives it, so the sampler must have taken it as stored.
  stored.calibrations.front().calibration.scale *= 2.0;
  const Campaign doubled(stored, fresh.samples());
  EXPECT_TRUE(SameBits(doubled.sampling().sampler.scales().front().calibration.scale,
                       2.0 * fresh.sampling().sampler.scales().front().calibration.scale));
}

TEST(StoredCalibration, AStoredCalibrationOfAnotherToleranceIsIgnoredAndTheClassCalibrated) {
  const TempFile file(kCalibratedCampaign);
  const TempFile results("", ".h5");
  const Campaign fresh(file.path(), std::nullopt, std::nullopt);
  CampaignIdentity stored = StoredIdentityOf(fresh, results.path());
  stored.calibrations.front().tolerance *= 2.0;
  stored.calibrations.front().calibration.scale *= 2.0;
  const Campaign rebuilt(stored, fresh.samples());
  EXPECT_TRUE(SameCalibration(rebuilt.sampling().sampler.scales().front(), fresh.sampling().sampler.scales().front()));
}

// A report counts the independent draws of samples it does not read (those beyond a file's
// written end) by this count: on a Saltelli design, the A and B leading each row of
// 4 groups + 2.
TEST(Campaign, IndependentDrawsCountsWhatIndependentDrawSaysOfEachSample) {
  const Campaign campaign(std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/campaigns/sensitivity.toml",
                          std::nullopt, std::nullopt);
  std::int64_t counted = 0;
  for (std::int64_t end = 0; end <= 20; ++end) {
    EXPECT_EQ(campaign.IndependentDraws(end), counted) << end;
    counted += campaign.IndependentDraw(end) ? 1 : 0;
  }
  EXPECT_EQ(campaign.IndependentDraws(campaign.samples()), campaign.samples() / 3);
}

}  // namespace
}  // namespace ringtol::jobs
