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

// What the shards cost rank 0: the messages it exchanged with worker ranks, and joining
// the shards into the results file.
void PrintShards(std::ostream& out, const PoolReport& run, const CampaignStore::Absorbed& joined, double join_time) {
  if (run.ranks < 2 || run.computed == 0) return;
  const auto per_sample = [&](double x) { return x / static_cast<double>(run.computed); };
  fmt::print(out,
             "coordinator       {:.3f} messages ({:.0f} bytes) per sample with the workers; joining their shards: "
             "{} samples ({} in whole chunks, {:.1f} MB) in {:.2f} s\n",
             per_sample(static_cast<double>(run.coordinator_messages)),
             per_sample(static_cast<double>(run.coordinator_bytes)), joined.samples, joined.chunk_samples,
             static_cast<double>(joined.bytes) / 1e6, join_time);
}

nlohmann::json RunJson(const PoolReport& run, const CampaignStore::Absorbed& joined, double join_time,
                       double join_cpu_time) {
  return {{"computed", run.computed},
          {"coordinator_cpu_time_s", run.coordinator_cpu_time},
          {"shard_join_cpu_time_s", join_cpu_time},
          {"coordinator_messages", run.coordinator_messages},
          {"coordinator_bytes", run.coordinator_bytes},
          {"shard_samples_joined", joined.samples},
          {"shard_chunk_samples_joined", joined.chunk_samples},
          {"shard_bytes_joined", joined.bytes},
          {"shard_join_time_s", join_time},
          {"already_done", run.already_done},
          {"wall_time_s", run.wall_time},
          {"samples_per_s", SamplesPerSecond(run)},
          {"solver_time_s", run.solver_time},
          {"commit_time_s", run.commit_time},
          {"coordinator_time_s", run.coordinator_time},
          {"ranks", run.ranks},
          {"computing_ranks", run.computing_ranks}};
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

std::int64_t SamplesOnDisk(const std::filesystem::path& file) {
  const CampaignReader results(file);
  constexpr std::int64_t kBlock = std::int64_t{1} << 20;
  std::int64_t done = 0;
  for (std::int64_t begin = 0; begin < results.samples(); begin += kBlock) {
    const std::vector<SampleStatus> status = results.ReadStatus(begin, std::min(kBlock, results.samples() - begin));
    done += std::count_if(status.begin(), status.end(), [](SampleStatus s) { return s != SampleStatus::kPending; });
  }
  return done;
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

  std::unique_ptr<CampaignStore> store;
  std::string error;
  if (rank == 0) {
    error = Attempt([&] {
      const std::vector<std::filesystem::path> shards = FindShards(command.out);
      if (!command.resume && !shards.empty()) {
        throw InputError(fmt::format("{}: shards of an earlier run of it exist ({}); pass --resume to continue that "
                                     "run, or remove them to start a new one",
                                     command.out.string(), shards.front().string()));
      }
      CampaignStoreOptions options;
      if (command.store_inputs) options.inputs_stored_below = std::numeric_limits<std::int64_t>::max();
      store = std::make_unique<CampaignStore>(
          command.resume ? CampaignStore::Resume(command.out, campaign->identity(), campaign->samples())
                         : CampaignStore::Create(command.out, campaign->identity(), campaign->samples(), options));
      // What a run killed before joining its shards left in them.
      for (const std::filesystem::path& shard : shards) store->Absorb(shard);
    });
  }
  ThrowAgreed(world, error);

  // Worker ranks file what they compute in shards of their own, chunked as the results
  // file is and keeping the same samples' inputs, so that rank 0 joins them by copying
  // whole chunks.
  std::array<std::int64_t, 2> layout = {rank == 0 ? store->chunk_rows() : 0,
                                        rank == 0 ? store->inputs_stored_below() : 0};
  MPI_Bcast(layout.data(), 2, MPI_INT64_T, 0, world);
  const std::int64_t chunk_rows = layout[0];
  pool.align_samples = chunk_rows;
  std::unique_ptr<CampaignStore> shard;
  if (rank != 0) {
    error = Attempt([&] {
      CampaignStoreOptions options;
      options.chunk_samples = chunk_rows;
      options.inputs_stored_below = layout[1];
      shard = std::make_unique<CampaignStore>(
          CampaignStore::Create(ShardPath(command.out, rank), campaign->identity(), campaign->samples(), options));
    });
  }
  ThrowAgreed(world, error);

  std::function<void(const PoolProgress&)> report_progress;
  if (rank == 0 && !command.quiet) {
    report_progress = ProgressPrinter(progress, isatty(STDERR_FILENO) == 1, command.progress_seconds);
  }
  const PoolReport run = RunPool(world, *campaign, rank == 0 ? store.get() : shard.get(), pool, report_progress);
  shard.reset();  // committed and closed before rank 0 joins it
  MPI_Barrier(world);
  const int stopped = run.stopped != 0 ? run.stopped : signals->received();
  if (rank != 0) return signals->received() != 0 ? StopSignals::ExitCode(signals->received()) : 0;
  CampaignStore::Absorbed joined;
  const auto join_start = std::chrono::steady_clock::now();
  const double join_cpu_start = ThreadCpuSeconds();
  for (const std::filesystem::path& path : FindShards(command.out)) {
    const CampaignStore::Absorbed one = store->Absorb(path);
    joined.samples += one.samples;
    joined.chunk_samples += one.chunk_samples;
    joined.bytes += one.bytes;
  }
  const double join_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - join_start).count();
  const double join_cpu_time = ThreadCpuSeconds() - join_cpu_start;
  store.reset();  // closes the file: the summary reads what is on disk
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
  const CampaignSummary summary =
      Summarise(results, [&campaign = *campaign](std::int64_t index) { return campaign.IndependentDraw(index); });
  if (command.json) {
    nlohmann::json json = SummaryJson(summary);
    json["run"] = RunJson(run, joined, join_time, join_cpu_time);
    out << json.dump(2) << "\n";
  } else {
    fmt::print(out, "campaign          {}\n", command.file.string());
    fmt::print(out, "results           {}\n", command.out.string());
    fmt::print(out, "design            {}, seed {}, {} inputs; solver {}\n\n", campaign->identity().design,
               campaign->identity().seed, campaign->identity().inputs.size(), campaign->identity().solver);
    PrintSummary(out, summary);
    PrintRun(out, run);
    PrintShards(out, run, joined, join_time);
  }
  return 0;
}

}  // namespace ringtol::jobs
