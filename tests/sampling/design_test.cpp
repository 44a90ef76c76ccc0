#include "sampling/design.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>
#include <stdexcept>
#include <vector>

#include "tests/support/statistics.h"

namespace ringtol::sampling {
namespace {

using ::testing::HasSubstr;

template <typename Set>
DesignOptions Options(Set set) {
  DesignOptions options;
  set(options);
  return options;
}

std::vector<std::vector<double>> Points(Design& design, std::int64_t count) {
  std::vector<std::vector<double>> points;
  for (std::int64_t i = 0; i < count; ++i) {
    std::vector<double> u(static_cast<std::size_t>(design.dimension()));
    design.Point(i, u);
    points.push_back(u);
  }
  return points;
}

// Counts per cell of a 2^a x 2^b grid on dimensions (j, k).
std::vector<int> GridCounts(const std::vector<std::vector<double>>& points, std::size_t j, std::size_t k, int a,
                            int b) {
  const int nx = 1 << a, ny = 1 << b;
  std::vector<int> counts(static_cast<std::size_t>(nx * ny), 0);
  for (const auto& p : points) {
    const int x = static_cast<int>(p[j] * nx), y = static_cast<int>(p[k] * ny);
    ++counts[static_cast<std::size_t>(x * ny + y)];
  }
  return counts;
}

TEST(SobolDesign, FirstTwoDimensionsAreAZeroNetShiftedOrNot) {
  // Sobol' dimensions 1 and 2 form a (0, m, 2)-net in base 2: every elementary interval of area
  // 2^-m (a 2^a x 2^(m-a) grid cell) holds exactly one of the first 2^m points. A digital shift
  // permutes those intervals, so the property survives randomisation.
  constexpr int kM = 10;
  for (const bool randomise : {false, true}) {
    Design design(4, Options([&](DesignOptions& o) {
                    o.kind = DesignKind::kSobol;
                    o.seed = 7;
                    o.randomise = randomise;
                  }));
    const auto points = Points(design, 1 << kM);
    for (int a = 0; a <= kM; ++a) {
      const std::vector<int> counts = GridCounts(points, 0, 1, a, kM - a);
      EXPECT_EQ(*std::min_element(counts.begin(), counts.end()), 1) << "a = " << a << " randomise " << randomise;
      EXPECT_EQ(*std::max_element(counts.begin(), counts.end()), 1) << "a = " << a << " randomise " << randomise;
    }
  }
}

TEST(SobolDesign, EveryDimensionHasOnePointPerStratum) {
  constexpr int kM = 9;
  Design design(60, Options([&](DesignOptions& o) {
                  o.kind = DesignKind::kSobol;
                  o.seed = 3;
                }));
  const auto points = Points(design, 1 << kM);
  for (std::size_t k = 0; k < 60; ++k) {
    std::vector<int> counts(1 << kM, 0);
    for (const auto& p : points) ++counts[static_cast<std::size_t>(p[k] * (1 << kM))];
    EXPECT_EQ(*std::max_element(counts.begin(), counts.end()), 1) << "dimension " << k;
  }
}

TEST(SobolDesign, StartsAtTheOriginAndFollowsTheNet) {
  // Unshifted, point 0 is the origin (the centre of its 2^-53 cell) and point 1 is 1/2 in every
  // dimension: Boost's engine skips the origin, the design puts it back.
  Design design(3, Options([&](DesignOptions& o) {
                  o.kind = DesignKind::kSobol;
                  o.randomise = false;
                }));
  const auto points = Points(design, 2);
  for (const double x : points[0]) EXPECT_EQ(x, 0x1p-54);
  for (const double x : points[1]) EXPECT_EQ(x, 0.5 + 0x1p-54);
}

TEST(SobolDesign, ReplicatesAreIndependentShiftsOfOneNetAndGrowTogether) {
  Design design(2, Options([&](DesignOptions& o) {
                  o.kind = DesignKind::kSobol;
                  o.seed = 11;
                  o.replicates = 3;
                }));
  EXPECT_EQ(design.ReplicateOf(7), 1);
  const auto points = Points(design, 3 * 16);
  // Each replicate's 16 points are balanced in each dimension on their own.
  for (int r = 0; r < 3; ++r) {
    std::set<int> strata;
    for (int j = 0; j < 16; ++j) strata.insert(static_cast<int>(points[static_cast<std::size_t>(3 * j + r)][0] * 16));
    EXPECT_EQ(strata.size(), 16u) << "replicate " << r;
  }
  EXPECT_NE(points[0], points[1]);
  EXPECT_EQ(design.CheckSampleCount(48), "");
  EXPECT_THAT(design.CheckSampleCount(30), HasSubstr("power of two points per replicate"));
  EXPECT_THAT(design.CheckSampleCount(30), HasSubstr("use 24 or 48"));
}

TEST(SobolDesign, SampleCountsThatBreakBalanceAreRefusedWithTheNearestValidCounts) {
  Design design(5, Options([&](DesignOptions& o) { o.kind = DesignKind::kSobol; }));
  EXPECT_EQ(design.CheckSampleCount(1024), "");
  EXPECT_THAT(design.CheckSampleCount(1000), HasSubstr("use 512 or 1024"));
}

TEST(LatinHypercube, EveryStratumOfEveryDimensionHoldsExactlyOnePoint) {
  for (const std::int64_t n : {1, 2, 7, 100, 1000}) {
    Design design(12, Options([&](DesignOptions& o) {
                    o.kind = DesignKind::kLatinHypercube;
                    o.seed = 5;
                    o.latin_samples = n;
                  }));
    const auto points = Points(design, n);
    for (std::size_t k = 0; k < 12; ++k) {
      std::set<std::int64_t> strata;
      for (const auto& p : points) strata.insert(static_cast<std::int64_t>(p[k] * static_cast<double>(n)));
      EXPECT_EQ(static_cast<std::int64_t>(strata.size()), n) << "n " << n << " dimension " << k;
    }
  }
}

TEST(LatinHypercube, CannotGrowBeyondItsStrata) {
  Design design(2, Options([&](DesignOptions& o) {
                  o.kind = DesignKind::kLatinHypercube;
                  o.latin_samples = 10;
                }));
  std::vector<double> u(2);
  EXPECT_THROW(design.Point(10, u), std::out_of_range);
  EXPECT_THAT(design.CheckSampleCount(20), HasSubstr("cannot grow"));
  EXPECT_EQ(design.CheckSampleCount(10), "");
}

TEST(PermuteIndex, IsABijectionForEverySize) {
  for (const std::int64_t n : {1, 2, 3, 5, 16, 17, 1000, 4097}) {
    std::vector<bool> seen(static_cast<std::size_t>(n), false);
    for (std::int64_t i = 0; i < n; ++i) {
      const std::int64_t j = PermuteIndex(9, 2, n, i);
      ASSERT_GE(j, 0);
      ASSERT_LT(j, n);
      EXPECT_FALSE(seen[static_cast<std::size_t>(j)]);
      seen[static_cast<std::size_t>(j)] = true;
    }
  }
}

TEST(MonteCarloDesign, CoordinatesAreUniformAndIndependentAcrossDimensions) {
  // Kolmogorov-Smirnov per dimension against U(0, 1), and of the difference of two
  // coordinates against the triangular law it has when they are independent; overall
  // significance 1e-3 split over 9 tests.
  constexpr double kAlpha = 1e-3 / 9.0;
  constexpr std::int64_t kN = 20000;
  Design design(8, Options([&](DesignOptions& o) {
                  o.kind = DesignKind::kMonteCarlo;
                  o.seed = 2024;
                }));
  const auto points = Points(design, kN);
  for (std::size_t k = 0; k < 8; ++k) {
    std::vector<double> column;
    for (const auto& p : points) column.push_back(p[k]);
    const double d = testing::KolmogorovSmirnovStatistic(column, [](double x) { return x; });
    EXPECT_GT(testing::KolmogorovSmirnovPValue(d, column.size()), kAlpha) << "dimension " << k;
  }
  // u_0 - u_1 has the triangular distribution if independent.
  std::vector<double> difference;
  for (const auto& p : points) difference.push_back(p[0] - p[1]);
  const double d = testing::KolmogorovSmirnovStatistic(
      difference, [](double x) { return x < 0 ? 0.5 * (1 + x) * (1 + x) : 1 - 0.5 * (1 - x) * (1 - x); });
  EXPECT_GT(testing::KolmogorovSmirnovPValue(d, difference.size()), kAlpha);
}

// Sample i is a pure function of (options, i): drawn alone, in reverse order, in chunks, or by
// another Design object, it is bit for bit the same point.
class Reproducibility : public ::testing::TestWithParam<DesignKind> {};

TEST_P(Reproducibility, SampleIIsTheSameWhateverTheOrderChunkingOrInstance) {
  const DesignKind kind = GetParam();
  const DesignOptions options = Options([&](DesignOptions& o) {
    o.kind = kind;
    o.seed = 99;
    o.latin_samples = 64;
    o.groups = {{0, 2}, {1}};
  });
  constexpr std::int64_t kCount = 64;
  Design forward(5, options);
  const auto reference = Points(forward, kCount);
  Design reverse(5, options);
  for (std::int64_t i = kCount - 1; i >= 0; --i) {
    std::vector<double> u(5);
    reverse.Point(i, u);
    EXPECT_EQ(u, reference[static_cast<std::size_t>(i)]) << DesignName(kind) << " sample " << i;
  }
  Design chunked(5, options);
  for (std::int64_t start = 0; start < kCount; start += 13) {
    for (std::int64_t i = std::min(kCount, start + 13) - 1; i >= start; --i) {
      std::vector<double> u(5);
      chunked.Point(i, u);
      EXPECT_EQ(u, reference[static_cast<std::size_t>(i)]);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Designs, Reproducibility,
                         ::testing::Values(DesignKind::kMonteCarlo, DesignKind::kLatinHypercube, DesignKind::kSobol,
                                           DesignKind::kSaltelli),
                         [](const auto& param_info) { return std::string(DesignName(param_info.param)); });

TEST(Design, GrowingTheSetLeavesEarlierSamplesUnchanged) {
  for (const DesignKind kind : {DesignKind::kMonteCarlo, DesignKind::kSobol, DesignKind::kSaltelli}) {
    const DesignOptions options = Options([&](DesignOptions& o) {
      o.kind = kind;
      o.seed = 4;
      o.groups = {{0}, {1, 2}};
    });
    Design small(3, options);
    const auto first = Points(small, 32);
    Design large(3, options);
    const auto grown = Points(large, 128);
    for (std::size_t i = 0; i < first.size(); ++i) EXPECT_EQ(first[i], grown[i]) << DesignName(kind);
  }
}

TEST(SaltelliDesign, MixesAAndBByGroup) {
  for (const DesignKind base : {DesignKind::kMonteCarlo, DesignKind::kSobol}) {
    Design design(4, Options([&](DesignOptions& o) {
                    o.kind = DesignKind::kSaltelli;
                    o.seed = 1;
                    o.saltelli_base = base;
                    o.groups = {{0, 3}, {2}};
                  }));
    ASSERT_EQ(design.samples_per_row(), 4);
    const auto points = Points(design, 8);  // two rows
    for (int row = 0; row < 2; ++row) {
      const auto& a = points[static_cast<std::size_t>(4 * row)];
      const auto& b = points[static_cast<std::size_t>(4 * row + 1)];
      const auto& ab0 = points[static_cast<std::size_t>(4 * row + 2)];
      const auto& ab1 = points[static_cast<std::size_t>(4 * row + 3)];
      for (std::size_t k = 0; k < 4; ++k) EXPECT_NE(a[k], b[k]);
      EXPECT_EQ(ab0, (std::vector<double>{b[0], a[1], a[2], b[3]}));
      EXPECT_EQ(ab1, (std::vector<double>{a[0], a[1], b[2], a[3]}));
    }
    EXPECT_EQ(design.Locate(6).row, 1);
    EXPECT_EQ(design.Locate(6).matrix, 2);
  }
}

TEST(SaltelliDesign, SobolBaseNeedsAPowerOfTwoRows) {
  Design design(3, Options([&](DesignOptions& o) {
                  o.kind = DesignKind::kSaltelli;
                  o.groups = {{0}, {1}, {2}};
                }));
  EXPECT_EQ(design.CheckSampleCount(5 * 64), "");
  EXPECT_THAT(design.CheckSampleCount(5 * 100), HasSubstr("power of two rows"));
  EXPECT_THAT(design.CheckSampleCount(5 * 100), HasSubstr("use 320 or 640"));
  EXPECT_THAT(design.CheckSampleCount(7), HasSubstr("whole rows"));
}

TEST(Design, BadOptionsAreRefusedWithTheirAllowedRange) {
  EXPECT_THROW(Design(0, {}), std::invalid_argument);
  EXPECT_THROW(Design(2, Options([&](DesignOptions& o) { o.kind = DesignKind::kLatinHypercube; })),
               std::invalid_argument);
  EXPECT_THROW(Design(2, Options([&](DesignOptions& o) {
                        o.kind = DesignKind::kMonteCarlo;
                        o.replicates = 2;
                      })),
               std::invalid_argument);
  EXPECT_THROW(Design(2, Options([&](DesignOptions& o) { o.kind = DesignKind::kSaltelli; })), std::invalid_argument);
  EXPECT_THROW(Design(2, Options([&](DesignOptions& o) {
                        o.kind = DesignKind::kSaltelli;
                        o.groups = {{0}, {0, 1}};
                      })),
               std::invalid_argument);
  EXPECT_THROW(Design(2, Options([&](DesignOptions& o) {
                        o.kind = DesignKind::kSaltelli;
                        o.groups = {{2}};
                      })),
               std::invalid_argument);
  try {
    Design(2000, Options([&](DesignOptions& o) {
             o.kind = DesignKind::kSaltelli;
             o.groups = {{0}};
           }));
    FAIL() << "a 4000-dimensional Sobol' net was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("<= 3667"));
  }
}

}  // namespace
}  // namespace ringtol::sampling
