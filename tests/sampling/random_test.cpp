// The contract of sampling/random.h, which every design and every redraw relies on: a
// draw is a pure function of its arguments, distinct arguments give distinct draws, unit
// draws lie inside (0, 1), and draws are uniform and independent whichever argument
// varies. The statistical checks use fixed seeds, so they pass or fail the same way on
// every run; each states its significance level.
#include "sampling/random.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "tests/support/statistics.h"

namespace ringtol::sampling {
namespace {

constexpr std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max();

constexpr std::array<RandomStream, 6> kStreams = {RandomStream::kMonteCarlo,       RandomStream::kLatinJitter,
                                                  RandomStream::kLatinPermutation, RandomStream::kSobolShift,
                                                  RandomStream::kRedraw,           RandomStream::kCalibration};

// Small values (so that swapping two arguments, or a seed for a stream number, gives
// an argument list that is also in the grid), and the bits at the ends of a word.
constexpr std::array<std::uint64_t, 7> kSeeds = {0, 1, 2, 3, 6, std::uint64_t{1} << 63, kMax};
constexpr std::array<std::uint64_t, 7> kCounters = {0, 1, 2, 3, std::uint64_t{1} << 32, std::uint64_t{1} << 63, kMax};

struct Arguments {
  std::uint64_t seed;
  RandomStream stream;
  std::uint64_t a, b, c;
};

std::vector<Arguments> ArgumentGrid() {
  std::vector<Arguments> grid;
  for (const std::uint64_t seed : kSeeds)
    for (const RandomStream stream : kStreams)
      for (const std::uint64_t a : kCounters)
        for (const std::uint64_t b : kCounters)
          for (const std::uint64_t c : kCounters) grid.push_back({seed, stream, a, b, c});
  return grid;
}

std::uint64_t BitsFor(const Arguments& x) { return RandomBits(x.seed, x.stream, x.a, x.b, x.c); }

double UniformCdf(double x) { return x; }

// The law of u - v for independent u, v ~ U(0, 1): triangular on (-1, 1).
double DifferenceCdf(double x) { return x < 0 ? 0.5 * (1 + x) * (1 + x) : 1 - 0.5 * (1 - x) * (1 - x); }

// The i-th value of a sequence of draws, and what the sequence is, for messages.
struct DrawSequence {
  const char* name;
  double (*draw)(std::uint64_t i);
};

constexpr std::uint64_t kSequenceLength = 20000;

// Kolmogorov-Smirnov of the first kSequenceLength values of each sequence against `cdf`:
// the p-value must exceed `alpha`.
void ExpectEachSequenceFollows(double (*cdf)(double), double alpha, const std::vector<DrawSequence>& sequences) {
  for (const DrawSequence& sequence : sequences) {
    std::vector<double> values;
    for (std::uint64_t i = 0; i < kSequenceLength; ++i) values.push_back(sequence.draw(i));
    const double d = testing::KolmogorovSmirnovStatistic(values, cdf);
    EXPECT_GT(testing::KolmogorovSmirnovPValue(d, values.size()), alpha) << sequence.name;
  }
}

TEST(RandomBits, IsAPureFunctionOfItsArgumentsWhateverTheOrderOfTheDraws) {
  const std::vector<Arguments> grid = ArgumentGrid();
  std::vector<std::uint64_t> forward;
  for (const Arguments& x : grid) forward.push_back(BitsFor(x));

  std::vector<std::size_t> order(grid.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::reverse(order.begin(), order.end());
  for (const std::size_t i : order) ASSERT_EQ(BitsFor(grid[i]), forward[i]) << "drawn in reverse, entry " << i;
  std::shuffle(order.begin(), order.end(), std::mt19937_64(20240611));
  for (const std::size_t i : order) ASSERT_EQ(BitsFor(grid[i]), forward[i]) << "drawn shuffled, entry " << i;
}

TEST(RandomBits, DiffersForEveryDistinctSeedStreamAndCounters) {
  // 7 x 6 x 7^3 = 14406 argument lists. Even truly random 64-bit words would collide
  // with probability n^2 / 2^65 < 1e-11, so any repeat is a generator that ignores, or
  // confuses, an argument.
  std::vector<std::uint64_t> bits;
  for (const Arguments& x : ArgumentGrid()) bits.push_back(BitsFor(x));
  std::sort(bits.begin(), bits.end());
  EXPECT_EQ(std::adjacent_find(bits.begin(), bits.end()), bits.end()) << "two argument lists gave the same bits";
}

TEST(RandomBits, SetsEachOfItsSixtyFourBitsHalfTheTime) {
  // Designs use the low bits too (permutation keys, digital shifts), not only the 53 high
  // bits that RandomUnit keeps. Each bit's count of ones in n draws is Binomial(n, 1/2);
  // with n = 2^16 its normal approximation is good far into the tail. Overall significance
  // 1e-3, split over the 64 bits.
  constexpr std::uint64_t kDraws = 1 << 16;
  constexpr std::uint64_t kSeed = 8128;
  constexpr double kAlpha = 1e-3 / 64.0;
  // ones - n/2 has standard deviation sqrt(n / 4).
  const double limit = testing::TwoSidedNormalQuantile(kAlpha) * std::sqrt(static_cast<double>(kDraws) / 4.0);
  std::array<int, 64> ones{};
  for (std::uint64_t i = 0; i < kDraws; ++i) {
    const std::uint64_t x = RandomBits(kSeed, RandomStream::kLatinPermutation, i, 0, 0);
    for (std::size_t bit = 0; bit < 64; ++bit) ones[bit] += static_cast<int>((x >> bit) & 1u);
  }
  for (std::size_t bit = 0; bit < 64; ++bit) {
    EXPECT_LT(std::abs(ones[bit] - static_cast<double>(kDraws) / 2.0), limit) << "bit " << bit;
  }
}

TEST(UnitFromBits, IsTheCentreOfTheCellOfTheHigh53Bits) {
  // (floor(x / 2^11) + 0.5) / 2^53, written out for cells whose centre is exact in a double.
  EXPECT_EQ(UnitFromBits(0), 0x1p-54);
  EXPECT_EQ(UnitFromBits(0x7ff), 0x1p-54);  // the 11 low bits are dropped
  EXPECT_EQ(UnitFromBits(0x800), 0x3p-54);
  EXPECT_EQ(UnitFromBits(std::uint64_t{1} << 62), 0.25 + 0x1p-54);
  EXPECT_EQ(UnitFromBits((std::uint64_t{1} << 63) - 1), 0.5 - 0x1p-54);
}

TEST(UnitFromBits, NeverReturnsZeroSoMinusLogIsFinite) {
  EXPECT_GT(UnitFromBits(0), 0.0);
  EXPECT_TRUE(std::isfinite(-std::log(UnitFromBits(0))));
}

TEST(UnitFromBits, NeverReturnsOneSoTheNormalQuantileIsFinite) {
  // The top cell's centre, 1 - 2^-54, rounds to 1 in a double; it is held just below.
  constexpr std::uint64_t kTopCell = std::numeric_limits<std::uint64_t>::max();
  EXPECT_LT(UnitFromBits(kTopCell), 1.0);
  EXPECT_EQ(UnitFromBits(kTopCell), std::nextafter(1.0, 0.0));
  EXPECT_TRUE(std::isfinite(-std::log1p(-UnitFromBits(kTopCell))));
}

TEST(RandomUnit, IsUnitFromBitsOfRandomBitsStrictlyInsideTheUnitInterval) {
  for (const Arguments& x : ArgumentGrid()) {
    const double u = RandomUnit(x.seed, x.stream, x.a, x.b, x.c);
    ASSERT_EQ(u, UnitFromBits(BitsFor(x)));
    ASSERT_GT(u, 0.0);
    ASSERT_LT(u, 1.0);
  }
}

constexpr std::uint64_t kStatisticsSeed = 271828;
constexpr RandomStream kStatisticsStream = RandomStream::kMonteCarlo;

TEST(RandomUnit, IsUniformAlongEachOfItsArguments) {
  // Counting up one argument with the others fixed, as designs count samples and
  // dimensions. Overall significance 1e-3, split over the 4 arguments that take any value.
  constexpr double kAlpha = 1e-3 / 4.0;
  ExpectEachSequenceFollows(
      UniformCdf, kAlpha,
      {{"counting up the seed", [](std::uint64_t i) { return RandomUnit(i, kStatisticsStream, 0, 0, 0); }},
       {"counting up a", [](std::uint64_t i) { return RandomUnit(kStatisticsSeed, kStatisticsStream, i, 0, 0); }},
       {"counting up b", [](std::uint64_t i) { return RandomUnit(kStatisticsSeed, kStatisticsStream, 0, i, 0); }},
       {"counting up c", [](std::uint64_t i) { return RandomUnit(kStatisticsSeed, kStatisticsStream, 0, 0, i); }}});
}

// The draw at counters (2i, 0, 0): pairing it with the draw at (2i + 1, 0, 0) keeps the
// pairs disjoint, so the differences below are independent of each other.
double Reference(std::uint64_t i) { return RandomUnit(kStatisticsSeed, kStatisticsStream, 2 * i, 0, 0); }

TEST(RandomUnit, DrawsOfOtherStreamsSeedsAndCountersAreIndependent) {
  // Independent purposes must not share draws: u - v, for u the reference draw and v the
  // same counters in another stream, with the next seed, or the next value of one counter,
  // has the triangular law only if u and v are independent. Overall significance 1e-3,
  // split over the 5 neighbours.
  constexpr double kAlpha = 1e-3 / 5.0;
  ExpectEachSequenceFollows(
      DifferenceCdf, kAlpha,
      {{"the Latin jitter stream",
        [](std::uint64_t i) {
          return Reference(i) - RandomUnit(kStatisticsSeed, RandomStream::kLatinJitter, 2 * i, 0, 0);
        }},
       {"the next seed",
        [](std::uint64_t i) { return Reference(i) - RandomUnit(kStatisticsSeed + 1, kStatisticsStream, 2 * i, 0, 0); }},
       {"the next a",
        [](std::uint64_t i) { return Reference(i) - RandomUnit(kStatisticsSeed, kStatisticsStream, 2 * i + 1, 0, 0); }},
       {"the next b",
        [](std::uint64_t i) { return Reference(i) - RandomUnit(kStatisticsSeed, kStatisticsStream, 2 * i, 1, 0); }},
       {"the next c",
        [](std::uint64_t i) { return Reference(i) - RandomUnit(kStatisticsSeed, kStatisticsStream, 2 * i, 0, 1); }}});
}

}  // namespace
}  // namespace ringtol::sampling
