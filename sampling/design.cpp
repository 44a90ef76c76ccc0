#include "sampling/design.h"

#include <algorithm>
#include <bit>
#include <stdexcept>
#include <string>

#include <boost/random/sobol.hpp>

#include "sampling/random.h"

namespace ringtol::sampling {
namespace {

using SobolEngine = boost::random::sobol_engine<std::uint64_t, 64, boost::random::default_sobol_table>;

int SobolMaxDimension() {
  // A local copy: odr-using the BOOST_STATIC_CONSTANT fails to link at -O0.
  const int max_dimension = static_cast<int>(boost::random::default_sobol_table::max_dimension);
  return max_dimension;
}

std::string Text(std::int64_t value) { return std::to_string(value); }

bool IsPowerOfTwo(std::int64_t n) { return n > 0 && std::has_single_bit(static_cast<std::uint64_t>(n)); }

// "512 or 1024" for 1000: the powers of two around n, times `unit`.
std::string NearestPowersOfTwo(std::int64_t n, std::int64_t unit) {
  const auto floor = static_cast<std::int64_t>(std::bit_floor(static_cast<std::uint64_t>(std::max<std::int64_t>(n, 1))));
  return floor == n ? Text(n * unit) : Text(floor * unit) + " or " + Text(2 * floor * unit);
}

}  // namespace

struct Design::SobolNet {
  explicit SobolNet(int dimension) : engine(static_cast<std::size_t>(dimension)) {}
  SobolEngine engine;
  std::vector<std::uint64_t> shifts;  // replicate-major: shifts[r * dimension + k]
};

Design::Design(int dimension, DesignOptions options) : dimension_(dimension), options_(std::move(options)) {
  if (dimension_ < 1) throw std::invalid_argument("design dimension " + Text(dimension_) + ": must be >= 1");
  const DesignKind kind = options_.kind;
  if (kind == DesignKind::kLatinHypercube && options_.latin_samples < 1)
    throw std::invalid_argument("a Latin hypercube needs its sample count (the number of strata) >= 1 when it is made");
  if (options_.replicates < 1)
    throw std::invalid_argument("replicates = " + Text(options_.replicates) + ": must be >= 1");
  if (kind != DesignKind::kSobol && options_.replicates != 1)
    throw std::invalid_argument("replicates apply to the sobol design only; " + std::string(DesignName(kind)) +
                                " takes 1");
  if (kind == DesignKind::kSaltelli) {
    if (options_.saltelli_base != DesignKind::kMonteCarlo && options_.saltelli_base != DesignKind::kSobol)
      throw std::invalid_argument(std::string("Saltelli base design ") + std::string(DesignName(options_.saltelli_base)) +
                                  ": allowed: monte_carlo, sobol");
    if (options_.groups.empty()) throw std::invalid_argument("a Saltelli design needs at least one group");
    group_of_.assign(static_cast<std::size_t>(dimension_), -1);
    for (std::size_t g = 0; g < options_.groups.size(); ++g) {
      if (options_.groups[g].empty()) throw std::invalid_argument("Saltelli group " + Text(static_cast<std::int64_t>(g)) + " is empty");
      for (const int k : options_.groups[g]) {
        if (k < 0 || k >= dimension_)
          throw std::invalid_argument("Saltelli group " + Text(static_cast<std::int64_t>(g)) + " names dimension " +
                                      Text(k) + "; allowed: 0.." + Text(dimension_ - 1));
        int& owner = group_of_[static_cast<std::size_t>(k)];
        if (owner >= 0)
          throw std::invalid_argument("dimension " + Text(k) + " is in Saltelli groups " + Text(owner) + " and " +
                                      Text(static_cast<std::int64_t>(g)) + "; groups must be disjoint");
        owner = static_cast<int>(g);
      }
    }
    scratch_.resize(2 * static_cast<std::size_t>(dimension_));
  }
  const bool sobol = kind == DesignKind::kSobol ||
                     (kind == DesignKind::kSaltelli && options_.saltelli_base == DesignKind::kSobol);
  if (sobol) {
    const int net_dimension = kind == DesignKind::kSaltelli ? 2 * dimension_ : dimension_;
    if (net_dimension > SobolMaxDimension())
      throw std::invalid_argument("a Sobol' net of dimension " + Text(net_dimension) +
                                  (kind == DesignKind::kSaltelli ? " (2 x " + Text(dimension_) + " for Saltelli)" : "") +
                                  " is beyond Boost's direction-number table; allowed: <= " +
                                  Text(SobolMaxDimension()) + "; use a monte_carlo base instead");
    sobol_ = std::make_unique<SobolNet>(net_dimension);
    const auto n = static_cast<std::size_t>(net_dimension);
    sobol_->shifts.assign(static_cast<std::size_t>(options_.replicates) * n, 0);
    if (options_.randomise) {
      for (std::size_t r = 0; r < static_cast<std::size_t>(options_.replicates); ++r)
        for (std::size_t k = 0; k < n; ++k)
          sobol_->shifts[r * n + k] = RandomBits(options_.seed, RandomStream::kSobolShift, r, k, 0);
    }
  }
}

Design::~Design() = default;
Design::Design(Design&&) noexcept = default;
Design& Design::operator=(Design&&) noexcept = default;

int Design::samples_per_row() const {
  return options_.kind == DesignKind::kSaltelli ? static_cast<int>(options_.groups.size()) + 2 : 1;
}

SaltelliPlace Design::Locate(std::int64_t sample) const {
  const int per_row = samples_per_row();
  return {sample / per_row, static_cast<int>(sample % per_row)};
}

int Design::ReplicateOf(std::int64_t sample) const {
  return options_.kind == DesignKind::kSobol ? static_cast<int>(sample % options_.replicates) : 0;
}

std::string Design::CheckSampleCount(std::int64_t samples) const {
  if (samples < 1) return "a design needs at least 1 sample; got " + Text(samples);
  switch (options_.kind) {
    case DesignKind::kMonteCarlo:
      return "";
    case DesignKind::kLatinHypercube:
      if (samples == options_.latin_samples) return "";
      return "a Latin hypercube of " + Text(options_.latin_samples) + " strata has exactly " +
             Text(options_.latin_samples) + " samples (its strata depend on the count, so it cannot grow); got " +
             Text(samples) + "; start a new design, or use sobol or monte_carlo to extend";
    case DesignKind::kSobol: {
      const std::int64_t r = options_.replicates;
      if (samples % r == 0 && IsPowerOfTwo(samples / r)) return "";
      return "a Sobol' net is balanced only at a power of two points per replicate: " + Text(samples) + " = " +
             Text(r) + " replicate(s) x " + (samples % r == 0 ? Text(samples / r) : Text(samples) + "/" + Text(r)) +
             "; use " + NearestPowersOfTwo(samples / r, r);
    }
    case DesignKind::kSaltelli: {
      const std::int64_t per_row = samples_per_row();
      const std::string shape = Text(samples) + " samples at " + Text(per_row) + " per row (A, B and " +
                                Text(per_row - 2) + " groups)";
      if (samples % per_row != 0)
        return "a Saltelli design has whole rows: " + shape + "; use " + Text((samples / per_row + 1) * per_row);
      if (options_.saltelli_base == DesignKind::kSobol && !IsPowerOfTwo(samples / per_row))
        return "a Saltelli design on a Sobol' base needs a power of two rows: " + shape + " = " +
               Text(samples / per_row) + " rows; use " + NearestPowersOfTwo(samples / per_row, per_row);
      return "";
    }
  }
  return "";
}

void Design::SobolPoint(std::int64_t index, int replicate, std::span<double> u) {
  // Boost's engine skips the origin (its point k is the net's point k + 1); the net's
  // first 2^m points, origin included, are what is balanced.
  SobolEngine& engine = sobol_->engine;
  const std::size_t n = u.size();
  const std::uint64_t* shift = sobol_->shifts.data() + static_cast<std::size_t>(replicate) * n;
  if (index > 0) engine.seed(static_cast<std::uint64_t>(index - 1));
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint64_t x = index > 0 ? engine() : 0;
    u[k] = UnitFromBits(x ^ shift[k]);
  }
}

void Design::Point(std::int64_t sample, std::span<double> u) {
  if (static_cast<int>(u.size()) != dimension_) throw std::invalid_argument("design point of the wrong size");
  if (sample < 0) throw std::out_of_range("sample index " + Text(sample) + " < 0");
  const std::uint64_t seed = options_.seed;
  const auto i = static_cast<std::uint64_t>(sample);
  switch (options_.kind) {
    case DesignKind::kMonteCarlo:
      for (std::size_t k = 0; k < u.size(); ++k) u[k] = RandomUnit(seed, RandomStream::kMonteCarlo, i, k, 0);
      return;
    case DesignKind::kLatinHypercube: {
      const std::int64_t n = options_.latin_samples;
      if (sample >= n)
        throw std::out_of_range("sample " + Text(sample) + " is beyond the Latin hypercube's " + Text(n) + " strata");
      for (std::size_t k = 0; k < u.size(); ++k) {
        const std::int64_t stratum = PermuteIndex(seed, k, n, sample);
        const double jitter = RandomUnit(seed, RandomStream::kLatinJitter, i, k, 0);
        u[k] = (static_cast<double>(stratum) + jitter) / static_cast<double>(n);
      }
      return;
    }
    case DesignKind::kSobol: {
      const int r = ReplicateOf(sample);
      SobolPoint(sample / options_.replicates, r, u);
      return;
    }
    case DesignKind::kSaltelli: {
      const SaltelliPlace place = Locate(sample);
      const std::size_t d = u.size();
      if (sobol_) {
        SobolPoint(place.row, 0, scratch_);
      } else {
        const auto row = static_cast<std::uint64_t>(place.row);
        for (std::size_t k = 0; k < 2 * d; ++k) scratch_[k] = RandomUnit(seed, RandomStream::kMonteCarlo, row, k, 0);
      }
      for (std::size_t k = 0; k < d; ++k) {
        const bool from_b = place.matrix == 1 || (place.matrix >= 2 && group_of_[k] == place.matrix - 2);
        u[k] = scratch_[from_b ? d + k : k];
      }
      return;
    }
  }
}

std::int64_t PermuteIndex(std::uint64_t seed, std::uint64_t key, std::int64_t n, std::int64_t i) {
  if (n < 1 || i < 0 || i >= n) throw std::out_of_range("PermuteIndex: index outside 0..n-1");
  int bits = std::max(2, static_cast<int>(std::bit_width(static_cast<std::uint64_t>(n - 1))));
  bits += bits % 2;
  const int half = bits / 2;
  const std::uint64_t mask = (std::uint64_t{1} << half) - 1;
  auto x = static_cast<std::uint64_t>(i);
  // Cycle walking: the network permutes {0..2^bits - 1}; re-applying it until the value
  // lands below n restricts it to a permutation of {0..n-1}. At most 4x expected walks,
  // since 2^bits < 4n.
  do {
    std::uint64_t left = x >> half, right = x & mask;
    for (std::uint64_t round = 0; round < 4; ++round) {
      const std::uint64_t f = RandomBits(seed, RandomStream::kLatinPermutation, key, round, right) & mask;
      const std::uint64_t next = left ^ f;
      left = right;
      right = next;
    }
    x = (left << half) | right;
  } while (x >= static_cast<std::uint64_t>(n));
  return static_cast<std::int64_t>(x);
}

}  // namespace ringtol::sampling
