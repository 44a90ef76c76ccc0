// `ringtol allocate`: a tolerance allocation from an allocation file
// (jobs/allocation/allocation_file.h) into a results file (jobs/store/allocation_store.h),
// alone or as an MPI pool (jobs/pool/allocation_pool.h), ending with the recommendation.
#pragma once

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "jobs/pool/pool.h"

namespace ringtol::jobs {

struct AllocateCommand {
  std::filesystem::path file;      // allocation file
  std::filesystem::path out;       // results file (HDF5)
  bool resume = false;             // continue `out`, computing only what it lacks
  bool json = false;               // the recommendation as one JSON object
  bool quiet = false;              // no progress on stderr
  double progress_seconds = 10.0;  // [s] > 0: between progress lines when stderr is not a terminal
  PoolOptions pool;                // its `stop` is set by RunAllocate
  std::vector<std::string> arguments;  // argv, repeated with --resume after a stop
};

// As RunCampaign (jobs/cli/campaign_command.h): call on every rank between MPI_Init_thread
// and MPI_Finalize; every input is checked on every rank before the first sample; SIGINT
// and SIGTERM stop cleanly with every finished sample on disk and the resume command
// printed (exit 130 / 143). Rank 0 prints the recommended allocation (the cheapest
// feasible candidate, its cost against the reference, its margin to every limit, the next
// two alternatives, the undecided candidates that could still undercut it) or, when no
// candidate is feasible, the constraints that bind. Returns 0.
int RunAllocate(const AllocateCommand& command, std::ostream& out, std::ostream& progress);

// `ringtol bench allocate`: runs `command.file` as RunAllocate does, into a temporary
// results file (command.out is ignored and the file removed after), and prints what the
// run cost: candidates simulated per second, samples per second by role, the share of
// candidates the screening rung settled. MPI as RunAllocate.
int RunBenchAllocate(const AllocateCommand& command, std::ostream& out, std::ostream& progress);

}  // namespace ringtol::jobs
