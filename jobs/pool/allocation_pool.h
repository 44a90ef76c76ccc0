// A tolerance allocation on the campaign pool: rank 0 plays the search forward
// (jobs/allocation/allocation.h, AllocationDriver) and every round's candidate samples are
// computed by the pool (jobs/pool/pool.h) into the allocation's results file
// (jobs/store/allocation_store.h), the same code alone or under `mpirun -n K`.
//
// Each round, rank 0 broadcasts its segments (role, candidate, samples); the pool numbers
// their samples in segment order and hands them out as it hands out a campaign's, with
// the same adaptive chunks, commits, clean stop and kill hooks (PoolOptions). Which
// candidates a round holds is decided by the driver from the samples on disk alone, so the
// outcome does not depend on the number of ranks, the chunks, or an interruption.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <vector>

#include "jobs/allocation/allocation.h"
#include "jobs/pool/pool.h"
#include "jobs/store/allocation_store.h"

namespace ringtol::jobs {

struct AllocationProgress {
  std::int64_t round = 0;      // rounds played so far, this one included
  std::int64_t simulated = 0;  // candidates settled by simulation so far
  std::int64_t candidates = 0;
  PoolProgress samples;        // within this round
  std::int64_t computed = 0;   // samples computed by this run, all rounds
  double elapsed = 0.0;        // [s] since the allocation started
};

struct AllocationRunReport {
  std::int64_t rounds = 0;    // rounds this run computed samples in
  std::int64_t computed = 0;  // samples computed by this run
  std::map<SampleStatus, std::int64_t> status;
  double wall_time = 0.0;     // [s]
  double solver_time = 0.0;   // [s] sum of the samples' solve times, all ranks
  int computing_ranks = 0;
  int ranks = 0;
  int stopped = 0;            // nonzero: stopped early at this request (PoolOptions::stop)
  AllocationOutcome outcome;  // rank 0: as written last to the file
  // With shards: how many the index lists, the mappings of its [C, N] datasets of both
  // roles when last written, and rank 0's time writing it, all writes.
  std::int64_t shards = 0;
  std::int64_t shard_mappings = 0;
  double index_time = 0.0;  // [s]
};

// Shards as the results file (jobs/store/allocation_store.h): every rank files what it
// computes in its own shard, ShardPath(results, rank), and sends it to rank 0 too, which
// holds every finished sample's outputs in memory for the search (about (Q + 2) x 8 bytes
// a sample) and writes `results` as the shards' index whenever it writes the outcome: at
// the start, between rounds at most every commit_seconds, and at the end or stop. At the
// start each rank reads its shard's finished samples and sends them to rank 0.
struct AllocationShards {
  std::filesystem::path results;
  // Rank 0: shards an earlier run's ranks left that this run has no rank for; rank 0
  // resumes (repairs) and reads each, and indexes it after the ranks' own.
  std::vector<std::filesystem::path> stale;
};

// Runs on every rank of `communicator`; `store` is rank 0's open results file (null on the
// others), or with `shards` (the same on every rank) each rank's own open shard. Commits
// the outcome with the samples, at the end and whenever the pool commits (with shards: the
// samples, and the index between rounds). Throws std::runtime_error for any failure after
// the start (MPI, HDF5, a damaged chunk read back), which the caller must treat as fatal to
// every rank (MPI_Abort). PoolOptions' kill hooks count within one round: a round is one
// run of the pool.
AllocationRunReport RunAllocation(MPI_Comm communicator, const Allocation& allocation, AllocationStore* store,
                                  const PoolOptions& options,
                                  const std::function<void(const AllocationProgress&)>& progress,
                                  const AllocationShards* shards = nullptr);

}  // namespace ringtol::jobs
