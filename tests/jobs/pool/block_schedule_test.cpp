// Block-cyclic assignment (jobs/pool/block_schedule.h), on simulated runs: ranks of given
// speeds take a few blocks at a time, as the pool's workers do, in the order a clock says.
#include "jobs/pool/block_schedule.h"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace ringtol::jobs {
namespace {

std::vector<std::int64_t> Range(std::int64_t begin, std::int64_t end) {
  std::vector<std::int64_t> blocks(static_cast<std::size_t>(end - begin));
  std::iota(blocks.begin(), blocks.end(), begin);
  return blocks;
}

// Ascending, distinct blocks as the ranges BlockSchedule takes.
std::vector<BlockRange> Ranges(const std::vector<std::int64_t>& blocks) {
  std::vector<BlockRange> ranges;
  for (const std::int64_t block : blocks) {
    if (!ranges.empty() && ranges.back().end == block) {
      ++ranges.back().end;
    } else {
      ranges.push_back({block, block + 1});
    }
  }
  return ranges;
}

struct Simulated {
  BlockSchedule schedule;
  double makespan = 0.0;      // [s] when the last rank finished
  double ideal = 0.0;         // [s] the blocks' work spread over every rank's speed
  std::vector<std::int64_t> finished;  // blocks, in the order they finished
};

// Ranks of `seconds_per_block` take `lease` blocks whenever they are idle (the earliest
// idle first, ties by rank) until nothing is left.
Simulated Simulate(const std::vector<std::int64_t>& pending, const std::vector<double>& seconds_per_block,
                   std::int64_t lease) {
  const int ranks = static_cast<int>(seconds_per_block.size());
  Simulated run{BlockSchedule(Ranges(pending), ranks), 0.0, 0.0, {}};
  std::vector<double> idle_at(seconds_per_block.size(), 0.0);
  std::vector<std::pair<double, std::int64_t>> ends;  // (finish time, block)
  while (true) {
    const auto next = std::min_element(idle_at.begin(), idle_at.end());
    const int rank = static_cast<int>(next - idle_at.begin());
    const std::vector<std::int64_t> blocks = run.schedule.Take(rank, lease);
    if (blocks.empty()) break;
    for (const std::int64_t block : blocks) {
      *next += seconds_per_block[static_cast<std::size_t>(rank)];
      ends.emplace_back(*next, block);
    }
  }
  std::sort(ends.begin(), ends.end());
  for (const auto& [time, block] : ends) run.finished.push_back(block);
  run.makespan = ends.empty() ? 0.0 : ends.back().first;
  double rate = 0.0;
  for (const double seconds : seconds_per_block) rate += 1.0 / seconds;
  run.ideal = static_cast<double>(pending.size()) / rate;
  return run;
}

// Every pending block is taken exactly once, by someone.
void ExpectEachBlockOnce(const BlockSchedule& schedule, const std::vector<std::int64_t>& pending) {
  std::vector<std::int64_t> all;
  for (int rank = 0; rank < schedule.ranks(); ++rank) {
    all.insert(all.end(), schedule.taken(rank).begin(), schedule.taken(rank).end());
  }
  std::sort(all.begin(), all.end());
  EXPECT_EQ(all, pending);
  EXPECT_EQ(schedule.untaken(), 0);
}

TEST(BlockRuns, CutsWhereTheStepChangesAndReadsDownwardRunsUpwards) {
  EXPECT_EQ(BlockRuns({}), std::vector<BlockRun>{});
  EXPECT_EQ(BlockRuns({5}), (std::vector<BlockRun>{{5, 1, 1}}));
  EXPECT_EQ(BlockRuns({1, 9, 17, 25, 30, 22, 14}), (std::vector<BlockRun>{{1, 8, 4}, {14, 8, 3}}));
}

TEST(BlockSchedule, RanksOfOneSpeedEachTakeExactlyTheirOwnBlocksAsOneRun) {
  constexpr int kRanks = 8;
  const std::vector<std::int64_t> pending = Range(0, 800);
  const Simulated run = Simulate(pending, std::vector<double>(kRanks, 1.0), 3);
  ExpectEachBlockOnce(run.schedule, pending);
  for (int rank = 0; rank < kRanks; ++rank) {
    EXPECT_EQ(BlockRuns(run.schedule.taken(rank)), (std::vector<BlockRun>{{rank, kRanks, 100}})) << "rank " << rank;
  }
  // Finished blocks stay near a prefix: when any number of blocks is done, at most a lease
  // per rank lies beyond them.
  std::set<std::int64_t> done;
  for (std::size_t i = 0; i < run.finished.size(); ++i) {
    done.insert(run.finished[i]);
    EXPECT_LT(*done.rbegin(), static_cast<std::int64_t>(done.size()) + kRanks * 3);
  }
}

TEST(BlockSchedule, ASlowRankKeepsAPrefixOfItsOwnAndThievesAddAtMostTwoRunsEach) {
  constexpr int kRanks = 8;
  constexpr std::int64_t kLease = 2;
  const std::vector<std::int64_t> pending = Range(0, 1000);
  std::vector<double> seconds(kRanks, 1.0);
  seconds[3] = 3.0;  // one rank three times slower
  const Simulated run = Simulate(pending, seconds, kLease);
  ExpectEachBlockOnce(run.schedule, pending);
  const std::vector<BlockRun> slow = BlockRuns(run.schedule.taken(3));
  ASSERT_EQ(slow.size(), 1u);
  EXPECT_EQ(slow[0].first, 3);
  EXPECT_EQ(slow[0].stride, kRanks);
  for (int rank = 0; rank < kRanks; ++rank) {
    EXPECT_LE(BlockRuns(run.schedule.taken(rank)).size(), 3u) << "rank " << rank;
  }
  // Balanced: the run ends within a few blocks' time of the work spread over every rank.
  EXPECT_LT(run.makespan, run.ideal + 2 * kLease * seconds[3]);
}

TEST(BlockSchedule, EveryBlockIsTakenOnceWhateverTheSpeedsAndTheLease) {
  std::mt19937_64 random(20261126);
  std::uniform_real_distribution<double> speed(0.2, 5.0);
  for (int trial = 0; trial < 50; ++trial) {
    const int ranks = 1 + static_cast<int>(random() % 12);
    std::vector<std::int64_t> pending;
    for (std::int64_t block = 0; block < 300; ++block) {
      if (random() % 3 != 0) pending.push_back(block);  // as a resume finds them
    }
    std::vector<double> seconds(static_cast<std::size_t>(ranks));
    for (double& s : seconds) s = speed(random);
    const Simulated run = Simulate(pending, seconds, 1 + static_cast<std::int64_t>(random() % 5));
    ExpectEachBlockOnce(run.schedule, pending);
  }
}

TEST(BlockSchedule, AResumeWithTheSameRanksGivesEachTheRestOfItsOwnSequence) {
  constexpr int kRanks = 4;
  // A killed run left each rank's sequence done up to a different block.
  std::vector<std::int64_t> pending;
  const std::int64_t done_up_to[kRanks] = {40, 13, 70, 22};
  for (std::int64_t block = 0; block < 100; ++block) {
    if (block >= done_up_to[block % kRanks]) pending.push_back(block);
  }
  BlockSchedule schedule(Ranges(pending), kRanks);
  for (int rank = 0; rank < kRanks; ++rank) {
    const std::vector<std::int64_t> first = schedule.Take(rank, 2);
    ASSERT_FALSE(first.empty());
    EXPECT_EQ(first.front() % kRanks, rank);
    EXPECT_GE(first.front(), done_up_to[rank]);
  }
}

TEST(BlockSchedule, RefusesUnorderedBlocksAndRanksOutsideTheSchedule) {
  EXPECT_THROW(BlockSchedule({{3, 4}, {2, 3}}, 2), std::invalid_argument);
  EXPECT_THROW(BlockSchedule({{1, 3}, {2, 4}}, 2), std::invalid_argument);
  EXPECT_THROW(BlockSchedule({{2, 2}}, 2), std::invalid_argument);
  EXPECT_THROW(BlockSchedule({{-1, 2}}, 2), std::invalid_argument);
  EXPECT_THROW(BlockSchedule({{0, 1}}, 0), std::invalid_argument);
  BlockSchedule schedule({{0, 4}}, 2);
  EXPECT_THROW(schedule.Take(2, 1), std::invalid_argument);
  EXPECT_THROW(schedule.Take(0, 0), std::invalid_argument);
  EXPECT_EQ(schedule.Take(0, 5), (std::vector<std::int64_t>{0, 2}));
  EXPECT_EQ(schedule.Take(0, 5), (std::vector<std::int64_t>{3}));  // the back half of rank 1's two
  EXPECT_EQ(schedule.Take(1, 5), (std::vector<std::int64_t>{1}));
  EXPECT_TRUE(schedule.Take(1, 5).empty());
}

// A campaign of 2^40 samples has 2^30 blocks: the schedule holds runs of them, so that it
// is made and taken from at once, and its ranks adopt from each other as they would with
// few blocks.
TEST(BlockSchedule, HoldsTwoToTheThirtyBlocksAsRunsAndHandsThemOutInTurn) {
  constexpr std::int64_t kBlocks = std::int64_t{1} << 30;
  constexpr int kRanks = 3;
  BlockSchedule schedule({{0, 7}, {9, kBlocks}}, kRanks);
  EXPECT_EQ(schedule.untaken(), kBlocks - 2);
  EXPECT_EQ(schedule.Take(0, 4), (std::vector<std::int64_t>{0, 3, 6, 9}));
  EXPECT_EQ(schedule.Take(1, 3), (std::vector<std::int64_t>{1, 4, 10}));
  EXPECT_EQ(schedule.Take(2, 2), (std::vector<std::int64_t>{2, 5}));
  EXPECT_EQ(schedule.Take(2, 2), (std::vector<std::int64_t>{11, 14}));
  EXPECT_EQ(schedule.untaken(), kBlocks - 2 - 11);
}

TEST(BlockSchedule, AdoptsTheBackHalfOfTheLongestQueueAcrossItsRanges) {
  // Rank 0 has blocks 0 and 2; rank 1 has 1, 3, 5, 7 and 9, in two ranges.
  BlockSchedule schedule({{0, 4}, {5, 6}, {7, 8}, {9, 10}}, 2);
  EXPECT_EQ(schedule.Take(0, 5), (std::vector<std::int64_t>{0, 2}));
  EXPECT_EQ(schedule.Take(0, 5), (std::vector<std::int64_t>{5, 7, 9}));  // the back 3 of rank 1's 5
  EXPECT_EQ(schedule.Take(1, 5), (std::vector<std::int64_t>{1, 3}));
  EXPECT_TRUE(schedule.Take(1, 5).empty());
  EXPECT_EQ(schedule.untaken(), 0);
}

}  // namespace
}  // namespace ringtol::jobs
