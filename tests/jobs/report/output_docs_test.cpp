// The manual's tables of outputs against the outputs table (kOutputs,
// jobs/campaign/sample_record.h): docs/results.md's /outputs datasets, docs/usage.md's
// "What a sample gives" and docs/inputs.md's [spec] keys and allocation constraints each
// list exactly its outputs, in its order, with its units where they state one. An output
// added, renamed, reordered or re-united in the table fails here until the manual says so.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <functional>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "jobs/campaign/sample_record.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

using ::testing::ElementsAreArray;
using ::testing::HasSubstr;

std::string Doc(std::string_view name) {
  return ringtol::testing::ReadText(std::filesystem::path(RINGTOL_SOURCE_DIR) / "docs" / name);
}

// The lines from the heading that starts with `heading` to the next heading of its level or
// above (outside code blocks, whose "# file.toml" lines are no headings); empty when there
// is none.
std::string Section(const std::string& doc, std::string_view heading) {
  const std::size_t level = heading.find(' ');  // its number of '#'
  std::istringstream in(doc);
  std::string line, section;
  bool inside = false, code = false;
  while (std::getline(in, line)) {
    if (line.starts_with("```")) code = !code;
    if (!code && line.starts_with("#")) {
      if (line.starts_with(heading)) {
        inside = true;
      } else if (inside && line.find_first_not_of('#') <= level) {
        break;
      }
    }
    if (inside) section += line + "\n";
  }
  return section;
}

// The cells of each row ("| a | b |") of the tables in `text`, header and rule rows left out.
std::vector<std::vector<std::string>> Rows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  std::string line;
  bool header = false;
  while (std::getline(in, line)) {
    if (!line.starts_with("|")) {
      header = false;
      continue;
    }
    if (!header) {  // a table's first row is its header
      header = true;
      continue;
    }
    if (line.starts_with("|---")) continue;
    std::vector<std::string> cells;
    std::size_t from = 1;
    for (std::size_t bar = line.find('|', from); bar != std::string::npos; bar = line.find('|', from)) {
      std::string cell = line.substr(from, bar - from);
      cell.erase(0, cell.find_first_not_of(' '));
      cell.erase(cell.find_last_not_of(' ') + 1);
      cells.push_back(cell);
      from = bar + 1;
    }
    rows.push_back(cells);
  }
  return rows;
}

// The text between each pair of `quote` in `cell`: the names "`a`, `b`" -> a, b.
std::vector<std::string> Quoted(const std::string& cell, char quote = '`') {
  std::vector<std::string> names;
  for (std::size_t open = cell.find(quote); open != std::string::npos; open = cell.find(quote, open + 1)) {
    const std::size_t close = cell.find(quote, open + 1);
    if (close == std::string::npos) break;
    names.push_back(cell.substr(open + 1, close - open - 1));
    open = close;
  }
  return names;
}

std::vector<std::string> TableNames() { return {kOutputNames.begin(), kOutputNames.end()}; }

// The outputs' units, each once, in the table's order.
std::vector<std::string> TableUnits() {
  std::vector<std::string> units;
  for (const OutputDescription& output : kOutputs) {
    if (std::find(units.begin(), units.end(), output.unit) == units.end()) units.emplace_back(output.unit);
  }
  return units;
}

// The datasets of docs/results.md's /outputs and /timing table that are not outputs of the
// table: what the store keeps of each sample besides (jobs/store/campaign_store.h).
const std::set<std::string, std::less<>> kOtherDatasets = {"steps", "rung", "d_trajectory_error_mm", "off_bore_percent",
                                                            "status", "/timing/solve_time_s"};

TEST(OutputDocs, ResultsListsEveryOutputDatasetInTheTablesOrderWithItsUnit) {
  const std::string section = Section(Doc("results.md"), "### `/outputs` and `/timing`");
  ASSERT_FALSE(section.empty()) << "docs/results.md has no section \"`/outputs` and `/timing`\"";
  std::vector<std::string> names;
  for (const std::vector<std::string>& row : Rows(section)) {
    ASSERT_GE(row.size(), 3u);
    const std::vector<std::string> quoted = Quoted(row[0]);
    ASSERT_EQ(quoted.size(), 1u) << row[0];
    if (kOtherDatasets.contains(quoted[0])) continue;
    names.push_back(quoted[0]);
    const std::size_t output = OutputIndex(quoted[0]);
    if (output < kOutputCount) {
      EXPECT_EQ(row[2], kOutputs[output].unit) << "the unit of " << quoted[0];
    }
  }
  EXPECT_THAT(names, ElementsAreArray(TableNames()))
      << "docs/results.md's /outputs rows (besides the store's own datasets: steps, rung, ...)";
}

// docs/usage.md's "What a sample gives" names every output, a row for one or a few, in the
// table's order, and says where the life and the error motion are defined.
TEST(OutputDocs, UsageNamesEveryOutputInTheTablesOrderAndPointsToTheDefinitionOfTheLife) {
  const std::string section = Section(Doc("usage.md"), "### What a sample gives");
  ASSERT_FALSE(section.empty()) << "docs/usage.md has no section \"What a sample gives\"";
  std::vector<std::string> names;
  for (const std::vector<std::string>& row : Rows(section)) {
    for (const std::string& name : Quoted(row.at(0))) names.push_back(name);
  }
  EXPECT_THAT(names, ElementsAreArray(TableNames()));
  EXPECT_THAT(section, HasSubstr("model.md#9-over-the-stages-life-many-revolutions-and-iso-230-7-error-motion"));
}

// docs/inputs.md: a [spec] key for every output, in the table's order; an allocation
// constraint may name every output, and has a limit key for every unit.
TEST(OutputDocs, InputsHasASpecKeyForEveryOutputAndAConstraintLimitForEveryUnit) {
  const std::string inputs = Doc("inputs.md");
  const std::string campaign = Section(inputs, "## Campaign files");
  const std::string allocation = Section(inputs, "## Allocation files");
  ASSERT_FALSE(campaign.empty());
  ASSERT_FALSE(allocation.empty());
  std::vector<std::string> spec;
  for (const std::vector<std::string>& row : Rows(campaign)) {
    const std::vector<std::string> key = Quoted(row.at(0));
    if (key.size() == 1 && key[0].starts_with("spec.")) spec.push_back(key[0].substr(5));
  }
  EXPECT_THAT(spec, ElementsAreArray(TableNames())) << "docs/inputs.md's spec.* keys";

  constexpr std::string_view kConstraint = "allocation.constraint[].";
  std::vector<std::string> outputs, limit_units;
  for (const std::vector<std::string>& row : Rows(allocation)) {
    const std::vector<std::string> key = Quoted(row.at(0));
    if (key.size() != 1 || !key[0].starts_with(kConstraint)) continue;
    const std::string field = key[0].substr(kConstraint.size());
    if (field == "output") outputs = Quoted(row.at(2), '"');
    if (field.starts_with("upper_")) limit_units.push_back(field.substr(6));
  }
  EXPECT_THAT(outputs, ElementsAreArray(TableNames())) << "docs/inputs.md's allocation.constraint[].output";
  EXPECT_THAT(limit_units, ElementsAreArray(TableUnits())) << "docs/inputs.md's allocation.constraint[].upper_<unit>";
}

}  // namespace
}  // namespace ringtol::jobs
