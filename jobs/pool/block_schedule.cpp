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

BlockSchedule::BlockSchedule(const std::vector<std::int64_t>& pending, int ranks) {
  if (ranks < 1) throw std::invalid_argument("BlockSchedule: ranks = " + std::to_string(ranks) + " must be >= 1");
  queues_.resize(static_cast<std::size_t>(ranks));
  taken_.resize(static_cast<std::size_t>(ranks));
  for (std::size_t i = 0; i < pending.size(); ++i) {
    if (pending[i] < 0 || (i > 0 && pending[i] <= pending[i - 1])) {
      throw std::invalid_argument("BlockSchedule: pending blocks must be ascending, distinct and >= 0");
    }
    queues_[static_cast<std::size_t>(pending[i] % ranks)].blocks.push_back(pending[i]);
  }
  for (Queue& queue : queues_) queue.back = queue.blocks.size();
  untaken_ = static_cast<std::int64_t>(pending.size());
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
  if (own.left() == 0) {
    // Adopts the back half of the longest queue as its own: the rank it belonged to keeps a
    // prefix of its sequence, and the adopted blocks are one run, taken in order.
    const auto victim = std::max_element(queues_.begin(), queues_.end(),
                                         [](const Queue& a, const Queue& b) { return a.left() < b.left(); });
    if (victim->left() == 0) return blocks;
    const std::size_t middle = victim->back - (victim->left() + 1) / 2;
    own.blocks.assign(victim->blocks.begin() + static_cast<std::ptrdiff_t>(middle),
                      victim->blocks.begin() + static_cast<std::ptrdiff_t>(victim->back));
    own.front = 0;
    own.back = own.blocks.size();
    victim->back = middle;
  }
  const std::size_t n = std::min(own.left(), static_cast<std::size_t>(count));
  blocks.assign(own.blocks.begin() + static_cast<std::ptrdiff_t>(own.front),
                own.blocks.begin() + static_cast<std::ptrdiff_t>(own.front + n));
  own.front += n;
  untaken_ -= static_cast<std::int64_t>(blocks.size());
  std::vector<std::int64_t>& taken = taken_[static_cast<std::size_t>(rank)];
  taken.insert(taken.end(), blocks.begin(), blocks.end());
  return blocks;
}

}  // namespace ringtol::jobs
