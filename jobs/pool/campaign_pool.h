// The pool (jobs/pool/pool.h) on a campaign: its samples are the items, evaluated as
// SampleEvaluator does (or spun for PoolOptions::Testing::sample_seconds), into its
// results file or, under mpirun with shards, each rank's shard.
#pragma once

#include <mpi.h>

#include <functional>
#include <vector>

#include "jobs/campaign/campaign.h"
#include "jobs/pool/pool.h"
#include "jobs/store/campaign_store.h"

namespace ringtol::jobs {

// A campaign's pending samples into its results file (`store`: rank 0's; on a worker rank
// its shard, or null). With `finished` (rank 0; jobs/store/campaign_store.h: shards as the
// results file; ascending, disjoint runs) `store` is rank 0's own shard and the samples to
// compute are those `finished` does not hold, instead of the store's pending ones.
PoolReport RunPool(MPI_Comm communicator, const Campaign& campaign, CampaignStore* store, const PoolOptions& options,
                   const std::function<void(const PoolProgress&)>& progress,
                   const std::vector<SampleRange>* finished = nullptr);

}  // namespace ringtol::jobs
