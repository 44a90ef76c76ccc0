// The default campaign's sample as a campaign computes it (draw, simulate, life, record),
// and a campaign's start-up (reading, calibrating, designing): the costs issue-free
// campaigns pay per sample and per run. Each iteration evaluates a block of consecutive
// samples, so the median is over many draws; the counter `per_sample` is a sample's CPU
// time. Run:
//   build/ringtol_sample_benchmark --benchmark_repetitions=10 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <cstdint>
#include <filesystem>
#include <optional>

#include "jobs/campaign/campaign.h"

namespace {

using namespace ringtol;

const std::filesystem::path kDefault = std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/campaigns/default.toml";
constexpr std::int64_t kBlock = 256;      // samples an iteration
constexpr std::int64_t kSamples = 16384;  // the blocks cycle through the first 16,384 samples

void DefaultSample(benchmark::State& state) {
  const jobs::Campaign campaign(kDefault, kSamples, std::nullopt);
  jobs::SampleEvaluator evaluator(campaign);
  std::int64_t next = 0;
  for (auto _ : state) {
    for (std::int64_t i = 0; i < kBlock; ++i) {
      jobs::SampleRecord record = evaluator.Evaluate(next);
      benchmark::DoNotOptimize(record);
      next = (next + 1) % kSamples;
    }
  }
  state.SetItemsProcessed(state.iterations() * kBlock);
  state.counters["per_sample"] = benchmark::Counter(static_cast<double>(state.iterations() * kBlock),
                                                    benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(DefaultSample)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

void CampaignStartUp(benchmark::State& state) {
  for (auto _ : state) {
    const jobs::Campaign campaign(kDefault, std::nullopt, std::nullopt);
    benchmark::DoNotOptimize(&campaign);
  }
}
BENCHMARK(CampaignStartUp)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
