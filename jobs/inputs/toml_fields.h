// Internal to jobs/ (used by scene_file.cpp and sweep_file.cpp, not installed with the
// public headers): how a TOML table becomes a value.
//
// Each table of an input file lists its keys once, as a std::vector<Field<T>>: the key,
// whether it is required, what it accepts (type, unit factor to SI, range or allowed
// values) and where the value lands in T. TableReader::Read walks that list, so reading,
// range checks, the unknown-key check and the error messages all come from the same
// entries and cannot drift apart. Rules that tie several keys together (exactly one of
// two keys, one value above another, a roller smaller than the ring) are checked by the
// caller after Read, through TableReader::Fail, which words the message as
// jobs/inputs/input_error.h promises.
//
// Ranges are stated and checked in the file's units (those in the key names), so
// messages quote numbers as the user wrote them; values are converted to SI when stored.
// Every number must be finite; integers are accepted where a float is expected.
// Everything here throws InputError and nothing else (std::bad_alloc aside).
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <toml++/toml.h>

#include "engine/enum_names.h"
#include "engine/option_range.h"
#include "engine/profile.h"
#include "engine/scene.h"
#include "engine/units.h"

namespace ringtol::jobs {

// Factors from the unit named in a key to SI.
inline constexpr double kSameUnit = 1.0;  // keys already in SI: N, N/m, kg, kg/m^3, kg m^2, -

// Highest harmonic order accepted. On the article's ring order 1000 is a 1.9 mm
// wavelength, already surface texture rather than form error; the convexity check costs
// O(order^2) (64 samples per undulation, each a sum over all orders), so the cap also
// keeps reading a file instant.
inline constexpr int kMaxHarmonicOrder = 1000;

// Ranges (engine/option_range.h) are in file units here: "> 0", ">= 1 and <= 3", "any
// finite number".
std::string Describe(const Range& range);
// A range in SI (an options struct's) in the units of a key whose values are multiplied by
// `to_si` to SI.
Range InFileUnits(const Range& si, double to_si);
// What an options struct's field accepts, for a message: "an integer >= 0 and <= 9", "> 0";
// in the units of a key whose values are multiplied by `to_si` to SI.
std::string Allowed(const InvalidOption& invalid, double to_si = kSameUnit);

// How an input file or the command line names a field of an options struct: by a key or a
// flag, whose values are multiplied by `to_si` to the field's units.
struct OptionName {
  std::string_view field;  // as IsValid names it: "simulation.steps"
  std::string_view name;   // "steps", "--steps"
  double to_si = kSameUnit;
};
// The entry of `names` for IsValid's report; a field none names is a broken invariant
// (std::logic_error): every field a user can set has its key or flag.
const OptionName& NameOfOption(std::span<const OptionName> names, const InvalidOption& invalid);

// Shortest text that reads back as the same double ("400", "0.14", "nan").
std::string ShowNumber(double value);
// A derived number (a sum, a converted limit) to 6 significant digits.
std::string ShowDerived(double value);
// The most of a value or a line from a file a message shows: longer text is cut, and the
// position the message gives locates the rest.
inline constexpr std::size_t kMaxShownLength = 80;
// A TOML value as written (numbers as by ShowNumber, strings quoted), cut to kMaxShownLength.
std::string ShowValue(const toml::node& node);
// Text as a TOML string ("\"penalty\""), or "" for empty text.
std::string ShowText(const std::string& text);
// "file:line:col", or "file" when the parser recorded no position.
std::string Where(const std::string& file, const toml::source_region& region);

// Throws InputError "<where>: <subject>: <problem>; allowed: <allowed>", where subject is
// usually "<key path> = <value>".
[[noreturn]] void FailAt(const std::string& where, std::string_view subject, std::string_view problem,
                         std::string_view allowed);

// One value in a file, with what an error message about it needs. Short-lived: it refers
// to the parsed document and the file name, both owned by the caller.
struct Site {
  const std::string& file;  // source name shown in messages
  std::string key_path;     // e.g. "rollers[2].radius_mm"
  const toml::node& node;

  // InputError "<file>:<line>:<col>: <key path> = <value>: <problem>; allowed: <allowed>".
  [[noreturn]] void Fail(std::string_view problem, std::string_view allowed) const;
  // Element `index` of this array value (the caller has checked it is an array).
  Site Element(std::size_t index) const;
};

// Typed reads: check type, finiteness and range; `allowed` words the error messages.
double ReadNumber(const Site& site, const Range& range);  // in file units
int ReadInteger(const Site& site, const Range& range);    // range within int
// The same, worded by `allowed` instead of the range.
double ReadNumber(const Site& site, const Range& range, std::string_view allowed);
int ReadInteger(const Site& site, const Range& range, std::string_view allowed);
std::string ReadText(const Site& site, std::string_view allowed);  // non-empty string
bool ReadFlag(const Site& site);                                    // true or false
const toml::table& ReadTable(const Site& site, std::string_view allowed);
const toml::array& ReadArray(const Site& site, std::string_view allowed);
// Array of harmonic tables {order, amplitude_mm, phase_deg}, converted to SI.
std::vector<engine::Harmonic> ReadHarmonics(const Site& site);
// What a harmonics key accepts, for messages.
inline constexpr std::string_view kHarmonicsAllowed =
    "an array of tables { order = integer 1..1000, amplitude_mm >= 0, phase_deg (default 0) }";

enum class Presence { kRequired, kOptional };

// What a reader's field lists say about one key, as docs/inputs.md states it; the test that
// holds that reference to the readers (tests/jobs/cli/input_reference_test.cpp) collects
// them by reading the reference's own examples.
struct KeyRecord {
  std::string file;  // the source name the reader was given
  std::string path;  // "ring.inner_radius_mm", "rollers[].angle_deg": element indices dropped
  bool required = false;
  std::string allowed;    // Field::allowed
  std::string only_when;  // Field::applies_when, "" for every configuration
  // The value the reader keeps when the key is absent, in file units as the file would write
  // it ("1.5", "\"penalty\"", "true"); "" where that is not a single value (a list, a value
  // derived from other keys, a key with no default).
  std::string default_value;
};

// While one is alive, every TableReader::Read on its thread records each field of the list
// it reads with (the first sighting of a file's path wins), before reading that field, so
// the recorded default is what the key's absence leaves. Readers behave as without it. At
// most one per thread: a second throws std::logic_error. Not copyable or movable.
class KeyRecorder {
 public:
  KeyRecorder();
  ~KeyRecorder();
  KeyRecorder(const KeyRecorder&) = delete;
  KeyRecorder& operator=(const KeyRecorder&) = delete;

  const std::vector<KeyRecord>& keys() const { return keys_; }

  // The recorder alive on this thread, or null.
  static KeyRecorder* Active();
  void Add(KeyRecord record);

 private:
  std::vector<KeyRecord> keys_;
};

// One key of a table: read, checked and stored into a T.
template <typename T>
struct Field {
  std::string_view key;
  Presence presence = Presence::kOptional;
  std::string allowed;                        // what the key accepts, quoted in messages
  std::function<void(const Site&, T&)> read;  // checks the value and stores it in SI
  // Keys that belong to one configuration only (a spring roller's spring): when set,
  // `applies` is asked about the fields read so far (earlier in the list); if it says no,
  // the key is forbidden, and `presence` holds only when it says yes. `applies_when`
  // words the condition for messages, e.g. mount = "spring".
  std::function<bool(const T&)> applies;
  std::string_view applies_when;
  // The key's current value in `T` as the file would write it, or "" (KeyRecord::default_value).
  std::function<std::string(const T&)> show = {};

  Field When(std::function<bool(const T&)> condition, std::string_view description) && {
    applies = std::move(condition);
    applies_when = description;
    return std::move(*this);
  }
  // For a key whose absence means something other than the member's initial value (the
  // tolerance numbers a class stands in for): nothing is shown as its default.
  Field WithoutDefault() && {
    show = {};
    return std::move(*this);
  }
};

class TableReader;

// Field factories. M is the member type: double or std::optional<double> and so on; an
// absent optional key leaves the member at its in-class default, which is therefore the
// documented default.
// A number's value in file units, to 6 significant digits (the conversion to SI and back
// need not round-trip exactly); "" for an absent optional.
template <typename M>
std::string ShowInFileUnits(const M& value, double to_si) {
  if constexpr (std::is_same_v<M, std::optional<double>>) {
    return value ? ShowDerived(*value / to_si) : "";
  } else {
    return ShowDerived(static_cast<double>(value) / to_si);
  }
}

template <typename T, typename M>
Field<T> Number(std::string_view key, Presence presence, double to_si, Range range, M T::*member) {
  std::string allowed = Describe(range);
  return {key, presence, allowed,
          [to_si, range, member](const Site& site, T& target) { target.*member = ReadNumber(site, range) * to_si; },
          {}, {}, [to_si, member](const T& target) { return ShowInFileUnits(target.*member, to_si); }};
}

template <typename T>
Field<T> Integer(std::string_view key, Presence presence, Range range, int T::*member) {
  return {key, presence, "an integer " + Describe(range),
          [range, member](const Site& site, T& target) { target.*member = ReadInteger(site, range); }, {}, {},
          [member](const T& target) { return std::to_string(target.*member); }};
}

// Keys that set a field of an options struct whose IsValid checks its range (the reader
// calls it after Read and names the key: TableReader::FailOption): read here for their
// type, `range` (the struct's, in file units: InFileUnits) wording what they accept.
template <typename T, typename M>
Field<T> OptionNumber(std::string_view key, Presence presence, double to_si, Range range, M T::*member) {
  Field<T> field = Number(key, presence, to_si, range, member);
  field.read = [to_si, allowed = field.allowed, member](const Site& site, T& target) {
    target.*member = ReadNumber(site, AnyFinite(), allowed) * to_si;
  };
  return field;
}

template <typename T>
Field<T> OptionInteger(std::string_view key, Presence presence, Range range, int T::*member) {
  Field<T> field = Integer(key, presence, range, member);
  field.read = [allowed = field.allowed, member](const Site& site, T& target) {
    target.*member = ReadInteger(site, Between(std::numeric_limits<int>::min(), std::numeric_limits<int>::max()), allowed);
  };
  return field;
}

template <typename T>
Field<T> Text(std::string_view key, Presence presence, std::string_view allowed, std::string T::*member) {
  return {key, presence, std::string(allowed),
          [allowed = std::string(allowed), member](const Site& site, T& target) {
            target.*member = ReadText(site, allowed);
          },
          {}, {}, [member](const T& target) { return ShowText(target.*member); }};
}

template <typename T>
Field<T> Flag(std::string_view key, Presence presence, bool T::*member) {
  return {key, presence, "true or false",
          [member](const Site& site, T& target) { target.*member = ReadFlag(site); }, {}, {},
          [member](const T& target) { return std::string(target.*member ? "true" : "false"); }};
}

// A string from a fixed set, stored as the matching enumerator.
template <typename T, typename E>
Field<T> Choice(std::string_view key, Presence presence, std::vector<std::pair<std::string_view, E>> options,
                E T::*member) {
  std::string allowed;
  for (const auto& option : options) allowed += (allowed.empty() ? "\"" : ", \"") + std::string(option.first) + "\"";
  return {key, presence, allowed,
          [options, allowed, member](const Site& site, T& target) {
            const std::string text = ReadText(site, allowed);
            for (const auto& [name, value] : options) {
              if (text == name) {
                target.*member = value;
                return;
              }
            }
            site.Fail("unknown value", allowed);
          },
          {}, {},
          [options, member](const T& target) {
            for (const auto& [name, value] : options) {
              if (target.*member == value) return ShowText(std::string(name));
            }
            return std::string();
          }};
}

// The same, from the enum's name table (engine/enum_names.h).
template <typename T, typename E, std::size_t N>
Field<T> Choice(std::string_view key, Presence presence, const NameTable<E, N>& names, E T::*member) {
  std::vector<std::pair<std::string_view, E>> options;
  for (const auto& [value, name] : names) options.emplace_back(name, value);
  return Choice<T, E>(key, presence, std::move(options), member);
}

// Harmonic tables; M is std::vector<engine::Harmonic> or an optional of it.
template <typename T, typename M>
Field<T> HarmonicList(std::string_view key, Presence presence, M T::*member) {
  return {key, presence, std::string(kHarmonicsAllowed),
          [member](const Site& site, T& target) { target.*member = ReadHarmonics(site); }, {}, {}};
}

// A non-empty array of numbers, each in `range` (file units), stored in SI.
template <typename T>
Field<T> NumberList(std::string_view key, Presence presence, double to_si, Range range,
                    std::vector<double> T::*member) {
  const std::string allowed = "a non-empty array of numbers " + Describe(range);
  return {key, presence, allowed,
          [to_si, range, allowed, member](const Site& site, T& target) {
            const toml::array& array = ReadArray(site, allowed);
            if (array.empty()) site.Fail("empty", allowed);
            std::vector<double> values;
            for (std::size_t i = 0; i < array.size(); ++i) values.push_back(ReadNumber(site.Element(i), range) * to_si);
            target.*member = std::move(values);
          },
          {}, {}};
}

// A non-empty array of integers, each in `range`.
template <typename T>
Field<T> IntegerList(std::string_view key, Presence presence, Range range, std::vector<int> T::*member) {
  const std::string allowed = "a non-empty array of integers " + Describe(range);
  return {key, presence, allowed,
          [range, allowed, member](const Site& site, T& target) {
            const toml::array& array = ReadArray(site, allowed);
            if (array.empty()) site.Fail("empty", allowed);
            std::vector<int> values;
            for (std::size_t i = 0; i < array.size(); ++i) values.push_back(ReadInteger(site.Element(i), range));
            target.*member = std::move(values);
          },
          {}, {}};
}

// A sub-table ([ring]); `read` usually calls TableReader::Read with that table's fields.
template <typename T>
Field<T> Section(std::string_view key, Presence presence, std::function<void(const TableReader&, T&)> read);

// An array of tables ([[rollers]]) with at least `min_count` entries; `read` is called
// for each in file order with its 0-based index.
template <typename T>
Field<T> Sections(std::string_view key, Presence presence, std::size_t min_count,
                  std::function<void(const TableReader&, std::size_t, T&)> read);

// A table of a parsed document with its key path. Refers to the document and the file
// name; both must outlive it.
class TableReader {
 public:
  // path: "" for the document's root, "ring", "rollers[2]", ...
  TableReader(const toml::table& table, std::string path, const std::string& file)
      : table_(&table), path_(std::move(path)), file_(&file) {}

  const toml::table& table() const { return *table_; }
  const std::string& file() const { return *file_; }
  std::string KeyPath(std::string_view key) const;  // "ring" + "harmonics" -> "ring.harmonics"
  bool Has(std::string_view key) const { return table_->contains(key); }
  // Where the table starts, or the bare file name for the root.
  std::string Location() const;

  // Rejects keys not in `fields`, then reads the fields in list order into `target`.
  template <typename T>
  void Read(const std::vector<Field<T>>& fields, T& target) const;

  // The value at `key`, which must be present (for checks after Read).
  Site At(std::string_view key) const;
  // The table at element `index` of the array of tables at `key` (present, checked by Read).
  TableReader Element(std::string_view key, std::size_t index) const;

  // InputError about `key`: with its value and position when present, the table's
  // position otherwise.
  [[noreturn]] void Fail(std::string_view key, std::string_view problem, std::string_view allowed) const;
  // The same for a rule that several keys break together or a key that was left at its
  // default: `subject` replaces "<key path> = <value>" after the position of `key`.
  [[noreturn]] void FailAbout(std::string_view key, std::string_view subject, std::string_view problem,
                              std::string_view allowed) const;
  // InputError about the key that `keys` names for IsValid's report on the options this
  // table set (after Read): the key's value and position, and the field's range in the
  // key's units.
  [[noreturn]] void FailOption(const InvalidOption& invalid, std::span<const OptionName> keys) const;
  // Exactly one of keys a and b must be present.
  void RequireExactlyOne(std::string_view a, std::string_view b, std::string_view allowed) const;

 private:
  void RejectUnknownKeys(const std::vector<std::string_view>& valid) const;
  [[noreturn]] void FailMissing(std::string_view key, std::string_view allowed, std::string_view condition) const;

  const toml::table* table_;
  std::string path_;
  const std::string* file_;
};

// Reads a whole file. Throws InputError naming it when it is missing or unreadable.
std::string ReadTextFile(const std::filesystem::path& file);
// Parses TOML; a syntax error becomes InputError "<source>:<line>:<col>: not valid TOML: ...".
toml::table ParseToml(std::string_view text, const std::string& source_name);

// sum_n |C_n| [m]: how far a form can stray from its mean.
double AmplitudeSum(const std::vector<engine::Harmonic>& harmonics);
// |mean_deviation| + sum_n C_n [m]: how far a profile can stray from its radius. The
// polar form needs it below the radius, or r(theta) can reach zero.
double DeviationBound(const engine::PolarProfile& profile);
// What CheckGeometry's fit test allows, for messages (ring_radius in m).
std::string FitRule(double ring_radius);
// What CheckGeometry's test that no two rollers overlap allows, for messages.
std::string ClearanceRule();
// What a step count given by the user must reach for a scene whose fastest term is
// `fastest` (engine::MinimumSteps), for messages: the minimum and the term that sets it.
std::string StepsRule(const engine::Scene& scene, const engine::FastestHarmonic& fastest);

// ---------------------------------------------------------------------------------------
// Template definitions.

template <typename T>
void TableReader::Read(const std::vector<Field<T>>& fields, T& target) const {
  std::vector<std::string_view> keys;
  for (const Field<T>& field : fields) keys.push_back(field.key);
  RejectUnknownKeys(keys);
  KeyRecorder* const recorder = KeyRecorder::Active();
  for (const Field<T>& field : fields) {
    if (recorder != nullptr) {
      recorder->Add({*file_, KeyPath(field.key), field.presence == Presence::kRequired, field.allowed,
                     std::string(field.applies_when), field.show ? field.show(target) : std::string()});
    }
    const bool applies = !field.applies || field.applies(target);
    const toml::node* node = table_->get(field.key);
    if (node == nullptr) {
      if (applies && field.presence == Presence::kRequired) FailMissing(field.key, field.allowed, field.applies_when);
      continue;
    }
    const Site site{*file_, KeyPath(field.key), *node};
    if (!applies) site.Fail("not valid here", "only when " + std::string(field.applies_when));
    field.read(site, target);
  }
}

// The tables of an array of tables, checked to number at least min_count.
std::vector<TableReader> ReadTableArray(const Site& site, std::size_t min_count, std::string_view allowed);

template <typename T>
Field<T> Section(std::string_view key, Presence presence, std::function<void(const TableReader&, T&)> read) {
  const std::string allowed = "a table [" + std::string(key) + "]";
  return {key, presence, allowed,
          [allowed, read](const Site& site, T& target) {
            read(TableReader(ReadTable(site, allowed), site.key_path, site.file), target);
          },
          {}, {}};
}

template <typename T>
Field<T> Sections(std::string_view key, Presence presence, std::size_t min_count,
                  std::function<void(const TableReader&, std::size_t, T&)> read) {
  const std::string allowed = "at least " + std::to_string(min_count) + " [[" + std::string(key) + "]] tables";
  return {key, presence, allowed,
          [min_count, allowed, read](const Site& site, T& target) {
            const std::vector<TableReader> tables = ReadTableArray(site, min_count, allowed);
            for (std::size_t i = 0; i < tables.size(); ++i) read(tables[i], i, target);
          },
          {}, {}};
}

}  // namespace ringtol::jobs
