// Sample designs: where in the unit cube (0, 1)^d each sample of a campaign sits. A
// design point is turned into tolerances by sampling/assembly_sampler.h; the design knows
// nothing of rings.
//
// Every point is a pure function of (options, dimension, sample index): sample i can be
// regenerated alone, on any rank, in any order and any batch size. Designs that can grow
// do so without moving the points already drawn:
//   - Monte Carlo: independent uniform points from a counter-based generator. Grows freely.
//   - Latin hypercube (McKay, Beckman & Conover 1979): N strata per dimension, one point
//     in each; stratum of sample i in dimension k = pi_k(i) for a seeded random
//     permutation pi_k of {0..N-1}. N is fixed when the design is made: it cannot grow.
//   - Sobol' (Joe & Kuo direction numbers, via Boost.Random) with a random digital shift
//     per replicate (XOR of every coordinate with a random 64-bit word), which keeps the
//     net's stratification and makes the estimate unbiased. `replicates` independent
//     shifts give error bars; sample i belongs to replicate i % replicates and is point
//     i / replicates of that replicate's net, so every replicate grows together. A net is
//     balanced only at powers of two points per replicate: other counts are refused.
//   - Saltelli pick-and-freeze (Saltelli et al. 2010): rows j = 0, 1, ... each of G + 2
//     samples: A_j, B_j, and for every group g, A_j with the group's coordinates taken
//     from B_j. A and B are the two halves of one 2d-dimensional Monte Carlo or Sobol'
//     point. Sample i is row i / (G + 2), matrix i % (G + 2). Grows by whole rows (of a
//     power of two for a Sobol' base).
//
// Coordinates are strictly inside (0, 1) (see sampling/random.h), so inverse CDFs of
// unbounded distributions stay finite.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "engine/enum_names.h"

namespace ringtol::sampling {

enum class DesignKind { kMonteCarlo, kLatinHypercube, kSobol, kSaltelli };

inline constexpr NameTable<DesignKind, 4> kDesignNames = {{{DesignKind::kMonteCarlo, "monte_carlo"},
                                                            {DesignKind::kLatinHypercube, "latin_hypercube"},
                                                            {DesignKind::kSobol, "sobol"},
                                                            {DesignKind::kSaltelli, "saltelli"}}};
constexpr std::string_view DesignName(DesignKind kind) { return NameOf(kDesignNames, kind); }

struct DesignOptions {
  DesignKind kind = DesignKind::kMonteCarlo;
  std::uint64_t seed = 1;
  // Latin hypercube only: the number of strata, which is the design's whole size, >= 1.
  std::int64_t latin_samples = 0;
  // Sobol' only: independently shifted copies of the net, >= 1.
  int replicates = 1;
  // Sobol' and the Sobol' base of Saltelli: false gives the raw, unshifted net (for tests
  // and comparisons; its estimates have no error bars and a bias).
  bool randomise = true;
  // Saltelli only: kMonteCarlo or kSobol.
  DesignKind saltelli_base = DesignKind::kSobol;
  // Saltelli only: the groups whose indices are estimated, each a non-empty set of
  // dimensions (0-based) that are frozen together; groups are disjoint. A single input
  // is a group of one.
  std::vector<std::vector<int>> groups;
};

// Which of the pick-and-freeze matrices a Saltelli sample belongs to.
struct SaltelliPlace {
  std::int64_t row = 0;
  int matrix = 0;  // 0 = A, 1 = B, 2 + g = A with group g from B (AB_g)
};

class Design {
 public:
  // dimension >= 1. Throws std::invalid_argument, with a message naming the option and its
  // allowed range, for options that cannot make a design: a Latin hypercube without
  // samples, replicates < 1, a Sobol' dimension beyond Boost's table (3667; 2d for
  // Saltelli), overlapping or out-of-range groups, an unknown Saltelli base.
  Design(int dimension, DesignOptions options);
  ~Design();
  Design(Design&&) noexcept;
  Design& operator=(Design&&) noexcept;

  int dimension() const { return dimension_; }
  const DesignOptions& options() const { return options_; }

  // The coordinates of sample `sample` (>= 0) into u (size dimension()). Throws
  // std::out_of_range beyond a Latin hypercube's N. Not thread-safe: it reuses a Sobol'
  // engine; give each thread its own Design.
  void Point(std::int64_t sample, std::span<double> u);

  // Samples per Saltelli row, G + 2; 1 for other designs.
  int samples_per_row() const;
  // Saltelli only.
  SaltelliPlace Locate(std::int64_t sample) const;
  // Sobol' only: which shifted copy sample belongs to (0 for other designs).
  int ReplicateOf(std::int64_t sample) const;

  // Empty when `samples` is a size this design can have; otherwise why not, with the
  // nearest valid sizes, e.g. "a Sobol' net is balanced only at a power of two points
  // per replicate: 1000 = 1 x 1000; use 512 or 1024".
  std::string CheckSampleCount(std::int64_t samples) const;

 private:
  void SobolPoint(std::int64_t index, int replicate, std::span<double> u);

  int dimension_ = 0;
  DesignOptions options_;
  std::vector<int> group_of_;  // Saltelli: group of each dimension, -1 if none
  struct SobolNet;
  std::unique_ptr<SobolNet> sobol_;  // Sobol' and Saltelli-Sobol'; null otherwise
  std::vector<double> scratch_;      // Saltelli: the 2d-dimensional base point
};

// A seeded random permutation of {0, ..., n - 1} evaluated one element at a time: a
// four-round Feistel network on the smallest even-bit domain >= n, with cycle walking
// (Black & Rogaway 2002). Pure function of (seed, key, n, i). The Latin hypercube's
// strata; exposed for tests.
std::int64_t PermuteIndex(std::uint64_t seed, std::uint64_t key, std::int64_t n, std::int64_t i);

}  // namespace ringtol::sampling
