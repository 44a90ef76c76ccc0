#include "jobs/cli/campaign_command.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "jobs/campaign/campaign.h"
#include "jobs/cli/contact_warning.h"
#include "jobs/cli/pool_run.h"
#include "jobs/inputs/input_error.h"
#include "jobs/pool/stop_signals.h"
#include "jobs/report/campaign_summary.h"
#include "jobs/store/campaign_store.h"

namespace ringtol::jobs {
namespace {

double SamplesPerSecond(const PoolReport& run) {
  return run.wall_time > 0 ? static_cast<double>(run.computed) / run.wall_time : 0.0;
}

// This run's cost, after the campaign's summary.
void PrintRun(std::ostream& out, const PoolReport& run) {
  const double busy = run.wall_time * std::max(1, run.computing_ranks);
  fmt::print(out, "\nthis run          {} samples computed ({} already on disk) in {:.2f} s: {:.1f} samples/s on {} rank{}\n",
             run.computed, run.already_done, run.wall_time, SamplesPerSecond(run), run.ranks, run.ranks == 1 ? "" : "s");
  if (run.computed > 0) {
    fmt::print(out,
               "time              {:.1f} % of the computing ranks' time in samples; rank 0 handled results for "
               "{:.2f} s ({:.1f} us per sample), {:.2f} s of it writing the file\n",
               100 * run.solver_time / busy, run.coordinator_time,
               1e6 * run.coordinator_time / static_cast<double>(run.computed), run.commit_time);
  }
}

// Under mpirun: what the workers cost rank 0 (the messages it exchanged with them) and the
// index it wrote of their shards.
struct Indexed {
  ShardIndexSummary index;
  double seconds = 0.0;      // [s] writing the index
  double cpu_seconds = 0.0;  // [s] of which CPU
};

void PrintShards(std::ostream& out, const PoolReport& run, const std::optional<Indexed>& indexed) {
  if (!indexed) return;
  const auto per_sample = [&](double x) { return run.computed > 0 ? x / static_cast<double>(run.computed) : 0.0; };
  fmt::print(out,
             "coordinator       {:.3f} messages ({:.0f} bytes) per sample with the workers; the results file indexes "
             "{} shards ({} mappings, at most {} a shard), written in {:.3f} s\n",
             per_sample(static_cast<double>(run.coordinator_messages)),
             per_sample(static_cast<double>(run.coordinator_bytes)), indexed->index.shards, indexed->index.mappings,
             indexed->index.most_mappings, indexed->seconds);
}

nlohmann::json RunJson(const PoolReport& run, const std::optional<Indexed>& indexed) {
  nlohmann::json json = {{"computed", run.computed},
                         {"coordinator_cpu_time_s", run.coordinator_cpu_time},
                         {"coordinator_messages", run.coordinator_messages},
                         {"coordinator_bytes", run.coordinator_bytes},
                         {"worker_cpu_time_s", run.worker_cpu_time},
                         {"worker_sample_cpu_time_s", run.worker_sample_cpu_time},
                         {"worker_wait_cpu_time_s", run.worker_wait_cpu_time},
                         {"tail_time_s", run.tail_time},
                         {"already_done", run.already_done},
                         {"wall_time_s", run.wall_time},
                         {"samples_per_s", SamplesPerSecond(run)},
                         {"solver_time_s", run.solver_time},
                         {"commit_time_s", run.commit_time},
                         {"coordinator_time_s", run.coordinator_time},
                         {"ranks", run.ranks},
                         {"computing_ranks", run.computing_ranks}};
  if (indexed) {
    json["shards"] = indexed->index.shards;
    json["shard_mappings"] = indexed->index.mappings;
    json["shard_mappings_most"] = indexed->index.most_mappings;
    json["index_time_s"] = indexed->seconds;
    json["index_cpu_time_s"] = indexed->cpu_seconds;
  }
  return json;
}

// Progress on stderr: a bar redrawn in place on a terminal, a line every `interval`
// seconds otherwise (logs of batch jobs).
class ProgressPrinter {
 public:
  ProgressPrinter(std::ostream& out, bool terminal, double interval) : out_(out), terminal_(terminal), interval_(interval) {}

  void operator()(const PoolProgress& p) {
    const bool last = p.done == p.total;
    const double wait = terminal_ ? kRedrawSeconds : interval_;
    if (!last && p.elapsed - printed_at_ < wait && printed_at_ >= 0.0) return;
    if (last && finished_) return;
    finished_ = last;
    printed_at_ = p.elapsed;
    const double rate = p.elapsed > 0 ? static_cast<double>(p.this_run) / p.elapsed : 0.0;
    const double fraction = p.total > 0 ? static_cast<double>(p.done) / static_cast<double>(p.total) : 1.0;
    const std::string eta =
        rate > 0 ? Clock(static_cast<double>(p.total - p.done) / rate) : std::string("-");
    const std::string text = fmt::format("{}/{} samples ({:.1f} %), {:.1f} samples/s, ETA {}, {} failed", p.done,
                                         p.total, 100 * fraction, rate, eta, p.failed);
    if (terminal_) {
      constexpr int kWidth = 30;
      const auto filled = static_cast<int>(fraction * kWidth);
      fmt::print(out_, "\r[{}{}] {}\x1b[K{}", std::string(static_cast<std::size_t>(filled), '#'),
                 std::string(static_cast<std::size_t>(kWidth - filled), '.'), text, last ? "\n" : "");
    } else {
      fmt::print(out_, "campaign: {}\n", text);
    }
    out_.flush();
  }

 private:
  static constexpr double kRedrawSeconds = 0.2;
  std::ostream& out_;
  bool terminal_;
  double interval_;
  double printed_at_ = -1.0;
  bool finished_ = false;
};


// The command that continues the campaign: the same arguments with --resume.
std::string ResumeCommand(const CampaignCommand& command, int ranks) {
  std::vector<std::string> words = command.arguments;
  if (words.empty()) {
    words = {"ringtol", "campaign", command.file.string(), "--out", command.out.string()};
    if (command.samples) words.insert(words.end(), {"--samples", std::to_string(*command.samples)});
    if (command.seed) words.insert(words.end(), {"--seed", std::to_string(*command.seed)});
  }
  return ResumeLine(std::move(words), ranks);
}

// Read where the file was written only: a stop does not wait on the samples asked for.
std::int64_t SamplesOnDisk(const std::filesystem::path& file) {
  std::int64_t done = 0;
  for (const SampleRange& run : CampaignReader(file).Finished()) done += run.end - run.begin;
  return done;
}



// The contents of every rank's shard, on rank 0 in rank order (collective): each rank
// reads its own (`mine`; samples < 0 when it could not), so that the cost is spread
// over the ranks; rank 0 reads itself a shard whose rank could not.
std::vector<ShardContents> GatherContents(MPI_Comm world, const ShardContents& mine, const std::filesystem::path& out,
                                          const CampaignIdentity& identity, std::int64_t samples) {
  int rank = 0;
  int ranks = 1;
  MPI_Comm_rank(world, &rank);
  MPI_Comm_size(world, &ranks);
  std::vector<std::int64_t> packed = {mine.samples, mine.chunk_rows, mine.inputs_stored_below, mine.failure_rows,
                                      mine.schema};
  for (const SampleRange& range : mine.finished) packed.insert(packed.end(), {range.begin, range.end});
  const int count = static_cast<int>(packed.size());
  std::vector<int> counts(static_cast<std::size_t>(ranks));
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, world);
  std::vector<int> offsets(static_cast<std::size_t>(ranks), 0);
  for (std::size_t r = 1; r < offsets.size(); ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
  std::vector<std::int64_t> all(rank == 0 ? static_cast<std::size_t>(offsets.back() + counts.back()) : 0);
  MPI_Gatherv(packed.data(), count, MPI_INT64_T, all.data(), counts.data(), offsets.data(), MPI_INT64_T, 0, world);
  std::vector<ShardContents> contents;
  if (rank != 0) return contents;
  for (int r = 0; r < ranks; ++r) {
    const std::int64_t* at = all.data() + offsets[static_cast<std::size_t>(r)];
    if (at[0] < 0) {
      contents.push_back(ReadShardContents(ShardPath(out, r), identity, samples));
      continue;
    }
    ShardContents shard{ShardPath(out, r), at[0], at[1], at[2], at[3], {}, static_cast<int>(at[4])};
    for (int k = 5; k + 1 < counts[static_cast<std::size_t>(r)]; k += 2) shard.finished.push_back({at[k], at[k + 1]});
    contents.push_back(std::move(shard));
  }
  return contents;
}

// What `store` holds, or samples = -1 when it cannot say (GatherContents reads it then).
ShardContents ContentsOf(CampaignStore* store) {
  ShardContents contents;
  contents.samples = -1;
  if (store == nullptr) return contents;
  try {
    return store->Contents();
  } catch (const std::exception&) {
    return contents;
  }
}

}  // namespace

int RunCampaign(const CampaignCommand& command, std::ostream& out, std::ostream& progress) {
  const MPI_Comm world = MPI_COMM_WORLD;
  int rank = 0;
  int ranks = 1;
  MPI_Comm_rank(world, &rank);
  MPI_Comm_size(world, &ranks);
  // Watched from the start: a signal during the checks or the calibration stops the pool
  // before its first sample, with the file created and closed.
  std::optional<StopSignals> signals(std::in_place, UnderLauncher(world) ? StopSignals::Repeat::kIgnored
                                                                         : StopSignals::Repeat::kEndsAtOnce);
  PoolOptions pool = command.pool;
  pool.stop = [&signals] { return signals->received(); };

  // Cheap checks first, so a wrong option fails before a second of calibration.
  CheckBeforeWork(world, command.pool, command.progress_seconds, command.out, command.resume);
  // A shard that cannot be read holds nothing to continue: renamed aside, its samples are
  // computed again, like those no shard holds.
  if (command.resume) SetAsideUnreadable(world, progress, [&] { return SetAsideUnreadableShards(command.out); });

  // A resume without --samples never asks a file grown by an earlier --samples to shrink:
  // the larger of the campaign file's count and the file's own. A file that does not read
  // is refused below, by Resume.
  std::optional<std::int64_t> stored_samples;
  if (command.resume && !command.samples) {
    std::int64_t stored = 0;
    if (rank == 0) {
      try {
        stored = CampaignReader(command.out).samples();
      } catch (const std::exception&) {
        stored = 0;
      }
    }
    MPI_Bcast(&stored, 1, MPI_INT64_T, 0, world);
    if (stored > 0) stored_samples = stored;
  }
  std::unique_ptr<Campaign> campaign;
  ThrowAgreed(world, Attempt([&] {
    std::optional<std::int64_t> samples = command.samples;
    if (stored_samples && *stored_samples > ReadCampaignFile(command.file).sampling.samples) samples = stored_samples;
    campaign = std::make_unique<Campaign>(command.file, samples, command.seed);
  }));
  if (rank == 0) WarnAboutContactLaw(campaign->plan().sampling.scene, campaign->plan().sampling.scene_file, progress);

  // Rank 0's results file, or under mpirun the shard of every computing rank (rank 0's
  // included) and `finished`, what the shards already hold.
  std::unique_ptr<CampaignStore> store;
  std::vector<ShardContents> stale;  // shards of ranks this run does not have
  std::vector<SampleRange> finished;  // ascending, disjoint runs
  std::array<std::int64_t, 4> layout = {0, 0, 0, 0};  // sharded, chunk rows, inputs stored below, schema
  std::string error;
  if (rank == 0) {
    error = Attempt([&] {
      CampaignStoreOptions options;
      if (command.store_inputs) options.inputs_stored_below = std::numeric_limits<std::int64_t>::max();
      if (!command.resume) RefuseLiveOutput(command.out);  // one may have started since CheckBeforeWork
      const ShardPlan plan =
          PlanCampaignShards(command.out, campaign->identity(), campaign->samples(), ranks, command.resume);
      if (plan.sharded) {
        stale = RepairStaleShards(plan.stale, campaign->identity(), campaign->samples());
        store = std::make_unique<CampaignStore>(
            OpenCampaignShard(command.out, 0, campaign->identity(), campaign->samples(), options));
      } else {
        store = std::make_unique<CampaignStore>(
            command.resume ? CampaignStore::Resume(command.out, campaign->identity(), campaign->samples())
                           : CampaignStore::Create(command.out, campaign->identity(), campaign->samples(), options));
      }
      layout = {plan.sharded ? 1 : 0, store->chunk_rows(), store->inputs_stored_below(), store->schema()};
    });
  }
  ThrowAgreed(world, error);

  // Every other rank files what it computes in a shard of its own, chunked as rank 0's,
  // keeping the same samples' inputs, in its schema.
  MPI_Bcast(layout.data(), static_cast<int>(layout.size()), MPI_INT64_T, 0, world);
  const bool sharded = layout[0] != 0;
  const std::int64_t chunk_rows = layout[1];
  pool.align_samples = chunk_rows;
  std::unique_ptr<CampaignStore> shard;
  if (rank != 0) {
    error = Attempt([&] {
      CampaignStoreOptions options;
      options.chunk_samples = chunk_rows;
      options.inputs_stored_below = layout[2];
      options.schema = static_cast<int>(layout[3]);
      shard = std::make_unique<CampaignStore>(
          OpenCampaignShard(command.out, rank, campaign->identity(), campaign->samples(), options));
    });
  }
  ThrowAgreed(world, error);
  // The results file exists from the start: an index of the shards, showing what they
  // hold now (rewritten when the run ends or stops). Each rank reads its own shard.
  if (sharded) {
    std::vector<ShardContents> contents = GatherContents(world, ContentsOf(rank == 0 ? store.get() : shard.get()),
                                                         command.out, campaign->identity(), campaign->samples());
    if (rank == 0) {
      error = Attempt([&] {
        contents.insert(contents.end(), stale.begin(), stale.end());
        for (const ShardContents& one : contents) finished.insert(finished.end(), one.finished.begin(), one.finished.end());
        finished = MergeRanges(std::move(finished));
        WriteShardIndex(command.out, campaign->identity(), campaign->samples(), contents);
      });
    }
    ThrowAgreed(world, error);
  }

  std::function<void(const PoolProgress&)> report_progress;
  if (rank == 0 && !command.quiet) {
    report_progress = ProgressPrinter(progress, isatty(STDERR_FILENO) == 1, command.progress_seconds);
  }
  const PoolReport run = RunPool(world, *campaign, rank == 0 ? store.get() : shard.get(), pool, report_progress,
                                 rank == 0 && sharded ? &finished : nullptr);
  // Every rank commits and says what its shard holds; all are closed before rank 0 indexes
  // them, and the summary reads what is on disk.
  const auto index_start = std::chrono::steady_clock::now();
  const double index_cpu_start = ThreadCpuSeconds();
  std::vector<ShardContents> contents;
  if (sharded) {
    contents = GatherContents(world, ContentsOf(rank == 0 ? store.get() : shard.get()), command.out,
                              campaign->identity(), campaign->samples());
  }
  shard.reset();
  store.reset();
  MPI_Barrier(world);
  const int stopped = run.stopped != 0 ? run.stopped : signals->received();
  if (rank != 0) return signals->received() != 0 ? StopSignals::ExitCode(signals->received()) : 0;
  std::optional<Indexed> indexed;
  if (sharded) {
    contents.insert(contents.end(), stale.begin(), stale.end());
    indexed = Indexed{WriteShardIndex(command.out, campaign->identity(), campaign->samples(), contents)};
    indexed->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - index_start).count();
    indexed->cpu_seconds = ThreadCpuSeconds() - index_cpu_start;
  }
  if (stopped != 0) {
    const std::int64_t on_disk = SamplesOnDisk(command.out);
    fmt::print(progress,
               "{}ringtol: stopped by {}: {} of {} samples are on disk in {} ({} computed by this run, every one it "
               "finished); continue with:\n  {}\n",
               report_progress && isatty(STDERR_FILENO) == 1 ? "\n" : "", StopSignals::Name(stopped), on_disk,
               campaign->samples(), command.out.string(), run.computed, ResumeCommand(command, ranks));
    progress.flush();
    return StopSignals::ExitCode(stopped);
  }
  signals.reset();  // the file is complete and closed: a signal now ends the summary at once

  const CampaignReader results(command.out);
  // A disposition's intervals are at its confidence, the summary's with them.
  const std::optional<DispositionRule>& disposition = campaign->plan().disposition;
  CampaignSummary summary =
      Summarise(results, [&campaign = *campaign](std::int64_t index) { return campaign.IndependentDraw(index); },
                disposition ? disposition->confidence : kSummaryConfidence);
  if (disposition && summary.in_spec) {
    summary.disposition = Dispose(*disposition, summary.in_spec->successes, summary.in_spec->trials);
  }
  if (command.json) {
    nlohmann::json json = SummaryJson(summary);
    json["run"] = RunJson(run, indexed);
    out << json.dump(2) << "\n";
  } else {
    fmt::print(out, "campaign          {}\n", command.file.string());
    fmt::print(out, "results           {}\n", command.out.string());
    fmt::print(out, "design            {}, seed {}, {} inputs; solver {}\n\n", campaign->identity().design,
               campaign->identity().seed, campaign->identity().inputs.size(), campaign->identity().solver);
    PrintSummary(out, summary);
    PrintRun(out, run);
    PrintShards(out, run, indexed);
  }
  return summary.disposition ? DispositionExitCode(*summary.disposition) : 0;
}

}  // namespace ringtol::jobs
