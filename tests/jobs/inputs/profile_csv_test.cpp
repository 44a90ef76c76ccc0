#include "jobs/inputs/profile_csv.h"

#include <cmath>
#include <filesystem>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "jobs/inputs/input_error.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr double kDeg = std::numbers::pi / 180.0;

std::string ErrorFor(const std::string& text) {
  return ringtol::testing::MessageOf<InputError>([&] { ParseProfileCsv(text, "ring.csv"); });
}

// `text` as ring.csv in a folder of the test's own.
std::filesystem::path WriteFile(const std::string& text) {
  const std::filesystem::path path = ringtol::testing::FreshTestFolder("profile_csv_test") / "ring.csv";
  ringtol::testing::WriteText(path, text);
  return path;
}

// Every value is one correctly rounded parse times one unit factor, as the reference
// here computes it, so both agree to within EXPECT_DOUBLE_EQ's 4 ulp.
TEST(ParseProfileCsv, ReadsDegreesAndMillimetresAsRadiansAndMetres) {
  const MeasuredProfile profile = ParseProfileCsv("angle_deg,radius_mm\n0,100.0012\n90.5,99.9987\n", "ring.csv");
  EXPECT_EQ(profile.quantity, ProfileQuantity::kRadius);
  ASSERT_EQ(profile.samples.size(), 2u);
  EXPECT_DOUBLE_EQ(profile.samples[0].angle, 0.0);
  EXPECT_DOUBLE_EQ(profile.samples[0].value, 100.0012e-3);
  EXPECT_DOUBLE_EQ(profile.samples[1].angle, 90.5 * kDeg);
  EXPECT_DOUBLE_EQ(profile.samples[1].value, 99.9987e-3);
}

TEST(ParseProfileCsv, ReadsMicrometreDeviationsWithCommentsCrlfSpacesAndExtraColumns) {
  const std::string text =
      "\xEF\xBB\xBF# Talyrond export, ring 42\r\n"
      "\r\n"
      "  angle_deg , deviation_um,\tquality\r\n"
      "# first turn\r\n"
      "0.0, +1.25, ok\r\n"
      "\r\n"
      "359.5 ,-0.75 ,\tretake\r\n";
  const MeasuredProfile profile = ParseProfileCsv(text, "ring.csv");
  EXPECT_EQ(profile.quantity, ProfileQuantity::kDeviation);
  ASSERT_EQ(profile.samples.size(), 2u);
  EXPECT_DOUBLE_EQ(profile.samples[0].angle, 0.0);
  EXPECT_DOUBLE_EQ(profile.samples[0].value, 1.25e-6);
  EXPECT_DOUBLE_EQ(profile.samples[1].angle, 359.5 * kDeg);
  EXPECT_DOUBLE_EQ(profile.samples[1].value, -0.75e-6);
}

TEST(ParseProfileCsv, ReadsRadiansAndMillimetreDeviationsUnconverted) {
  const MeasuredProfile profile = ParseProfileCsv("angle_rad,deviation_mm\n-1.5,-0.002\n6.5,0\n", "ring.csv");
  EXPECT_EQ(profile.quantity, ProfileQuantity::kDeviation);
  ASSERT_EQ(profile.samples.size(), 2u);
  EXPECT_DOUBLE_EQ(profile.samples[0].angle, -1.5);
  EXPECT_DOUBLE_EQ(profile.samples[0].value, -0.002e-3);
  EXPECT_DOUBLE_EQ(profile.samples[1].angle, 6.5);
  EXPECT_DOUBLE_EQ(profile.samples[1].value, 0.0);
}

TEST(ReadProfileCsv, ReadsAFileFromDisk) {
  const MeasuredProfile profile = ReadProfileCsv(WriteFile("angle_deg, radius_mm\n10, 50\n"));
  ASSERT_EQ(profile.samples.size(), 1u);
  EXPECT_DOUBLE_EQ(profile.samples[0].angle, 10.0 * kDeg);
  EXPECT_DOUBLE_EQ(profile.samples[0].value, 50e-3);
}

TEST(ReadProfileCsv, RejectsAMissingFileOrADirectoryNamingThePath) {
  const std::filesystem::path missing = std::filesystem::path(::testing::TempDir()) / "no_such_profile.csv";
  try {
    ReadProfileCsv(missing);
    ADD_FAILURE() << "a missing file was accepted";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), AllOf(HasSubstr(missing.string()), HasSubstr("no such file")));
  }
  try {
    ReadProfileCsv(::testing::TempDir());
    ADD_FAILURE() << "a directory was accepted";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("a directory"));
  }
}

TEST(ParseProfileCsv, WordsErrorsInTheInputErrorForm) {
  EXPECT_EQ(ErrorFor("angle_deg,radius_mm\n0,1\n1,1\n2,1\n3,1\n4,1\n5,abc\n"),
            "ring.csv:7: radius_mm = abc: not a number; allowed: a finite number > 0");
}

TEST(ParseProfileCsv, RejectsNonNumericValuesNamingLineColumnAndValue) {
  EXPECT_THAT(ErrorFor("angle_deg,radius_mm\n0,100\n1.2.3,100\n"),
              HasSubstr("ring.csv:3: angle_deg = 1.2.3: not a number; allowed: a finite number"));
  EXPECT_THAT(ErrorFor("angle_deg,deviation_um\n0, \n"), HasSubstr("ring.csv:2: deviation_um = \"\": not a number"));
  EXPECT_THAT(ErrorFor("angle_deg,deviation_um\n0,+-1\n"), HasSubstr("ring.csv:2: deviation_um = +-1: not a number"));
}

TEST(ParseProfileCsv, RejectsNanAndInfinityNamingLineColumnAndValue) {
  EXPECT_THAT(ErrorFor("angle_deg,deviation_um\n0,nan\n"), HasSubstr("ring.csv:2: deviation_um = nan: not finite"));
  EXPECT_THAT(ErrorFor("angle_rad,radius_mm\n\n-inf,100\n"), HasSubstr("ring.csv:3: angle_rad = -inf: not finite"));
  EXPECT_THAT(ErrorFor("angle_deg,radius_mm\n0,1e999\n"),
              HasSubstr("ring.csv:2: radius_mm = 1e999: out of the range of a double"));
}

TEST(ParseProfileCsv, RejectsRadiiThatAreNotPositive) {
  EXPECT_THAT(ErrorFor("angle_deg,radius_mm\n0,-3\n"),
              HasSubstr("ring.csv:2: radius_mm = -3: not positive; allowed: a finite number > 0"));
  EXPECT_THAT(ErrorFor("angle_deg,radius_mm\n0,1\n5,0\n"), HasSubstr("ring.csv:3: radius_mm = 0: not positive"));
}

TEST(ParseProfileCsv, RejectsRowsWithTheWrongNumberOfFields) {
  EXPECT_THAT(ErrorFor("angle_deg,radius_mm\n0,100,7\n"),
              AllOf(HasSubstr("ring.csv:2: row `0,100,7`: 3 fields"),
                    HasSubstr("; allowed: 2 fields, one per column of the header on line 1")));
  EXPECT_THAT(ErrorFor("# c\nangle_deg,radius_mm,note\n0,100\n"),
              AllOf(HasSubstr("ring.csv:3: row `0,100`: 2 fields"), HasSubstr("header on line 2")));
}

TEST(ParseProfileCsv, RejectsUnknownColumnNamesListingTheAllowedOnes) {
  EXPECT_THAT(ErrorFor("angle,radius_mm\n0,100\n"),
              HasSubstr("ring.csv:1: column 1 = angle: unknown column name; allowed: angle_deg, angle_rad"));
  EXPECT_THAT(ErrorFor("# export\nangle_deg,radius_um\n0,100\n"),
              HasSubstr("ring.csv:2: column 2 = radius_um: unknown column name; "
                        "allowed: radius_mm, deviation_mm, deviation_um"));
  EXPECT_THAT(ErrorFor("angle_deg\n0\n"), HasSubstr("ring.csv:1: header `angle_deg`: fewer than 2 columns"));
}

TEST(ParseProfileCsv, RejectsAFileWithoutAHeader) {
  EXPECT_THAT(ErrorFor("# no header\n0, 100\n1, 100\n"),
              AllOf(HasSubstr("ring.csv:2: row `0, 100`: data before any header line"), HasSubstr("angle_deg")));
  EXPECT_THAT(ErrorFor("# only a comment\n\n"),
              HasSubstr("ring.csv: no header line: the file holds only comments and blank lines"));
  EXPECT_THAT(ErrorFor(""), HasSubstr("ring.csv: no header line"));
}

TEST(ParseProfileCsv, RejectsAHeaderWithoutDataRows) {
  EXPECT_THAT(ErrorFor("# export\nangle_deg, radius_mm\n# nothing measured\n"),
              HasSubstr("ring.csv:2: header `angle_deg, radius_mm`: no data rows follow; "
                        "allowed: at least one row of numbers"));
}

// A spreadsheet's "Unicode text" is UTF-16: named, not quoted as bytes (a message was cut at
// its first NUL byte).
TEST(ParseProfileCsv, RefusesUtf16AndUtf32TextNamingTheEncoding) {
  const std::string utf16le("\xFF\xFE" "a\0n\0g\0", 8);
  EXPECT_THAT(ErrorFor(utf16le), AllOf(HasSubstr("ring.csv: UTF-16 (little-endian) text"),
                                       HasSubstr("allowed: UTF-8 text"), HasSubstr("save the file as UTF-8")));
  EXPECT_THAT(ErrorFor(std::string("\0a\0n\0g\0l", 8)), HasSubstr("ring.csv: UTF-16 (big-endian) text, by its NUL bytes"));
  EXPECT_THAT(ErrorFor(std::string("\xFF\xFE\0\0a\0\0\0", 8)), HasSubstr("ring.csv: UTF-32 (little-endian) text"));
  EXPECT_THAT(ErrorFor(std::string("angle_deg, radius_mm\n0, 1\n1, \0\n", 30)),
              HasSubstr("ring.csv:3: a NUL byte (binary data, not text)"));
}

// Where the decimal separator is a comma, spreadsheets separate columns with semicolons.
TEST(ParseProfileCsv, NamesASeparatorOtherThanTheComma) {
  EXPECT_THAT(ErrorFor("angle_deg;radius_mm\n0,5;302,0012\n"),
              AllOf(HasSubstr("ring.csv:1: header `angle_deg;radius_mm`: columns separated by semicolons, not commas"),
                    HasSubstr("allowed: comma-separated columns and decimal points")));
  EXPECT_THAT(ErrorFor("angle_deg\tradius_mm\n0.5\t302.0012\n"),
              HasSubstr("header `angle_deg\\tradius_mm`: columns separated by tabs, not commas"));
  EXPECT_THAT(ErrorFor("angle_deg, radius_mm\n0,5, 302,0012\n"),
              HasSubstr("ring.csv:2: row `0,5, 302,0012`: 4 fields (decimal commas? numbers take a decimal point)"));
}

TEST(ParseProfileCsv, ShowsInvisibleCharactersInColumnNamesEscaped) {
  EXPECT_THAT(ErrorFor("angle_deg, radius_mm\xE2\x80\x8B\n0, 100\n"),
              HasSubstr("ring.csv:1: column 2 = radius_mm\\u200B: unknown column name"));
}

// ---- the fit's rules (profile_csv.h)

// `value(theta)` [m] at `points` angles spread evenly over one turn, as a tester exports it:
// the angle in `angle_column`'s unit, the value in `value_column`'s (metres per unit).
template <typename Value>
std::filesystem::path WriteExport(std::string_view angle_column, std::string_view value_column, double metres_per_unit,
                                  int points, Value value) {
  const double per_radian = angle_column == "angle_deg" ? 180.0 / std::numbers::pi : 1.0;
  std::ostringstream text;
  text.precision(17);
  text << angle_column << ", " << value_column << "\n";
  for (int i = 0; i < points; ++i) {
    const double theta = 2.0 * std::numbers::pi * i / points;
    text << theta * per_radian << ", " << value(theta) / metres_per_unit << "\n";
  }
  return WriteFile(text.str());
}

constexpr double kRadius = 0.302;  // [m]
// A bore with 20 um of ovality and 8 um at order 5.
double Bore(double theta) { return kRadius + 20e-6 * std::cos(2.0 * theta + 0.5) + 8e-6 * std::cos(5.0 * theta - 1.0); }

std::string FitErrorFor(const std::filesystem::path& file, int orders, std::optional<double> ring_radius = {}) {
  return ringtol::testing::MessageOf<InputError>([&] { FitProfileFile(file, orders, ring_radius); });
}

// The same readings in degrees under angle_rad: each wrapped to a far-away angle, the fit
// finds almost nothing, and the ovality would vanish from the ring silently.
TEST(FitProfileFile, RefusesDegreesUnderAngleRadNamingTheFitsRSquared) {
  std::ostringstream text;
  text.precision(17);
  text << "angle_rad, radius_mm\n";
  for (int degree = 0; degree < 360; ++degree) text << degree << ", " << Bore(degree * kDeg) * 1e3 << "\n";
  const std::filesystem::path file = WriteFile(text.str());
  EXPECT_THAT(FitErrorFor(file, 6),
              AllOf(HasSubstr(file.string() + ": a fit of orders 0..6 with R^2 = 0.0"),
                    HasSubstr("leaves most of the readings unexplained"), HasSubstr("span 57.1 turns"),
                    HasSubstr("degrees under angle_rad?"), HasSubstr("allowed: angles in the unit the column names")));
}

TEST(FitProfileFile, RefusesRadiansUnderAngleDeg) {
  const std::filesystem::path file = WriteExport("angle_rad", "radius_mm", 1e-3, 360, Bore);
  ringtol::testing::WriteText(file, ringtol::testing::ReplaceOnce(ringtol::testing::ReadText(file), "angle_rad", "angle_deg"));
  EXPECT_THAT(FitErrorFor(file, 6), AllOf(HasSubstr(file.string() + ": angle_deg: the readings span 6.266 degrees"),
                                          HasSubstr("radians under angle_deg?")));
}

TEST(FitProfileFile, RefusesAFitThatLeavesOutTheForm) {
  const std::filesystem::path file = WriteExport("angle_deg", "radius_mm", 1e-3, 360, Bore);
  // Orders 0..1 hold none of the ovality: the residual is the whole form.
  EXPECT_THAT(FitErrorFor(file, 1), AllOf(HasSubstr("a fit of orders 0..1 with R^2 = "), HasSubstr("form at orders above 1?")));
  EXPECT_NO_THROW(FitProfileFile(file, 5));
}

// A ring as round as the tester's noise: the fit explains little of the readings, but what
// it leaves is noise, and its numbers stand.
TEST(FitProfileFile, AcceptsARingAsRoundAsTheTestersNoise) {
  std::mt19937_64 random(7);
  std::normal_distribution<double> noise(0.0, 0.1e-6);  // [m]
  const std::filesystem::path file = WriteExport("angle_deg", "deviation_um", 1e-6, 720, [&](double theta) {
    return 0.03e-6 * std::cos(3.0 * theta) + noise(random);
  });
  const MeasuredFit measured = FitProfileFile(file, 6);
  EXPECT_LT(measured.fit.r_squared, kMinRSquared) << "the readings must be mostly noise for this test";
}

// Micrometres under deviation_mm: a form a thousand times too large, refused by `ringtol
// fit` too, which has no ring to hold it to.
TEST(FitProfileFile, RefusesAFormTooLargeForTheColumnsUnit) {
  const auto in_micrometres = [](double theta) { return (Bore(theta) - kRadius) * 1e3; };
  const std::filesystem::path file = WriteExport("angle_deg", "deviation_mm", 1e-3, 360, in_micrometres);
  EXPECT_THAT(FitErrorFor(file, 6),
              AllOf(HasSubstr(file.string() + ": deviation_mm: a form of 28 mm"), HasSubstr("more than 1 mm"),
                    HasSubstr("deviations in another unit than the column names?"),
                    HasSubstr("allowed: deviation_um for micrometres")));
  EXPECT_THAT(FitErrorFor(file, 6, 0.05), HasSubstr("more than 1 % of a ring of 50 mm"));
  // The loosest class's form, 0.2 mm, in millimetres, stands.
  const std::filesystem::path loose =
      WriteExport("angle_deg", "deviation_mm", 1e-3, 360, [](double theta) { return 0.2e-3 * std::cos(2.0 * theta); });
  EXPECT_NO_THROW(FitProfileFile(loose, 6));
}

}  // namespace
}  // namespace ringtol::jobs
