// The allocation's candidates and its driver, in one process: common random numbers
// between candidates, and an outcome that depends only on the samples simulated, not on
// the order they were simulated in or on an interruption.
#include "jobs/allocation/allocation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "tests/support/small_allocation.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

// Six candidates on a Sobol' design; the ring is drawn as made (process), so its
// amplitudes are the class's scale times the same quantiles.
const std::string kAllocation = testing::SmallAllocation({"sobol", 32, 8, "auto", "process"});

std::filesystem::path AllocationFile() {
  const std::filesystem::path file = testing::FreshTestFolder("allocation_test") / "allocation.toml";
  testing::WriteText(file, kAllocation);
  return file;
}

// Stored samples in memory, as a results file would hold them.
class MemorySamples final : public StoredSamples {
 public:
  void Add(EvaluationRole role, std::int64_t candidate, const SampleRecord& r) {
    records_[{role, candidate, r.index}] = r;
  }
  bool AllDone(EvaluationRole role, std::int64_t candidate, std::int64_t begin, std::int64_t end) const override {
    for (std::int64_t i = begin; i < end; ++i)
      if (!records_.contains({role, candidate, i})) return false;
    return true;
  }
  std::vector<SampleStatus> Status(EvaluationRole role, std::int64_t candidate, std::int64_t begin,
                                   std::int64_t end) const override {
    std::vector<SampleStatus> status;
    for (std::int64_t i = begin; i < end; ++i) status.push_back(records_.at({role, candidate, i}).status);
    return status;
  }
  std::vector<double> Output(EvaluationRole role, const std::string& output, std::int64_t candidate,
                             std::int64_t begin, std::int64_t end) const override {
    const auto k = static_cast<std::size_t>(
        std::find_if(kOutputNames.begin(), kOutputNames.end(), [&](const char* n) { return output == n; }) -
        kOutputNames.begin());
    std::vector<double> values;
    for (std::int64_t i = begin; i < end; ++i) values.push_back(records_.at({role, candidate, i}).outputs[k]);
    return values;
  }
  std::vector<double> ErrorBound(std::int64_t candidate, std::int64_t begin, std::int64_t end) const override {
    std::vector<double> values;
    for (std::int64_t i = begin; i < end; ++i)
      values.push_back(records_.at({EvaluationRole::kScreen, candidate, i}).d_trajectory_error);
    return values;
  }
  std::size_t size() const { return records_.size(); }

 private:
  std::map<std::tuple<EvaluationRole, std::int64_t, std::int64_t>, SampleRecord> records_;
};

// Plays the driver to its end; `budget` >= 0 stops after that many samples (an
// interruption), leaving the rest of the round undone. Samples of a round are simulated
// last first, the opposite of the pool's order.
void Play(const Allocation& allocation, MemorySamples& samples, AllocationDriver& driver, std::int64_t budget = -1,
          const std::function<void(EvaluationRole, SampleRecord&)>& alter = {}) {
  AllocationEvaluator evaluator(allocation);
  std::int64_t spent = 0;
  for (;;) {
    const std::vector<RoundSegment> round = driver.Advance(samples);
    if (round.empty()) return;
    for (auto s = round.rbegin(); s != round.rend(); ++s) {
      for (std::int64_t i = s->end - 1; i >= s->begin; --i) {
        if (samples.AllDone(s->role, s->candidate, i, i + 1)) continue;
        if (budget >= 0 && spent == budget) return;
        SampleRecord record = evaluator.Evaluate(s->role, s->candidate, i);
        if (alter) alter(s->role, record);
        samples.Add(s->role, s->candidate, record);
        ++spent;
      }
    }
  }
}

TEST(Allocation, EveryCandidateDrawsTheSameDesignPointForTheSameSample) {
  const Allocation allocation(AllocationFile());
  const std::int64_t candidates = allocation.space().size();
  std::vector<SampleEvaluator> evaluators;
  for (std::int64_t c = 0; c < candidates; ++c)
    evaluators.emplace_back(allocation.CandidateCampaign(c, EvaluationRole::kConfirm));
  const std::vector<double> points = allocation.DesignPoints();
  const std::size_t d = allocation.identity().inputs.size();
  for (std::int64_t i = 0; i < allocation.samples(); ++i) {
    const std::vector<double> expected(points.begin() + static_cast<std::ptrdiff_t>(i * static_cast<std::int64_t>(d)),
                                       points.begin() + static_cast<std::ptrdiff_t>((i + 1) * static_cast<std::int64_t>(d)));
    for (std::int64_t c = 0; c < candidates; ++c) {
      const SampleRecord r = evaluators[static_cast<std::size_t>(c)].Evaluate(i);
      ASSERT_EQ(std::memcmp(r.u.data(), expected.data(), d * sizeof(double)), 0) << "sample " << i << " candidate " << c;
    }
  }
}

TEST(Allocation, ARingDrawnAsMadeDiffersBetweenClassesOnlyByItsScale) {
  const Allocation allocation(AllocationFile());
  // Candidates 0 and 4: ring waterjet and IT7/2, rollers Normal in both.
  const Campaign& loose = allocation.CandidateCampaign(0, EvaluationRole::kConfirm);
  const Campaign& tight = allocation.CandidateCampaign(4, EvaluationRole::kConfirm);
  const double ratio =
      tight.sampling().sampler.scales().front().calibration.scale / loose.sampling().sampler.scales().front().calibration.scale;
  SampleEvaluator a(loose);
  SampleEvaluator b(tight);
  // Drawn values are recorded in um from SI numbers: a few ulps apart.
  constexpr double kRecordTolerance = 1e-12;
  const std::vector<sampling::SampledInput>& inputs = allocation.identity().inputs;
  for (std::int64_t i = 0; i < allocation.samples(); ++i) {
    const SampleRecord x = a.Evaluate(i);
    const SampleRecord y = b.Evaluate(i);
    for (std::size_t k = 0; k < inputs.size(); ++k) {
      if (inputs[k].source != sampling::ErrorSource::kRingShape) continue;
      if (inputs[k].name.ends_with("amplitude_um")) {
        EXPECT_NEAR(y.values[k], ratio * x.values[k], kRecordTolerance * std::abs(x.values[k])) << inputs[k].name;
      } else {
        EXPECT_EQ(y.values[k], x.values[k]) << inputs[k].name;  // phases: the same draw
      }
    }
  }
}

// A constraint may name a life output: every candidate's samples carry them, and the
// asynchronous error motion, which only the rollers' lobes make, shrinks with the rollers'
// class (ISO 492 class 5 allows a third of Normal's radial runout at this size).
TEST(Allocation, AConstraintCanNameALifeOutputAndTheRollersClassDecidesItsAsynchronousPart) {
  std::string text = kAllocation;
  const std::string constraint = "output = \"d_trajectory_mm\"";
  text.replace(text.find(constraint), constraint.size(), "output = \"error_motion_asynchronous_mm\"");
  const std::filesystem::path file = testing::FreshTestFolder("allocation_life_test") / "allocation.toml";
  testing::WriteText(file, text);
  const Allocation allocation(file);
  ASSERT_EQ(allocation.stored_outputs(), std::vector<std::string>{"error_motion_asynchronous_mm"});
  // Candidates 0 and 1: the waterjet ring with Normal and with class 5 rollers.
  SampleEvaluator normal(allocation.CandidateCampaign(0, EvaluationRole::kConfirm));
  SampleEvaluator precise(allocation.CandidateCampaign(1, EvaluationRole::kConfirm));
  const auto column = [](const char* name) {
    return static_cast<std::size_t>(std::find_if(kOutputNames.begin(), kOutputNames.end(),
                                                 [&](const char* n) { return std::string_view(n) == name; }) -
                                    kOutputNames.begin());
  };
  const std::size_t asynchronous = column("error_motion_asynchronous_mm");
  const std::size_t life = column("life_d_trajectory_mm");
  const std::size_t one = column("d_trajectory_mm");
  double sum_normal = 0.0, sum_precise = 0.0;
  constexpr std::int64_t kSamples = 16;
  for (std::int64_t i = 0; i < kSamples; ++i) {
    const SampleRecord a = normal.Evaluate(i), b = precise.Evaluate(i);
    ASSERT_EQ(a.status, SampleStatus::kOk) << a.message;
    ASSERT_EQ(b.status, SampleStatus::kOk) << b.message;
    EXPECT_GE(a.outputs[life], a.outputs[one] - 1e-9) << "sample " << i;
    EXPECT_GT(a.outputs[asynchronous], 0.0) << "sample " << i;
    sum_normal += a.outputs[asynchronous];
    sum_precise += b.outputs[asynchronous];
  }
  EXPECT_LT(sum_precise, 0.6 * sum_normal);
}

TEST(AllocationDriver, AnInterruptedRunInAnyOrderEndsAsAnUninterruptedOne) {
  const Allocation allocation(AllocationFile());
  MemorySamples whole;
  AllocationDriver uninterrupted(allocation);
  Play(allocation, whole, uninterrupted);
  ASSERT_TRUE(uninterrupted.done());
  const AllocationOutcome expected = uninterrupted.Outcome(whole);

  MemorySamples partial;
  {
    AllocationDriver first(allocation);
    Play(allocation, partial, first, 37);  // stops inside a round
    ASSERT_FALSE(first.done());
  }
  AllocationDriver resumed(allocation);  // rebuilt from the samples alone, as after a crash
  Play(allocation, partial, resumed);
  ASSERT_TRUE(resumed.done());
  const AllocationOutcome outcome = resumed.Outcome(partial);
  EXPECT_EQ(partial.size(), whole.size());
  EXPECT_EQ(outcome.recommendation, expected.recommendation);
  EXPECT_EQ(outcome.front, expected.front);
  for (std::size_t c = 0; c < outcome.candidates.size(); ++c) {
    EXPECT_EQ(outcome.candidates[c].verdict, expected.candidates[c].verdict) << c;
    EXPECT_EQ(outcome.candidates[c].samples, expected.candidates[c].samples) << c;
    EXPECT_EQ(outcome.candidates[c].yield.successes, expected.candidates[c].yield.successes) << c;
  }
}

TEST(AllocationDriver, TheScreenSettlesOnlyWhatItsErrorBoundDecides) {
  const Allocation allocation(AllocationFile());
  MemorySamples samples;
  AllocationDriver driver(allocation);
  Play(allocation, samples, driver);
  const AllocationOutcome outcome = driver.Outcome(samples);
  // The waterjet ring's D_trajectory is about twice the limit: the screen decides those.
  EXPECT_GT(outcome.settled_by_screen, 0);
  for (std::size_t c = 0; c < outcome.candidates.size(); ++c) {
    const CandidateOutcome& candidate = outcome.candidates[c];
    if (candidate.settled_by != EvaluationRole::kScreen) continue;
    // Settled by the screen: decided with the linear value widened by its own bound, and
    // the accurate rung was never run on it.
    EXPECT_NE(candidate.verdict, analysis::Verdict::kUndecided) << c;
    EXPECT_FALSE(samples.AllDone(EvaluationRole::kConfirm, static_cast<std::int64_t>(c), 0, 1)) << c;
    const analysis::ConstraintJudgement& j = candidate.constraints.front();
    if (candidate.verdict == analysis::Verdict::kInfeasible) {
      EXPECT_GT(j.interval.lower, 0.1) << c;
    }
  }
}

TEST(AllocationDriver, PathsTheScreenRefusesSettleNothingAndGoToTheAccurateRung) {
  const Allocation allocation(AllocationFile());
  MemorySamples samples;
  AllocationDriver driver(allocation);
  // Every screened path beyond the linear rung's range: it knows nothing of any candidate.
  Play(allocation, samples, driver, -1, [](EvaluationRole role, SampleRecord& record) {
    if (role != EvaluationRole::kScreen) return;
    record.status = static_cast<SampleStatus>(solvers::Status::kBeyondLinearRange);
    record.outputs.fill(std::numeric_limits<double>::quiet_NaN());
    record.d_trajectory_error = std::numeric_limits<double>::quiet_NaN();
  });
  const AllocationOutcome outcome = driver.Outcome(samples);
  EXPECT_EQ(outcome.settled_by_screen, 0);
  for (std::size_t c = 0; c < outcome.candidates.size(); ++c) {
    if (outcome.candidates[c].settlement != analysis::Settlement::kSimulated) continue;
    EXPECT_EQ(outcome.candidates[c].settled_by, EvaluationRole::kConfirm) << c;
  }
  // The same answer as when the screen works: the accurate rung decided every candidate.
  MemorySamples reference_samples;
  AllocationDriver reference(allocation);
  Play(allocation, reference_samples, reference);
  EXPECT_EQ(outcome.recommendation, reference.Outcome(reference_samples).recommendation);
}

}  // namespace
}  // namespace ringtol::jobs
