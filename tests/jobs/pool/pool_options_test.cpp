#include "jobs/pool/pool.h"

#include <limits>

#include <gtest/gtest.h>

#include "tests/support/invalid_options.h"

namespace ringtol::jobs {
namespace {

using testing::ExpectEachRefusedByName;

TEST(PoolOptions, DefaultsAreValid) {
  InvalidOption invalid;
  EXPECT_TRUE(PoolOptions{}.IsValid(&invalid));
  EXPECT_EQ(invalid.field, "");  // left as it was
}

// Each field one step outside its range, the test hooks' too, is refused under its name.
TEST(PoolOptions, EachFieldOutsideItsRangeIsRefusedNamingTheField) {
  ExpectEachRefusedByName<PoolOptions>({
      {"chunk_samples", [](PoolOptions& o) { o.chunk_samples = -1; }},
      {"align_samples", [](PoolOptions& o) { o.align_samples = -1; }},
      {"chunk_seconds", [](PoolOptions& o) { o.chunk_seconds = 0.0; }},
      {"chunk_seconds", [](PoolOptions& o) { o.chunk_seconds = std::numeric_limits<double>::quiet_NaN(); }},
      {"commit_seconds", [](PoolOptions& o) { o.commit_seconds = -0.5; }},
      {"coordinator_computes", [](PoolOptions& o) { o.coordinator_computes = 2; }},
      {"coordinator_computes", [](PoolOptions& o) { o.coordinator_computes = -2; }},
      {"threads", [](PoolOptions& o) { o.threads = 4097; }},
      {"threads", [](PoolOptions& o) { o.threads = -1; }},
      {"testing.kill_after_committed", [](PoolOptions& o) { o.testing.kill_after_committed = -2; }},
      {"testing.kill_rank", [](PoolOptions& o) { o.testing.kill_rank = -2; }},
      {"testing.sample_seconds", [](PoolOptions& o) { o.testing.sample_seconds = -1e-6; }},
  });
}

// Callers word the range by its kind: an integer field's as integers.
TEST(PoolOptions, ReportsWhetherTheFieldIsAnInteger) {
  PoolOptions options;
  options.threads = 5000;
  InvalidOption invalid;
  ASSERT_FALSE(options.IsValid(&invalid));
  EXPECT_TRUE(invalid.integer);
  EXPECT_EQ(invalid.value, 5000.0);
  options = {};
  options.chunk_seconds = -1.0;
  ASSERT_FALSE(options.IsValid(&invalid));
  EXPECT_FALSE(invalid.integer);
}

}  // namespace
}  // namespace ringtol::jobs
