#include "jobs/store/shards.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>

#include "jobs/inputs/input_error.h"
#include "jobs/store/hdf5_file.h"

namespace ringtol::jobs {

namespace fs = std::filesystem;
using namespace hdf5;  // NOLINT(google-build-using-namespace): the store's own HDF5 helpers

fs::path ShardPath(const fs::path& results, int rank) {
  fs::path shard = results;
  shard += fmt::format(".shard-{}", rank);
  return shard;
}

std::vector<fs::path> FindShards(const fs::path& results) {
  const fs::path directory = results.has_parent_path() ? results.parent_path() : fs::path(".");
  const std::string prefix = results.filename().string() + ".shard-";
  std::vector<std::pair<int, fs::path>> found;
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(directory, error)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    const std::string rank = name.substr(prefix.size());
    constexpr std::size_t kMaxDigits = 9;  // fits an int
    if (rank.empty() || rank.size() > kMaxDigits || !std::all_of(rank.begin(), rank.end(), [](char c) { return c >= '0' && c <= '9'; })) continue;
    found.emplace_back(std::stoi(rank), ShardPath(results, std::stoi(rank)));  // named as ShardPath names it
  }
  std::sort(found.begin(), found.end());
  std::vector<fs::path> shards;
  for (auto& [rank, path] : found) shards.push_back(std::move(path));
  return shards;
}

ShardPlan PlanShards(const fs::path& results, int ranks, bool resume,
                     const std::function<void(const fs::path&)>& resume_file) {
  std::vector<fs::path> left = FindShards(results);
  if (!resume && !left.empty()) {
    throw InputError(fmt::format("{}: shards of an earlier run of it exist ({}); pass --resume to continue that run, "
                                 "or remove them to start a new one",
                                 results.string(), left.front().string()));
  }
  std::error_code error;
  const bool exists = fs::exists(results, error);
  const bool index = resume && exists && IsShardIndex(results);
  ShardPlan plan;
  plan.sharded = ranks > 1 || !left.empty() || index;
  if (!plan.sharded) return plan;
  if (resume && exists && !index) {
    const fs::path own = ShardPath(results, 0);
    if (fs::exists(own, error)) {
      throw InputError(fmt::format("{}: keeps samples itself and {} exists beside it: move one of them away",
                                   results.string(), own.string()));
    }
    resume_file(results);
    fs::rename(results, own);
    left = FindShards(results);
  }
  for (fs::path& shard : left) {
    bool has_rank = false;
    for (int r = 0; r < ranks && !has_rank; ++r) has_rank = shard == ShardPath(results, r);
    if (!has_rank) plan.stale.push_back(std::move(shard));
  }
  return plan;
}

fs::path SetAsidePath(const fs::path& shard) {
  fs::path aside = shard;
  aside += ".unreadable";
  std::error_code error;
  for (int k = 2; fs::exists(aside, error); ++k) {
    aside = shard;
    aside += fmt::format(".unreadable-{}", k);
  }
  return aside;
}

std::string UnreadableShardMessage(const std::string& index, const fs::path& shard, const std::string& why,
                                   std::string_view command, const std::string& input) {
  return fmt::format(
      "{}: its shard {} cannot be read ({}); `ringtol {} {} --out {} --resume` sets it aside (renamed {}, never "
      "deleted) and computes its samples again",
      index, shard.string(), why, command, input, index, SetAsidePath(shard).string());
}

std::vector<UnreadableShard> SetAsideUnreadableShards(const fs::path& results,
                                                      const std::function<void(const fs::path&)>& read_shard) {
  const QuietErrors quiet;
  std::vector<UnreadableShard> aside;
  for (const fs::path& shard : FindShards(results)) {
    std::string why;
    try {
      read_shard(shard);
      continue;
    } catch (const InputError& error) {
      why = error.what();
    }
    const fs::path to = SetAsidePath(shard);
    std::error_code error;
    fs::rename(shard, to, error);
    if (error) throw InputError(fmt::format("{}: cannot be read ({}) nor set aside: {}", shard.string(), why, error.message()));
    aside.push_back({shard, to, why});
  }
  // A shard the index lists that is missing, and was never set aside, is refused as
  // readers refuse it.
  std::error_code error;
  if (fs::exists(results, error)) {
    const FileId file = OpenForReading(results);
    if (ListsShards(file.get())) {
      ListedShardFiles(Where{results.string(), true}, file.get(), results, [](const fs::path& shard) {
        fs::path first_aside = shard;
        first_aside += ".unreadable";
        std::error_code missing;
        return fs::exists(first_aside, missing);
      });
    }
  }
  return aside;
}

void CheckIndexTarget(const fs::path& results, const std::vector<fs::path>& shards, std::string_view writer) {
  std::error_code error;
  if (fs::exists(results, error) && !IsShardIndex(results)) {
    throw InputError(results.string() + ": keeps samples of its own; an index of shards cannot replace it");
  }
  const auto folder = [](const fs::path& path) {
    return path.has_parent_path() ? path.parent_path().lexically_normal() : fs::path(".");
  };
  for (const fs::path& shard : shards) {
    if (folder(shard) != folder(results)) {
      throw std::invalid_argument(
          fmt::format("{}: shard {} is not beside {}", writer, shard.string(), results.string()));
    }
  }
}

bool IsShardIndex(const fs::path& results) {
  const QuietErrors quiet;
  return ListsShards(OpenForReading(results).get());
}

std::optional<fs::path> BeingWritten(const fs::path& results) {
  if (FileLock::Held(results)) return results;
  for (const fs::path& shard : FindShards(results)) {
    if (FileLock::Held(shard)) return shard;
  }
  return std::nullopt;
}

}  // namespace ringtol::jobs
