#include "jobs/inputs/profile_csv.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <numbers>
#include <system_error>

#include <fmt/format.h>

#include "engine/units.h"
#include "engine/visible_text.h"
#include "jobs/inputs/input_error.h"
#include "jobs/inputs/text_encoding.h"
#include "jobs/inputs/toml_fields.h"

namespace ringtol::jobs {
namespace {

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
constexpr std::string_view kSeparatorAllowed =
    "comma-separated columns and decimal points, e.g. `angle_deg, radius_mm` then `0.5, 302.0012`: export the "
    "file as CSV with a comma between columns and a point as the decimal separator";
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

// Text from the file as it appears in a message, invisible characters escaped.
std::string Shown(std::string_view text) {
  if (text.empty()) return "\"\"";
  if (text.size() <= kMaxShownLength) return VisibleText(text);
  return VisibleText(text.substr(0, kMaxShownLength)) + "...";
}

// The separator a header of fewer than two comma-separated columns uses instead, in words;
// empty when it has none. Spreadsheets where the decimal separator is a comma export
// semicolons.
std::string_view ForeignSeparator(std::string_view header) {
  if (header.find(';') != std::string_view::npos) return "semicolons";
  if (header.find('\t') != std::string_view::npos) return "tabs";
  return {};
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
  text = Utf8Text(text, source_name);

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
        const std::string header = fmt::format("header `{}`", Shown(line.text));
        if (const std::string_view separator = ForeignSeparator(line.text); !separator.empty()) {
          line.Fail(header, fmt::format("columns separated by {}, not commas", separator), kSeparatorAllowed);
        }
        line.Fail(header, "fewer than 2 columns", kHeaderAllowed);
      }
      angle = FindColumn(kAngleColumns, fields[0]);
      if (angle == nullptr) line.Fail("column 1 = " + Shown(fields[0]), "unknown column name", kAngleNames);
      value = FindColumn(kValueColumns, fields[1]);
      if (value == nullptr) line.Fail("column 2 = " + Shown(fields[1]), "unknown column name", kValueNames);
      header_fields = fields.size();
      header_line = number;
      header_text = line.text;
      profile.quantity = value->quantity;
      profile.angle_column = angle->name;
      profile.value_column = value->name;
      continue;
    }

    if (fields.size() != header_fields) {
      // "0,5, 302,0012": a spreadsheet's decimal commas split every number in two.
      const std::string_view decimal_commas =
          fields.size() > header_fields ? " (decimal commas? numbers take a decimal point)" : "";
      line.Fail(fmt::format("row `{}`", Shown(line.text)), fmt::format("{} fields{}", fields.size(), decimal_commas),
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

namespace {

// Largest less smallest angle [rad], as read.
double AngleSpan(const MeasuredProfile& profile) {
  const auto [lowest, highest] = std::minmax_element(
      profile.samples.begin(), profile.samples.end(),
      [](const sampling::ProfileSample& a, const sampling::ProfileSample& b) { return a.angle < b.angle; });
  return highest->angle - lowest->angle;
}

constexpr std::string_view kAngleUnitAllowed =
    "angles in the unit the column names: angle_deg for degrees (a turn is 360), angle_rad for radians (a turn is "
    "2 pi)";

// Radians under angle_deg: a turn's worth of numbers, 2 pi, read as degrees. Fewer than half
// a turn's worth are left to the fit, which says what they support.
void RequireDegreesUnderAngleDeg(const MeasuredProfile& profile, const std::string& source_name) {
  if (profile.angle_column != "angle_deg") return;
  constexpr double kTurn = 2.0 * std::numbers::pi;
  const double span = AngleSpan(profile) * units::kDegreesPerRadian;  // the numbers as written
  if (span <= kTurn / 2.0 || span > kTurn * (1.0 + 1e-9)) return;
  throw InputError(fmt::format("{}: angle_deg: the readings span {:.4g} degrees, a turn in radians (2 pi = 6.283): "
                               "radians under angle_deg?; allowed: {}",
                               source_name, span, kAngleUnitAllowed));
}

// The residuals' correlation between neighbouring readings in the file's order [-].
double NeighbourCorrelation(const MeasuredProfile& profile, const sampling::FourierFit& fit) {
  std::vector<double> residuals;
  residuals.reserve(profile.samples.size());
  for (const sampling::ProfileSample& sample : profile.samples) {
    double fitted = fit.mean;
    for (const engine::Harmonic& h : fit.harmonics) fitted += h.amplitude * std::cos(h.order * sample.angle + h.phase);
    residuals.push_back(sample.value - fitted);
  }
  double lagged = 0.0, squares = 0.0;
  for (std::size_t i = 0; i < residuals.size(); ++i) {
    squares += residuals[i] * residuals[i];
    if (i > 0) lagged += residuals[i - 1] * residuals[i];
  }
  return squares > 0.0 ? lagged / squares : 0.0;
}

void RequireTheFitToExplainTheOutline(const MeasuredProfile& profile, const sampling::FourierFit& fit, int orders,
                                      const std::string& source_name) {
  if (fit.r_squared >= kMinRSquared) return;
  const double correlation = NeighbourCorrelation(profile, fit);
  if (correlation <= kMaxNoiseCorrelation) return;
  const std::string what = fmt::format(
      "a fit of orders 0..{} with R^2 = {:.4g}: it leaves most of the readings unexplained (R^2 below {}), and its "
      "residual of {:.4g} um rms follows the outline, not noise (neighbouring readings' residuals correlate {:.2f}, "
      "above {})",
      orders, fit.r_squared, kMinRSquared, units::InMicrometres(fit.residual_rms), correlation, kMaxNoiseCorrelation);
  const double turns = AngleSpan(profile) / (2.0 * std::numbers::pi);
  if (profile.angle_column == "angle_rad" && turns > 1.01) {
    throw InputError(fmt::format("{}: {}; the angles under angle_rad span {:.3g} turns: degrees under angle_rad?; "
                                 "allowed: {}",
                                 source_name, what, turns, kAngleUnitAllowed));
  }
  throw InputError(fmt::format("{}: {}: form at orders above {}?; allowed: enough orders to take in the outline's "
                               "form (R^2 >= {}), or readings whose residual is noise",
                               source_name, what, orders, kMinRSquared));
}

void RequireAFormOfThePartsSize(const MeasuredProfile& profile, const sampling::FourierFit& fit,
                                const std::string& source_name, std::optional<double> ring_radius, std::string_view part) {
  const bool radii = profile.quantity == ProfileQuantity::kRadius;
  if (radii) ring_radius = ring_radius.value_or(fit.mean);
  const double form = AmplitudeSum(FormHarmonics(fit, false));
  // As large as the radius: a fit gone wild, not a unit (the callers blame the orders).
  if (ring_radius && form >= *ring_radius) return;
  const double share_limit = ring_radius ? kSameRingShare * *ring_radius : std::numeric_limits<double>::infinity();
  const double limit = radii ? share_limit : std::min(share_limit, kMaxDeviationForm);
  if (form <= limit) return;
  const std::string bound =
      limit == share_limit ? fmt::format("more than {} % of a {} of {} mm", 100.0 * kSameRingShare, part,
                                         ShowDerived(units::InMillimetres(*ring_radius)))
                           : fmt::format("more than {} mm, five times the loosest circularity class of the catalogue",
                                         units::InMillimetres(kMaxDeviationForm));
  throw InputError(fmt::format(
      "{}: {}: a form of {} mm (sum of the amplitudes of orders 2 and up), {}: deviations in another unit than "
      "the column names?; allowed: deviation_um for micrometres, deviation_mm for millimetres, radius_mm for "
      "radii (docs/inputs.md, \"Profile CSV files\")",
      source_name, profile.value_column, ShowDerived(units::InMillimetres(form)), bound));
}

}  // namespace

MeasuredFit FitProfileFile(const std::filesystem::path& file, int orders, std::optional<double> ring_radius,
                           std::string_view part) {
  const std::string name = file.string();
  const MeasuredProfile profile = ReadProfileCsv(file);
  RequireDegreesUnderAngleDeg(profile, name);
  MeasuredFit measured{profile.quantity, {}};
  try {
    measured.fit = sampling::FitFourierSeries(profile.samples, orders);
  } catch (const std::invalid_argument& error) {
    throw InputError(fmt::format("{}: {}", name, error.what()));
  }
  RequireTheFitToExplainTheOutline(profile, measured.fit, orders, name);
  RequireAFormOfThePartsSize(profile, measured.fit, name, ring_radius, part);
  return measured;
}

std::vector<engine::Harmonic> FormHarmonics(const sampling::FourierFit& fit, bool keep_eccentricity) {
  std::vector<engine::Harmonic> form;
  for (const engine::Harmonic& h : fit.harmonics) {
    if (h.order >= 2 || keep_eccentricity) form.push_back(h);
  }
  return form;
}

double MeanDeviation(const MeasuredFit& measured, double ring_radius) {
  // A measured radius is the nominal radius plus the mean deviation.
  return measured.quantity == ProfileQuantity::kRadius ? measured.fit.mean - ring_radius : measured.fit.mean;
}

std::string OtherPartReason(const MeasuredFit& measured, double ring_radius, const std::string& file,
                            std::string_view radius_key, std::string_view part) {
  const double offset = MeanDeviation(measured, ring_radius);
  if (!(std::abs(offset) > kSameRingShare * ring_radius)) return {};
  const std::string what =
      measured.quantity == ProfileQuantity::kRadius
          ? fmt::format("its mean radius {} mm lies {} mm from {} = {} mm", units::InMillimetres(measured.fit.mean),
                        ShowDerived(units::InMillimetres(offset)), radius_key, units::InMillimetres(ring_radius))
          : fmt::format("its mean deviation is {} mm on a {} of {} mm", ShowDerived(units::InMillimetres(offset)), part,
                        units::InMillimetres(ring_radius));
  return fmt::format("{}: {}, more than {} %: a profile of another {} (or deviations in another unit)", file, what,
                     100.0 * kSameRingShare, part);
}

std::filesystem::path ReadProfilePath(const Site& site, const std::filesystem::path& folder, std::string_view allowed) {
  const std::filesystem::path file = folder / ReadText(site, allowed);
  std::error_code error;
  if (std::filesystem::is_regular_file(file, error)) return file;
  const bool exists = std::filesystem::exists(file, error);
  site.Fail(fmt::format("{}: {}", exists ? "not a file" : "no such file", file.string()), allowed);
}

}  // namespace ringtol::jobs
