#include <gtest/gtest.h>

#include <memory>
#include <utility>

#include "solvers/nominal_cache.h"
#include "tests/support/paper_scene.h"

namespace ringtol {
namespace {

struct Entry {
  engine::Scene perfect;
  int number = 0;  // which computation made it
};

// A cache whose computations count themselves.
struct CountingCache {
  solvers::NominalCache<Entry> cache;
  int computed = 0;
  std::shared_ptr<const Entry> Get(const engine::Scene& scene) {
    return cache.Get(scene, [this](engine::Scene perfect) {
      return std::make_shared<const Entry>(Entry{std::move(perfect), ++computed});
    });
  }
};

TEST(NominalCache, ComputesOnceForScenesThatDifferOnlyInTheirErrors) {
  CountingCache cache;
  const engine::Scene scene = testing::CampaignLikeScene();
  const std::shared_ptr<const Entry> first = cache.Get(scene);
  EXPECT_EQ(first->perfect, engine::WithoutErrors(scene));
  engine::Scene other = scene;
  testing::SetRing(other, {{2, 30e-6, 1.0}});
  other.rollers[2].radial_offset = -4e-6;
  EXPECT_EQ(cache.Get(other), first);
  EXPECT_EQ(cache.Get(engine::WithoutErrors(scene)), first);
  EXPECT_EQ(cache.computed, 1);
}

TEST(NominalCache, ComputesAgainWhenTheSceneWithoutErrorsChanges) {
  CountingCache cache;
  const engine::Scene scene = testing::CampaignLikeScene();
  cache.Get(scene);
  engine::Scene heavier = scene;
  heavier.ring.mass *= 2.0;
  const std::shared_ptr<const Entry> second = cache.Get(heavier);
  EXPECT_EQ(cache.computed, 2);
  EXPECT_EQ(second->perfect, engine::WithoutErrors(heavier));
  EXPECT_EQ(cache.Get(scene)->number, 3) << "one entry: the last one computed";
}

}  // namespace
}  // namespace ringtol
