// Which computing rank computes which samples, block-cyclically: the samples are cut into
// blocks (a results file's chunk rows, so that each stored chunk is written by one rank),
// block j belongs to rank j mod K, and each rank takes its own blocks in ascending order.
// A rank that has taken all of its own adopts the back half of the untaken blocks of the
// rank with the most left (the tail's balance). What each rank writes is then one strided
// run of blocks, plus one run per adoption: regular selections, so that the results file can map
// every shard with a few hyperslabs (docs/results.md). Finished blocks stay close to a
// prefix of the campaign while every rank works at its own pace, so an interrupted Sobol'
// net is still balanced.
//
// Pure bookkeeping without MPI: the pool (jobs/pool/pool.h) decides how many
// blocks a rank takes at a time. Owners depend on the block's number, not its place among
// the pending ones, so a run resumed with the same number of ranks gives each rank the
// rest of its own sequence: one run again. The pending blocks are given, and kept, as
// runs: its memory grows with the ranges of pending blocks and the ranks, never with the
// blocks (a campaign of 2^40 samples has 2^30 of them).
//
// Failure: std::invalid_argument for ranges that are empty, negative or not ascending and
// disjoint, fewer than one rank, a rank outside [0, ranks) or a count below one.
#pragma once

#include <cstdint>
#include <deque>
#include <vector>

namespace ringtol::jobs {

// Blocks first, first + stride, ..., first + (count - 1) x stride (stride >= 1).
struct BlockRun {
  std::int64_t first = 0;
  std::int64_t stride = 1;
  std::int64_t count = 0;
  friend bool operator==(const BlockRun&, const BlockRun&) = default;
};

// Blocks [begin, end).
struct BlockRange {
  std::int64_t begin = 0;
  std::int64_t end = 0;
  friend bool operator==(const BlockRange&, const BlockRange&) = default;
};

// `blocks` in the order a rank took them, cut where the step between one block and the next
// changes (a run of one block has stride 1); a run taken downwards is given upwards.
std::vector<BlockRun> BlockRuns(const std::vector<std::int64_t>& blocks);

class BlockSchedule {
 public:
  // `pending`: the blocks with samples still to compute, as ascending, disjoint ranges;
  // `ranks` >= 1.
  BlockSchedule(const std::vector<BlockRange>& pending, int ranks);

  // Up to `count` blocks for `rank`, the next of its own. When it has none left, it first
  // adopts the back half (rounded up) of the untaken blocks of the rank with the most left
  // (ties: the lowest rank). Empty when nothing is left.
  std::vector<std::int64_t> Take(int rank, std::int64_t count);

  std::int64_t untaken() const { return untaken_; }
  int ranks() const { return static_cast<int>(queues_.size()); }
  // Every block `rank` has taken, in the order it took them.
  const std::vector<std::int64_t>& taken(int rank) const;

 private:
  struct Queue {
    std::deque<BlockRun> runs;  // untaken, ascending: its own, or those it adopted last
    std::int64_t left = 0;      // blocks in runs
  };
  void CheckRank(int rank) const;

  std::vector<Queue> queues_;
  std::vector<std::vector<std::int64_t>> taken_;
  std::int64_t untaken_ = 0;
};

}  // namespace ringtol::jobs
