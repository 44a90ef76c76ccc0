// Campaign files, the evaluation of one sample, and the summary, in process (the pool and
// the command line are tested through the executable in tests/jobs/mpi/).
#include "jobs/campaign/campaign.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "jobs/report/campaign_summary.h"
#include "jobs/inputs/input_error.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

const std::string kSceneLine =
    "scene = \"" + (std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/paper/scene.toml").string() + "\"\n";

// Quick to calibrate and to solve: a low-order ring spectrum, positions and springs.
const std::string kSmallCampaign = kSceneLine + R"(seed = 7
[design]
kind = "monte_carlo"
samples = 16
[tolerances.ring]
circularity_mm = 0.2
max_order = 6
[tolerances.roller_positions]
zone_diameter_mm = 0.05
[tolerances.springs]
class = "pm10"
[solver]
name = "quasistatic"
[spec]
d_trajectory_mm = 0.25
)";

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

}  // namespace
}  // namespace ringtol::jobs
