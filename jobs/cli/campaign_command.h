// `ringtol campaign`: a Monte Carlo campaign from a campaign file (jobs/campaign/campaign_file.h)
// into a results file (jobs/store/campaign_store.h), alone or as an MPI pool
// (jobs/pool/campaign_pool.h), ending with a summary (jobs/report/campaign_summary.h).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>

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
  double progress_seconds = 10.0;       // [s] > 0: between progress lines when stderr is not a terminal
  PoolOptions pool;
};

// Call on every rank, between MPI_Init_thread (MPI_THREAD_FUNNELED) and MPI_Finalize.
// Every input is read and checked, on every rank, and the results file opened, before
// the first sample; a problem on any rank becomes an InputError thrown on every rank
// with the same message (rank 0 prints it), so no rank is left waiting. Rank 0 writes the
// summary to `out` and the progress to `progress`; other ranks print nothing. Returns 0.
int RunCampaign(const CampaignCommand& command, std::ostream& out, std::ostream& progress);

}  // namespace ringtol::jobs
