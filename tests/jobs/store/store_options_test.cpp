#include <cstdint>
#include <limits>

#include <gtest/gtest.h>

#include "jobs/store/campaign_store.h"
#include "tests/support/invalid_options.h"

namespace ringtol::jobs {
namespace {

using testing::ExpectEachRefusedByName;

TEST(CampaignStoreOptions, DefaultsAndStoringEveryInputAreValid) {
  EXPECT_TRUE(CampaignStoreOptions{}.IsValid());
  CampaignStoreOptions every;
  every.inputs_stored_below = std::numeric_limits<std::int64_t>::max();  // --store-inputs
  EXPECT_TRUE(every.IsValid());
}

TEST(CampaignStoreOptions, EachFieldOutsideItsRangeIsRefusedNamingTheField) {
  ExpectEachRefusedByName<CampaignStoreOptions>({
      {"deflate_level", [](CampaignStoreOptions& o) { o.deflate_level = 10; }},
      {"deflate_level", [](CampaignStoreOptions& o) { o.deflate_level = -1; }},
      {"chunk_samples", [](CampaignStoreOptions& o) { o.chunk_samples = -1; }},
      {"inputs_stored_below", [](CampaignStoreOptions& o) { o.inputs_stored_below = -1; }},
  });
}

}  // namespace
}  // namespace ringtol::jobs
