#include "jobs/cli/allocate_command.h"

#include <unistd.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "jobs/allocation/allocation.h"
#include "jobs/cli/contact_warning.h"
#include "jobs/cli/pool_run.h"
#include "jobs/inputs/input_error.h"
#include "jobs/pool/allocation_pool.h"
#include "jobs/pool/stop_signals.h"
#include "jobs/report/allocation_summary.h"
#include "jobs/store/allocation_store.h"

namespace ringtol::jobs {
namespace {

// Whether `out` is kept in shards: an index of them, or shards a killed run left (beside a
// self-contained file, or before its first index).
bool IsShardedAllocation(const std::filesystem::path& out) {
  return !FindShards(out).empty() || (std::filesystem::exists(out) && IsShardIndex(out));
}

// Before a resume in shards (rank 0): a self-contained results file becomes shard 0
// (renamed: its samples stay where they are on disk), so that an allocation begun in one
// process continues under mpirun; it is checked and repaired as it is first.
void MakeShardZero(const std::filesystem::path& out, const AllocationIdentity& identity) {
  const std::filesystem::path own = ShardPath(out, 0);
  if (!std::filesystem::exists(out) || IsShardIndex(out)) return;
  if (std::filesystem::exists(own)) {
    throw InputError(fmt::format("{}: keeps samples itself and {} exists beside it: move one of them away",
                                 out.string(), own.string()));
  }
  { const AllocationStore plain = AllocationStore::Resume(out, identity); }
  std::filesystem::rename(out, own);
}

// A line per progress interval (redrawn in place on a terminal): rounds, candidates, the
// round's samples.
class AllocationProgressPrinter {
 public:
  AllocationProgressPrinter(std::ostream& out, bool terminal, double interval)
      : out_(out), terminal_(terminal), interval_(interval) {}

  void operator()(const AllocationProgress& p) {
    const double wait = terminal_ ? kRedrawSeconds : interval_;
    if (printed_at_ >= 0.0 && p.elapsed - printed_at_ < wait) return;
    printed_at_ = p.elapsed;
    const double rate = p.elapsed > 0 ? static_cast<double>(p.computed) / p.elapsed : 0.0;
    const std::string text =
        fmt::format("round {}: {} of {} candidates settled by simulation; round {}/{} samples; {} samples in {}, "
                    "{:.0f} samples/s",
                    p.round, p.simulated, p.candidates, p.samples.done, p.samples.total, p.computed,
                    Clock(p.elapsed), rate);
    if (terminal_) {
      fmt::print(out_, "\r{}\x1b[K", text);
    } else {
      fmt::print(out_, "allocate: {}\n", text);
    }
    out_.flush();
  }

 private:
  static constexpr double kRedrawSeconds = 0.2;
  std::ostream& out_;
  bool terminal_;
  double interval_;
  double printed_at_ = -1.0;
};

nlohmann::json RunJson(const AllocationRunReport& run) {
  nlohmann::json json = {{"computed", run.computed},
          {"rounds", run.rounds},
          {"wall_time_s", run.wall_time},
          {"samples_per_s", run.wall_time > 0 ? static_cast<double>(run.computed) / run.wall_time : 0.0},
          {"solver_time_s", run.solver_time},
          {"ranks", run.ranks},
          {"computing_ranks", run.computing_ranks}};
  if (run.shards > 0) {
    json["shards"] = run.shards;
    json["shard_mappings"] = run.shard_mappings;
    json["index_time_s"] = run.index_time;
  }
  return json;
}

// Checks, builds and runs the allocation into `command.out`; rank 0 gets the run's report.
// Returns the exit code of a stop (0 when it ran to the end), after printing how to resume
// when `resumable`.
int Execute(const AllocateCommand& command, std::ostream& progress, AllocationRunReport& run, bool resumable) {
  const MPI_Comm world = MPI_COMM_WORLD;
  int rank = 0;
  int ranks = 1;
  MPI_Comm_rank(world, &rank);
  MPI_Comm_size(world, &ranks);
  std::optional<StopSignals> signals(std::in_place, UnderLauncher(world) ? StopSignals::Repeat::kIgnored
                                                                         : StopSignals::Repeat::kEndsAtOnce);
  PoolOptions pool = command.pool;
  pool.stop = [&signals] { return signals->received(); };

  CheckBeforeWork(world, command.pool, command.progress_seconds, command.out, command.resume);
  // A shard that cannot be read holds nothing to continue: renamed aside, its samples are
  // computed again, like those no shard holds.
  if (command.resume) {
    SetAsideUnreadable(world, progress, [&] { return SetAsideUnreadableAllocationShards(command.out); });
  }

  std::unique_ptr<Allocation> allocation;
  ThrowAgreed(world, Attempt([&] { allocation = std::make_unique<Allocation>(command.file); }));
  const SamplingPlan& sampling = allocation->plan().campaign.sampling;
  if (rank == 0) WarnAboutContactLaw(sampling.scene, sampling.scene_file, progress);

  // Rank 0's results file, or under mpirun (and when continuing shards) every rank's own
  // shard, the results file becoming their index.
  std::unique_ptr<AllocationStore> store;
  std::optional<AllocationShards> shards;
  std::int32_t sharded = 0;
  std::string error;
  if (rank == 0) {
    error = Attempt([&] {
      if (!command.resume) {
        RefuseLiveOutput(command.out);  // one may have started since CheckBeforeWork
        if (const std::vector<std::filesystem::path> left = FindShards(command.out); !left.empty()) {
          throw InputError(fmt::format("{}: shards of an earlier run of it exist ({}); pass --resume to continue "
                                       "that run, or remove them to start a new one",
                                       command.out.string(), left.front().string()));
        }
      }
      sharded = ranks > 1 || (command.resume && IsShardedAllocation(command.out)) ? 1 : 0;
      if (sharded == 0) {
        store = std::make_unique<AllocationStore>(
            command.resume ? AllocationStore::Resume(command.out, allocation->identity())
                           : AllocationStore::Create(command.out, allocation->identity(), allocation->DesignPoints()));
        return;
      }
      if (command.resume) MakeShardZero(command.out, allocation->identity());
      shards.emplace();
      shards->results = command.out;
      for (const std::filesystem::path& path : FindShards(command.out)) {
        bool own = false;
        for (int r = 0; r < ranks; ++r) own = own || path == ShardPath(command.out, r);
        if (!own) shards->stale.push_back(path);
      }
    });
  }
  ThrowAgreed(world, error);
  MPI_Bcast(&sharded, 1, MPI_INT32_T, 0, world);
  if (sharded != 0) {
    if (rank != 0) shards.emplace(AllocationShards{command.out, {}});
    error = Attempt([&] {
      const std::filesystem::path own = ShardPath(command.out, rank);
      store = std::make_unique<AllocationStore>(std::filesystem::exists(own)
                                                    ? AllocationStore::Resume(own, allocation->identity())
                                                    : AllocationStore::CreateShard(own, allocation->identity()));
    });
    ThrowAgreed(world, error);
  }

  std::function<void(const AllocationProgress&)> report_progress;
  const bool terminal = isatty(STDERR_FILENO) == 1;
  if (rank == 0 && !command.quiet)
    report_progress = AllocationProgressPrinter(progress, terminal, command.progress_seconds);
  run = RunAllocation(world, *allocation, store.get(), pool, report_progress, shards ? &*shards : nullptr);
  const int stopped = run.stopped != 0 ? run.stopped : signals->received();
  if (rank != 0) return stopped != 0 ? StopSignals::ExitCode(stopped) : 0;
  store.reset();
  if (report_progress && terminal) fmt::print(progress, "\n");
  if (stopped != 0 && !resumable) {
    fmt::print(progress, "ringtol: stopped by {}\n", StopSignals::Name(stopped));
    return StopSignals::ExitCode(stopped);
  }
  if (stopped != 0) {
    std::vector<std::string> words = command.arguments;
    if (words.empty()) words = {"ringtol", "allocate", command.file.string(), "--out", command.out.string()};
    fmt::print(progress,
               "ringtol: stopped by {}: every sample this run finished ({}) is on disk in {}; continue with:\n  {}\n",
               StopSignals::Name(stopped), run.computed, command.out.string(), ResumeLine(std::move(words), ranks));
    progress.flush();
    return StopSignals::ExitCode(stopped);
  }
  return 0;
}

int Rank() {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

}  // namespace

int RunAllocate(const AllocateCommand& command, std::ostream& out, std::ostream& progress) {
  AllocationRunReport run;
  if (const int stopped = Execute(command, progress, run, true); stopped != 0 || Rank() != 0) return stopped;
  const AllocationReader results(command.out);
  const AllocationOutcome outcome = results.ReadOutcome();
  if (command.json) {
    nlohmann::json json = AllocationJson(results.identity(), outcome);
    json["run"] = RunJson(run);
    out << json.dump(2) << "\n";
    return 0;
  }
  fmt::print(out, "allocation        {}\n", command.file.string());
  fmt::print(out, "results           {}{}\n", command.out.string(),
             run.shards > 0 ? fmt::format(": an index of {} shards beside it (keep them together; `ringtol join` "
                                          "makes one file)",
                                          run.shards)
                            : std::string());
  PrintAllocation(out, results.identity(), outcome);
  const double rate = run.wall_time > 0 ? static_cast<double>(run.computed) / run.wall_time : 0.0;
  fmt::print(out, "\nthis run          {} samples in {} rounds, {:.1f} s: {:.0f} samples/s on {} rank{}\n", run.computed,
             run.rounds, run.wall_time, rate, run.ranks, run.ranks == 1 ? "" : "s");
  return 0;
}

int RunBenchAllocate(const AllocateCommand& command, std::ostream& out, std::ostream& progress) {
  AllocateCommand bench = command;
  bench.resume = false;
  // Rank 0 alone writes the file; the name only needs to be free there.
  bench.out = std::filesystem::temp_directory_path() / fmt::format("ringtol-bench-allocate-{}.h5", getpid());
  AllocationRunReport run;
  const int stopped = Execute(bench, progress, run, false);
  if (Rank() != 0) return stopped;
  const AllocationIdentity identity = AllocationReader(bench.out).identity();
  const AllocationOutcome outcome = AllocationReader(bench.out).ReadOutcome();
  std::filesystem::remove(bench.out);
  if (stopped != 0) return stopped;
  const auto candidates = static_cast<std::int64_t>(outcome.candidates.size());
  const auto share = [](std::int64_t part, std::int64_t whole) {
    return whole > 0 ? 100.0 * static_cast<double>(part) / static_cast<double>(whole) : 0.0;
  };
  const double seconds = std::max(run.wall_time, 1e-9);
  fmt::print(out, "allocation        {} on {} rank{} ({} computing)\n", command.file.string(), run.ranks,
             run.ranks == 1 ? "" : "s", run.computing_ranks);
  fmt::print(out, "candidates        {}; search {}; simulated {} ({:.1f} %), {} of them settled by the screen ({:.1f} %)\n",
             candidates, identity.search, outcome.simulated, share(outcome.simulated, candidates),
             outcome.settled_by_screen, share(outcome.settled_by_screen, outcome.simulated));
  fmt::print(out, "samples           {} screen ({}) + {} confirm ({})\n", outcome.samples_screen, identity.screen,
             outcome.samples_confirm, identity.solver);
  fmt::print(out, "wall time         {:.2f} s: {:.3g} candidates/s simulated, {:.0f} samples/s; {} rounds\n",
             run.wall_time, static_cast<double>(outcome.simulated) / seconds,
             static_cast<double>(run.computed) / seconds, run.rounds);
  if (outcome.recommendation) {
    fmt::print(out, "recommendation    candidate {}: {}\n", *outcome.recommendation,
               CandidateClasses(identity, outcome.candidates[static_cast<std::size_t>(*outcome.recommendation)]));
  }
  return 0;
}

}  // namespace ringtol::jobs
