// The results file of a tolerance allocation: one HDF5 file written by the coordinating
// rank, crash-safe and checksummed as the campaign's (jobs/store/campaign_store.h), with
// the same conventions. docs/results.md documents the schema for readers.
//
// Schema version 1 (C = candidates, N = most samples per candidate, d = sampler inputs,
// K = allocated components, O = options of all components, M = constraints, Q = stored outputs):
//   /                          attributes: format = "ringtol allocation", schema_version = 1,
//                              ringtol_version, catalogue_version, allocation_path,
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
//   /candidates/options        int32 [C, K]  option per component (0 = loosest)
//   /candidates/cost, relative_cost  float64 [C]
//   /samples/<role>/status     int8 enum [C, N]   SampleStatusName names, fill "pending";
//                              role: screen, confirm (EvaluationRole)
//   /samples/<role>/<output>   float64 [C, N]  each output a constraint names (Q of them),
//                              NaN unless ok
//   /samples/screen/d_trajectory_error_mm  float64 [C, N]  the screening rung's bound on its
//                              error in D_trajectory (Trajectory::error_estimate)
//   /samples/<role>/steps      int32 [C, N];  /samples/<role>/solve_time_s  float64 [C, N]
//   /outcome/...               the AllocationOutcome as of the last commit (derived from
//                              the samples; rewritten whole at every commit):
//     verdict, settlement, settled_by  int8 enums [C] (settled_by -1: none)
//     samples, implied_by      int64 [C]
//     estimate, lower, upper   float64 [C, M];  constraint_verdict int8 [C, M];
//     samples_to_decide        int64 [C, M]
//     yield, yield_lower, yield_upper  float64 [C];  yield_trials int64 [C]
//     recommendation (int64, -1 for none), complete (int8), simulated, settled_by_screen,
//     samples_screen, samples_confirm, common_random_numbers_gain: attributes of /outcome
//     alternatives, undecided_cheaper, front  int64 [*];  binding int32 [*]
// [C, N] datasets are chunked by candidate rows, so a candidate never simulated takes no
// space on disk.
//
// Crash safety as CampaignStore: statuses are flushed last, so a sample is on disk exactly
// when its status is not pending. Failure: InputError as CampaignStore's, naming the file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "jobs/allocation/allocation_outcome.h"
#include "jobs/campaign/sample_record.h"

namespace ringtol::jobs {

inline constexpr int kAllocationSchemaVersion = 1;

struct AllocationStoreOptions {
  // > 0: samples per chunk along N; 0: first_samples clamped to [64, 1024] and to N. The
  // stages end at multiples of first_samples, so a screened candidate fills its one chunk.
  std::int64_t chunk_samples = 0;
  std::size_t chunk_cache_bytes = 32u << 20;  // per [C, N] dataset: keeps the chunks a commit fills in memory
  bool checksums = true;  // false: no Fletcher-32, for tests and for measuring what it costs
};

class AllocationStore {
 public:
  // A new file, every sample pending, /inputs/u written from `design_points` (row-major
  // [N, d]). Refuses an existing path.
  static AllocationStore Create(const std::filesystem::path& path, const AllocationIdentity& identity,
                                const std::vector<double>& design_points, const AllocationStoreOptions& options = {});
  // An existing file of the same allocation, after a clean or killed run; damaged chunks of
  // [C, N] datasets are reset to pending (as CampaignStore::Resume).
  static AllocationStore Resume(const std::filesystem::path& path, const AllocationIdentity& identity,
                                const AllocationStoreOptions& options = {});
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
  // record.d_trajectory_error.
  void Add(EvaluationRole role, std::int64_t candidate, const SampleRecord& record);
  std::size_t buffered() const;
  // Writes every buffered sample (statuses last) and the outcome, and flushes.
  void Commit(const AllocationOutcome& outcome);

 private:
  struct File;
  explicit AllocationStore(std::unique_ptr<File> file);
  std::unique_ptr<File> file_;
};

class AllocationReader {
 public:
  explicit AllocationReader(const std::filesystem::path& path);
  ~AllocationReader();
  AllocationReader(AllocationReader&&) noexcept;

  const AllocationIdentity& identity() const;
  AllocationOutcome ReadOutcome() const;
  std::vector<SampleStatus> ReadStatus(EvaluationRole role, std::int64_t candidate, std::int64_t begin,
                                       std::int64_t end) const;
  std::vector<double> ReadOutput(EvaluationRole role, std::string_view output, std::int64_t candidate,
                                 std::int64_t begin, std::int64_t end) const;
  // Row-major [end - begin, d].
  std::vector<double> ReadDesignPoints(std::int64_t begin, std::int64_t end) const;

 private:
  struct File;
  std::unique_ptr<File> file_;
};

// What a results file holds, from its root `format` attribute: "ringtol campaign" or
// "ringtol allocation". InputError for a file that is not a ringtol results file.
enum class ResultsKind { kCampaign, kAllocation };
ResultsKind ReadResultsKind(const std::filesystem::path& path);

}  // namespace ringtol::jobs
