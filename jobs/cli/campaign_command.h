// `ringtol campaign`: a Monte Carlo campaign from a campaign file (jobs/campaign/campaign_file.h)
// into a results file (jobs/store/campaign_store.h), alone or as an MPI pool
// (jobs/pool/campaign_pool.h), ending with a summary (jobs/report/campaign_summary.h).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "jobs/pool/campaign_pool.h"

namespace ringtol::jobs {

struct CampaignCommand {
  std::filesystem::path file;           // campaign file
  std::filesystem::path out;            // results file (HDF5)
  std::optional<std::int64_t> samples;  // overrides design.samples
  std::optional<std::uint64_t> seed;    // overrides seed
  bool resume = false;                  // continue `out`, computing only what it lacks
  bool json = false;                    // the summary as one JSON object
  bool quiet = false;                   // no progress on stderr
  // A new results file keeps every sample's u and values, not only the first
  // kStoredInputSamples (jobs/store/campaign_store.h); a resumed file keeps its own choice.
  bool store_inputs = false;
  double progress_seconds = 10.0;       // [s] > 0: between progress lines when stderr is not a terminal
  PoolOptions pool;                     // its `stop` is set by RunCampaign
  // The command line as typed (argv), repeated with --resume in the message of a stop;
  // empty: the file, --out, --samples and --seed are repeated.
  std::vector<std::string> arguments;
};

// Call on every rank, between MPI_Init_thread (MPI_THREAD_FUNNELED) and MPI_Finalize.
// Every input is read and checked, on every rank, and the results file opened, before
// the first sample; a problem on any rank becomes an InputError thrown on every rank
// with the same message (rank 0 prints it), so no rank is left waiting. Rank 0 writes the
// summary to `out` and the progress to `progress`; other ranks print nothing. Returns 0.
//
// SIGINT or SIGTERM (jobs/pool/stop_signals.h) stops it cleanly: no more work is handed
// out, every finished sample is written and the file closed; rank 0 then prints, on
// `progress`, how many samples are on disk and the command that continues the campaign,
// and no summary. Returns 128 + the signal (130, 143). Alone, a second signal ends the
// process at once; under a launcher (mpirun), which may forward one signal several times,
// repeats are ignored and the launcher's own escalation (its SIGKILL) ends it.
int RunCampaign(const CampaignCommand& command, std::ostream& out, std::ostream& progress);

}  // namespace ringtol::jobs
