#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <vector>

#include "solvers/linear.h"
#include "solvers/path_kernels.h"
#include "tests/support/paper_scene.h"

namespace ringtol {
namespace {

using solvers::path_kernels::Isa;
using solvers::path_kernels::kLanes;
using solvers::path_kernels::Kernels;
using solvers::path_kernels::KernelsFor;
using solvers::path_kernels::Phasors;
using solvers::path_kernels::Supported;
using solvers::path_kernels::WeightedRows;

bool SameBits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// Rotating phasors at the given rates [rad per step] through `groups` lane groups of one
// build, from phase 0: the table (term-major, cosines then sines, groups x kLanes angles
// each) and the phasors where they stop.
struct TurnedTable {
  std::vector<double> table, now_cos, now_sin;
};

TurnedTable Turn(const Kernels& kernels, const std::vector<double>& rates, std::size_t groups) {
  const std::size_t terms = rates.size();
  std::vector<double> lane_cos(terms * kLanes), lane_sin(terms * kLanes), group_cos(terms), group_sin(terms);
  for (std::size_t p = 0; p < terms; ++p) {
    for (std::size_t l = 0; l < kLanes; ++l) {
      lane_cos[p * kLanes + l] = std::cos(rates[p] * static_cast<double>(l));
      lane_sin[p * kLanes + l] = std::sin(rates[p] * static_cast<double>(l));
    }
    group_cos[p] = std::cos(rates[p] * static_cast<double>(kLanes));
    group_sin[p] = std::sin(rates[p] * static_cast<double>(kLanes));
  }
  TurnedTable turned;
  turned.now_cos.assign(terms, 1.0);
  turned.now_sin.assign(terms, 0.0);
  const std::size_t count = groups * kLanes;
  turned.table.assign(2 * terms * count, 0.0);
  const Phasors phasors{terms, lane_cos.data(), lane_sin.data(), group_cos.data(), group_sin.data(),
                        turned.now_cos.data(), turned.now_sin.data()};
  for (std::size_t g = 0; g < groups; ++g) kernels.turn_phasors(phasors, turned.table.data() + g * kLanes, 2 * count, count);
  return turned;
}

// Weighted sums of a table's rows by one build, with each row's nonzero terms [first, last).
std::vector<double> Sum(const Kernels& kernels, const std::vector<double>& weights, std::size_t rows,
                        const std::vector<std::size_t>& first, const std::vector<std::size_t>& last,
                        const std::vector<double>& table, std::size_t table_stride, std::size_t lanes) {
  const WeightedRows weighted{rows, weights.size() / rows, weights.data(), first.data(), last.data()};
  std::vector<double> out(rows * lanes);
  kernels.sum_rows(weighted, table.data(), table_stride, lanes, out.data(), lanes);
  return out;
}

TEST(PathKernels, BestIsAvx2ExactlyWhereTheCpuHasItAndBaselineIsAlwaysAvailable) {
  EXPECT_TRUE(Supported(Isa::kBaseline));
  EXPECT_EQ(KernelsFor(Isa::kBaseline).isa, Isa::kBaseline);
  EXPECT_EQ(KernelsFor(Isa::kBest).isa, Supported(Isa::kAvx2) ? Isa::kAvx2 : Isa::kBaseline);
  EXPECT_EQ(KernelsFor(Isa::kAvx2).isa, KernelsFor(Isa::kBest).isa);
}

// Random weights and tables over twenty decades, random term ranges and lane counts that
// exercise both the wide chunks and the single lane groups: the builds must agree bit for
// bit, as the header's contract says.
TEST(PathKernels, Avx2AndBaselineGiveTheSameBitsOnRandomData) {
  if (!Supported(Isa::kAvx2)) GTEST_SKIP() << "this CPU has no AVX2";
  const Kernels& baseline = KernelsFor(Isa::kBaseline);
  const Kernels& avx2 = KernelsFor(Isa::kAvx2);
  std::mt19937_64 generator(20261125);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0), exponent(-10.0, 10.0), rate(-3.0, 3.0);
  const auto draw = [&] { return mantissa(generator) * std::pow(10.0, exponent(generator)); };
  for (const std::size_t terms : {1u, 7u, 33u, 98u}) {
    for (const std::size_t lanes : {kLanes, 3 * kLanes, 8 * kLanes, 9 * kLanes}) {
      const std::size_t rows = 11;
      std::vector<double> weights(rows * terms), table(terms * (lanes + kLanes));
      for (double& w : weights) w = draw();
      for (double& t : table) t = draw();
      std::vector<std::size_t> first(rows), last(rows);
      for (std::size_t o = 0; o < rows; ++o) {
        first[o] = generator() % (terms + 1);
        last[o] = first[o] + generator() % (terms + 1 - first[o]);
      }
      EXPECT_TRUE(SameBits(Sum(baseline, weights, rows, first, last, table, lanes + kLanes, lanes),
                           Sum(avx2, weights, rows, first, last, table, lanes + kLanes, lanes)))
          << terms << " terms, " << lanes << " lanes";
    }
    std::vector<double> rates(terms);
    for (double& r : rates) r = rate(generator);
    const TurnedTable a = Turn(baseline, rates, 9);
    const TurnedTable b = Turn(avx2, rates, 9);
    EXPECT_TRUE(SameBits(a.table, b.table)) << terms << " terms";
    EXPECT_TRUE(SameBits(a.now_cos, b.now_cos) && SameBits(a.now_sin, b.now_sin)) << terms << " terms";
  }
}

// A run of phasors turned one angle at a time, as LinearPath's coarse grid and refined
// stretches take them: blocks of terms full and partial, runs of whole and partial lane
// groups. Each build follows the header's recurrence, writes no lane past the run, leaves
// the phasors at the run's end, and the two agree bit for bit.
TEST(PathKernels, PhasorRunsFollowTheirRecurrenceAndAgreeUnderEitherBuild) {
  // A unit phasor turned n times drifts by about 2 ulp a turn: 50 turns, 2e-14; ten times.
  constexpr double kRoundOff = 2e-13;
  constexpr double kUnwritten = -7.0;  // no phasor's cosine or sine
  std::mt19937_64 generator(41);
  std::uniform_real_distribution<double> phase(-std::numbers::pi, std::numbers::pi);
  std::vector<Isa> builds = {Isa::kBaseline};
  if (Supported(Isa::kAvx2)) builds.push_back(Isa::kAvx2);
  for (const std::size_t terms : {1u, 8u, 13u}) {
    for (const std::size_t count : {1u, 4u, 7u, 50u}) {
      std::vector<double> start_cos(terms), start_sin(terms), turn_cos(terms), turn_sin(terms);
      for (std::size_t p = 0; p < terms; ++p) {
        const double start = phase(generator), turn = phase(generator);
        start_cos[p] = std::cos(start);
        start_sin[p] = std::sin(start);
        turn_cos[p] = std::cos(turn);
        turn_sin[p] = std::sin(turn);
      }
      const std::size_t stride = count + 3;
      std::vector<std::vector<double>> tables, ends;
      for (const Isa isa : builds) {
        std::vector<double> now_cos = start_cos, now_sin = start_sin, table(2 * terms * stride, kUnwritten);
        KernelsFor(isa).turn_run(terms, now_cos.data(), now_sin.data(), turn_cos.data(), turn_sin.data(), count,
                                 table.data(), stride);
        for (std::size_t p = 0; p < terms; ++p) {
          double c = start_cos[p], s = start_sin[p];
          for (std::size_t j = 0; j < count; ++j) {
            ASSERT_NEAR(table[2 * p * stride + j], c, kRoundOff) << terms << " terms, " << count << " angles";
            ASSERT_NEAR(table[(2 * p + 1) * stride + j], s, kRoundOff) << terms << " terms, " << count << " angles";
            const double next = c * turn_cos[p] - s * turn_sin[p];
            s = s * turn_cos[p] + c * turn_sin[p];
            c = next;
          }
          for (std::size_t j = count; j < stride; ++j) {
            ASSERT_EQ(table[2 * p * stride + j], kUnwritten);
            ASSERT_EQ(table[(2 * p + 1) * stride + j], kUnwritten);
          }
          ASSERT_NEAR(now_cos[p], c, kRoundOff) << terms << " terms, " << count << " angles";
          ASSERT_NEAR(now_sin[p], s, kRoundOff) << terms << " terms, " << count << " angles";
        }
        tables.push_back(table);
        ends.push_back(now_cos);
        ends.push_back(now_sin);
      }
      if (builds.size() == 2) {
        EXPECT_TRUE(SameBits(tables[0], tables[1])) << terms << " terms, " << count << " angles";
        EXPECT_TRUE(SameBits(ends[0], ends[2]) && SameBits(ends[1], ends[3])) << terms << " terms, " << count;
      }
    }
  }
}

// The linearisation of a campaign-like scene (bore orders 2..50, eight lobe orders per
// roller): its weights over the phasor table of its own rates, one campaign-resolution
// block, through both builds.
TEST(PathKernels, Avx2AndBaselineGiveTheSameBitsOnACampaignLinearisation) {
  if (!Supported(Isa::kAvx2)) GTEST_SKIP() << "this CPU has no AVX2";
  const solvers::PhasorSum phasors = solvers::LinearSolver().Phasors(testing::CampaignLikeScene());
  ASSERT_TRUE(phasors.usable);
  constexpr int kSteps = 3200;
  std::vector<double> rates;
  for (double r : phasors.rates) rates.push_back(r * 2.0 * std::numbers::pi / kSteps);
  const std::size_t terms = rates.size();
  const std::size_t groups = 8;
  const std::size_t count = groups * kLanes;
  const TurnedTable a = Turn(KernelsFor(Isa::kBaseline), rates, groups);
  const TurnedTable b = Turn(KernelsFor(Isa::kAvx2), rates, groups);
  ASSERT_TRUE(SameBits(a.table, b.table));
  // Cosine and sine weights interleaved as the table's rows: term p's at 2p and 2p + 1.
  const auto rows = static_cast<std::size_t>(phasors.cosine.rows());
  std::vector<double> weights;
  for (std::size_t o = 0; o < rows; ++o) {
    for (std::size_t p = 0; p < terms; ++p) {
      weights.push_back(phasors.cosine(static_cast<Eigen::Index>(o), static_cast<Eigen::Index>(p)));
      weights.push_back(phasors.sine(static_cast<Eigen::Index>(o), static_cast<Eigen::Index>(p)));
    }
  }
  const std::vector<std::size_t> first(rows, 0), last(rows, 2 * terms);
  EXPECT_TRUE(SameBits(Sum(KernelsFor(Isa::kBaseline), weights, rows, first, last, a.table, count, count),
                       Sum(KernelsFor(Isa::kAvx2), weights, rows, first, last, a.table, count, count)));
}

// The whole revolution, folded over a quarter turn (3200 steps), over a half turn (3201)
// and summed at every angle (30, too few for a lane group in a quarter turn), with either
// build of the kernels: the same bits in every output and the same error estimate.
TEST(PathKernels, LinearRevolutionIsTheSameUnderEitherBuild) {
  if (!Supported(Isa::kAvx2)) GTEST_SKIP() << "this CPU has no AVX2";
  const engine::Scene scene = testing::CampaignLikeScene();
  solvers::LinearOptions baseline_options, avx2_options;
  baseline_options.kernels = Isa::kBaseline;
  avx2_options.kernels = Isa::kAvx2;
  for (const int steps : {3200, 3201, 30}) {
    const solvers::Trajectory a = solvers::LinearSolver(baseline_options).SolveRevolution(scene, steps);
    const solvers::Trajectory b = solvers::LinearSolver(avx2_options).SolveRevolution(scene, steps);
    ASSERT_EQ(a.status, solvers::Status::kOk) << a.message;
    ASSERT_EQ(b.status, a.status);
    ASSERT_EQ(a.centre.size(), b.centre.size());
    EXPECT_EQ(std::memcmp(a.centre.data(), b.centre.data(), a.centre.size() * sizeof(a.centre[0])), 0) << steps;
    EXPECT_TRUE(SameBits(a.travel, b.travel)) << steps;
    EXPECT_TRUE(SameBits(a.contact_force, b.contact_force)) << steps;
    EXPECT_EQ(std::memcmp(&a.error_estimate, &b.error_estimate, sizeof(double)), 0) << steps;
  }
}

}  // namespace
}  // namespace ringtol
