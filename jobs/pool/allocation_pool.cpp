#include "jobs/pool/allocation_pool.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "jobs/inputs/input_error.h"

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

class RoundResults final : public PoolResults {
 public:
  RoundResults(AllocationStore& store, const RoundIndex& index, const AllocationOutcome& outcome)
      : store_(store), index_(index), outcome_(outcome) {}
  std::int64_t items() const override { return index_.size(); }
  std::vector<std::int64_t> Pending(std::int64_t begin, std::int64_t end) const override {
    std::vector<std::int64_t> pending;
    for (std::size_t k = index_.SegmentOf(begin); k < index_.segments().size() && index_.Start(k) < end; ++k) {
      const RoundSegment& s = index_.segments()[k];
      const std::int64_t first = std::max(begin, index_.Start(k));
      const std::int64_t last = std::min(end, index_.Start(k + 1));
      const std::int64_t offset = s.begin - index_.Start(k);
      const std::vector<bool> done = store_.Done(s.role, s.candidate, first + offset, last + offset);
      for (std::int64_t item = first; item < last; ++item)
        if (!done[static_cast<std::size_t>(item - first)]) pending.push_back(item);
    }
    return pending;
  }
  void Add(SampleRecord record) override {
    const std::size_t k = index_.SegmentOf(record.index);
    const RoundSegment& s = index_.segments()[k];
    record.index = s.begin + (record.index - index_.Start(k));
    store_.Add(s.role, s.candidate, record);
  }
  std::size_t buffered() const override { return store_.buffered(); }
  void Commit() override { store_.Commit(outcome_); }

 private:
  AllocationStore& store_;
  const RoundIndex& index_;
  const AllocationOutcome& outcome_;
};

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

void Check(int code, const char* call) {
  if (code != MPI_SUCCESS) throw std::runtime_error(std::string("allocation pool: ") + call + " failed");
}

// Rank 0's segments, known to every rank after the call.
std::vector<RoundSegment> Broadcast(MPI_Comm communicator, std::vector<RoundSegment> segments) {
  std::int64_t count = static_cast<std::int64_t>(segments.size());
  Check(MPI_Bcast(&count, 1, MPI_INT64_T, 0, communicator), "MPI_Bcast");
  std::vector<std::int64_t> flat;
  for (const RoundSegment& s : segments)
    flat.insert(flat.end(), {static_cast<std::int64_t>(s.role), s.candidate, s.begin, s.end});
  flat.resize(static_cast<std::size_t>(4 * count));
  Check(MPI_Bcast(flat.data(), static_cast<int>(flat.size()), MPI_INT64_T, 0, communicator), "MPI_Bcast");
  segments.resize(static_cast<std::size_t>(count));
  for (std::size_t k = 0; k < segments.size(); ++k) {
    segments[k] = {static_cast<EvaluationRole>(flat[4 * k]), flat[4 * k + 1], flat[4 * k + 2], flat[4 * k + 3]};
  }
  return segments;
}

}  // namespace

namespace {

AllocationRunReport Run(MPI_Comm communicator, const Allocation& allocation, AllocationStore* store,
                        const PoolOptions& options, const std::function<void(const AllocationProgress&)>& progress);

}  // namespace

AllocationRunReport RunAllocation(MPI_Comm communicator, const Allocation& allocation, AllocationStore* store,
                                  const PoolOptions& options,
                                  const std::function<void(const AllocationProgress&)>& progress) {
  // Once the ranks work together, any failure is one that must stop them all (the caller
  // aborts on std::runtime_error): an InputError here (a damaged chunk read back, a
  // candidate's sampler refused on one rank) would otherwise end one rank and leave the
  // others waiting for it.
  try {
    return Run(communicator, allocation, store, options, progress);
  } catch (const InputError& e) {
    throw std::runtime_error(e.what());
  }
}

namespace {

AllocationRunReport Run(MPI_Comm communicator, const Allocation& allocation, AllocationStore* store,
                        const PoolOptions& options, const std::function<void(const AllocationProgress&)>& progress) {
  int rank = 0;
  Check(MPI_Comm_rank(communicator, &rank), "MPI_Comm_rank");
  if (rank == 0 && store == nullptr) throw std::logic_error("RunAllocation: rank 0 needs the results file");
  const Clock::time_point start = Clock::now();
  AllocationRunReport report;
  std::optional<AllocationDriver> driver;
  std::optional<StoreSamples> samples;
  if (rank == 0) {
    driver.emplace(allocation);
    samples.emplace(*store);
  }
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
        store->Commit(report.outcome);
        outcome_written = Clock::now();
      }
      first = false;
    }
    const RoundIndex round(Broadcast(communicator, std::move(segments)));
    if (round.segments().empty()) break;

    const RoundWork work(allocation, round);
    std::optional<RoundResults> results;
    if (rank == 0) results.emplace(*store, round, report.outcome);
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
