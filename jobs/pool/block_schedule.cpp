#include "jobs/pool/block_schedule.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace ringtol::jobs {

std::vector<BlockRun> BlockRuns(const std::vector<std::int64_t>& blocks) {
  std::vector<BlockRun> runs;
  for (const std::int64_t block : blocks) {
    if (!runs.empty()) {
      BlockRun& run = runs.back();
      if (run.count == 1 && block != run.first) {
        run.stride = block - run.first;
        run.count = 2;
        continue;
      }
      if (run.count > 1 && block == run.first + run.count * run.stride) {
        ++run.count;
        continue;
      }
    }
    runs.push_back({block, 1, 1});
  }
  // Blocks taken from another rank's back come in descending order: the same run, read upwards.
  for (BlockRun& run : runs) {
    if (run.stride < 0) {
      run.first += (run.count - 1) * run.stride;
      run.stride = -run.stride;
    }
  }
  return runs;
}

BlockSchedule::BlockSchedule(const std::vector<BlockRange>& pending, int ranks) {
  if (ranks < 1) throw std::invalid_argument("BlockSchedule: ranks = " + std::to_string(ranks) + " must be >= 1");
  queues_.resize(static_cast<std::size_t>(ranks));
  taken_.resize(static_cast<std::size_t>(ranks));
  for (std::size_t i = 0; i < pending.size(); ++i) {
    const BlockRange& range = pending[i];
    if (range.begin < 0 || range.end <= range.begin || (i > 0 && range.begin < pending[i - 1].end)) {
      throw std::invalid_argument("BlockSchedule: pending blocks must be non-empty ranges >= 0, ascending and disjoint");
    }
    // Rank r's blocks in the range: the first one of its residue, then every ranks-th.
    for (int rank = 0; rank < ranks; ++rank) {
      const std::int64_t first = range.begin + ((rank - range.begin) % ranks + ranks) % ranks;
      if (first >= range.end) continue;
      const std::int64_t count = (range.end - 1 - first) / ranks + 1;
      Queue& queue = queues_[static_cast<std::size_t>(rank)];
      queue.runs.push_back({first, ranks, count});
      queue.left += count;
    }
    untaken_ += range.end - range.begin;
  }
}

void BlockSchedule::CheckRank(int rank) const {
  if (rank < 0 || rank >= ranks()) {
    throw std::invalid_argument("BlockSchedule: rank " + std::to_string(rank) + " is outside [0, " +
                                std::to_string(ranks()) + ")");
  }
}

const std::vector<std::int64_t>& BlockSchedule::taken(int rank) const {
  CheckRank(rank);
  return taken_[static_cast<std::size_t>(rank)];
}

std::vector<std::int64_t> BlockSchedule::Take(int rank, std::int64_t count) {
  CheckRank(rank);
  if (count < 1) throw std::invalid_argument("BlockSchedule::Take: count = " + std::to_string(count) + " must be >= 1");
  std::vector<std::int64_t> blocks;
  Queue& own = queues_[static_cast<std::size_t>(rank)];
  if (own.left == 0) {
    // Adopts the back half of the longest queue as its own: the rank it belonged to keeps a
    // prefix of its sequence, and the adopted blocks are one run, taken in order.
    const auto victim = std::max_element(queues_.begin(), queues_.end(),
                                         [](const Queue& a, const Queue& b) { return a.left < b.left; });
    if (victim->left == 0) return blocks;
    std::int64_t adopt = (victim->left + 1) / 2;
    own.runs.clear();
    own.left = adopt;
    victim->left -= adopt;
    while (adopt > 0) {
      BlockRun& back = victim->runs.back();
      const std::int64_t n = std::min(adopt, back.count);
      own.runs.push_front({back.first + (back.count - n) * back.stride, back.stride, n});
      back.count -= n;
      adopt -= n;
      if (back.count == 0) victim->runs.pop_back();
    }
  }
  const std::int64_t n = std::min(own.left, count);
  blocks.reserve(static_cast<std::size_t>(n));
  while (static_cast<std::int64_t>(blocks.size()) < n) {
    BlockRun& front = own.runs.front();
    blocks.push_back(front.first);
    front.first += front.stride;
    if (--front.count == 0) own.runs.pop_front();
  }
  own.left -= n;
  untaken_ -= n;
  std::vector<std::int64_t>& taken = taken_[static_cast<std::size_t>(rank)];
  taken.insert(taken.end(), blocks.begin(), blocks.end());
  return blocks;
}

}  // namespace ringtol::jobs
