#include "sampling/assembly_sampler.h"

#include <boost/math/special_functions/erf.hpp>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <vector>

#include "tests/support/paper_scene.h"
#include "tests/support/statistics.h"

namespace ringtol::sampling {
namespace {

using ::testing::HasSubstr;

constexpr double kUm = 1e-6;
// Values are recorded in um and degrees from the SI numbers put in the scene: one
// multiplication apart, so they agree to a few ulps.
constexpr double kRecordTolerance = 1e-12;

AssemblyTolerances Everything(Capability capability, int rollers) {
  AssemblyTolerances t;
  t.ring = RingFormTolerance{"", 200 * kUm, {2, 12, 1.0, {}}, capability};
  RollerShapeTolerance shape{"", 15 * kUm, 10 * kUm, -8 * kUm, 0.0, {2, 4, 1.0, {}}, capability};
  for (int i = 0; i < rollers; ++i) {
    t.roller_shapes.push_back(shape);
    t.roller_positions.push_back(PositionTolerance{"", 50 * kUm, capability});
    t.springs.push_back(i == 0 ? std::optional(SpringTolerance{"", 0.1, 0.1, capability}) : std::nullopt);
  }
  return t;
}

AssemblySamplerOptions Fast() {
  AssemblySamplerOptions options;
  options.calibration.min_draws = 4096;
  return options;
}

TEST(AssemblySampler, NamesEveryCoordinateAndGroupsThemBySourceAndOrder) {
  const engine::Scene scene = testing::PaperScene();
  const AssemblySampler sampler(scene, Everything({}, 3), Fast());
  // ring 11 orders x 2; per roller: eccentricity 2 + 3 form orders x 2 + size 1 + position 2;
  // one spring: 2.
  EXPECT_EQ(sampler.dimension(), 22 + 3 * (2 + 6 + 1 + 2) + 2);
  EXPECT_EQ(sampler.inputs().front().name, "ring.order2.amplitude_um");
  const InputGroups sources = sampler.Groups(InputGrouping::kSource);
  EXPECT_EQ(sources.names, (std::vector<std::string>{"ring_shape", "roller_shape", "roller_position", "spring"}));
  const InputGroups orders = sampler.Groups(InputGrouping::kOrder);
  // order 2 gathers the ring's and the three rollers' order-2 amplitude and phase.
  EXPECT_EQ(orders.names.front(), "order2");
  EXPECT_EQ(orders.coordinates.front().size(), 8u);
  std::size_t total = 0;
  for (const auto& g : sampler.Groups(InputGrouping::kQuantity).coordinates) total += g.size();
  EXPECT_EQ(total, static_cast<std::size_t>(sampler.dimension()));
}

TEST(AssemblySampler, RealisedSceneCarriesExactlyTheRecordedDraws) {
  engine::Scene scene = testing::PaperScene();
  testing::SetRing(scene, {{3, 10 * kUm, 0.0}});
  const AssemblySampler sampler(scene, Everything({}, 3), Fast());
  Design design(sampler.dimension(), {});
  const SampledAssembly a = sampler.Sample(design, 17);
  const auto& inputs = sampler.inputs();
  // The base scene's order-3 error stays, the drawn order 3 adds to it.
  double drawn3 = 0.0, drawn3_phase = 0.0;
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    if (inputs[k].name == "ring.order3.amplitude_um") drawn3 = a.values[k] * kUm;
    if (inputs[k].name == "ring.order3.phase_deg") drawn3_phase = a.values[k] * std::numbers::pi / 180;
  }
  const engine::PolarProfile& ring = a.scene.ring.inner;
  EXPECT_NEAR(ring.cos_coefficient(3), 10 * kUm + drawn3 * std::cos(drawn3_phase), kRecordTolerance * kUm);
  EXPECT_NEAR(ring.sin_coefficient(3), drawn3 * std::sin(drawn3_phase), kRecordTolerance * kUm);
  // Position offsets and spring deviations land on the right roller.
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    if (inputs[k].name == "roller.spring.spring.stiffness_deviation_percent") {
      EXPECT_NEAR(a.scene.rollers[0].spring.stiffness / scene.rollers[0].spring.stiffness - 1, a.values[k] / 100,
                  kRecordTolerance);
    }
    if (inputs[k].name == "roller.fixed_a.position.offset_um") {
      const engine::Roller& r = a.scene.rollers[1];
      EXPECT_NEAR(std::hypot(r.radial_offset, r.tangential_offset), a.values[k] * kUm, kRecordTolerance * kUm);
    }
  }
  EXPECT_EQ(a.scene.rollers[1].spring, scene.rollers[1].spring);  // a fixed roller has no spring draw
}

TEST(AssemblySampler, SampleIReplaysAloneBitForBit) {
  const AssemblySampler sampler(testing::PaperScene(), Everything({ToleranceMode::kInspected, 0.5}, 3), Fast());
  DesignOptions options;
  options.kind = DesignKind::kSobol;
  options.seed = 3;
  Design forward(sampler.dimension(), options);
  std::vector<SampledAssembly> first;
  for (int i = 0; i < 16; ++i) first.push_back(sampler.Sample(forward, i));
  Design alone(sampler.dimension(), options);
  for (int i = 15; i >= 0; --i) {
    const SampledAssembly again = sampler.Sample(alone, i);
    EXPECT_EQ(again.scene, first[static_cast<std::size_t>(i)].scene) << i;
    EXPECT_EQ(again.values, first[static_cast<std::size_t>(i)].values) << i;
  }
}

TEST(CalibrationCache, SamplersSharingItCalibrateEachClassOnceAndDrawTheSameAssemblies) {
  const engine::Scene scene = testing::PaperScene();
  const AssemblyTolerances loose = Everything({}, 3);
  AssemblyTolerances tight = loose;
  tight.ring->circularity /= 2;
  AssemblySamplerOptions shared = Fast();
  shared.calibrations = std::make_shared<CalibrationCache>();
  const AssemblySampler alone(scene, tight, Fast());
  const AssemblySampler first(scene, loose, shared);
  // The ring and the (shared) roller shape class.
  EXPECT_EQ(shared.calibrations->size(), 2u);
  const AssemblySampler second(scene, tight, shared);
  // Only the tighter ring is new: the rollers' class comes from the cache.
  EXPECT_EQ(shared.calibrations->size(), 3u);
  std::vector<double> u(static_cast<std::size_t>(alone.dimension()), 0.3);
  EXPECT_EQ(second.Realise(7, u).scene, alone.Realise(7, u).scene);
}

TEST(AssemblySampler, InspectedPartsAllMeetTheirTolerances) {
  // Cp = 0.5 puts 13 % of parts outside: inspection must reject and redraw every one.
  const AssemblySampler sampler(testing::PaperScene(), Everything({ToleranceMode::kInspected, 0.5}, 3), Fast());
  Design design(sampler.dimension(), {});
  int redraws = 0;
  for (int i = 0; i < 200; ++i) {
    const SampledAssembly a = sampler.Sample(design, i);
    redraws += a.redraws;
    EXPECT_LE(MeasureForm(FormMeasure::kRoundness, a.scene.ring.inner.harmonics()), 200 * kUm);
    for (const engine::Roller& r : a.scene.rollers) {
      std::vector<engine::Harmonic> form;
      double eccentricity = 0.0;
      for (const auto& h : r.outline.harmonics()) {
        if (h.order == 1) eccentricity = h.amplitude;
        form.push_back(h);
      }
      EXPECT_LE(2 * eccentricity, 15 * kUm);
      EXPECT_LE(MeasureForm(FormMeasure::kTwoPointVariation, form), 10 * kUm);
      EXPECT_LE(2 * r.outline.mean_deviation(), 0.0);
      EXPECT_GE(2 * r.outline.mean_deviation(), -8 * kUm);
      EXPECT_LE(std::hypot(r.radial_offset, r.tangential_offset), 25 * kUm);
    }
  }
  EXPECT_GT(redraws, 0);
}

TEST(AssemblySampler, BoundedInspectionDrawsTheAssembliesOfTheExactMeasure) {
  // The catalogue's loosest and tightest classes, every part inspected: ring ISO2768-L (RONt
  // 0.5 mm) and IT5/2 at 250-315 mm (11.5 um), rollers Normal and 2 at D 6-18 mm (Kea 15 and
  // 1.5 um, VDsp 10 and 2.5 um, mean diameter -8 and -2.5 um), with their default spectra. At
  // Cp 0.3 a third of the rings and rollers are redrawn, at Cp 1 a few: judged by bounds or by
  // the exact measure, the same parts must pass, so every assembly, value and redraw count is
  // the same bits.
  struct Classes {
    double ring, kea, vdsp, mean_lower;
  };
  int redraws = 0;
  for (const Classes& c : {Classes{500 * kUm, 15 * kUm, 10 * kUm, -8 * kUm},
                           Classes{11.5 * kUm, 1.5 * kUm, 2.5 * kUm, -2.5 * kUm}}) {
    for (const double cp : {0.3, 1.0}) {
      const Capability inspected{ToleranceMode::kInspected, cp};
      AssemblyTolerances t;
      t.ring = RingFormTolerance{"", c.ring, {}, inspected};
      t.roller_shapes.assign(
          3, RollerShapeTolerance{"", c.kea, c.vdsp, c.mean_lower, 0.0, {2, 8, 1.0, {}}, inspected});
      AssemblySamplerOptions exact = Fast();
      exact.exact_form_inspection = true;
      const AssemblySampler bounded_sampler(testing::PaperScene(), t, Fast());
      const AssemblySampler exact_sampler(testing::PaperScene(), t, exact);
      Design design(bounded_sampler.dimension(), {});
      for (int i = 0; i < 300; ++i) {
        const SampledAssembly a = bounded_sampler.Sample(design, i);
        const SampledAssembly b = exact_sampler.Sample(design, i);
        ASSERT_EQ(a.redraws, b.redraws) << i;
        ASSERT_EQ(a.u, b.u) << i;
        ASSERT_EQ(a.values, b.values) << i;
        ASSERT_EQ(a.scene, b.scene) << i;
        redraws += a.redraws;
      }
    }
  }
  EXPECT_GT(redraws, 300);  // the limits were crossed often, not only in principle
}

TEST(AssemblySampler, ProcessPartsMeetTheirToleranceAtTheStatedCoverage) {
  // Positions are exact Rayleigh draws: P(2|offset| <= zone) = erf(3 Cp / sqrt 2). With
  // Cp = 0.5 that is 86.6 %; binomial z-test over 3 x 4000 offsets at significance 1e-3.
  const Capability cp{ToleranceMode::kProcess, 0.5};
  AssemblyTolerances t;
  t.roller_positions.assign(3, PositionTolerance{"", 50 * kUm, cp});
  const AssemblySampler sampler(testing::PaperScene(), t, Fast());
  Design design(sampler.dimension(), {});
  int inside = 0, total = 0;
  for (int i = 0; i < 4000; ++i) {
    for (const engine::Roller& r : sampler.Sample(design, i).scene.rollers) {
      inside += 2 * std::hypot(r.radial_offset, r.tangential_offset) <= 50 * kUm;
      ++total;
    }
  }
  const double p = cp.Coverage(), f = static_cast<double>(inside) / total;
  EXPECT_LT(std::abs(f - p) / std::sqrt(p * (1 - p) / total), testing::TwoSidedNormalQuantile(1e-3));
}

TEST(AssemblySampler, RefusesTolerancesItCannotDraw) {
  const engine::Scene scene = testing::PaperScene();
  AssemblyTolerances spring_on_fixed;
  spring_on_fixed.springs = {std::nullopt, SpringTolerance{"", 0.1, 0.1, {}}, std::nullopt};
  EXPECT_THAT([&] { AssemblySampler(scene, spring_on_fixed, Fast()); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("spring rollers only")));
  AssemblyTolerances low_cutoff;
  low_cutoff.ring = RingFormTolerance{"", 100 * kUm, {2, 1, 1.0, {}}, {}};
  EXPECT_THAT([&] { AssemblySampler(scene, low_cutoff, Fast()); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("cutoff 1 is below")));
  AssemblyTolerances negative;
  negative.roller_positions.assign(3, PositionTolerance{"", -1 * kUm, {}});
  EXPECT_THROW(AssemblySampler(scene, negative, Fast()), std::invalid_argument);
  AssemblyTolerances too_capable;
  too_capable.ring = RingFormTolerance{"", 100 * kUm, {2, 10, 1.0, {}}, {ToleranceMode::kProcess, 2.0}};
  EXPECT_THAT([&] { AssemblySampler(scene, too_capable, Fast()); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("<= 1.33")));
}

// ---- Populations of measured parts

double NormalQuantile(double p) { return std::numbers::sqrt2 * boost::math::erf_inv(2.0 * p - 1.0); }

MeasuredPart Part(std::string name, double mean_deviation, std::vector<engine::Harmonic> harmonics) {
  return {std::move(name), mean_deviation, std::move(harmonics)};
}

AssemblyTolerances RingsFrom(std::vector<MeasuredPart> parts, PopulationDraw draw) {
  AssemblyTolerances t;
  t.ring_population = PartPopulation{std::move(parts), draw};
  return t;
}

// Resampling: u in [k/M, (k+1)/M) takes part k, whose size and harmonics add to the base
// scene's ring, and records k.
TEST(RingPopulation, ResamplingTakesThePartTheCoordinateFallsOn) {
  engine::Scene base = testing::PaperScene();
  base.ring.inner = engine::PolarProfile(base.ring.inner.radius(), 0.0, {{5, 1 * kUm, 0.0}});
  const std::vector<MeasuredPart> parts = {Part("a.csv", 2 * kUm, {{2, 10 * kUm, 0.5}}),
                                           Part("b.csv", -3 * kUm, {{3, 20 * kUm, -1.0}}),
                                           Part("c.csv", 0.0, {{2, 7 * kUm, 0.1}, {4, 4 * kUm, 2.0}})};
  const AssemblySampler sampler(base, RingsFrom(parts, PopulationDraw::kResample));
  ASSERT_EQ(sampler.dimension(), 1);
  EXPECT_EQ(sampler.inputs()[0].name, "ring.population.part_index");
  for (const auto& [u, part] : {std::pair{0.0, 0}, {0.3333, 0}, {0.3334, 1}, {0.6667, 2}, {0.9999999, 2}}) {
    SCOPED_TRACE(u);
    const SampledAssembly drawn = sampler.Realise(0, std::vector{u});
    EXPECT_EQ(drawn.values[0], part);
    const auto p = static_cast<std::size_t>(part);
    EXPECT_EQ(drawn.scene.ring.inner.mean_deviation(), parts[p].mean_deviation);
    std::vector<engine::Harmonic> expected = {{5, 1 * kUm, 0.0}};
    expected.insert(expected.end(), parts[p].harmonics.begin(), parts[p].harmonics.end());
    EXPECT_EQ(drawn.scene.ring.inner.harmonics(), expected);
  }
}

// The model: per order, the coefficients' mean and one spread. Parts (+-1 um, 0) at order 2
// and (5, 0) and (7, 0) um at order 3 give order 2 a spread of 1 um about 0 and order 3
// a spread of 1 um about (6, 0): a coordinate at the normal's 84.13 % point draws one spread
// above the mean.
TEST(RingPopulation, TheModelDrawsEachOrdersCoefficientsAboutTheirMeanWithTheirSpread) {
  const std::vector<MeasuredPart> parts = {Part("a.csv", 1 * kUm, {{2, 1 * kUm, 0.0}, {3, 5 * kUm, 0.0}}),
                                           Part("b.csv", 3 * kUm, {{2, 1 * kUm, std::numbers::pi}, {3, 7 * kUm, 0.0}})};
  const AssemblySampler sampler(testing::PaperScene(), RingsFrom(parts, PopulationDraw::kModel));
  ASSERT_EQ(sampler.dimension(), 5);  // two orders' amplitude and phase, the size
  EXPECT_EQ(sampler.inputs()[0].name, "ring.order2.amplitude_um");
  EXPECT_EQ(sampler.inputs()[4].name, "ring.size.mean_deviation_um");
  const double one_sigma = 0.5 * (1.0 + std::erf(1.0 / std::numbers::sqrt2));
  const SampledAssembly at_means = sampler.Realise(0, std::vector{0.5, 0.5, 0.5, 0.5, 0.5});
  EXPECT_NEAR(at_means.values[0], 0.0, 1e-9);  // order 2's mean is zero
  EXPECT_NEAR(at_means.values[2], 6.0, 1e-9);
  EXPECT_NEAR(at_means.values[3], 0.0, 1e-9);
  EXPECT_NEAR(at_means.values[4], 2.0, 1e-9);
  EXPECT_NEAR(at_means.scene.ring.inner.mean_deviation(), 2 * kUm, 1e-15);
  const SampledAssembly above = sampler.Realise(0, std::vector{one_sigma, 0.5, 0.5, one_sigma, one_sigma});
  EXPECT_NEAR(above.values[0], 1.0, 1e-9);   // (1, 0) um: amplitude 1, phase 0
  EXPECT_NEAR(above.values[1], 0.0, 1e-9);
  EXPECT_NEAR(above.values[2], std::hypot(6.0, 1.0), 1e-9);  // (6, 1) um
  EXPECT_NEAR(above.values[3], std::atan2(1.0, 6.0) * 180.0 / std::numbers::pi, 1e-9);
  EXPECT_NEAR(above.values[4], 2.0 + std::sqrt(2.0), 1e-9);  // sizes 1 and 3 um: spread sqrt 2
}

// Fitted to many parts drawn from a known law, the model draws that law: the mean and spread
// of the drawn coefficients approach the law's, within their sampling error.
TEST(RingPopulation, AModelFittedToManyPartsOfAKnownLawDrawsThatLaw) {
  constexpr int kParts = 4000;
  constexpr double kMean = 15 * kUm, kSpread = 4 * kUm;
  std::vector<MeasuredPart> parts;
  for (int k = 0; k < kParts; ++k) {
    const double a = kMean + kSpread * NormalQuantile((k + 0.5) / kParts);
    const double b = kSpread * NormalQuantile(std::fmod((k * 0.6180339887498949) + 0.5 / kParts, 1.0));
    parts.push_back(Part("p.csv", 0.0, {{3, std::hypot(a, b), std::atan2(b, a)}}));
  }
  const AssemblySampler sampler(testing::PaperScene(), RingsFrom(parts, PopulationDraw::kModel));
  ASSERT_EQ(sampler.dimension(), 2);  // no size: every part's is 0
  double sum_a = 0.0, sum_b = 0.0, squares = 0.0;
  constexpr int kDraws = 4000;
  for (int k = 0; k < kDraws; ++k) {
    const std::vector<double> u = {(k + 0.5) / kDraws, std::fmod(k * 0.7548776662466927 + 0.5 / kDraws, 1.0)};
    const engine::Harmonic h = sampler.Realise(k, u).scene.ring.inner.harmonics().front();
    const double a = h.amplitude * std::cos(h.phase), b = h.amplitude * std::sin(h.phase);
    sum_a += a;
    sum_b += b;
    squares += (a - kMean) * (a - kMean) + b * b;
  }
  EXPECT_NEAR(sum_a / kDraws, kMean, 0.1 * kUm);
  EXPECT_NEAR(sum_b / kDraws, 0.0, 0.1 * kUm);
  EXPECT_NEAR(std::sqrt(squares / (2.0 * kDraws)), kSpread, 0.1 * kUm);
}

// A batch of rollers is resampled without replacement, as a fitter takes rollers off the
// bench: the i-th roller of the scene takes, among the parts still left in list order, the
// one its coordinate falls on; no two rollers of an assembly are the same part.
TEST(RollerPopulation, ResamplingTakesEachPartOnceInAnAssembly) {
  const engine::Scene base = testing::PaperScene();  // spring, fixed_a, fixed_b
  std::vector<MeasuredPart> batch;
  for (int k = 0; k < 4; ++k) batch.push_back(Part("r" + std::to_string(k) + ".csv", -1e-6 * k, {{2 + k, 1e-6, 0.0}}));
  AssemblyTolerances t;
  t.roller_population = PartPopulation{batch, PopulationDraw::kResample};
  const AssemblySampler sampler(base, t);
  ASSERT_EQ(sampler.dimension(), 3);
  EXPECT_EQ(sampler.inputs()[1].name, "roller.fixed_a.population.part_index");
  const auto taken = [&](std::vector<double> u) {
    const SampledAssembly drawn = sampler.Realise(0, u);
    for (std::size_t i = 0; i < 3; ++i) {
      const auto part = static_cast<std::size_t>(drawn.values[i]);
      EXPECT_EQ(drawn.scene.rollers[i].outline.harmonics(), batch[part].harmonics) << "roller " << i;
      EXPECT_EQ(drawn.scene.rollers[i].outline.mean_deviation(), batch[part].mean_deviation) << "roller " << i;
    }
    return drawn.values;
  };
  EXPECT_EQ(taken({0.0, 0.0, 0.0}), (std::vector<double>{0, 1, 2}));
  EXPECT_EQ(taken({0.99, 0.99, 0.99}), (std::vector<double>{3, 2, 1}));
  EXPECT_EQ(taken({0.5, 0.5, 0.5}), (std::vector<double>{2, 1, 3}));  // of 4: the third; of 0, 1, 3: 1; of 0, 3: 3
  for (int k = 0; k < 64; ++k) {
    const std::vector<double> values = taken({(k + 0.5) / 64.0, std::fmod(k * 0.618034, 1.0), std::fmod(k * 0.414214, 1.0)});
    EXPECT_NE(values[0], values[1]);
    EXPECT_NE(values[0], values[2]);
    EXPECT_NE(values[1], values[2]);
  }
  // A roller model draws each roller on its own, named as the class's draws are.
  t.roller_population->draw = PopulationDraw::kModel;
  const AssemblySampler model(base, t);
  EXPECT_EQ(model.inputs().front().name, "roller.spring.order2.amplitude_um");
  EXPECT_EQ(model.inputs().back().name, "roller.fixed_b.size.mean_diameter_deviation_um");
  t.roller_population->parts.resize(2);
  t.roller_population->draw = PopulationDraw::kResample;
  EXPECT_THAT([&] { AssemblySampler(base, t); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("2 parts for 3 rollers")));
}

// A batch may fill some rollers only (batch_rollers): the others keep the scene's outline
// (a measured roller judged against the batch) or their class's draw, and the filled ones
// take distinct parts in the order listed; a roller both drawn and filled is refused.
TEST(RollerPopulation, ABatchFillsOnlyTheRollersItIsGiven) {
  engine::Scene base = testing::PaperScene();  // spring, fixed_a, fixed_b
  base.rollers[1].outline = engine::PolarProfile(base.rollers[1].outline.radius(), 0.0, {{3, 2e-6, 0.5}});
  std::vector<MeasuredPart> batch;
  for (int k = 0; k < 3; ++k) batch.push_back(Part("r" + std::to_string(k) + ".csv", -1e-6 * k, {{2 + k, 1e-6, 0.0}}));
  AssemblyTolerances t;
  t.roller_population = PartPopulation{batch, PopulationDraw::kResample};
  t.batch_rollers = {0, 2};
  const AssemblySampler sampler(base, t);
  ASSERT_EQ(sampler.dimension(), 2);
  EXPECT_EQ(sampler.inputs()[0].name, "roller.spring.population.part_index");
  EXPECT_EQ(sampler.inputs()[1].name, "roller.fixed_b.population.part_index");
  for (int k = 0; k < 16; ++k) {
    const SampledAssembly drawn = sampler.Realise(k, std::vector<double>{(k + 0.5) / 16.0, std::fmod(k * 0.618034, 1.0)});
    const auto spring = static_cast<std::size_t>(drawn.values[0]);
    const auto fixed_b = static_cast<std::size_t>(drawn.values[1]);
    EXPECT_NE(spring, fixed_b);
    EXPECT_EQ(drawn.scene.rollers[0].outline.harmonics(), batch[spring].harmonics);
    EXPECT_EQ(drawn.scene.rollers[2].outline.harmonics(), batch[fixed_b].harmonics);
    EXPECT_EQ(drawn.scene.rollers[1].outline.harmonics(), base.rollers[1].outline.harmonics());
    const std::array<std::size_t, 2> rollers = {0, 2};
    const std::array<std::size_t, 2> parts = {spring, fixed_b};
    EXPECT_EQ(WithRollerParts(base, *t.roller_population, rollers, parts).rollers[2].outline.mean_deviation(),
              drawn.scene.rollers[2].outline.mean_deviation());
  }
  EXPECT_EQ(BatchRollers(t, 3), (std::vector<std::size_t>{0, 2}));
  EXPECT_EQ(BatchRollers(AssemblyTolerances(), 3), (std::vector<std::size_t>{0, 1, 2}));
  AssemblyTolerances overlapping = t;
  overlapping.roller_shapes = {RollerShapeTolerance{"", 5 * kUm, 0.0, 0.0, 0.0, {}, {}}, std::nullopt, std::nullopt};
  EXPECT_THAT([&] { AssemblySampler(base, overlapping); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("roller spring has a shape tolerance")));
  AssemblyTolerances disjoint = overlapping;
  disjoint.batch_rollers = {1, 2};
  EXPECT_EQ(AssemblySampler(base, disjoint).dimension(), 2 + 2);  // the spring's eccentricity, and two parts
  AssemblyTolerances unsorted = t;
  unsorted.batch_rollers = {2, 0};
  EXPECT_THAT([&] { AssemblySampler(base, unsorted); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("ascending")));
}

TEST(RingPopulation, IsRefusedBesideARingToleranceWithoutPartsOrWithOnePartToModel) {
  AssemblyTolerances both = RingsFrom({Part("a.csv", 0.0, {})}, PopulationDraw::kResample);
  both.ring = RingFormTolerance{"", 200 * kUm, {2, 12, 1.0, {}}, {}};
  EXPECT_THAT([&] { AssemblySampler(testing::PaperScene(), both, Fast()); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("draw it from one")));
  EXPECT_THAT([] { AssemblySampler(testing::PaperScene(), RingsFrom({}, PopulationDraw::kResample)); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("no parts")));
  EXPECT_THAT([] { AssemblySampler(testing::PaperScene(), RingsFrom({Part("a.csv", 0.0, {})}, PopulationDraw::kModel)); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("at least 2 parts")));
}

}  // namespace
}  // namespace ringtol::sampling
