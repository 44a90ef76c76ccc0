// The results file of a tolerance allocation: one HDF5 file written by the coordinating
// rank (under mpirun: shards of every rank and their index, below), crash-safe and
// checksummed as the campaign's (jobs/store/campaign_store.h), with the same conventions.
// docs/results.md documents the schema for readers.
//
// Schema version 1 (C = candidates, N = most samples per candidate, d = sampler inputs,
// K = allocated components, O = options of all components, M = constraints, Q = stored outputs):
//   /                          attributes: format = "ringtol allocation", schema_version = 1,
//                              layout = "file" (as a campaign's), ringtol_version, catalogue_version, allocation_path,
//                              allocation_file, base_scene, design, solver, screen, search,
//                              seed (uint64), samples (int64 N), first_samples, confidence,
//                              candidates (int64 C), reference (int64, -1 for none)
//   /inputs/name, quantity, component, source, roller, order   [d] as in a campaign file
//   /inputs/u                  float64 [N, d]  the design point of sample i: the same for
//                              every candidate (common random numbers)
//   /components/name           [K] strings
//   /options/component         int32 [O]  the component each option belongs to, options in
//                              component order, loosest first within one
//   /options/class, mode       [O] strings
//   /options/tolerance, cost   float64 [O]  characteristic tolerance (µm, % for springs), cost
//   /constraints/output, kind  [M] strings;  /constraints/level, upper  float64 [M]
//   /candidates/options        int32 [C, K]  option per component (0 = loosest), mixed radix
//                              with the last component fastest (analysis::AllocationSpace)
//   /candidates/cost, relative_cost  float64 [C]  the sum of its options' costs, and that
//                              over the reference candidate's (candidate 0's when there is
//                              none; NaN when that costs 0). Written by Create, from the identity.
//   /samples/<role>/status     int8 enum [C, N]   SampleStatusName names, fill "pending";
//                              role: screen, confirm (EvaluationRole)
//   /samples/<role>/<output>   float64 [C, N]  each output a constraint names (Q of them),
//                              NaN unless ok
//   /samples/screen/d_trajectory_error_mm  float64 [C, N]  the screening rung's bound on its
//                              error in D_trajectory (Trajectory::error_estimate)
//   /samples/<role>/steps      int32 [C, N];  /samples/<role>/solve_time_s  float64 [C, N]
//   /outcome/...               the AllocationOutcome as of the last commit (derived from
//                              the samples; rewritten whole at every commit):
//     verdict, settlement, settled_by  int8 enums [C] named by kVerdictNames,
//                              kSettlementNames, kEvaluationRoleNames (settled_by -1: "none")
//     samples, implied_by      int64 [C]
//     estimate, lower, upper   float64 [C, M];  constraint_verdict int8 enum [C, M];
//     samples_to_decide        int64 [C, M]  (rows of candidates not simulated: NaN, unknown, 0)
//     yield, yield_lower, yield_upper  float64 [C];  yield_trials int64 [C]
//     recommendation (int64, -1 for none), complete (int8), simulated, settled_by_screen,
//     samples_screen, samples_confirm, common_random_numbers_gain: attributes of /outcome
//     alternatives, undecided_cheaper, front  int64 [*];  binding int32 [*]  (extendable)
// Create writes /outcome as an allocation with nothing visited. Every dataset is chunked
// and ends its filters with Fletcher-32; nothing is compressed (in SWMR mode HDF5 leaves
// the old copy of a rewritten compressed chunk behind). [C, N] datasets are chunked by
// candidate rows (1 x chunk_samples) and their chunks allocated when first written, so a
// candidate never simulated takes no space on disk (docs/results.md gives a measured size).
//
// Crash safety as CampaignStore, on the same sample table (jobs/store/sample_table.h):
// Commit writes each role's buffered outputs, steps and times, then their statuses, then
// /outcome whole, flushing each; a sample is on disk exactly when its status is not
// pending, and /outcome describes the last complete commit (a kill during its rewrite can
// tear it: it is derived, and the next commit rewrites it). Failure: InputError as CampaignStore's, naming the file: creating over an
// existing file or in a missing directory, resuming a file that is missing, not a ringtol
// allocation file (a campaign file is named as one), of another schema or of another
// allocation (the first differing field is named), reading a damaged chunk (naming the
// dataset, the candidate and the samples). Arguments that do not fit the allocation:
// std::invalid_argument or std::out_of_range. HDF5 write errors: std::runtime_error.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "jobs/allocation/allocation_outcome.h"
#include "jobs/campaign/sample_record.h"
#include "jobs/store/results_check.h"
#include "jobs/store/shards.h"

namespace ringtol::jobs {

inline constexpr int kAllocationSchemaVersion = 1;
// The schema_version of an index of shards (below: schema 1's datasets with every [C, N]
// one virtual, layout = "shard index", rows_schema = 1), which numbers the index's layout;
// indexes written before `layout` existed are recognised by it alone.
inline constexpr int kAllocationIndexSchemaVersion = 2;

// One finished sample of an allocation file: what the search judges a candidate by.
struct AllocationSample {
  EvaluationRole role = EvaluationRole::kScreen;
  std::int64_t candidate = 0;
  std::int64_t sample = 0;
  SampleStatus status = SampleStatus::kPending;
  std::vector<double> outputs;  // the stored outputs (AllocationStore::outputs()), NaN unless ok
  double error_bound = 0.0;     // [mm] the screening rung's bound; NaN unless ok, or confirming
};
// What a file keeps of `record` (sample record.index of a candidate): `outputs` by name
// from record.outputs, the error bound from record.d_trajectory_error (screen only), each
// NaN unless the sample is ok.
AllocationSample KeptSample(EvaluationRole role, std::int64_t candidate, const SampleRecord& record,
                            const std::vector<std::string>& outputs);

struct AllocationStoreOptions {
  // > 0: samples per chunk along N; 0: first_samples clamped to [64, 1024] and to N. The
  // stages end at multiples of first_samples, so a screened candidate fills its one chunk.
  std::int64_t chunk_samples = 0;
  // Per [C, N] dataset: keeps the chunks a batch of candidates fills in memory between its
  // commits (8 candidates of 2,048 samples are 128 KiB a dataset); finished candidates'
  // chunks are never written again, so more only holds memory.
  std::size_t chunk_cache_bytes = 4u << 20;
  bool checksums = true;  // false: no Fletcher-32, for tests and for measuring what it costs
};

class AllocationStore {
 public:
  // A new file, every sample pending, /inputs/u written from `design_points` (row-major
  // [N, d]). Refuses an existing path.
  static AllocationStore Create(const std::filesystem::path& path, const AllocationIdentity& identity,
                                const std::vector<double>& design_points, const AllocationStoreOptions& options = {});
  // An existing file of the same allocation, after a clean or killed run; damaged chunks of
  // [C, N] datasets are reset to pending (as CampaignStore::Resume: every allocated chunk
  // is read first, a refused file is never modified). Damage elsewhere (/inputs/u, the
  // descriptions, /outcome) is not repaired: the descriptions are refused when they do
  // not read, /outcome is rewritten by the next Commit. An index of shards is refused
  // (its shards are resumed instead).
  static AllocationStore Resume(const std::filesystem::path& path, const AllocationIdentity& identity,
                                const AllocationStoreOptions& options = {});
  // A new shard of an allocation run under mpirun (ShardPath): the same schema, with
  // /inputs/u left unwritten (it reads as NaN: the index keeps the design points) and
  // /outcome as created (CommitSamples; the index keeps the outcome). Resume continues one.
  static AllocationStore CreateShard(const std::filesystem::path& path, const AllocationIdentity& identity,
                                     const AllocationStoreOptions& options = {});
  // Commits the buffered samples (as CampaignStore does) but not an outcome, which only
  // Commit has: /outcome may then lag the samples on disk, as it does between two commits,
  // until the next run's first Commit. Never throws (errors go to stderr).
  ~AllocationStore();
  AllocationStore(AllocationStore&&) noexcept;
  AllocationStore& operator=(AllocationStore&&) noexcept;

  const std::filesystem::path& path() const;
  const AllocationIdentity& identity() const;

  // Whether each sample of [begin, end) of a candidate is done for a role, read from the
  // file and the buffer: true where its status is not pending.
  std::vector<bool> Done(EvaluationRole role, std::int64_t candidate, std::int64_t begin, std::int64_t end) const;
  // Statuses and one stored output of samples [begin, end) of a candidate, from the file
  // and the buffer (so the coordinator can judge before committing).
  std::vector<SampleStatus> ReadStatus(EvaluationRole role, std::int64_t candidate, std::int64_t begin,
                                       std::int64_t end) const;
  std::vector<double> ReadOutput(EvaluationRole role, std::string_view output, std::int64_t candidate,
                                 std::int64_t begin, std::int64_t end) const;
  std::vector<double> ReadErrorBound(std::int64_t candidate, std::int64_t begin, std::int64_t end) const;  // [mm]

  // Buffers one finished sample of a candidate: `record.index` is the sample index; the
  // stored outputs are taken from record.outputs by name, the error bound from
  // record.d_trajectory_error (screen only), each NaN unless the sample is ok. The last of
  // two records of one sample wins. std::out_of_range for a candidate or index outside the
  // file, std::invalid_argument for a pending or unknown status.
  void Add(EvaluationRole role, std::int64_t candidate, const SampleRecord& record);
  std::size_t buffered() const;
  // Writes every buffered sample (statuses last) and the outcome, and flushes; also with
  // nothing buffered. std::invalid_argument, before writing anything, for an outcome of
  // another candidate count, judgements of another constraint count, or a list naming a
  // candidate outside [0, C) or a constraint outside [0, M). The outcome's options, cost
  // and relative_cost are not stored (they are /candidates', from the identity).
  void Commit(const AllocationOutcome& outcome);
  // Writes every buffered sample (statuses last) and flushes, leaving /outcome as it is: a
  // shard's commit.
  void CommitSamples();

  // Copies into this file every finished sample of the shard at `shard` (a file of the same
  // allocation) that it has pending, and flushes, as CampaignStore::Absorb does: a chunk of
  // which this file holds no sample copied as stored, the others sample by sample. Returns
  // the samples copied. InputError for a shard that does not read or is of another
  // allocation.
  std::int64_t Absorb(const std::filesystem::path& shard);

  // The outputs every sample keeps, in AllocationSample::outputs' order.
  const std::vector<std::string>& outputs() const;
  // Every finished sample on disk (buffered ones are not), by role, candidate and sample:
  // what a shard tells the coordinator when a run resumes. Reads every status (C x N bytes
  // a role) and the rows of the candidates with finished samples.
  std::vector<AllocationSample> Finished() const;

 private:
  struct File;
  explicit AllocationStore(std::unique_ptr<File> file);
  static AllocationStore CreateFile(const std::filesystem::path& path, const AllocationIdentity& identity,
                                    const std::vector<double>& design_points, const AllocationStoreOptions& options);
  std::unique_ptr<File> file_;
};

class AllocationReader {
 public:
  explicit AllocationReader(const std::filesystem::path& path);
  ~AllocationReader();
  AllocationReader(AllocationReader&&) noexcept;

  const AllocationIdentity& identity() const;
  // The outcome of the last commit; options, cost and relative_cost from /candidates;
  // constraint judgements for simulated candidates only, each with the candidate's samples;
  // yield.successes = round(yield x trials), yield.confidence the identity's.
  AllocationOutcome ReadOutcome() const;
  std::vector<SampleStatus> ReadStatus(EvaluationRole role, std::int64_t candidate, std::int64_t begin,
                                       std::int64_t end) const;
  std::vector<double> ReadOutput(EvaluationRole role, std::string_view output, std::int64_t candidate,
                                 std::int64_t begin, std::int64_t end) const;
  // The screening rung's error bound [mm], NaN unless ok.
  std::vector<double> ReadErrorBound(std::int64_t candidate, std::int64_t begin, std::int64_t end) const;
  std::vector<std::int32_t> ReadSteps(EvaluationRole role, std::int64_t candidate, std::int64_t begin,
                                      std::int64_t end) const;
  std::vector<double> ReadSolveTime(EvaluationRole role, std::int64_t candidate, std::int64_t begin,
                                    std::int64_t end) const;  // [s]
  // Row-major [end - begin, d].
  std::vector<double> ReadDesignPoints(std::int64_t begin, std::int64_t end) const;

 private:
  struct File;
  std::unique_ptr<File> file_;
};

// Shards as the results file, as a campaign's (jobs/store/campaign_store.h): under mpirun
// every computing rank files its samples in its own shard (AllocationStore::CreateShard,
// at ShardPath), and the results file becomes their index (schema 2, layout "shard index",
// rows_schema 1): schema 1's
// identity, /inputs, /candidates and /outcome, /shards/file [K] (the shards' file names,
// beside the index), and every [C, N] dataset under /samples a virtual dataset showing
// each sample from the shard that holds it (fill elsewhere: pending, NaN, 0). h5py and
// HDF5's tools read it as one file; AllocationReader and CheckAllocationResults open every
// listed shard first and refuse an index whose shard is missing or of another allocation.
struct AllocationShard {
  std::filesystem::path path;  // in the index's folder
  // Per role (screen, confirm): (candidate, its samples the shard shows), candidates
  // ascending, each one's samples ascending and disjoint. No sample in two shards.
  struct Rows {
    std::int64_t candidate = 0;
    std::vector<SampleRange> samples;
  };
  std::array<std::vector<Rows>, 2> rows;
};
// Writes `results` as the index of `shards`, opening none of them, with the design points
// (row-major [N, d]) and `outcome` (as Commit's). Built beside it and renamed over it, so a
// kill leaves the old index or the new one. InputError when `results` is an allocation file
// that keeps samples of its own (they would be lost). Returns the mappings of one dataset.
std::int64_t WriteAllocationIndex(const std::filesystem::path& results, const AllocationIdentity& identity,
                                  const std::vector<double>& design_points, const AllocationOutcome& outcome,
                                  const std::vector<AllocationShard>& shards);
// The shards an allocation file's index lists, each checked to exist and to be a file of
// its allocation (InputError naming the missing or wrong one); empty for a self-contained
// file.
std::vector<std::filesystem::path> IndexedAllocationShards(const std::filesystem::path& results);

// A run of an allocation in shards (PlanShards, jobs/store/shards.h).
ShardPlan PlanAllocationShards(const std::filesystem::path& results, const AllocationIdentity& identity, int ranks,
                               bool resume);
// Rank `rank`'s own shard of `results`: resumed when it exists, else created (CreateShard).
AllocationStore OpenAllocationShard(const std::filesystem::path& results, int rank,
                                    const AllocationIdentity& identity);

// SetAsideUnreadableShards (jobs/store/campaign_store.h) for an allocation's results file:
// before a resume continues it in shards, each shard that cannot be read is renamed aside,
// never deleted, so that its samples are computed again.
std::vector<UnreadableShard> SetAsideUnreadableAllocationShards(const std::filesystem::path& results);

// Writes the samples of an index and its shards into `out`, one self-contained allocation
// file (schema 1) of the same allocation, design points and outcome. `out` may be
// `results` itself: the joined file then replaces the index, and the shards are removed
// once it has; a join killed half-way leaves the index and its shards as they were.
// InputError for a self-contained file (nothing to join), a missing shard, or a damaged
// chunk anywhere (CheckAllocationResults, read first: named with its shard, candidate and
// samples, and the --resume that repairs it; nothing is written or removed). Returns the
// finished samples copied.
std::int64_t JoinAllocationShards(const std::filesystem::path& results, const std::filesystem::path& out);

// Reads every allocated chunk of an allocation file (an index: of every shard it lists,
// and its own /inputs/u and /outcome; its virtual datasets count as checksummed, their
// shards' datasets being checked). InputError when it cannot be opened as one (metadata and
// description damage included).
// The result is a ResultsCheck of an allocation (jobs/store/campaign_store.h says how its
// rows are numbered).
ResultsCheck CheckAllocationResults(const std::filesystem::path& path);

// What a results file holds, from its root `format` attribute: "ringtol campaign" or
// "ringtol allocation". InputError for a file that is not a ringtol results file.
enum class ResultsKind { kCampaign, kAllocation };
ResultsKind ReadResultsKind(const std::filesystem::path& path);

}  // namespace ringtol::jobs
