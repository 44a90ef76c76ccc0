#include "jobs/inputs/profile_csv.h"

#include <array>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <numbers>
#include <system_error>

#include <fmt/format.h>

#include "jobs/inputs/input_error.h"
#include "engine/units.h"

namespace ringtol::jobs {
namespace {

constexpr std::size_t kMaxShownLength = 80;  // longer text is cut: the line number locates it

struct AngleColumn {
  std::string_view name;
  double to_si;
};
constexpr std::array<AngleColumn, 2> kAngleColumns{{{"angle_deg", units::kRadiansPerDegree}, {"angle_rad", 1.0}}};

struct ValueColumn {
  std::string_view name;
  double to_si;
  ProfileQuantity quantity;
};
constexpr std::array<ValueColumn, 3> kValueColumns{{{"radius_mm", units::kMetresPerMillimetre, ProfileQuantity::kRadius},
                                                    {"deviation_mm", units::kMetresPerMillimetre, ProfileQuantity::kDeviation},
                                                    {"deviation_um", units::kMetresPerMicrometre, ProfileQuantity::kDeviation}}};

constexpr std::string_view kAngleNames = "angle_deg, angle_rad";
constexpr std::string_view kValueNames = "radius_mm, deviation_mm, deviation_um";
constexpr std::string_view kHeaderAllowed =
    "a header line before the data, e.g. `angle_deg, radius_mm`: first column angle_deg or angle_rad, second "
    "radius_mm, deviation_mm or deviation_um, any further columns ignored";

template <typename Column, std::size_t N>
const Column* FindColumn(const std::array<Column, N>& columns, std::string_view name) {
  for (const Column& column : columns) {
    if (column.name == name) return &column;
  }
  return nullptr;
}

std::string_view Trim(std::string_view text) {
  const std::size_t first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

std::vector<std::string_view> SplitFields(std::string_view line) {
  std::vector<std::string_view> fields;
  for (std::size_t start = 0;;) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(Trim(line.substr(start, comma - start)));
    if (comma == std::string_view::npos) return fields;
    start = comma + 1;
  }
}

// Text from the file as it appears in a message.
std::string Shown(std::string_view text) {
  if (text.empty()) return "\"\"";
  if (text.size() <= kMaxShownLength) return std::string(text);
  return std::string(text.substr(0, kMaxShownLength)) + "...";
}

// A finite double written in full, or the reason it is not one.
struct ParsedNumber {
  double value = 0.0;
  std::string_view problem;  // empty when value holds the number
};

ParsedNumber ParseNumber(std::string_view field) {
  // Exports write "+0.5"; std::from_chars takes a minus sign only.
  if (field.size() > 1 && field.front() == '+' && field[1] != '-') field.remove_prefix(1);
  double value = 0.0;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (error == std::errc::invalid_argument || end != field.data() + field.size()) return {0.0, "not a number"};
  if (error == std::errc::result_out_of_range) return {0.0, "out of the range of a double"};
  if (!std::isfinite(value)) return {0.0, "not finite"};
  return {value, {}};
}

// One line of the file, with what a message about it needs.
struct Line {
  const std::string& source;
  std::size_t number;  // 1-based
  std::string_view text;

  [[noreturn]] void Fail(std::string_view subject, std::string_view problem, std::string_view allowed) const {
    throw InputError(fmt::format("{}:{}: {}: {}; allowed: {}", source, number, subject, problem, allowed));
  }

  // The field of column `name`, converted to SI.
  double Number(std::string_view name, std::string_view field, double to_si, bool positive) const {
    const std::string_view allowed = positive ? "a finite number > 0" : "a finite number";
    const ParsedNumber parsed = ParseNumber(field);
    const std::string subject = fmt::format("{} = {}", name, Shown(field));
    if (!parsed.problem.empty()) Fail(subject, parsed.problem, allowed);
    if (positive && !(parsed.value > 0.0)) Fail(subject, "not positive", allowed);
    return parsed.value * to_si;
  }
};

}  // namespace

MeasuredProfile ParseProfileCsv(std::string_view text, const std::string& source_name) {
  // Windows tools open UTF-8 files with a byte-order mark.
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);

  const AngleColumn* angle = nullptr;
  const ValueColumn* value = nullptr;
  std::size_t header_fields = 0;
  std::size_t header_line = 0;
  std::string_view header_text;
  MeasuredProfile profile;

  std::size_t number = 0;
  for (std::size_t start = 0; start <= text.size();) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view raw = text.substr(start, end - start);
    if (raw.ends_with('\r')) raw.remove_suffix(1);
    start = end + 1;
    ++number;

    const Line line{source_name, number, Trim(raw)};
    if (line.text.empty() || line.text.starts_with('#')) continue;
    const std::vector<std::string_view> fields = SplitFields(line.text);

    if (angle == nullptr) {
      if (ParseNumber(fields[0]).problem.empty()) {
        line.Fail(fmt::format("row `{}`", Shown(line.text)), "data before any header line", kHeaderAllowed);
      }
      if (fields.size() < 2) {
        line.Fail(fmt::format("header `{}`", Shown(line.text)), "fewer than 2 columns", kHeaderAllowed);
      }
      angle = FindColumn(kAngleColumns, fields[0]);
      if (angle == nullptr) line.Fail("column 1 = " + Shown(fields[0]), "unknown column name", kAngleNames);
      value = FindColumn(kValueColumns, fields[1]);
      if (value == nullptr) line.Fail("column 2 = " + Shown(fields[1]), "unknown column name", kValueNames);
      header_fields = fields.size();
      header_line = number;
      header_text = line.text;
      profile.quantity = value->quantity;
      continue;
    }

    if (fields.size() != header_fields) {
      line.Fail(fmt::format("row `{}`", Shown(line.text)), fmt::format("{} fields", fields.size()),
                fmt::format("{} fields, one per column of the header on line {}", header_fields, header_line));
    }
    profile.samples.push_back({line.Number(angle->name, fields[0], angle->to_si, false),
                               line.Number(value->name, fields[1], value->to_si,
                                           value->quantity == ProfileQuantity::kRadius)});
  }

  if (angle == nullptr) {
    throw InputError(fmt::format("{}: no header line: the file holds only comments and blank lines; allowed: {}",
                                 source_name, kHeaderAllowed));
  }
  if (profile.samples.empty()) {
    Line{source_name, header_line, header_text}.Fail(fmt::format("header `{}`", Shown(header_text)),
                                                      "no data rows follow", "at least one row of numbers");
  }
  return profile;
}

MeasuredProfile ReadProfileCsv(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(file, error);
  if (!std::filesystem::exists(status)) {
    throw InputError(fmt::format("{}: cannot read: no such file; allowed: the path of an existing CSV file", name));
  }
  if (std::filesystem::is_directory(status)) {
    throw InputError(fmt::format("{}: cannot read: a directory; allowed: the path of a CSV file", name));
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open for reading (check its permissions)", name));
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw InputError(fmt::format("{}: read error", name));
  return ParseProfileCsv(text, name);
}

MeasuredFit FitProfileFile(const std::filesystem::path& file, int orders) {
  MeasuredProfile profile = ReadProfileCsv(file);
  try {
    return {profile.quantity, sampling::FitFourierSeries(profile.samples, orders)};
  } catch (const std::invalid_argument& error) {
    throw InputError(fmt::format("{}: {}", file.string(), error.what()));
  }
}

std::vector<engine::Harmonic> FormHarmonics(const sampling::FourierFit& fit, bool keep_eccentricity) {
  std::vector<engine::Harmonic> form;
  for (const engine::Harmonic& h : fit.harmonics) {
    if (h.order >= 2 || keep_eccentricity) form.push_back(h);
  }
  return form;
}

}  // namespace ringtol::jobs
