#include "jobs/cli/join_command.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <chrono>
#include <filesystem>

#include "jobs/inputs/input_error.h"
#include "jobs/store/allocation_store.h"
#include "jobs/store/campaign_store.h"

namespace ringtol::jobs {

int RunJoin(const JoinCommand& command, std::ostream& out) {
  const std::filesystem::path target = command.out.value_or(command.results);
  if (command.out && std::filesystem::exists(*command.out)) {
    throw InputError(command.out->string() + ": exists; choose another --out, or remove it");
  }
  const bool allocation = ReadResultsKind(command.results) == ResultsKind::kAllocation;
  const std::size_t shards =
      (allocation ? IndexedAllocationShards(command.results) : IndexedShards(command.results)).size();
  if (shards == 0) {
    throw InputError(command.results.string() + ": keeps its samples itself: there are no shards to join");
  }
  const auto start = std::chrono::steady_clock::now();
  const auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  if (allocation) {
    const std::int64_t samples = JoinAllocationShards(command.results, target);
    fmt::print(out, "joined {} shards into {}: {} samples in {:.2f} s\n", shards, target.string(), samples, seconds());
    return 0;
  }
  const CampaignStore::Absorbed joined = JoinShards(command.results, target);
  fmt::print(out, "joined {} shards into {}: {} samples ({} in whole chunks, {:.1f} MB) in {:.2f} s\n", shards,
             target.string(), joined.samples, joined.chunk_samples, static_cast<double>(joined.bytes) / 1e6,
             seconds());
  return 0;
}

}  // namespace ringtol::jobs
