// What the end of a run under mpirun costs rank 0: writing the index of K shards of a
// 10^7-sample campaign (jobs/store/campaign_store.h, WriteShardIndex), each shard one
// strided run of blocks of 1,024 samples as the block-cyclic pool leaves it, from the
// contents the ranks report (no shard is opened, so none has to exist). The second
// argument gives each shard that many more mappings: its last block cut into pieces of
// unequal length, as the pool's tail sharing leaves a few.
//
//   build/ringtol_shard_index_benchmark --benchmark_filter=WriteShardIndex
#include <benchmark/benchmark.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "jobs/store/campaign_store.h"

namespace ringtol::jobs {
namespace {

constexpr std::int64_t kSamples = 10'000'000;
constexpr std::int64_t kBlock = 1024;
constexpr std::size_t kInputs = 157;  // the default campaign's

CampaignIdentity Identity() {
  CampaignIdentity identity;
  identity.ringtol_version = "benchmark";
  identity.catalogue_version = "benchmark";
  identity.campaign_path = "campaign.toml";
  identity.campaign_file = "seed = 1\n";
  identity.base_scene = "[ring]\n";
  identity.design = "sobol";
  identity.solver = "linear";
  identity.seed = 1;
  identity.rollers = {"spring", "fixed_a", "fixed_b"};
  for (std::size_t i = 0; i < kInputs; ++i) {
    const int order = static_cast<int>(i) + 2;
    identity.inputs.push_back({"ring.order" + std::to_string(order) + ".amplitude_um",
                               sampling::ErrorSource::kRingShape, -1, order, "ring", "ring"});
  }
  return identity;
}

void WriteShardIndexOfShards(benchmark::State& state) {
  const auto shards = static_cast<int>(state.range(0));
  const auto pieces = state.range(1);
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / "ringtol_shard_index_benchmark";
  std::filesystem::create_directories(folder);
  const std::filesystem::path index = folder / "results.h5";
  std::vector<ShardContents> contents;
  for (int r = 0; r < shards; ++r) {
    ShardContents shard{ShardPath(index, r), kSamples, kBlock, kStoredInputSamples, 0, {}};
    for (std::int64_t begin = r * kBlock; begin < kSamples; begin += shards * kBlock) {
      shard.finished.push_back({begin, std::min(kSamples, begin + kBlock)});
    }
    if (pieces > 0) {
      const std::int64_t last = shard.finished.back().begin;
      shard.finished.pop_back();
      for (std::int64_t k = 0; k < pieces; ++k) {
        const std::int64_t begin = last + k * (kBlock / pieces);
        shard.finished.push_back({begin, begin + kBlock / (2 * pieces) + k});
      }
    }
    contents.push_back(std::move(shard));
  }
  const CampaignIdentity identity = Identity();
  for (auto _ : state) {
    state.PauseTiming();
    std::filesystem::remove(index);
    state.ResumeTiming();
    const ShardIndexSummary summary = WriteShardIndex(index, identity, kSamples, contents);
    benchmark::DoNotOptimize(summary);
    state.counters["mappings"] = static_cast<double>(summary.mappings);
  }
  std::filesystem::remove_all(folder);
}
BENCHMARK(WriteShardIndexOfShards)
    ->ArgsProduct({{9, 100, 1000}, {0, 4}})
    ->ArgNames({"shards", "pieces"})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ringtol::jobs

BENCHMARK_MAIN();
