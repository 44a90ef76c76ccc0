#include "jobs/pool/campaign_pool.h"

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <utility>

namespace ringtol::jobs {
namespace {

class CampaignWork final : public PoolWork {
 public:
  CampaignWork(const Campaign& campaign, double sample_seconds)
      : campaign_(campaign), sample_seconds_(sample_seconds) {}
  Evaluator MakeEvaluator() const override {
    if (sample_seconds_ > 0.0) {
      auto drawer = std::make_shared<SampleDrawer>(campaign_);
      return [drawer, seconds = sample_seconds_](std::int64_t index) { return Spin(*drawer, index, seconds); };
    }
    auto evaluator = std::make_shared<SampleEvaluator>(campaign_);
    return [evaluator](std::int64_t index) { return evaluator->Evaluate(index); };
  }
  std::size_t dimension() const override { return campaign_.identity().inputs.size(); }

 private:
  // PoolOptions::Testing::sample_seconds: the sample's real draw, then CPU spent to the
  // given total, and outputs that are a function of the index alone.
  static SampleRecord Spin(SampleDrawer& drawer, std::int64_t index, double seconds) {
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = ThreadCpuSeconds();
    SampleRecord record = drawer.Draw(index);
    while (ThreadCpuSeconds() - cpu_start < seconds) {
    }
    if (record.status == SampleStatus::kPending) record.status = SampleStatus::kOk;
    for (std::size_t k = 0; k < record.outputs.size(); ++k) {
      record.outputs[k] = 1e-6 * static_cast<double>(index % 1000) + 1e-3 * static_cast<double>(k);
    }
    record.rung = 0;
    record.d_trajectory_error = 0.0;
    record.solve_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return record;
  }

  const Campaign& campaign_;
  double sample_seconds_;
};

// A campaign's results file, or rank 0's shard with what every shard held at the start.
class CampaignResults final : public PoolResults {
 public:
  CampaignResults(CampaignStore& store, const std::vector<SampleRange>* finished)
      : store_(store), finished_(finished) {}
  std::int64_t items() const override { return store_.samples(); }
  std::vector<SampleRange> Pending(std::int64_t begin, std::int64_t end) const override {
    if (finished_ == nullptr) return store_.Pending(begin, end);
    // [begin, end) less the finished runs that meet it.
    std::vector<SampleRange> pending;
    auto run = std::upper_bound(finished_->begin(), finished_->end(), begin,
                                [](std::int64_t sample, const SampleRange& r) { return sample < r.end; });
    for (std::int64_t at = begin; at < end; ++run) {
      const std::int64_t stop = run == finished_->end() ? end : std::min(end, run->begin);
      if (at < stop) pending.push_back({at, stop});
      if (run == finished_->end()) break;
      at = std::max(at, run->end);
    }
    return pending;
  }
  void Add(SampleRecord record) override { store_.Add(std::move(record)); }
  std::size_t buffered() const override { return store_.buffered(); }
  void Commit() override { store_.Commit(); }

 private:
  CampaignStore& store_;
  const std::vector<SampleRange>* finished_;  // ascending, disjoint
};

}  // namespace

PoolReport RunPool(MPI_Comm communicator, const Campaign& campaign, CampaignStore* store, const PoolOptions& options,
                   const std::function<void(const PoolProgress&)>& progress,
                   const std::vector<SampleRange>* finished) {
  const CampaignWork work(campaign, options.testing.sample_seconds);
  std::optional<CampaignResults> results;
  if (store != nullptr) results.emplace(*store, finished);
  return RunPool(communicator, work, results ? &*results : nullptr, options, progress);
}

}  // namespace ringtol::jobs
