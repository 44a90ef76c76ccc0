// docs/inputs.md against the readers: its example files must read, and its key tables
// must list exactly the keys the readers' field lists hold, each with the reader's
// presence, allowed values and default. A key added, renamed, re-ranged or re-defaulted in
// a reader fails here until the reference says so; the failure prints the row it expects.
#include <algorithm>
#include <cstddef>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "jobs/allocation/allocation_file.h"
#include "jobs/campaign/campaign_file.h"
#include "jobs/inputs/catalogue_file.h"
#include "jobs/inputs/input_error.h"
#include "jobs/inputs/profile_csv.h"
#include "jobs/inputs/scene_file.h"
#include "jobs/inputs/sweep_file.h"
#include "jobs/inputs/toml_fields.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

using ringtol::testing::FreshTestFolder;
using ringtol::testing::ReadText;
using ringtol::testing::WriteText;

const std::filesystem::path kReference = std::filesystem::path(RINGTOL_SOURCE_DIR) / "docs" / "inputs.md";

// The reference's sections, by heading, and which keys each documents.
constexpr std::string_view kSceneSection = "Scene files";
constexpr std::string_view kHarmonicSection = "Harmonic tables";
constexpr std::string_view kCampaignSection = "Campaign files";
constexpr std::string_view kCatalogueSection = "Tolerance catalogue";
constexpr std::string_view kAllocationSection = "Allocation files";
constexpr std::string_view kSweepSection = "Sweep files";
constexpr std::string_view kProfileSection = "Profile CSV files";

struct Example {
  std::string name;  // from the block's first line, "# scene.toml"
  std::string text;
};

struct Row {
  std::string required, allowed, default_value;
};

struct Reference {
  std::vector<Example> examples;
  std::map<std::string, std::map<std::string, Row>> rows;  // section -> key path -> row
  std::map<std::string, std::string> sections;             // section -> its text
};

std::string Trim(std::string_view text) {
  const std::size_t first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const std::size_t last = text.find_last_not_of(" \t");
  return std::string(text.substr(first, last - first + 1));
}

// The cells of "| a | b \| c |", unescaped.
std::vector<std::string> Cells(std::string_view line) {
  std::vector<std::string> cells;
  std::string cell;
  for (std::size_t i = 1; i < line.size(); ++i) {
    if (line[i] == '\\' && i + 1 < line.size() && line[i + 1] == '|') {
      cell += '|';
      ++i;
    } else if (line[i] == '|') {
      cells.push_back(Trim(cell));
      cell.clear();
    } else {
      cell += line[i];
    }
  }
  return cells;
}

Reference ReadReference() {
  Reference reference;
  std::istringstream in(ReadText(kReference));
  std::string line, section;
  Example* example = nullptr;
  bool in_block = false, first_line = false;
  while (std::getline(in, line)) {
    if (line.starts_with("```")) {
      in_block = !in_block;
      first_line = in_block;
      example = nullptr;
      continue;
    }
    if (in_block) {
      if (first_line && line.starts_with("# ") && line.find(' ', 2) == std::string::npos) {
        reference.examples.push_back({line.substr(2), ""});
        example = &reference.examples.back();
      }
      first_line = false;
      if (example != nullptr) example->text += line + "\n";
      continue;
    }
    if (line.starts_with("## ")) section = line.substr(3);
    reference.sections[section] += line + "\n";
    if (!line.starts_with("| `")) continue;
    const std::vector<std::string> cells = Cells(line);
    if (cells.size() < 5) continue;
    const std::string key = cells[0].substr(1, cells[0].find('`', 1) - 1);
    reference.rows[section][key] = {cells[1], cells[2], cells[3]};
  }
  return reference;
}

// What the readers' field lists hold, section by section, as read from the examples.
// The four components of [allocation.components] share their keys: documented once, as
// allocation.components.*.options and so on.
std::string ComponentsShared(std::string path) {
  constexpr std::string_view kComponents = "allocation.components.";
  if (!path.starts_with(kComponents)) return path;
  const std::size_t end = path.find('.', kComponents.size());
  if (end == std::string::npos) return path;
  return std::string(kComponents) + "*" + path.substr(end);
}

std::map<std::string, std::map<std::string, KeyRecord>> ReadersKeys(const std::vector<KeyRecord>& records,
                                                                     const std::set<std::string>& example_files) {
  std::set<std::string> harmonic_lists;  // paths whose value is an array of harmonic tables
  for (const KeyRecord& record : records) {
    if (record.allowed == kHarmonicsAllowed) harmonic_lists.insert(record.path + "[].");
  }
  std::map<std::string, std::map<std::string, KeyRecord>> keys;
  for (KeyRecord record : records) {
    if (record.allowed.empty()) continue;  // passed on to the reader that reads it
    const std::string file = std::filesystem::path(record.file).filename().string();
    if (!example_files.contains(file)) continue;  // the shipped catalogue, read with every campaign file
    record.path = ComponentsShared(record.path);
    std::string section;
    for (const std::string& list : harmonic_lists) {
      if (record.path.starts_with(list)) {
        record.path = "harmonics[]." + record.path.substr(list.size());
        section = kHarmonicSection;
      }
    }
    if (section.empty()) {
      if (file.starts_with("scene")) {
        section = kSceneSection;
      } else if (file.starts_with("campaign")) {
        section = record.path.starts_with("catalogue") ? kCatalogueSection : kCampaignSection;
      } else if (file.starts_with("allocation")) {
        if (!record.path.starts_with("allocation")) continue;  // a campaign file's keys
        section = kAllocationSection;
      } else if (file.starts_with("sweep")) {
        section = kSweepSection;
      }
    }
    if (section.empty()) {
      ADD_FAILURE() << "no section for " << file << ": " << record.path;
      continue;
    }
    keys[section].emplace(record.path, record);
  }
  return keys;
}

std::string Required(const KeyRecord& record) {
  std::string text = record.required ? "yes" : "no";
  if (!record.only_when.empty()) text += ", only when " + record.only_when;
  return text;
}

std::string Escaped(const std::string& text) {
  std::string escaped;
  for (const char c : text) escaped += c == '|' ? std::string("\\|") : std::string(1, c);
  return escaped;
}

// The row the reference should have for `record`, meaning left to the writer.
std::string ExpectedRow(const KeyRecord& record) {
  const std::string shown_default = record.default_value.empty() ? "" : "`" + record.default_value + "`";
  return "| `" + record.path + "` | " + Required(record) + " | " + Escaped(record.allowed) + " | " + shown_default +
         " | |";
}

class InputReference : public ::testing::Test {
 protected:
  void SetUp() override {
    reference_ = ReadReference();
    folder_ = FreshTestFolder("input_reference");
    for (const Example& example : reference_.examples) WriteText(folder_ / example.name, example.text);
  }

  Reference reference_;
  std::filesystem::path folder_;
};

TEST_F(InputReference, ExamplesReadAndKeyTablesMatchTheReaders) {
  ASSERT_FALSE(reference_.examples.empty()) << kReference << " has no example files (blocks starting `# name.toml`)";
  KeyRecorder recorder;
  std::set<std::string> kinds;
  for (const Example& example : reference_.examples) {
    const std::filesystem::path file = folder_ / example.name;
    const std::string& name = example.name;
    try {
      if (name.starts_with("scene")) {
        ReadScene(file);
      } else if (name.starts_with("campaign")) {
        ReadCampaignFile(file);
      } else if (name.starts_with("allocation")) {
        ReadAllocationFile(file);
      } else if (name.starts_with("sweep")) {
        ReadSweep(file);
      } else if (name.ends_with(".csv")) {
        ReadProfileCsv(file);
      } else {
        ADD_FAILURE() << "an example file of no known kind: " << name;
      }
    } catch (const InputError& error) {
      ADD_FAILURE() << "the example " << name << " in " << kReference << " does not read:\n" << error.what();
    }
    kinds.insert(name.substr(0, name.find_first_of("_.")));
  }
  for (const char* kind : {"scene", "campaign", "allocation", "sweep"}) {
    EXPECT_TRUE(kinds.contains(kind)) << kReference << " has no example " << kind << " file";
  }

  std::set<std::string> example_files;
  for (const Example& example : reference_.examples) example_files.insert(example.name);
  const auto keys = ReadersKeys(recorder.keys(), example_files);
  std::string missing;
  for (const auto& [section, section_keys] : keys) {
    const auto documented = reference_.rows.find(section);
    for (const auto& [path, record] : section_keys) {
      const Row* row = nullptr;
      if (documented != reference_.rows.end() && documented->second.contains(path)) row = &documented->second.at(path);
      if (row == nullptr) {
        missing += "\n  " + ExpectedRow(record);
        continue;
      }
      EXPECT_EQ(row->required, Required(record)) << "section \"" << section << "\", " << path;
      EXPECT_EQ(row->allowed, record.allowed) << "section \"" << section << "\", " << path;
      if (!record.required && !record.default_value.empty()) {
        EXPECT_TRUE(row->default_value.starts_with("`" + record.default_value + "`"))
            << "section \"" << section << "\", " << path << ": the reader's default is " << record.default_value
            << ", the reference says " << row->default_value;
      }
    }
  }
  EXPECT_TRUE(missing.empty()) << "keys the readers have and " << kReference << " lacks (rows to add):" << missing;
  for (const auto& [section, rows] : reference_.rows) {
    for (const auto& [path, row] : rows) {
      const auto known = keys.find(section);
      EXPECT_TRUE(known != keys.end() && known->second.contains(path))
          << kReference << ", section \"" << section << "\": " << path
          << " is not a key of the readers (or no example file reaches its table)";
    }
  }
}

// Every column name the profile reader knows is in the reference: an unknown column makes
// it list them.
TEST_F(InputReference, ProfileColumnsAreTheReadersOnes) {
  const std::string& section = reference_.sections[std::string(kProfileSection)];
  ASSERT_FALSE(section.empty()) << kReference << " has no section " << kProfileSection;
  for (const char* header : {"bearing_deg, radius_mm", "angle_deg, size_mm"}) {
    try {
      ParseProfileCsv(std::string(header) + "\n0, 1\n", "probe.csv");
      ADD_FAILURE() << "an unknown column was accepted: " << header;
    } catch (const InputError& error) {
      const std::string message = error.what();
      const std::size_t list = message.find("allowed: ");
      ASSERT_NE(list, std::string::npos) << message;
      std::istringstream names(message.substr(list + 9));
      std::string name;
      while (std::getline(names, name, ',')) {
        name = Trim(name);
        EXPECT_NE(section.find("`" + name + "`"), std::string::npos)
            << kReference << ", " << kProfileSection << ", lacks the column " << name << " (" << message << ")";
      }
    }
  }
}

// Every shipped class is named where a user looks for the classes there are.
TEST_F(InputReference, ShippedClassesAreListed) {
  const std::string& section = reference_.sections[std::string(kCatalogueSection)];
  ASSERT_FALSE(section.empty()) << kReference << " has no section " << kCatalogueSection;
  const sampling::ToleranceCatalogue catalogue = ShippedCatalogue();
  std::vector<std::string> names;
  for (const auto& c : catalogue.roller_classes) names.push_back(c.name);
  for (const auto& c : catalogue.ring_classes) names.push_back(c.name);
  for (const auto& c : catalogue.position_classes) names.push_back(c.name);
  for (const auto& c : catalogue.spring_classes) names.push_back(c.name);
  for (const std::string& name : names) {
    EXPECT_NE(section.find("`" + name + "`"), std::string::npos)
        << kReference << ", " << kCatalogueSection << ", does not list the shipped class " << name;
  }
}

}  // namespace
}  // namespace ringtol::jobs
