// Counter-based random numbers: every draw is a pure function of (seed, stream, and three
// counters), with no generator state. That is what lets sample i of a campaign be
// regenerated alone, on any rank, in any order, and lets a campaign grow later without
// changing the draws already made (docs/architecture.md: results never depend on rank count or order).
//
// The generator is Random123's Philox4x64-10 (Salmon et al., SC'11), which passes
// TestU01's BigCrush for every counter and key pattern; it is header-only in Debian's
// librandom123-dev.
#pragma once

#include <algorithm>
#include <cstdint>

namespace ringtol::sampling {

// Independent purposes get different streams, so that e.g. the jitter of a Latin
// hypercube and the shift of a Sobol' net never share draws.
enum class RandomStream : std::uint64_t {
  kMonteCarlo = 1,      // plain Monte Carlo points: (sample, dimension, 0)
  kLatinJitter = 2,     // position inside a Latin-hypercube stratum: (sample, dimension, 0)
  kLatinPermutation = 3,  // keys of the stratum permutations: (dimension, round, 0)
  kSobolShift = 4,      // digital shifts: (replicate, dimension, 0)
  kRedraw = 5,          // inspected parts drawn again after rejection: (sample, dimension, attempt)
  kCalibration = 6,     // spectrum calibration draws: (draw, dimension, 0)
  kMatch = 7,           // `ringtol match`'s random assignments: (assignment, slot, 0)
};

// 64 random bits for (seed, stream, a, b, c).
std::uint64_t RandomBits(std::uint64_t seed, RandomStream stream, std::uint64_t a, std::uint64_t b,
                         std::uint64_t c);

// The 53 high bits of x as a double strictly inside (0, 1): the centre of their cell,
// (floor(x / 2^11) + 0.5) / 2^53, rounded to a double. From 1/2 up doubles are 2^-53
// apart, so the centre rounds (to even) onto a cell's edge, and the top cell's edge is 1:
// that one cell is held at the largest double below 1. Never 0 or 1, so -log(u) and the
// normal quantile of u are always finite.
inline double UnitFromBits(std::uint64_t x) {
  constexpr double kLargestBelowOne = 1.0 - 0x1p-53;
  return std::min((static_cast<double>(x >> 11) + 0.5) * 0x1p-53, kLargestBelowOne);
}

// A uniform draw in (0, 1): UnitFromBits(RandomBits(...)).
inline double RandomUnit(std::uint64_t seed, RandomStream stream, std::uint64_t a, std::uint64_t b,
                         std::uint64_t c) {
  return UnitFromBits(RandomBits(seed, stream, a, b, c));
}

}  // namespace ringtol::sampling
