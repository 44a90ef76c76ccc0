// SecondOrderTerms' batched kernel (AtEach) against the one-angle At it must equal bit for
// bit, on random scenes of 3 to 9 rollers under each contact law, with lanes that fail the
// expansion's premises beside lanes that hold; and the second order's work buffers, which
// must not touch the heap once warm.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <new>
#include <numbers>
#include <random>
#include <span>
#include <vector>

#include "solvers/linear.h"
#include "solvers/second_order.h"
#include "tests/support/paper_scene.h"

namespace {

// Heap allocations made on this thread while `counting` is set (operator new replaced for
// this test executable; every other test only pays a thread-local check).
thread_local bool counting = false;
thread_local long allocations = 0;

}  // namespace

// The replacements pair malloc with free, which GCC cannot see through inlining.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t size) {
  if (counting) ++allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop

namespace ringtol {
namespace {

using Law = engine::ContactLaw::Model;

struct Case {
  std::size_t rollers;
  Law law;
  double exponent;    // [-] of the penalty law
  double lobe_scale;  // [-] the rollers' lobes, times the default campaign's
};

// The article's law (e = 1.5, x^(e-3) without pow), the law of the materials (e = 10/9,
// pow), and the rigid law; lobes out to where some angles' remainders are infinite.
const std::vector<Case> kCases = {
    {3, Law::kPenalty, 1.5, 1.0},   {3, Law::kPenalty, 1.5, 150.0}, {3, Law::kRigid, 1.5, 5.0},
    {4, Law::kPenalty, 10.0 / 9.0, 5.0}, {5, Law::kRigid, 1.5, 1.0},    {8, Law::kPenalty, 1.5, 9.0},
    {9, Law::kPenalty, 1.5, 1.0},
};

engine::Scene SceneOf(const Case& c, std::mt19937_64& random) {
  engine::Scene scene = testing::WithSpringRollers(testing::RandomCampaignLikeScene(random, c.lobe_scale), c.rollers);
  scene.contact.model = c.law;
  scene.contact.exponent = c.exponent;
  return scene;
}

// One angle of Samples::first_order (angle-major, 2 + 6Z doubles) as At reads it.
solvers::FirstOrderAngle AngleAt(const double* row, std::size_t z) {
  return {Eigen::Vector2d(row[0], row[1]), std::span<const double>(row + 2, z), std::span<const double>(row + 2 + z, z),
          std::span<const double>(row + 2 + 2 * z, 2 * z), std::span<const double>(row + 2 + 4 * z, 2 * z)};
}

std::uint64_t Bits(double x) { return std::bit_cast<std::uint64_t>(x); }

// Every coarse angle of each case's path (random steps and stride), some pushed past the
// expansion's premises (slopes and curvatures a thousand times theirs: At's first-order
// fallback and an infinite remainder) or past the penalty law's (a force ten times its
// own), fed to AtEach in blocks of 1, 3 and all the angles (a lone last lane, odd counts,
// a row stride wider than the block): every output's bits are At's at that angle. The
// unpushed angles' outputs in LinearPath::Samples are the first order plus At's, bit for bit.
TEST(SecondOrderTermsAtEach, EqualsAtAngleByAngleBitForBit) {
  std::mt19937_64 random(4141);
  const solvers::LinearSolver solver;
  long finite = 0, infinite = 0;
  for (const Case& c : kCases) {
    const engine::Scene scene = SceneOf(c, random);
    const int steps = 3000 + static_cast<int>(random() % 400);
    const int stride = 5 + static_cast<int>(random() % 7);
    solvers::LinearPath path = solver.Path(scene, steps);
    ASSERT_EQ(path.status(), solvers::Status::kOk) << c.rollers << " rollers: " << path.message();
    solvers::LinearPath::Samples samples;
    path.EvaluateCoarse(stride, samples);
    const solvers::SecondOrderTerms& terms = path.second_order();
    const std::size_t z = c.rollers;
    const std::size_t width = path.FirstOrderWidth();
    const std::size_t count = samples.size();
    std::vector<double> inputs = samples.first_order;  // angle-major
    for (std::size_t j = 0; j < count; j += 7) {
      for (std::size_t r = 2 + 2 * z; r < width; ++r) inputs[j * width + r] *= 1e3;
    }
    for (std::size_t j = 3; j < count; j += 11) {
      for (std::size_t i = 0; i < z; ++i) inputs[j * width + 2 + z + i] *= 10.0;
    }
    const std::size_t stride_rows = count + 3;
    std::vector<double> block(width * stride_rows);
    for (std::size_t j = 0; j < count; ++j) {
      for (std::size_t f = 0; f < width; ++f) block[f * stride_rows + j] = inputs[j * width + f];
    }
    const std::size_t outputs = 3 + 2 * z;
    for (const std::size_t size : {std::size_t{1}, std::size_t{3}, count}) {
      std::vector<double> out(outputs * stride_rows, std::numeric_limits<double>::quiet_NaN());
      for (std::size_t from = 0; from < count; from += size) {
        const std::size_t n = std::min(size, count - from);
        terms.AtEach({block.data() + from, stride_rows, n}, {out.data() + from, stride_rows});
      }
      solvers::SecondOrderAngle at;
      for (std::size_t j = 0; j < count; ++j) {
        terms.At(AngleAt(inputs.data() + j * width, z), at);
        const auto expect_bits = [&](std::size_t row, double expected) {
          EXPECT_EQ(Bits(out[row * stride_rows + j]), Bits(expected))
              << c.rollers << " rollers, block " << size << ", angle " << j << ", row " << row << ": "
              << out[row * stride_rows + j] << " against " << expected;
        };
        expect_bits(0, at.centre.x());
        expect_bits(1, at.centre.y());
        for (std::size_t i = 0; i < z; ++i) {
          expect_bits(2 + i, at.travel[i]);
          expect_bits(2 + z + i, at.contact_force[i]);
        }
        expect_bits(2 + 2 * z, at.remainder);
        if (size == count) ++(std::isfinite(at.remainder) ? finite : infinite);
      }
    }
    solvers::SecondOrderAngle at;
    for (std::size_t j = 0; j < count; ++j) {
      const double* first = samples.first_order.data() + j * width;
      terms.At(AngleAt(first, z), at);
      EXPECT_EQ(Bits(samples.centre[j].x()), Bits(first[0] + at.centre.x())) << j;
      EXPECT_EQ(Bits(samples.centre[j].y()), Bits(first[1] + at.centre.y())) << j;
      EXPECT_EQ(Bits(samples.remainder[j]), Bits(at.remainder)) << j;
      for (std::size_t i = 0; i < z; ++i) {
        EXPECT_EQ(Bits(samples.travel[j * z + i]), Bits(first[2 + i] + at.travel[i])) << j;
        EXPECT_EQ(Bits(samples.contact_force[j * z + i]), Bits(first[2 + z + i] + at.contact_force[i])) << j;
      }
    }
  }
  // Both kinds of lane were met.
  EXPECT_GT(finite, 0);
  EXPECT_GT(infinite, 0);
}

// For the article's exponent e = 1.5 the remainder's x^(e-3) is 1 / (x sqrt(x)) instead of
// pow(x, -1.5): sqrt, the product and the quotient each round within half an ulp, pow
// within about one, so the two differ by at most ~2.5 ulp; allowed 4 ulp, over the
// penetrations [m] any contact law studied reaches.
TEST(SecondOrderTerms, ArticleLawsPowerIsPowsToRoundOff) {
  constexpr double kRoundOff = 4.0 * std::numeric_limits<double>::epsilon();  // [-] relative
  std::mt19937_64 random(15);
  std::uniform_real_distribution<double> decade(-10.0, -3.0);
  for (int n = 0; n < 100000; ++n) {
    const double x = std::pow(10.0, decade(random));
    const double power = std::pow(x, -1.5);
    EXPECT_NEAR(1.0 / (x * std::sqrt(x)), power, kRoundOff * power) << x;
  }
}

// Once a thread has called them, At, AtEach and Over allocate nothing for a scene of up to
// eight rollers (Over's per-contact intervals live on the stack).
TEST(SecondOrderTerms, AllocateNothingOnceWarmUpToEightRollers) {
  std::mt19937_64 random(8);
  const solvers::LinearSolver solver;
  for (const std::size_t rollers : {std::size_t{3}, std::size_t{8}}) {
    const engine::Scene scene = SceneOf({rollers, Law::kPenalty, 1.5, 1.0}, random);
    solvers::LinearPath path = solver.Path(scene, 3200);
    ASSERT_EQ(path.status(), solvers::Status::kOk) << path.message();
    solvers::LinearPath::Samples samples;
    path.EvaluateCoarse(8, samples);
    const solvers::LinearPath::Straying straying = path.StrayingAt(2.0 * std::numbers::pi * 8 / 3200);
    solvers::FirstOrderRange range;
    path.RangeOver(samples, 0, 4, straying, range);
    const solvers::SecondOrderTerms& terms = path.second_order();
    const std::size_t width = path.FirstOrderWidth();
    std::vector<double> block(width * samples.size());
    for (std::size_t j = 0; j < samples.size(); ++j) {
      for (std::size_t f = 0; f < width; ++f) block[f * samples.size() + j] = samples.first_order[j * width + f];
    }
    std::vector<double> out((3 + 2 * rollers) * samples.size());
    solvers::SecondOrderAngle at;
    solvers::SecondOrderRange over;
    const solvers::FirstOrderAngle first = AngleAt(samples.first_order.data(), rollers);
    const auto call_each = [&] {
      terms.At(first, at);
      terms.AtEach({block.data(), samples.size(), samples.size()}, {out.data(), samples.size()});
      terms.Over(range, over);
    };
    call_each();  // warm: the outputs' and the thread's buffers take their sizes
    allocations = 0;
    counting = true;
    call_each();
    counting = false;
    EXPECT_EQ(allocations, 0) << rollers << " rollers";
    EXPECT_TRUE(std::isfinite(over.centre));
  }
}

}  // namespace
}  // namespace ringtol
