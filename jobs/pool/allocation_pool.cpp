#include "jobs/pool/allocation_pool.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/check.h"
#include "jobs/inputs/input_error.h"
#include "jobs/store/campaign_store.h"

namespace ringtol::jobs {
namespace {

using Clock = std::chrono::steady_clock;

// A round's samples, numbered in segment order.
class RoundIndex {
 public:
  explicit RoundIndex(std::vector<RoundSegment> segments) : segments_(std::move(segments)) {
    starts_.reserve(segments_.size() + 1);
    starts_.push_back(0);
    for (const RoundSegment& s : segments_) starts_.push_back(starts_.back() + (s.end - s.begin));
  }
  std::int64_t size() const { return starts_.back(); }
  const std::vector<RoundSegment>& segments() const { return segments_; }
  std::size_t SegmentOf(std::int64_t item) const {
    const auto after = std::upper_bound(starts_.begin(), starts_.end(), item);
    return static_cast<std::size_t>(after - starts_.begin() - 1);
  }
  std::int64_t Start(std::size_t segment) const { return starts_[segment]; }

 private:
  std::vector<RoundSegment> segments_;
  std::vector<std::int64_t> starts_;
};

class RoundWork final : public PoolWork {
 public:
  RoundWork(const Allocation& allocation, const RoundIndex& index) : allocation_(allocation), index_(index) {}
  Evaluator MakeEvaluator() const override {
    auto evaluator = std::make_shared<AllocationEvaluator>(allocation_);
    return [evaluator, this](std::int64_t item) {
      const std::size_t k = index_.SegmentOf(item);
      const RoundSegment& s = index_.segments()[k];
      SampleRecord record = evaluator->Evaluate(s.role, s.candidate, s.begin + (item - index_.Start(k)));
      record.index = item;
      return record;
    };
  }
  // The results file keeps one design point per sample for all candidates
  // (AllocationEvaluator drops them from the records).
  std::size_t dimension() const override { return 0; }

 private:
  const Allocation& allocation_;
  const RoundIndex& index_;
};

// Rank 0's copy of what every shard holds, for the search to judge by and the index to
// be written from: per role and simulated candidate, each sample's status, stored outputs,
// error bound and the shard that holds it. The first shard to report a sample keeps it.
class Ledger final : public StoredSamples {
 public:
  Ledger(std::int64_t samples, std::vector<std::string> outputs) : samples_(samples), outputs_(std::move(outputs)) {}

  void Learn(const AllocationSample& sample, int shard) {
    Row& row = Rows(sample.role, sample.candidate);
    const auto i = static_cast<std::size_t>(sample.sample);
    if (row.status[i] != SampleStatus::kPending) return;
    row.status[i] = sample.status;
    for (std::size_t q = 0; q < outputs_.size(); ++q) row.outputs[q][i] = sample.outputs[q];
    row.bound[i] = sample.error_bound;
    row.shard[i] = shard;
  }
  const std::vector<std::string>& outputs() const { return outputs_; }

  bool AllDone(EvaluationRole role, std::int64_t candidate, std::int64_t begin, std::int64_t end) const override {
    const std::vector<SampleStatus> status = Status(role, candidate, begin, end);
    return std::none_of(status.begin(), status.end(), [](SampleStatus s) { return s == SampleStatus::kPending; });
  }
  std::vector<SampleStatus> Status(EvaluationRole role, std::int64_t candidate, std::int64_t begin,
                                   std::int64_t end) const override {
    const Row* row = Find(role, candidate);
    if (row == nullptr) return std::vector<SampleStatus>(static_cast<std::size_t>(end - begin), SampleStatus::kPending);
    return Slice(row->status, begin, end);
  }
  std::vector<double> Output(EvaluationRole role, const std::string& output, std::int64_t candidate,
                             std::int64_t begin, std::int64_t end) const override {
    const auto q = static_cast<std::size_t>(std::find(outputs_.begin(), outputs_.end(), output) - outputs_.begin());
    if (q == outputs_.size()) throw std::invalid_argument("allocation pool: output '" + output + "' is not stored");
    const Row* row = Find(role, candidate);
    if (row == nullptr) return std::vector<double>(static_cast<std::size_t>(end - begin), kNaN);
    return Slice(row->outputs[q], begin, end);
  }
  std::vector<double> ErrorBound(std::int64_t candidate, std::int64_t begin, std::int64_t end) const override {
    const Row* row = Find(EvaluationRole::kScreen, candidate);
    if (row == nullptr) return std::vector<double>(static_cast<std::size_t>(end - begin), kNaN);
    return Slice(row->bound, begin, end);
  }

  // What each of `files` (shard k is files[k]) holds, for its index.
  std::vector<AllocationShard> Shards(const std::vector<std::filesystem::path>& files) const {
    std::vector<AllocationShard> shards(files.size());
    for (std::size_t k = 0; k < files.size(); ++k) shards[k].path = files[k];
    for (std::size_t r = 0; r < rows_.size(); ++r) {
      for (const auto& [candidate, row] : rows_[r]) {
        for (std::int64_t i = 0; i < samples_;) {
          const auto at = static_cast<std::size_t>(i);
          if (row.status[at] == SampleStatus::kPending) {
            ++i;
            continue;
          }
          const int shard = row.shard[at];
          std::int64_t end = i + 1;
          while (end < samples_ && row.status[static_cast<std::size_t>(end)] != SampleStatus::kPending &&
                 row.shard[static_cast<std::size_t>(end)] == shard) {
            ++end;
          }
          std::vector<AllocationShard::Rows>& rows = shards[static_cast<std::size_t>(shard)].rows[r];
          if (rows.empty() || rows.back().candidate != candidate) rows.push_back({candidate, {}});
          rows.back().samples.push_back({i, end});
          i = end;
        }
      }
    }
    return shards;
  }

 private:
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  struct Row {
    std::vector<SampleStatus> status;
    std::vector<std::vector<double>> outputs;  // per stored output
    std::vector<double> bound;
    std::vector<int> shard;
  };
  static std::size_t RoleIndex(EvaluationRole role) { return role == EvaluationRole::kScreen ? 0 : 1; }
  template <typename T>
  static std::vector<T> Slice(const std::vector<T>& values, std::int64_t begin, std::int64_t end) {
    return std::vector<T>(values.begin() + begin, values.begin() + end);
  }
  const Row* Find(EvaluationRole role, std::int64_t candidate) const {
    const auto& rows = rows_[RoleIndex(role)];
    const auto found = rows.find(candidate);
    return found == rows.end() ? nullptr : &found->second;
  }
  Row& Rows(EvaluationRole role, std::int64_t candidate) {
    auto [found, added] = rows_[RoleIndex(role)].try_emplace(candidate);
    if (added) {
      const auto n = static_cast<std::size_t>(samples_);
      found->second.status.assign(n, SampleStatus::kPending);
      found->second.outputs.assign(outputs_.size(), std::vector<double>(n, kNaN));
      found->second.bound.assign(n, kNaN);
      found->second.shard.assign(n, -1);
    }
    return found->second;
  }

  std::int64_t samples_;
  std::vector<std::string> outputs_;
  std::array<std::map<std::int64_t, Row>, 2> rows_;  // per role, by candidate
};

// A round's items in a results file or a shard. `outcome`: committed with the samples
// (rank 0's self-contained file); null: a shard, whose commits write samples only.
// `ledger`: rank 0's knowledge of every shard, told of each sample it files here too.
class RoundResults final : public PoolResults {
 public:
  RoundResults(AllocationStore& store, const RoundIndex& index, const AllocationOutcome* outcome,
               Ledger* ledger = nullptr)
      : store_(store), index_(index), outcome_(outcome), ledger_(ledger) {}
  std::int64_t items() const override { return index_.size(); }
  std::vector<SampleRange> Pending(std::int64_t begin, std::int64_t end) const override;
  void Add(SampleRecord record) override;
  std::size_t buffered() const override { return store_.buffered(); }
  void Commit() override {
    if (outcome_ != nullptr) {
      store_.Commit(*outcome_);
    } else {
      store_.CommitSamples();
    }
  }
  // A worker's shard: the search on rank 0 needs every sample's outputs.
  bool sends_records() const override { return outcome_ == nullptr && ledger_ == nullptr; }
  void Learn(SampleRecord record, int rank) override;

 private:
  // The segment of a round item, and the item as that candidate's sample.
  std::pair<const RoundSegment*, std::int64_t> Locate(std::int64_t item) const {
    const std::size_t k = index_.SegmentOf(item);
    const RoundSegment& s = index_.segments()[k];
    return {&s, s.begin + (item - index_.Start(k))};
  }

  AllocationStore& store_;
  const RoundIndex& index_;
  const AllocationOutcome* outcome_;
  Ledger* ledger_;
};

std::vector<SampleRange> RoundResults::Pending(std::int64_t begin, std::int64_t end) const {
  std::vector<SampleRange> pending;
  for (std::size_t k = index_.SegmentOf(begin); k < index_.segments().size() && index_.Start(k) < end; ++k) {
    const RoundSegment& s = index_.segments()[k];
    const std::int64_t first = std::max(begin, index_.Start(k));
    const std::int64_t last = std::min(end, index_.Start(k + 1));
    const std::int64_t offset = s.begin - index_.Start(k);
    const std::vector<SampleStatus> status =
        ledger_ != nullptr ? ledger_->Status(s.role, s.candidate, first + offset, last + offset)
                           : store_.ReadStatus(s.role, s.candidate, first + offset, last + offset);
    for (std::int64_t item = first; item < last; ++item) {
      if (status[static_cast<std::size_t>(item - first)] != SampleStatus::kPending) continue;
      if (!pending.empty() && pending.back().end == item) {
        ++pending.back().end;
      } else {
        pending.push_back({item, item + 1});
      }
    }
  }
  return pending;
}

void RoundResults::Add(SampleRecord record) {
  const auto [segment, sample] = Locate(record.index);
  record.index = sample;
  if (ledger_ != nullptr) ledger_->Learn(KeptSample(segment->role, segment->candidate, record, ledger_->outputs()), 0);
  store_.Add(segment->role, segment->candidate, record);
}

void RoundResults::Learn(SampleRecord record, int rank) {
  RINGTOL_CHECK(ledger_ != nullptr, rank, record.index);  // only rank 0's results learn records
  const auto [segment, sample] = Locate(record.index);
  record.index = sample;
  ledger_->Learn(KeptSample(segment->role, segment->candidate, record, ledger_->outputs()), rank);
}

class StoreSamples final : public StoredSamples {
 public:
  explicit StoreSamples(const AllocationStore& store) : store_(store) {}
  bool AllDone(EvaluationRole role, std::int64_t candidate, std::int64_t begin, std::int64_t end) const override {
    const std::vector<bool> done = store_.Done(role, candidate, begin, end);
    return std::all_of(done.begin(), done.end(), [](bool d) { return d; });
  }
  std::vector<SampleStatus> Status(EvaluationRole role, std::int64_t candidate, std::int64_t begin,
                                   std::int64_t end) const override {
    return store_.ReadStatus(role, candidate, begin, end);
  }
  std::vector<double> Output(EvaluationRole role, const std::string& output, std::int64_t candidate,
                             std::int64_t begin, std::int64_t end) const override {
    return store_.ReadOutput(role, output, candidate, begin, end);
  }
  std::vector<double> ErrorBound(std::int64_t candidate, std::int64_t begin, std::int64_t end) const override {
    return store_.ReadErrorBound(candidate, begin, end);
  }

 private:
  const AllocationStore& store_;
};

// The allocation's own collectives (rounds, gathers) fail as the allocation pool's.
void CheckAllocationCall(int code, const char* call) {
  if (code != MPI_SUCCESS) throw std::runtime_error(std::string("allocation pool: ") + call + " failed");
}

// Rank 0's segments, known to every rank after the call.
std::vector<RoundSegment> Broadcast(MPI_Comm communicator, std::vector<RoundSegment> segments) {
  std::int64_t count = static_cast<std::int64_t>(segments.size());
  CheckAllocationCall(MPI_Bcast(&count, 1, MPI_INT64_T, 0, communicator), "MPI_Bcast");
  std::vector<std::int64_t> flat;
  for (const RoundSegment& s : segments)
    flat.insert(flat.end(), {static_cast<std::int64_t>(s.role), s.candidate, s.begin, s.end});
  flat.resize(static_cast<std::size_t>(4 * count));
  CheckAllocationCall(MPI_Bcast(flat.data(), static_cast<int>(flat.size()), MPI_INT64_T, 0, communicator), "MPI_Bcast");
  segments.resize(static_cast<std::size_t>(count));
  for (std::size_t k = 0; k < segments.size(); ++k) {
    segments[k] = {static_cast<EvaluationRole>(flat[4 * k]), flat[4 * k + 1], flat[4 * k + 2], flat[4 * k + 3]};
  }
  return segments;
}

// A sample as doubles for MPI: role, candidate, sample, status, error bound, outputs.
void Pack(const AllocationSample& sample, std::vector<double>& out) {
  out.insert(out.end(), {static_cast<double>(sample.role), static_cast<double>(sample.candidate),
                         static_cast<double>(sample.sample), static_cast<double>(sample.status), sample.error_bound});
  out.insert(out.end(), sample.outputs.begin(), sample.outputs.end());
}

AllocationSample Unpack(const double* in, std::size_t outputs) {
  return {static_cast<EvaluationRole>(in[0]), static_cast<std::int64_t>(in[1]), static_cast<std::int64_t>(in[2]),
          static_cast<SampleStatus>(static_cast<std::int8_t>(in[3])), std::vector<double>(in + 5, in + 5 + outputs),
          in[4]};
}

// Every rank's shard's finished samples, learned by rank 0's ledger as held by that rank's
// shard (collective).
void GatherFinished(MPI_Comm communicator, const AllocationStore& shard, Ledger* ledger) {
  int rank = 0;
  int ranks = 1;
  CheckAllocationCall(MPI_Comm_rank(communicator, &rank), "MPI_Comm_rank");
  CheckAllocationCall(MPI_Comm_size(communicator, &ranks), "MPI_Comm_size");
  std::vector<double> mine;
  for (const AllocationSample& sample : shard.Finished()) Pack(sample, mine);
  const int count = static_cast<int>(mine.size());
  std::vector<int> counts(static_cast<std::size_t>(ranks));
  CheckAllocationCall(MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, communicator), "MPI_Gather");
  std::vector<int> offsets(static_cast<std::size_t>(ranks), 0);
  for (std::size_t r = 1; r < offsets.size(); ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
  std::vector<double> all(rank == 0 ? static_cast<std::size_t>(offsets.back() + counts.back()) : 0);
  CheckAllocationCall(MPI_Gatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE, 0,
                    communicator),
        "MPI_Gatherv");
  if (rank != 0) return;
  const std::size_t width = 5 + ledger->outputs().size();
  for (int r = 0; r < ranks; ++r) {
    const auto begin = static_cast<std::size_t>(offsets[static_cast<std::size_t>(r)]);
    const auto end = begin + static_cast<std::size_t>(counts[static_cast<std::size_t>(r)]);
    for (std::size_t at = begin; at + width <= end; at += width) {
      ledger->Learn(Unpack(all.data() + at, ledger->outputs().size()), r);
    }
  }
}

}  // namespace

namespace {

AllocationRunReport Run(MPI_Comm communicator, const Allocation& allocation, AllocationStore* store,
                        const PoolOptions& options, const std::function<void(const AllocationProgress&)>& progress,
                        const AllocationShards* shards);

}  // namespace

AllocationRunReport RunAllocation(MPI_Comm communicator, const Allocation& allocation, AllocationStore* store,
                                  const PoolOptions& options,
                                  const std::function<void(const AllocationProgress&)>& progress,
                                  const AllocationShards* shards) {
  // Once the ranks work together, any failure is one that must stop them all (the caller
  // aborts on std::runtime_error): an InputError here (a damaged chunk read back, a
  // candidate's sampler refused on one rank) would otherwise end one rank and leave the
  // others waiting for it.
  try {
    return Run(communicator, allocation, store, options, progress, shards);
  } catch (const InputError& e) {
    throw std::runtime_error(e.what());
  }
}

namespace {

AllocationRunReport Run(MPI_Comm communicator, const Allocation& allocation, AllocationStore* store,
                        const PoolOptions& options, const std::function<void(const AllocationProgress&)>& progress,
                        const AllocationShards* shards) {
  int rank = 0;
  int ranks = 1;
  CheckAllocationCall(MPI_Comm_rank(communicator, &rank), "MPI_Comm_rank");
  CheckAllocationCall(MPI_Comm_size(communicator, &ranks), "MPI_Comm_size");
  // Rank 0, and with shards every rank, needs its file.
  RINGTOL_CHECK(store != nullptr || (rank != 0 && shards == nullptr), rank, shards != nullptr);
  const Clock::time_point start = Clock::now();
  AllocationRunReport report;
  std::optional<AllocationDriver> driver;
  std::optional<StoreSamples> file_samples;
  std::optional<Ledger> ledger;
  std::vector<std::filesystem::path> shard_files;  // rank 0: shard k of the ledger is shard_files[k]
  std::vector<double> design_points;
  if (rank == 0) driver.emplace(allocation);
  if (shards != nullptr) {
    if (rank == 0) ledger.emplace(allocation.identity().samples, store->outputs());
    GatherFinished(communicator, *store, rank == 0 ? &*ledger : nullptr);
    if (rank == 0) {
      for (int r = 0; r < ranks; ++r) shard_files.push_back(ShardPath(shards->results, r));
      for (const std::filesystem::path& stale : shards->stale) {
        const AllocationStore resumed = AllocationStore::Resume(stale, allocation.identity());
        for (const AllocationSample& sample : resumed.Finished()) {
          ledger->Learn(sample, static_cast<int>(shard_files.size()));
        }
        shard_files.push_back(stale);
      }
      design_points = allocation.DesignPoints();
      report.shards = static_cast<std::int64_t>(shard_files.size());
    }
  } else if (rank == 0) {
    file_samples.emplace(*store);
  }
  const StoredSamples* samples = ledger ? static_cast<const StoredSamples*>(&*ledger)
                                 : file_samples ? static_cast<const StoredSamples*>(&*file_samples)
                                                : nullptr;
  // The outcome, with the samples it was judged from: into the file, or as the index.
  const auto write_outcome = [&] {
    if (!ledger) {
      store->Commit(report.outcome);
      return;
    }
    const Clock::time_point begin = Clock::now();
    store->CommitSamples();
    report.shard_mappings = WriteAllocationIndex(shards->results, allocation.identity(), design_points,
                                                 report.outcome, ledger->Shards(shard_files));
    report.index_time += std::chrono::duration<double>(Clock::now() - begin).count();
  };
  // The outcome is recomputed at most every commit_seconds between rounds (it scans every
  // candidate) and always at the end; the pool's commits within a round write it as last
  // recomputed.
  Clock::time_point outcome_written = start;
  bool first = true;
  for (;;) {
    std::vector<RoundSegment> segments;
    if (rank == 0) {
      // Played forward after a stop too, so the outcome holds every stage on disk.
      segments = driver->Advance(*samples);
      if (report.stopped != 0) segments.clear();
      const bool last = segments.empty();
      if (first || last ||
          std::chrono::duration<double>(Clock::now() - outcome_written).count() >= options.commit_seconds) {
        report.outcome = driver->Outcome(*samples);
        write_outcome();
        outcome_written = Clock::now();
      }
      first = false;
    }
    const RoundIndex round(Broadcast(communicator, std::move(segments)));
    if (round.segments().empty()) break;

    const RoundWork work(allocation, round);
    std::optional<RoundResults> results;
    if (rank == 0) {
      results.emplace(*store, round, ledger ? nullptr : &report.outcome, ledger ? &*ledger : nullptr);
    } else if (shards != nullptr) {
      results.emplace(*store, round, nullptr);
    }
    std::function<void(const PoolProgress&)> round_progress;
    if (rank == 0 && progress) {
      round_progress = [&](const PoolProgress& p) {
        progress({driver->rounds() + 1, driver->simulated(), allocation.space().size(), p,
                  report.computed + p.this_run, std::chrono::duration<double>(Clock::now() - start).count()});
      };
    }
    const PoolReport run = RunPool(communicator, work, results ? &*results : nullptr, options, round_progress);
    if (rank != 0) continue;
    ++report.rounds;
    report.computed += run.computed;
    report.solver_time += run.solver_time;
    report.computing_ranks = run.computing_ranks;
    report.ranks = run.ranks;
    for (const auto& [status, count] : run.status) report.status[status] += count;
    if (run.stopped != 0) report.stopped = run.stopped;
  }
  report.wall_time = std::chrono::duration<double>(Clock::now() - start).count();
  return report;
}

}  // namespace

}  // namespace ringtol::jobs
