// The user manual's list of outputs (docs/usage.md, "Outputs") against the outputs a
// campaign stores: a user who reads only README and docs/ meets every column there, with
// where its definition is.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "jobs/campaign/sample_record.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

using ::testing::HasSubstr;

std::string OutputsSection() {
  const std::string usage = ringtol::testing::ReadText(std::filesystem::path(RINGTOL_SOURCE_DIR) / "docs/usage.md");
  const std::size_t begin = usage.find("\n## Outputs");
  if (begin == std::string::npos) return "";
  return usage.substr(begin, usage.find("\n## ", begin + 1) - begin);
}

TEST(UsageOutputs, NamesEveryOutputAndPointsToTheDefinitionOfTheLifeAndErrorMotion) {
  const std::string outputs = OutputsSection();
  ASSERT_FALSE(outputs.empty());
  for (const char* name : kOutputNames) EXPECT_THAT(outputs, HasSubstr(std::string("`") + name + "`")) << name;
  EXPECT_THAT(outputs, HasSubstr("model.md#9-over-the-stages-life-many-revolutions-and-iso-230-7-error-motion"));
}

}  // namespace
}  // namespace ringtol::jobs
