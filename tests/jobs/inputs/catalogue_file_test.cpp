// The shipped catalogue's roller classes against ISO 492's outer-ring table as the bearing
// makers' catalogues reprint it (docs/tolerances.md §0, §1). The expected values are typed
// here from the sources, not from jobs/inputs/catalogue.toml, so that a row mistyped or
// missing there fails.
#include "jobs/inputs/catalogue_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstddef>
#include <stdexcept>
#include <string>

#include "engine/units.h"

namespace ringtol::jobs {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using sampling::DiameterSeries;
using units::kMetresPerMicrometre;
using units::kMetresPerMillimetre;

// One row of ISO 492's outer-ring table for one class, over < D <= up to [mm], as the
// sources print it [µm]: Kea, VDsp by diameter series 9 | 0,1 | 2,3,4, and the lower
// deviation of ΔDmp (the upper is 0).
struct Iso492Row {
  const char* class_name;
  double over_mm, up_to_mm;
  double kea, vdsp_9, vdsp_0_1, vdsp_2_4, mean_lower;
};

// Sources, docs/tolerances.md §1.1, §1.2, §1.4: S2 (NSK E1102e Table 8.2.2) and S3 (NTN
// 2203/E Table 6.4 (2)) for every class; S1 (SKF 2018 Tables 2, 3, 4) for Normal, 6 and 5;
// S4 (Timken Table 16) for the Kea and ΔDmp of Normal, 6 and 5. Classes 5 and 4 print one
// VDsp for series 0 to 4, class 2 one for every series.
constexpr Iso492Row kIso492Rows[] = {
    {"Normal", 18, 30, 15, 12, 9, 7, -9},
    {"6", 18, 30, 9, 10, 8, 6, -8},
    {"5", 18, 30, 6, 6, 5, 5, -6},
    {"4", 18, 30, 4, 5, 4, 4, -5},
    {"2", 18, 30, 2.5, 4, 4, 4, -4},
    {"Normal", 30, 50, 20, 14, 11, 8, -11},
    {"6", 30, 50, 10, 11, 9, 7, -9},
    {"5", 30, 50, 7, 7, 5, 5, -7},
    {"4", 30, 50, 5, 6, 5, 5, -6},
    {"2", 30, 50, 2.5, 4, 4, 4, -4},
    {"Normal", 80, 120, 35, 19, 19, 11, -15},
    {"6", 80, 120, 18, 16, 16, 10, -13},
    {"5", 80, 120, 10, 10, 8, 8, -10},
    {"4", 80, 120, 6, 8, 6, 6, -8},
    {"2", 80, 120, 5, 5, 5, 5, -5},
    {"Normal", 400, 500, 80, 56, 56, 34, -45},  // no class 4 or 2 in any source
    {"6", 400, 500, 40, 41, 41, 25, -33},
    {"5", 400, 500, 23, 23, 17, 17, -23},
};

// Every class of kIso492Rows whose row starts over `over_mm`, looked up at `diameter_mm`,
// gives that row.
void ExpectRowAt(double diameter_mm, double over_mm) {
  const sampling::ToleranceCatalogue catalogue = ShippedCatalogue();
  int rows = 0;
  for (const Iso492Row& row : kIso492Rows) {
    if (row.over_mm != over_mm) continue;
    ++rows;
    ASSERT_TRUE(diameter_mm > row.over_mm && diameter_mm <= row.up_to_mm) << "a test of another row";
    const std::string where =
        std::string("class ") + row.class_name + " at D = " + ::testing::PrintToString(diameter_mm) + " mm";
    const double diameter = diameter_mm * kMetresPerMillimetre;
    const auto at = [&](DiameterSeries series) { return catalogue.Roller(row.class_name, diameter, series); };
    ASSERT_NO_THROW(at(DiameterSeries::kSeries9)) << where;
    const sampling::RollerTolerance series_9 = at(DiameterSeries::kSeries9);
    EXPECT_DOUBLE_EQ(series_9.kea, row.kea * kMetresPerMicrometre) << where;
    EXPECT_DOUBLE_EQ(series_9.vdsp, row.vdsp_9 * kMetresPerMicrometre) << where;
    EXPECT_DOUBLE_EQ(at(DiameterSeries::kSeries0To1).vdsp, row.vdsp_0_1 * kMetresPerMicrometre) << where;
    EXPECT_DOUBLE_EQ(at(DiameterSeries::kSeries2To4).vdsp, row.vdsp_2_4 * kMetresPerMicrometre) << where;
    EXPECT_DOUBLE_EQ(series_9.mean_diameter_lower, row.mean_lower * kMetresPerMicrometre) << where;
    EXPECT_EQ(series_9.mean_diameter_upper, 0.0) << where;
    EXPECT_THAT(series_9.source, HasSubstr("S2, S3")) << where;
  }
  EXPECT_GT(rows, 0) << "no row over " << over_mm << " mm in kIso492Rows";
}

// The natural track roller of an 800 mm rotary table.
TEST(ShippedCatalogue, FortyMillimetreRollersHaveIso492sRowInEveryClass) { ExpectRowAt(40, 30); }

TEST(ShippedCatalogue, HundredAndTwentyMillimetreRollersHaveIso492sRowInEveryClass) { ExpectRowAt(120, 80); }

// A row holds over < D <= up to.
TEST(ShippedCatalogue, ThirtyMillimetresIsTheTopOfTheRowBelowAndJustAboveStartsTheNext) {
  ExpectRowAt(30, 18);
  constexpr double kJustAbove30Mm = 30.001;
  ExpectRowAt(kJustAbove30Mm, 30);
}

TEST(ShippedCatalogue, FourHundredToFiveHundredMillimetresHasClassesNormalSixAndFiveOnly) {
  ExpectRowAt(450, 400);
  const sampling::ToleranceCatalogue catalogue = ShippedCatalogue();
  for (const char* name : {"4", "2"}) {
    EXPECT_THAT([&] { catalogue.Roller(name, 450 * kMetresPerMillimetre, DiameterSeries::kSeries9); },
                ::testing::ThrowsMessage<std::invalid_argument>(
                    AllOf(HasSubstr("no value for diameter 450 mm"), HasSubstr("does not extrapolate"))))
        << name;
  }
}

// ISO 492 tabulates Normal, 6 and 5 from D = 2.5 to 800 mm here, and 4 and 2 up to 400 mm
// (docs/tolerances.md §1.4): every roller class's rows follow one another without a gap.
TEST(ShippedCatalogue, RollerClassesCoverTheirDiametersWithoutGaps) {
  const sampling::ToleranceCatalogue catalogue = ShippedCatalogue();
  ASSERT_EQ(catalogue.roller_classes.size(), 5u);
  for (const auto& roller_class : catalogue.roller_classes) {
    ASSERT_FALSE(roller_class.rows.empty()) << roller_class.name;
    EXPECT_DOUBLE_EQ(roller_class.rows.front().outside_diameter.over, 2.5 * kMetresPerMillimetre) << roller_class.name;
    const bool to_400_mm = roller_class.name == "4" || roller_class.name == "2";
    EXPECT_DOUBLE_EQ(roller_class.rows.back().outside_diameter.up_to, (to_400_mm ? 400 : 800) * kMetresPerMillimetre)
        << roller_class.name;
    for (std::size_t k = 1; k < roller_class.rows.size(); ++k) {
      EXPECT_EQ(roller_class.rows[k].outside_diameter.over, roller_class.rows[k - 1].outside_diameter.up_to)
          << roller_class.name << " row " << k;
    }
  }
}

}  // namespace
}  // namespace ringtol::jobs
