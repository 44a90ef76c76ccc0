#include "jobs/inputs/profile_csv.h"

#include <cmath>
#include <filesystem>
#include <numbers>
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
              HasSubstr("ring.csv:2: row `0,100,7`: 3 fields; allowed: 2 fields, one per column of the header on line 1"));
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

}  // namespace
}  // namespace ringtol::jobs
