#include "jobs/inputs/toml_fields.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "engine/check.h"
#include "engine/units.h"
#include "engine/visible_text.h"
#include "jobs/inputs/input_error.h"
#include "jobs/inputs/text_encoding.h"

namespace ringtol::jobs {
namespace {

std::string_view TypeName(toml::node_type type) {
  switch (type) {
    case toml::node_type::none: return "nothing";
    case toml::node_type::table: return "table";
    case toml::node_type::array: return "array";
    case toml::node_type::string: return "string";
    case toml::node_type::integer: return "integer";
    case toml::node_type::floating_point: return "float";
    case toml::node_type::boolean: return "boolean";
    case toml::node_type::date: return "date";
    case toml::node_type::time: return "time";
    case toml::node_type::date_time: return "date-time";
  }
  return "unknown type";
}

[[noreturn]] void FailType(const Site& site, std::string_view expected, std::string_view allowed) {
  site.Fail(fmt::format("wrong type: expected {}, found {}", expected, TypeName(site.node.type())), allowed);
}

std::string ShowUncut(const toml::node& node) {
  if (const auto* integer = node.as_integer()) return fmt::format("{}", integer->get());
  if (const auto* number = node.as_floating_point()) return ShowNumber(number->get());
  if (const auto* text = node.as_string()) return fmt::format("\"{}\"", VisibleText(text->get()));
  if (const auto* boolean = node.as_boolean()) return boolean->get() ? "true" : "false";
  if (const auto* array = node.as_array()) {
    std::string shown;
    for (const toml::node& element : *array) shown += (shown.empty() ? "" : ", ") + ShowUncut(element);
    return "[" + shown + "]";
  }
  if (const auto* table = node.as_table()) {
    std::string shown;
    for (const auto& [key, value] : *table) {
      shown += fmt::format("{}{} = {}", shown.empty() ? "" : ", ", VisibleText(key.str()), ShowUncut(value));
    }
    return "{ " + shown + " }";
  }
  std::ostringstream out;
  out << toml::node_view<const toml::node>(node);
  return out.str();
}

std::vector<Field<engine::Harmonic>> HarmonicFields() {
  return {
      Integer("order", Presence::kRequired, Between(1.0, kMaxHarmonicOrder), &engine::Harmonic::order),
      Number("amplitude_mm", Presence::kRequired, units::kMetresPerMillimetre, AtLeast(0.0), &engine::Harmonic::amplitude),
      Number("phase_deg", Presence::kOptional, units::kRadiansPerDegree, AnyFinite(), &engine::Harmonic::phase),
  };
}

}  // namespace

namespace {
thread_local KeyRecorder* active_recorder = nullptr;
}  // namespace

KeyRecorder::KeyRecorder() {
  RINGTOL_CHECK(active_recorder == nullptr);  // one recorder a thread
  active_recorder = this;
}

KeyRecorder::~KeyRecorder() { active_recorder = nullptr; }

KeyRecorder* KeyRecorder::Active() { return active_recorder; }

void KeyRecorder::Add(KeyRecord record) {
  // "rollers[2].harmonics[0].order" -> "rollers[].harmonics[].order": one entry per key of a format.
  std::string path;
  bool in_index = false;
  for (const char c : record.path) {
    if (c == '[') in_index = true;
    if (c == ']') in_index = false;
    if (!in_index || c == '[') path += c;
  }
  record.path = std::move(path);
  const auto same = [&record](const KeyRecord& known) { return known.file == record.file && known.path == record.path; };
  const auto known = std::find_if(keys_.begin(), keys_.end(), same);
  if (known == keys_.end()) {
    keys_.push_back(std::move(record));
  } else if (known->allowed.empty()) {
    // A reader that passes a key on to another (a campaign file's root, which the sampling
    // reader shares) lists it with no allowed text; the reader that reads it says more.
    *known = std::move(record);
  }
}

std::string ShowText(const std::string& text) { return text.empty() ? std::string() : fmt::format("\"{}\"", text); }

std::string Describe(const Range& range) {
  std::string text;
  // Bounds are constants in file units: shown in full, as a user would type them.
  if (std::isfinite(range.lower)) text = fmt::format("{} {}", range.lower_open ? ">" : ">=", ShowNumber(range.lower));
  if (std::isfinite(range.upper)) {
    text += fmt::format("{}{} {}", text.empty() ? "" : " and ", range.upper_open ? "<" : "<=", ShowNumber(range.upper));
  }
  return text.empty() ? "any finite number" : text;
}

Range InFileUnits(const Range& si, double to_si) {
  return {si.lower / to_si, si.lower_open, si.upper / to_si, si.upper_open};
}

std::string Allowed(const InvalidOption& invalid, double to_si) {
  return (invalid.integer ? "an integer " : "") + Describe(InFileUnits(invalid.range, to_si));
}

const OptionName& NameOfOption(std::span<const OptionName> names, const InvalidOption& invalid) {
  const auto name = std::find_if(names.begin(), names.end(), [&](const OptionName& n) { return n.field == invalid.field; });
  RINGTOL_CHECK(name != names.end(), invalid.field);  // every field a user sets has a name
  return *name;
}

std::string ShowNumber(double value) { return fmt::format("{}", value); }

std::string ShowDerived(double value) { return fmt::format("{:.6g}", value); }

std::string ShowValue(const toml::node& node) {
  std::string shown = ShowUncut(node);
  if (shown.size() > kMaxShownLength) shown = shown.substr(0, kMaxShownLength) + " ...";
  return shown;
}

std::string Where(const std::string& file, const toml::source_region& region) {
  if (region.begin.line == 0) return file;
  return fmt::format("{}:{}:{}", file, region.begin.line, region.begin.column);
}

void FailAt(const std::string& where, std::string_view subject, std::string_view problem, std::string_view allowed) {
  throw InputError(fmt::format("{}: {}: {}; allowed: {}", where, subject, problem, allowed));
}

void Site::Fail(std::string_view problem, std::string_view allowed) const {
  FailAt(Where(file, node.source()), key_path + " = " + ShowValue(node), problem, allowed);
}

Site Site::Element(std::size_t index) const {
  return {file, fmt::format("{}[{}]", key_path, index), *node.as_array()->get(index)};
}

double ReadNumber(const Site& site, const Range& range) { return ReadNumber(site, range, Describe(range)); }

double ReadNumber(const Site& site, const Range& range, std::string_view allowed) {
  double value = 0.0;
  if (const auto* integer = site.node.as_integer()) {
    value = static_cast<double>(integer->get());
  } else if (const auto* number = site.node.as_floating_point()) {
    value = number->get();
  } else {
    FailType(site, "a number", allowed);
  }
  if (!std::isfinite(value)) site.Fail("not a finite number", allowed);
  if (!range.Contains(value)) site.Fail("out of range", allowed);
  return value;
}

int ReadInteger(const Site& site, const Range& range) { return ReadInteger(site, range, "an integer " + Describe(range)); }

int ReadInteger(const Site& site, const Range& range, std::string_view allowed) {
  const auto* integer = site.node.as_integer();
  if (integer == nullptr) FailType(site, "an integer", allowed);
  const auto value = integer->get();
  if (!range.Contains(static_cast<double>(value))) site.Fail("out of range", allowed);
  return static_cast<int>(value);
}

std::string ReadText(const Site& site, std::string_view allowed) {
  const auto* text = site.node.as_string();
  if (text == nullptr) FailType(site, "a string", allowed);
  if (text->get().empty()) site.Fail("empty", allowed);
  return text->get();
}

bool ReadFlag(const Site& site) {
  const auto* flag = site.node.as_boolean();
  if (flag == nullptr) FailType(site, "a boolean", "true or false");
  return flag->get();
}

const toml::table& ReadTable(const Site& site, std::string_view allowed) {
  const auto* table = site.node.as_table();
  if (table == nullptr) FailType(site, "a table", allowed);
  return *table;
}

const toml::array& ReadArray(const Site& site, std::string_view allowed) {
  const auto* array = site.node.as_array();
  if (array == nullptr) FailType(site, "an array", allowed);
  return *array;
}

std::vector<TableReader> ReadTableArray(const Site& site, std::size_t min_count, std::string_view allowed) {
  const toml::array& array = ReadArray(site, allowed);
  if (array.size() < min_count) {
    FailAt(Where(site.file, site.node.source()), fmt::format("{} ({} entries)", site.key_path, array.size()),
           "too few", allowed);
  }
  std::vector<TableReader> tables;
  for (std::size_t i = 0; i < array.size(); ++i) {
    const Site element = site.Element(i);
    tables.emplace_back(ReadTable(element, allowed), element.key_path, site.file);
  }
  return tables;
}

std::vector<engine::Harmonic> ReadHarmonics(const Site& site) {
  std::vector<engine::Harmonic> harmonics;
  for (const TableReader& table : ReadTableArray(site, 0, kHarmonicsAllowed)) {
    engine::Harmonic harmonic;
    table.Read(HarmonicFields(), harmonic);
    harmonics.push_back(harmonic);
  }
  return harmonics;
}

std::string TableReader::KeyPath(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

std::string TableReader::Location() const { return path_.empty() ? *file_ : Where(*file_, table_->source()); }

Site TableReader::At(std::string_view key) const {
  const toml::node* node = table_->get(key);
  if (node == nullptr) FailMissing(key, "a value: this key is required here", "");
  return {*file_, KeyPath(key), *node};
}

TableReader TableReader::Element(std::string_view key, std::size_t index) const {
  return ReadTableArray(At(key), 0, "an array of tables").at(index);
}

void TableReader::Fail(std::string_view key, std::string_view problem, std::string_view allowed) const {
  const toml::node* node = table_->get(key);
  if (node == nullptr) FailAt(Location(), KeyPath(key), problem, allowed);
  Site{*file_, KeyPath(key), *node}.Fail(problem, allowed);
}

void TableReader::FailOption(const InvalidOption& invalid, std::span<const OptionName> keys) const {
  const OptionName& key = NameOfOption(keys, invalid);
  Fail(key.name, "out of range", Allowed(invalid, key.to_si));
}

void TableReader::FailAbout(std::string_view key, std::string_view subject, std::string_view problem,
                            std::string_view allowed) const {
  const toml::node* node = table_->get(key);
  FailAt(node == nullptr ? Location() : Where(*file_, node->source()), subject, problem, allowed);
}

void TableReader::RequireExactlyOne(std::string_view a, std::string_view b, std::string_view allowed) const {
  if (Has(a) && Has(b)) Fail(b, fmt::format("given together with {}", KeyPath(a)), allowed);
  if (!Has(a) && !Has(b)) {
    FailAt(Location(), fmt::format("{} or {}", KeyPath(a), b), "missing required key (one of the two)", allowed);
  }
}

void TableReader::RejectUnknownKeys(const std::vector<std::string_view>& valid) const {
  for (const auto& [key, node] : *table_) {
    if (std::find(valid.begin(), valid.end(), key.str()) != valid.end()) continue;
    std::string listed;
    for (std::string_view name : valid) listed += (listed.empty() ? "" : ", ") + std::string(name);
    throw InputError(fmt::format("{}: unknown key '{}'; valid keys here: {}", Where(*file_, key.source()),
                                 VisibleText(KeyPath(key.str())), listed));
  }
}

void TableReader::FailMissing(std::string_view key, std::string_view allowed, std::string_view condition) const {
  const std::string problem =
      condition.empty() ? "missing required key" : fmt::format("missing required key (needed when {})", condition);
  FailAt(Location(), KeyPath(key), problem, allowed);
}

std::string ReadTextFile(const std::filesystem::path& file) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(file, error);
  if (!std::filesystem::exists(status)) {
    throw InputError(fmt::format("{}: cannot read: no such file; allowed: the path of an existing TOML file",
                                 file.string()));
  }
  if (std::filesystem::is_directory(status)) {
    throw InputError(fmt::format("{}: cannot read: a directory; allowed: the path of a TOML file", file.string()));
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open for reading (check its permissions)", file.string()));
  std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw InputError(fmt::format("{}: read error", file.string()));
  return text;
}

toml::table ParseToml(std::string_view text, const std::string& source_name) {
  text = Utf8Text(text, source_name);
  try {
    return toml::parse(text, std::string_view(source_name));
  } catch (const toml::parse_error& error) {
    // toml++ quotes the character it stumbled on as it is: a zero-width space or a stray
    // byte must be seen.
    throw InputError(fmt::format("{}: not valid TOML: {}", Where(source_name, error.source()),
                                 VisibleText(error.description())));
  }
}

double AmplitudeSum(const std::vector<engine::Harmonic>& harmonics) {
  double sum = 0.0;
  for (const engine::Harmonic& harmonic : harmonics) sum += std::abs(harmonic.amplitude);
  return sum;
}

double DeviationBound(const engine::PolarProfile& profile) {
  return std::abs(profile.mean_deviation()) + AmplitudeSum(profile.harmonics());
}

std::string FitRule(double ring_radius) {
  return fmt::format(
      "centre distance + roller reach - smallest bore radius <= the roller's radius_mm (for round parts: "
      "centre_radius_mm + radial position error <= ring.inner_radius_mm = {})",
      ShowDerived(units::InMillimetres(ring_radius)));
}

std::string ClearanceRule() {
  return "every two rollers' centres at least their largest radii's sum apart (angle_deg, centre_radius_mm, radius_mm "
         "and the position errors set them)";
}

std::string StepsRule(const engine::Scene& scene, const engine::FastestHarmonic& fastest) {
  const std::string whose =
      fastest.roller < 0 ? std::string("the ring's")
                         : fmt::format("roller {}'s", scene.rollers[static_cast<std::size_t>(fastest.roller)].name);
  return fmt::format(">= {} (more than two angles a period of the fastest undulation, {} order {}, {} per revolution), "
                     "or 0 to choose from the scene",
                     engine::MinimumSteps(fastest.rate), whose, fastest.order, ShowDerived(fastest.rate));
}

}  // namespace ringtol::jobs
