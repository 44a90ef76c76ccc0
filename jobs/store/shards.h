// Shards of a results file, whichever store wrote them: their names and discovery, the
// lock that tells a live run's files from a killed one's, and setting aside a shard that
// cannot be read. Naming only: the stores read and write what is inside
// (jobs/store/campaign_store.h, allocation_store.h).
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ringtol::jobs {

// Under mpirun each computing rank writes the samples it computes into a shard of its own,
// a results file of the same run (same schema, same chunks) beside the results file, so
// that results never travel through rank 0; the results file is their index (each store
// writes its own). ShardPath: "<results>.shard-<rank>". FindShards: those that exist, by
// rank.
std::filesystem::path ShardPath(const std::filesystem::path& results, int rank);
std::vector<std::filesystem::path> FindShards(const std::filesystem::path& results);
// The results file `results` (a campaign's or an allocation's) or one of its shards that a
// running ringtol writes now, if any: every writer holds an open file description lock on
// its file while it runs (released when it ends, however it ends), so a second run can
// tell a live run's files from a killed one's and never advise removing them.
std::optional<std::filesystem::path> BeingWritten(const std::filesystem::path& results);

// How a run of `ranks` computing ranks writes `results`, decided by rank 0 before any store
// opens: in `results` itself (one rank, nothing kept in shards), or each rank in a shard of
// its own with `results` their index.
struct ShardPlan {
  bool sharded = false;
  // Shards an earlier run's ranks left that this run has no rank for: rank 0 repairs and
  // reads each, and indexes it after the ranks' own.
  std::vector<std::filesystem::path> stale;
};
// A new run (`resume` false) refuses shards an earlier run left (InputError: resume them or
// remove them). A resume in shards first makes a self-contained `results` shard 0:
// `resume_file` resumes it as its store does (checking and repairing it), then it is
// renamed, its samples staying where they are on disk; InputError when shard 0 exists
// beside it. Each store wraps this with its own `resume_file` (PlanCampaignShards,
// PlanAllocationShards).
ShardPlan PlanShards(const std::filesystem::path& results, int ranks, bool resume,
                     const std::function<void(const std::filesystem::path&)>& resume_file);

// Shards that cannot be read at all (truncated, not HDF5, their metadata, descriptions or
// chunk indexes damaged) hold nothing a resume can use; every reader refuses them, naming
// the shard and the resume below. Before a resume continues `results` in shards, each such
// shard is set aside: renamed to SetAsidePath(shard), never deleted (nothing computed is
// ever lost), so that its samples are computed again. A shard of another campaign reads,
// and is refused for what it is; a shard with damaged chunks reads, and the resume repairs
// it (CampaignStore::Resume). Then InputError, as readers give, for a shard the index lists
// that is missing and was never set aside. Returns the shards set aside.
struct UnreadableShard {
  std::filesystem::path shard;
  std::filesystem::path aside;  // its new name
  std::string why;              // what reading it said
};
// As above, for shards of any results file: `read_shard` reads one as its readers would,
// throwing InputError when it cannot (an allocation's: SetAsideUnreadableAllocationShards,
// jobs/store/allocation_store.h).
std::vector<UnreadableShard> SetAsideUnreadableShards(const std::filesystem::path& results,
                                                      const std::function<void(const std::filesystem::path&)>& read_shard);
// What a reader of `index` says of its shard that cannot be read (`why`), with the resume
// that recovers its samples: `ringtol <command> <input> --out <index> --resume`.
std::string UnreadableShardMessage(const std::string& index, const std::filesystem::path& shard, const std::string& why,
                                   std::string_view command, const std::string& input);
// "<shard>.unreadable", or "<shard>.unreadable-2", -3, ...: the first name that is free.
std::filesystem::path SetAsidePath(const std::filesystem::path& shard);
// Before an index of `shards` is written at `results`: InputError when a file there keeps
// samples of its own (an index never replaces one), std::invalid_argument naming `writer`
// for a shard that is not beside it (an index lists its shards by name).
void CheckIndexTarget(const std::filesystem::path& results, const std::vector<std::filesystem::path>& shards,
                      std::string_view writer);
// Whether `results` is an index of shards, a campaign's or an allocation's: its root only is
// read, its shards not opened. InputError when it cannot be opened.
bool IsShardIndex(const std::filesystem::path& results);

}  // namespace ringtol::jobs
