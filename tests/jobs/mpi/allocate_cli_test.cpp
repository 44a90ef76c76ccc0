// `ringtol allocate` as users run it: alone and under mpirun, killed and resumed, given
// bad input or a spec no candidate meets. Which candidates are simulated, and what each
// is found to be, must not depend on the number of ranks, the chunks or interruptions.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "jobs/store/allocation_store.h"
#include "jobs/store/campaign_store.h"
#include "tests/support/background_run.h"
#include "tests/support/mpi_environment.h"
#include "tests/support/shell.h"
#include "tests/support/small_allocation.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Ne;

using testing::kMpiEnvironment;
using testing::Mpirun;
using Outcome = testing::ShellOutcome;

// Six candidates; the ring's class decides the constraint (tests/support/small_allocation.h).
const std::string kAllocation = testing::SmallAllocation();

std::filesystem::path TestFolder() { return testing::TestFolderPath("allocate_cli_test"); }
std::filesystem::path Folder() { return testing::FreshTestFolder("allocate_cli_test"); }

std::filesystem::path Write(const std::filesystem::path& file, const std::string& text) {
  testing::WriteText(file, text);
  return file;
}

Outcome Allocate(const std::filesystem::path& file, const std::filesystem::path& out, const std::string& options = "",
                 const std::string& prefix = "") {
  std::filesystem::create_directories(TestFolder());
  return testing::RunShell(kMpiEnvironment + "timeout 300 " + prefix + RINGTOL_EXECUTABLE + " allocate " +
                               file.string() + " --out " + out.string() + " --quiet " + options,
                           TestFolder() / "stderr.txt");
}

bool SameBits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// Every candidate's outcome and every stored sample of two results files.
void ExpectSameAllocation(const std::filesystem::path& a, const std::filesystem::path& b) {
  const AllocationReader x(a);
  const AllocationReader y(b);
  const AllocationOutcome p = x.ReadOutcome();
  const AllocationOutcome q = y.ReadOutcome();
  ASSERT_TRUE(p.complete);
  ASSERT_TRUE(q.complete);
  EXPECT_EQ(p.recommendation, q.recommendation);
  EXPECT_EQ(p.front, q.front);
  EXPECT_EQ(p.simulated, q.simulated);
  ASSERT_EQ(p.candidates.size(), q.candidates.size());
  const std::int64_t n = x.identity().samples;
  for (std::size_t c = 0; c < p.candidates.size(); ++c) {
    EXPECT_EQ(p.candidates[c].verdict, q.candidates[c].verdict) << c;
    EXPECT_EQ(p.candidates[c].samples, q.candidates[c].samples) << c;
    EXPECT_EQ(p.candidates[c].settled_by, q.candidates[c].settled_by) << c;
    for (const EvaluationRole role : {EvaluationRole::kScreen, EvaluationRole::kConfirm}) {
      const auto index = static_cast<std::int64_t>(c);
      EXPECT_EQ(x.ReadStatus(role, index, 0, n), y.ReadStatus(role, index, 0, n)) << c;
      EXPECT_TRUE(SameBits(x.ReadOutput(role, "d_trajectory_mm", index, 0, n),
                           y.ReadOutput(role, "d_trajectory_mm", index, 0, n)))
          << c;
    }
  }
}

TEST(Allocate, AloneItRecommendsTheCheapestFeasibleCandidate) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "allocation.toml", kAllocation);
  const Outcome run = Allocate(file, folder / "a.h5", "--json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  // As a campaign says: the article's law, which the base scene states, is worth one note.
  EXPECT_THAT(run.err, AllOf(::testing::StartsWith("ringtol: note: the contact law F = 1e+07 delta^1.5"),
                             HasSubstr("paper/scene.toml states")));
  EXPECT_EQ(run.err.find('\n'), run.err.size() - 1) << run.err;
  const nlohmann::json summary = nlohmann::json::parse(run.out);
  EXPECT_EQ(summary["candidates"], 6);
  EXPECT_TRUE(summary["complete"].get<bool>());
  // Exhaustive: every candidate is simulated, so every one is judged by its own samples.
  EXPECT_EQ(summary["simulated"], 6);
  ASSERT_FALSE(summary["recommendation"].is_null()) << run.out;
  const nlohmann::json& r = summary["recommendation"];
  EXPECT_EQ(r["verdict"], "feasible");
  EXPECT_LE(r["constraints"][0]["upper"].get<double>(), 0.1);
  // No feasible candidate is cheaper.
  const AllocationOutcome outcome = AllocationReader(folder / "a.h5").ReadOutcome();
  for (const CandidateOutcome& c : outcome.candidates) {
    if (c.verdict == analysis::Verdict::kFeasible) {
      EXPECT_GE(c.cost, r["cost"].get<double>());
    }
  }
}

// The six-roller stage's allocation (examples/six_roller_stage/allocation.toml, at a
// quarter of its samples, so on the 90 % quantiles, which 128 samples bound): four fixed rollers, two more than the ring needs, under two
// springs, with a life constraint. It ends with a recommendation, and no sample it computed
// failed but those the linear screen refused (beyond_linear_range), which the confirming
// rung then computed.
TEST(Allocate, OnTheSixRollerStageItRecommendsAndEverySampleItConfirmsIsOk) {
  const std::filesystem::path folder = Folder();
  const std::filesystem::path stage = std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/six_roller_stage";
  std::string text = testing::ReadText(stage / "allocation.toml");
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"samples = 512", "samples = 128"},
                                 {"first_samples = 128", "first_samples = 32"},
                                 {"quantile = 0.99", "quantile = 0.9"},
                                 {"quantile = 0.99", "quantile = 0.9"},
                                 {"scene = \"scene.toml\"", "scene = \"" + (stage / "scene.toml").string() + "\""}}) {
    const std::size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  }
  const auto file = Write(folder / "allocation.toml", text);
  const Outcome run = Allocate(file, folder / "six.h5", "--json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json summary = nlohmann::json::parse(run.out);
  EXPECT_TRUE(summary["complete"].get<bool>());
  ASSERT_FALSE(summary["recommendation"].is_null()) << run.out;
  EXPECT_EQ(summary["recommendation"]["verdict"], "feasible");
  const AllocationReader reader(folder / "six.h5");
  const std::int64_t candidates = static_cast<std::int64_t>(reader.ReadOutcome().candidates.size());
  std::int64_t confirmed = 0;
  for (std::int64_t c = 0; c < candidates; ++c) {
    for (const SampleStatus status : reader.ReadStatus(EvaluationRole::kConfirm, c, 0, 128)) {
      EXPECT_TRUE(status == SampleStatus::kOk || status == SampleStatus::kPending) << SampleStatusName(status);
      confirmed += status == SampleStatus::kOk ? 1 : 0;
    }
    for (const SampleStatus status : reader.ReadStatus(EvaluationRole::kScreen, c, 0, 128)) {
      EXPECT_TRUE(status == SampleStatus::kOk || status == SampleStatus::kPending ||
                  status == FromSolverStatus(solvers::Status::kBeyondLinearRange))
          << SampleStatusName(status);
    }
  }
  EXPECT_GT(confirmed, 0);
}

TEST(Allocate, ItsBenchNotesTheContactLawAsItDoes) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "allocation.toml", kAllocation);
  const Outcome bench = testing::RunShell(kMpiEnvironment + "timeout 300 " + RINGTOL_EXECUTABLE + " bench allocate " +
                                              file.string() + " --quiet",
                                          TestFolder() / "stderr.txt");
  ASSERT_EQ(bench.exit_code, 0) << bench.err;
  EXPECT_THAT(bench.err, ::testing::StartsWith("ringtol: note: the contact law F = 1e+07 delta^1.5"));
}

TEST(Allocate, ReportDrawsTheAllocationFromItsResultsFile) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "allocation.toml", kAllocation);
  ASSERT_EQ(Allocate(file, folder / "a.h5").exit_code, 0);
  const Outcome report = testing::RunShell(std::string(RINGTOL_EXECUTABLE) + " report " + (folder / "a.h5").string() +
                                               " --out " + (folder / "a.html").string() + " --json " +
                                               (folder / "a.json").string(),
                                           TestFolder() / "stderr.txt");
  ASSERT_EQ(report.exit_code, 0) << report.err;
  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(folder / "a.json"));
  const AllocationOutcome outcome = AllocationReader(folder / "a.h5").ReadOutcome();
  ASSERT_TRUE(outcome.recommendation);
  EXPECT_EQ(json["format"], "ringtol allocation report");
  EXPECT_THAT(testing::ReadText(folder / "a.html"),
              AllOf(HasSubstr("Recommended (candidate " + std::to_string(*outcome.recommendation) + ")"),
                    HasSubstr("Pareto")));
}

TEST(AllocateUnderMpirun, OneAndTwoRanksAndAKilledThenResumedRunFindTheSame) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "allocation.toml", kAllocation);
  const Outcome alone = Allocate(file, folder / "alone.h5");
  ASSERT_EQ(alone.exit_code, 0) << alone.err;
  EXPECT_THAT(alone.out, AllOf(HasSubstr("recommendation"), HasSubstr("margins"), HasSubstr("search")));
  const Outcome two = Allocate(file, folder / "two.h5", "--chunk 3", Mpirun(2));
  ASSERT_EQ(two.exit_code, 0) << two.err;
  ExpectSameAllocation(folder / "alone.h5", folder / "two.h5");

  const Outcome killed = Allocate(file, folder / "killed.h5", "--chunk 2 --commit-seconds 0 --test-kill-after 10");
  constexpr int kKilledBySigkill = 128 + SIGKILL;
  ASSERT_EQ(killed.exit_code, kKilledBySigkill) << killed.err;
  const Outcome resumed = Allocate(file, folder / "killed.h5", "--resume --json");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  ExpectSameAllocation(folder / "alone.h5", folder / "killed.h5");
}

TEST(AllocateUnderMpirun, KeepsItsSamplesInShardsThatAnyNumberOfRanksContinue) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "allocation.toml", kAllocation);
  ASSERT_EQ(Allocate(file, folder / "alone.h5").exit_code, 0);
  EXPECT_TRUE(IndexedAllocationShards(folder / "alone.h5").empty());

  // Three ranks, rank 0 killed; the results file is the index of every rank's shard.
  const std::filesystem::path three = folder / "three.h5";
  constexpr int kKilledBySigkill = 128 + SIGKILL;
  const Outcome killed = Allocate(file, three, "--chunk 2 --commit-seconds 0 --test-kill-after 10", Mpirun(3));
  ASSERT_EQ(killed.exit_code, kKilledBySigkill) << killed.err;
  EXPECT_EQ(IndexedAllocationShards(three).size(), 3u);
  // Continued alone: the shards stay the results, the third read by rank 0 as it is.
  const Outcome resumed = Allocate(file, three, "--resume --json");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(nlohmann::json::parse(resumed.out)["run"]["shards"], 3);
  ExpectSameAllocation(folder / "alone.h5", three);
  // And as h5py reads the index.
  const std::string python = "/usr/bin/python3 " + std::string(RINGTOL_SOURCE_DIR) + "/tests/jobs/mpi/same_columns.py " +
                             (folder / "alone.h5").string() + " " + three.string() + " > " +
                             (folder / "python.txt").string() + " 2>&1";
  EXPECT_EQ(std::system(python.c_str()), 0) << testing::ReadText(folder / "python.txt");
  const Outcome verify = testing::RunShell(std::string(RINGTOL_EXECUTABLE) + " verify " + three.string() + " --json",
                                           TestFolder() / "stderr.txt");
  ASSERT_EQ(verify.exit_code, 0) << verify.out << verify.err;
  const nlohmann::json check = nlohmann::json::parse(verify.out);
  EXPECT_EQ(check["verdict"], "intact");
  EXPECT_EQ(check["done_screen"].get<std::int64_t>() + check["done_confirm"].get<std::int64_t>(),
            nlohmann::json::parse(resumed.out)["samples_screen"].get<std::int64_t>() +
                nlohmann::json::parse(resumed.out)["samples_confirm"].get<std::int64_t>());

  // Joined in place, it is one self-contained file again.
  const Outcome join = testing::RunShell(std::string(RINGTOL_EXECUTABLE) + " join " + three.string(),
                                         TestFolder() / "stderr.txt");
  ASSERT_EQ(join.exit_code, 0) << join.err;
  EXPECT_TRUE(IndexedAllocationShards(three).empty());
  EXPECT_FALSE(std::filesystem::exists(ShardPath(three, 0)));
  ExpectSameAllocation(folder / "alone.h5", three);

  // A file begun alone continues under mpirun as shard 0.
  const std::filesystem::path begun = folder / "begun.h5";
  ASSERT_EQ(Allocate(file, begun, "--chunk 2 --commit-seconds 0 --test-kill-after 30").exit_code, kKilledBySigkill);
  const Outcome continued = Allocate(file, begun, "--resume", Mpirun(2));
  ASSERT_EQ(continued.exit_code, 0) << continued.err;
  EXPECT_EQ(IndexedAllocationShards(begun), (std::vector<std::filesystem::path>{ShardPath(begun, 0),
                                                                                ShardPath(begun, 1)}));
  ExpectSameAllocation(folder / "alone.h5", begun);

  // A missing shard is named, never read as pending.
  std::filesystem::rename(ShardPath(begun, 1), folder / "aside.h5");
  const Outcome report = testing::RunShell(std::string(RINGTOL_EXECUTABLE) + " report " + begun.string() + " --out " +
                                               (folder / "r.html").string(),
                                           TestFolder() / "stderr.txt");
  EXPECT_NE(report.exit_code, 0);
  EXPECT_THAT(report.err, AllOf(HasSubstr("begun.h5.shard-1"), HasSubstr("is missing")));
}

// A truncated shard holds nothing to continue, as a campaign's: verify, report and join name
// it and the resume that recovers it, and that resume (alone, of a run under mpirun) sets
// it aside, keeping its bytes, and computes its samples again, to what an uninterrupted run finds.
TEST(AllocateUnderMpirun, ATruncatedShardIsNamedByEveryCommandAndAResumeComputesItsSamplesAgain) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "allocation.toml", kAllocation);
  ASSERT_EQ(Allocate(file, folder / "whole.h5").exit_code, 0);
  const std::filesystem::path out = folder / "sharded.h5";
  const Outcome two = Allocate(file, out, "--chunk 3", Mpirun(2));
  ASSERT_EQ(two.exit_code, 0) << two.err;
  const std::filesystem::path shard = ShardPath(out, 1);
  const std::string truncate = "truncate -s " + std::to_string(std::filesystem::file_size(shard) / 2) + " " +
                               shard.string();
  ASSERT_EQ(std::system(truncate.c_str()), 0);
  const std::string truncated = testing::ReadText(shard);
  const auto names_it = AllOf(HasSubstr("sharded.h5.shard-1 cannot be read"),
                              HasSubstr("ringtol allocate " + file.string() + " --out " + out.string() + " --resume"),
                              HasSubstr("sharded.h5.shard-1.unreadable"));
  const auto ringtol = [&](const std::string& arguments) {
    return testing::RunShell(std::string(RINGTOL_EXECUTABLE) + " " + arguments, TestFolder() / "stderr.txt");
  };
  EXPECT_THAT(ringtol("verify " + out.string()), testing::ExitsWith(1, names_it));
  EXPECT_THAT(ringtol("report " + out.string() + " --out " + (folder / "report.html").string()),
              testing::ExitsWith(1, names_it));
  EXPECT_THAT(ringtol("join " + out.string()), testing::ExitsWith(1, names_it));
  const Outcome resumed = Allocate(file, out, "--resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_THAT(resumed.err, HasSubstr("set aside as " + shard.string() + ".unreadable"));
  EXPECT_EQ(testing::ReadText(shard.string() + ".unreadable"), truncated);
  ExpectSameAllocation(folder / "whole.h5", out);
  EXPECT_TRUE(CheckAllocationResults(out).intact());
}

TEST(AllocateUnderMpirun, BranchAndBoundFindsWhatExhaustiveSearchFinds) {
  const std::filesystem::path folder = Folder();
  const auto exhaustive = Write(folder / "exhaustive.toml", kAllocation);
  const auto pruned = Write(folder / "pruned.toml", testing::ReplaceOnce(kAllocation, "search = \"exhaustive\"",
                                                                         "search = \"branch_and_bound\""));
  const Outcome e = Allocate(exhaustive, folder / "e.h5", "--json");
  ASSERT_EQ(e.exit_code, 0) << e.err;
  const Outcome p = Allocate(pruned, folder / "p.h5", "--json", Mpirun(2));
  ASSERT_EQ(p.exit_code, 0) << p.err;
  const nlohmann::json x = nlohmann::json::parse(e.out);
  const nlohmann::json y = nlohmann::json::parse(p.out);
  EXPECT_EQ(x["recommendation"]["candidate"], y["recommendation"]["candidate"]);
  EXPECT_LE(y["simulated"].get<int>(), x["simulated"].get<int>());
}

// Samples of every candidate and role on disk.
std::int64_t SamplesDone(const std::filesystem::path& file) {
  const AllocationReader results(file);
  const std::int64_t candidates = static_cast<std::int64_t>(results.ReadOutcome().candidates.size());
  std::int64_t done = 0;
  for (std::int64_t c = 0; c < candidates; ++c) {
    for (const EvaluationRole role : {EvaluationRole::kScreen, EvaluationRole::kConfirm}) {
      for (const SampleStatus s : results.ReadStatus(role, c, 0, results.identity().samples))
        done += s != SampleStatus::kPending ? 1 : 0;
    }
  }
  return done;
}

TEST(Allocate, SigtermKeepsEveryFinishedSampleAndResumeEndsAsAnUninterruptedRun) {
  const std::filesystem::path folder = Folder();
  // Twice the samples and ten times the steps of kAllocation's, so that the run lasts long
  // enough to be stopped in its middle.
  const auto file = Write(folder / "allocation.toml",
                          testing::ReplaceOnce(testing::SmallAllocation({"monte_carlo", 128, 32, "exhaustive", "process"}),
                                               "path_tolerance_um = 2.0", "path_tolerance_um = 0.2"));
  ASSERT_EQ(Allocate(file, folder / "whole.h5").exit_code, 0);
  const std::filesystem::path out = folder / "stopped.h5";
  const testing::Running run =
      testing::Start(kMpiEnvironment + "exec " + RINGTOL_EXECUTABLE + " allocate " + file.string() + " --out " +
                         out.string() + " --quiet --commit-seconds 0.05",
                     TestFolder(), "stopped");
  // Stopped as soon as samples reach the file, mid-run.
  ASSERT_TRUE(testing::WaitFor([&] {
    try {
      return std::filesystem::exists(out) && SamplesDone(out) > 0;
    } catch (const std::exception&) {
      return false;  // caught between the file's creation and its first commit
    }
  }));
  kill(run.pid, SIGTERM);
  const testing::Ended ended = testing::Wait(run);
  ASSERT_FALSE(ended.killed) << ended.err;
  ASSERT_EQ(ended.code, 128 + SIGTERM) << ended.err;
  // "every sample this run finished (N) is on disk in FILE; continue with:\n  COMMAND"
  const std::string head = "every sample this run finished (";
  const std::size_t at = ended.err.find(head);
  ASSERT_NE(at, std::string::npos) << ended.err;
  const std::int64_t finished = std::stoll(ended.err.substr(at + head.size()));
  EXPECT_EQ(SamplesDone(out), finished) << "a sample it finished is missing from the file";
  const std::size_t line = ended.err.find("continue with:\n  ", at);
  ASSERT_NE(line, std::string::npos) << ended.err;
  const std::string resume = ended.err.substr(line + 17, ended.err.find('\n', line + 17) - line - 17);
  EXPECT_THAT(resume, AllOf(HasSubstr(out.string()), HasSubstr("--resume")));
  const testing::Ended last = testing::Wait(testing::Start(kMpiEnvironment + "exec " + resume, TestFolder(), "last"));
  ASSERT_EQ(last.code, 0) << last.err;
  ExpectSameAllocation(folder / "whole.h5", out);
}

TEST(Allocate, ASpecNoCandidateMeetsSaysSoAndNamesTheBindingConstraint) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "tight.toml", testing::ReplaceOnce(kAllocation, "upper_mm = 0.1", "upper_mm = 0.001"));
  const Outcome run = Allocate(file, folder / "a.h5");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_THAT(run.out, AllOf(HasSubstr("no candidate is feasible"), HasSubstr("d_trajectory_mm"), HasSubstr("binds")));
}

TEST(AllocateUnderMpirun, BadInputStopsEveryRankWithOneClearMessageBeforeAnySample) {
  const std::filesystem::path folder = Folder();
  const auto unknown_class = Write(
      folder / "class.toml", testing::ReplaceOnce(kAllocation, "options = [\"Normal\", \"5\"]", "options = [\"Normal\", \"P9\"]"));
  EXPECT_THAT(Allocate(unknown_class, folder / "r.h5", "", Mpirun(2)),
              testing::ExitsWith(Ne(0), AllOf(HasSubstr("class.toml"), HasSubstr("P9"))));
  EXPECT_FALSE(std::filesystem::exists(folder / "r.h5"));
  const auto no_output = Write(folder / "output.toml",
                               testing::ReplaceOnce(kAllocation, "output = \"d_trajectory_mm\"", "output = \"wobble_mm\""));
  EXPECT_THAT(Allocate(no_output, folder / "r.h5"),
              testing::ExitsWith(Ne(0), AllOf(HasSubstr("output.toml"), HasSubstr("wobble_mm"), HasSubstr("d_trajectory_mm"))));
  const auto file = Write(folder / "allocation.toml", kAllocation);
  ASSERT_EQ(Allocate(file, folder / "done.h5").exit_code, 0);
  EXPECT_THAT(Allocate(file, folder / "done.h5"), testing::ExitsWith(Ne(0), HasSubstr("--resume")));
}

}  // namespace
}  // namespace ringtol::jobs
