// RunFit on roundness-tester exports written here from known harmonics: the text, the
// JSON and the scene fragment must give them back, and bad input must be refused with
// messages that name the file.
#include "jobs/cli/fit_command.h"

#include <cmath>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "jobs/inputs/input_error.h"
#include "jobs/inputs/scene_file.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

using engine::Harmonic;
using ringtol::testing::ReadText;
using ringtol::testing::ReplaceOnce;
using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr double kPi = std::numbers::pi;
constexpr double kDegPerRad = 180.0 / kPi;
constexpr double kEps = std::numeric_limits<double>::epsilon();

// The paper ring's bore with micrometre form errors and a set-up eccentricity (order 1).
constexpr double kRadius = 0.302;  // [m]
const std::vector<Harmonic> kTruth = {{1, 3e-6, 0.4}, {2, 20e-6, 0.5}, {3, 15e-6, -1.0}, {5, 8e-6, 2.5}};
constexpr double kSmallestAmplitude = 3e-6;  // [m] of kTruth
constexpr int kOrders = 8;                   // above every order of kTruth: 4, 6, 7, 8 must come out zero
constexpr int kPoints = 331;                 // one per degree, none strictly between 100 and 130 deg

// Noise-free readings are the true radii rounded twice (shortest decimal in mm, then
// times 1e-3 on reading): <= 2 eps kRadius each. Least squares amplifies that by at most
// the condition number, asserted below kMaxCondition, and the solve adds rounding of the
// same size per unknown: (2 kOrders + 1) x 2 eps x kMaxCondition x kRadius.
constexpr double kMaxCondition = 10.0;
constexpr double kRoundOff = (2 * kOrders + 1) * 2.0 * kEps * kMaxCondition * kRadius;  // [m], 2.3e-14
// A coefficient error e turns the phase by at most e / C.
constexpr double kPhaseRoundOffDeg = kRoundOff / kSmallestAmplitude * kDegPerRad;
// The text prints amplitudes to 4 decimals in um and phases to 3 in degrees: half a unit
// of the last digit, plus the round-off.
constexpr double kTextAmplitudeUm = 0.5e-4 + kRoundOff * 1e6;
constexpr double kTextPhaseDeg = 0.5e-3 + kPhaseRoundOffDeg;
// The fragment writes mm and degrees to round-trip and the scene reader converts back:
// value / unit and number * unit, two roundings, plus one for 1 / kRadiansPerDegree.
constexpr double kFragmentRelative = 4.0 * kEps;

const std::filesystem::path kPaperScene = RINGTOL_SOURCE_DIR "/examples/paper/scene.toml";
const std::filesystem::path kExampleProfile = RINGTOL_SOURCE_DIR "/examples/measured/ring_profile.csv";
constexpr std::string_view kRingHarmonics = "harmonics = []                    # e.g.";

std::filesystem::path TestFolder() { return ringtol::testing::FreshTestFolder("fit_command_test"); }

double Value(double theta, double mean, const std::vector<Harmonic>& harmonics) {
  double value = mean;
  for (const Harmonic& h : harmonics) value += h.amplitude * std::cos(h.order * theta + h.phase);
  return value;
}

// A tester's export of `mean + harmonics` [m] in the column's unit (metres per unit).
std::filesystem::path WriteProfile(const std::filesystem::path& file, std::string_view column, double unit,
                                   double mean, const std::vector<Harmonic>& harmonics) {
  std::string text = fmt::format("# written by fit_command_test\nangle_deg, {}\n", column);
  for (int degree = 0; degree < 360; ++degree) {
    if (degree > 100 && degree < 130) continue;
    text += fmt::format("{}, {}\n", degree, Value(degree * kPi / 180.0, mean, harmonics) / unit);
  }
  ringtol::testing::WriteText(file, text);
  return file;
}

std::filesystem::path WriteRadii(const std::filesystem::path& folder) {
  return WriteProfile(folder / "profile.csv", "radius_mm", 1e-3, kRadius, kTruth);
}

// C_n and phi_n of kTruth, zero for orders it lacks.
Harmonic Truth(int order) {
  for (const Harmonic& h : kTruth) {
    if (h.order == order) return h;
  }
  return {order, 0.0, 0.0};
}

// a - b in degrees, wrapped into (-180, 180].
double AngleDifferenceDeg(double a, double b) { return std::remainder(a - b, 360.0); }

FitCommand Command(const std::filesystem::path& profile, int orders) {
  FitCommand command;
  command.profile = profile;
  command.orders = orders;
  return command;
}

std::string Output(const FitCommand& command) {
  std::ostringstream out;
  EXPECT_EQ(RunFit(command, out), 0);
  return out.str();
}

nlohmann::json JsonOutput(FitCommand command) {
  command.json = true;
  return nlohmann::json::parse(Output(command));
}

std::string ErrorFor(const FitCommand& command) {
  try {
    std::ostringstream out;
    RunFit(command, out);
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "RunFit accepted the input";
  return "";
}

// The [ring] keys of a fragment, pasted over the harmonics of the paper scene, or of the
// same scene at another nominal inner radius [mm].
std::string PaperSceneWithFragment(const std::string& fragment, const std::string& inner_radius_mm = "302.0") {
  const std::string keys = fragment.substr(fragment.find("[ring]\n") + std::string_view("[ring]\n").size());
  const std::string text =
      ReplaceOnce(ReadText(kPaperScene), "inner_radius_mm = 302.0\n", "inner_radius_mm = " + inner_radius_mm + "\n");
  return ReplaceOnce(text, kRingHarmonics, keys + "#");
}

TEST(RunFit, PrintsTheFittedHarmonicsAsATable) {
  const std::filesystem::path folder = TestFolder();
  const std::string text = Output(Command(WriteRadii(folder), kOrders));
  EXPECT_THAT(text, AllOf(HasSubstr("points            331\n"), HasSubstr("largest gap       30.000 deg\n"),
                          HasSubstr("mean radius       302.000000 mm\n"), HasSubstr("R^2               1.000000\n")));

  constexpr std::string_view kTableHeader = "standard_error_um\n";
  std::istringstream lines(text.substr(text.find(kTableHeader) + kTableHeader.size()));
  for (int order = 1; order <= kOrders; ++order) {
    SCOPED_TRACE("order " + std::to_string(order));
    std::string line;
    ASSERT_TRUE(std::getline(lines, line));
    std::istringstream fields(line);
    int printed_order = 0;
    double amplitude_um = 0.0;
    double phase_deg = 0.0;
    fields >> printed_order >> amplitude_um >> phase_deg;
    EXPECT_EQ(printed_order, order);
    const Harmonic truth = Truth(order);
    EXPECT_NEAR(amplitude_um, truth.amplitude * 1e6, kTextAmplitudeUm);
    if (truth.amplitude > 0.0) {
      EXPECT_NEAR(AngleDifferenceDeg(phase_deg, truth.phase * kDegPerRad), 0.0, kTextPhaseDeg);
    }
    EXPECT_EQ(line.find("set-up eccentricity") != std::string::npos, order == 1) << line;
  }
}

TEST(RunFit, PrintsTheSameFitAsJson) {
  const std::filesystem::path folder = TestFolder();
  const nlohmann::json j = JsonOutput(Command(WriteRadii(folder), kOrders));
  EXPECT_EQ(j["points"], kPoints);
  ASSERT_LT(j["condition_number"].get<double>(), kMaxCondition);
  // The gap runs from 100 to 130 degrees, each rounded to eps x 2 pi as an angle in rad.
  EXPECT_NEAR(j["largest_gap_deg"].get<double>(), 30.0, 2.0 * kEps * 360.0);
  EXPECT_NEAR(j["mean_radius_mm"].get<double>(), kRadius * 1e3, kRoundOff * 1e3);
  EXPECT_FALSE(j.contains("mean_deviation_um"));
  EXPECT_LE(j["residual_max_um"].get<double>(), kRoundOff * 1e6);
  ASSERT_EQ(j["harmonics"].size(), static_cast<std::size_t>(kOrders));
  for (int order = 1; order <= kOrders; ++order) {
    SCOPED_TRACE("order " + std::to_string(order));
    const nlohmann::json& h = j["harmonics"][static_cast<std::size_t>(order - 1)];
    const Harmonic truth = Truth(order);
    EXPECT_EQ(h["order"], order);
    EXPECT_NEAR(h["amplitude_um"].get<double>(), truth.amplitude * 1e6, kRoundOff * 1e6);
    if (truth.amplitude > 0.0) {
      EXPECT_NEAR(AngleDifferenceDeg(h["phase_deg"].get<double>(), truth.phase * kDegPerRad), 0.0, kPhaseRoundOffDeg);
    }
    EXPECT_LE(h["standard_error_um"].get<double>(), kRoundOff * 1e6);
    EXPECT_EQ(h["set_up_eccentricity"], order == 1);
  }
}

TEST(RunFit, ReportsTheMeanDeviationOfADeviationExport) {
  const std::filesystem::path folder = TestFolder();
  constexpr double kMeanDeviation = 1.5e-6;  // [m]
  const std::filesystem::path profile =
      WriteProfile(folder / "deviations.csv", "deviation_um", 1e-6, kMeanDeviation, kTruth);
  const nlohmann::json j = JsonOutput(Command(profile, kOrders));
  // Deviations of ~50 um, rounded twice: far below the radius-based round-off.
  EXPECT_NEAR(j["mean_deviation_um"].get<double>(), kMeanDeviation * 1e6, kRoundOff * 1e6);
  EXPECT_FALSE(j.contains("mean_radius_mm"));
  EXPECT_THAT(Output(Command(profile, kOrders)), HasSubstr("mean deviation    1.5000 um\n"));
}

TEST(RunFit, WritesAFragmentThatGivesASceneTheFittedRing) {
  const std::filesystem::path folder = TestFolder();
  const std::filesystem::path profile = WriteRadii(folder);
  const std::filesystem::path fragment = folder / "ring.toml";
  FitCommand command = Command(profile, kOrders);
  command.fragment = fragment;
  EXPECT_THAT(Output(command),
              HasSubstr("fragment          " + fragment.string() + " ([ring] with orders 2..8)\n"));
  const std::string written = ReadText(fragment);
  EXPECT_THAT(written, AllOf(HasSubstr("written by ringtol fit from\n#   " + profile.string() + "\n"),
                             HasSubstr("orders 0..8 to 331 points: R^2 = 1.000000"), HasSubstr("is left out")));

  const sampling::FourierFit fit = FitProfileFile(profile, kOrders).fit;
  const std::vector<Harmonic> form = FormHarmonics(fit, false);
  ASSERT_EQ(form.size(), static_cast<std::size_t>(kOrders - 1));
  EXPECT_EQ(form.front().order, 2);

  // The form alone: pasted into the article's scene and into a 150 mm design, the scene's
  // own size stays and the harmonics are the fit's.
  EXPECT_THAT(written, ::testing::Not(HasSubstr("\ninner_radius_mm =")));
  EXPECT_THAT(written, HasSubstr("# Its mean radius is 30"));
  for (const char* nominal : {"302.0", "150.0"}) {
    SCOPED_TRACE(std::string("inner_radius_mm = ") + nominal);
    const engine::Scene pasted = ParseScene(PaperSceneWithFragment(written, nominal), "pasted.toml");
    EXPECT_EQ(pasted.ring.inner.radius(), std::stod(nominal) * 1e-3);
    EXPECT_EQ(pasted.ring.inner.mean_deviation(), 0.0);
    const std::vector<Harmonic>& read = pasted.ring.inner.harmonics();
    ASSERT_EQ(read.size(), form.size());
    for (std::size_t i = 0; i < form.size(); ++i) {
      SCOPED_TRACE("order " + std::to_string(form[i].order));
      EXPECT_EQ(read[i].order, form[i].order);
      EXPECT_NEAR(read[i].amplitude, form[i].amplitude, kFragmentRelative * form[i].amplitude);
      EXPECT_NEAR(read[i].phase, form[i].phase, kFragmentRelative * std::abs(form[i].phase));
    }
  }

  // The scene that names the export directly has the same outline: the same harmonics,
  // and radius + mean deviation the fitted mean (one subtraction and one addition).
  const std::filesystem::path scene_file = folder / "scene.toml";
  std::ofstream(scene_file) << ReplaceOnce(ReadText(kPaperScene), kRingHarmonics,
                                           "measured_profile = { file = \"profile.csv\", orders = 8 } #");
  const engine::Scene measured = ReadScene(scene_file);
  EXPECT_EQ(measured.ring.inner.harmonics(), form);
  EXPECT_NEAR(measured.ring.inner.radius() + measured.ring.inner.mean_deviation(), fit.mean, 2.0 * kEps * fit.mean);
}

TEST(RunFit, KeepsTheEccentricityInTheFragmentWhenAsked) {
  const std::filesystem::path folder = TestFolder();
  const std::filesystem::path fragment = folder / "ring.toml";
  FitCommand command = Command(WriteRadii(folder), kOrders);
  command.keep_eccentricity = true;
  command.fragment = fragment;
  EXPECT_THAT(Output(command), HasSubstr("([ring] with orders 1..8)"));
  const engine::Scene scene = ParseScene(PaperSceneWithFragment(ReadText(fragment)), "pasted.toml");
  const std::vector<Harmonic>& read = scene.ring.inner.harmonics();
  ASSERT_EQ(read.size(), static_cast<std::size_t>(kOrders));
  EXPECT_EQ(read[0].order, 1);
  EXPECT_NEAR(read[0].amplitude, Truth(1).amplitude, kRoundOff);
  EXPECT_THAT(ReadText(fragment), HasSubstr("is kept"));
}

TEST(RunFit, StatesTheMeanDeviationOfADeviationExportInTheFragmentsComment) {
  const std::filesystem::path folder = TestFolder();
  const std::filesystem::path profile = WriteProfile(folder / "deviations.csv", "deviation_um", 1e-6, 2e-6, kTruth);
  const std::filesystem::path fragment = folder / "ring.toml";
  FitCommand command = Command(profile, kOrders);
  command.fragment = fragment;
  Output(command);
  const std::string written = ReadText(fragment);
  EXPECT_THAT(written, HasSubstr("# Its mean deviation is "));
  EXPECT_THAT(written, ::testing::Not(HasSubstr("\nmean_deviation_mm =")));
  EXPECT_THAT(written, ::testing::Not(HasSubstr("\ninner_radius_mm =")));
}

TEST(RunFit, ShowsStandardErrorsItCannotEstimateAsMissing) {
  // 5 points for orders 0..2: an interpolation, with no residual to estimate the noise from.
  const std::filesystem::path folder = TestFolder();
  const std::filesystem::path profile = folder / "five.csv";
  std::ofstream(profile) << "angle_deg, deviation_um\n0, 1\n72, 2\n144, -1\n216, 0.5\n288, 0\n";
  const nlohmann::json j = JsonOutput(Command(profile, 2));
  ASSERT_EQ(j["harmonics"].size(), 2u);
  EXPECT_TRUE(j["harmonics"][0]["standard_error_um"].is_null());
  EXPECT_THAT(Output(Command(profile, 2)), HasSubstr("n/a"));
}

TEST(RunFit, RefusesMoreOrdersThanThePointsSupportNamingTheFile) {
  const std::filesystem::path folder = TestFolder();
  const std::filesystem::path profile = folder / "short.csv";
  std::ofstream(profile) << "angle_deg, radius_mm\n0, 302\n36, 302.01\n72, 302\n108, 301.99\n144, 302\n";
  const std::filesystem::path fragment = folder / "ring.toml";
  std::ofstream(fragment) << "kept\n";
  FitCommand command = Command(profile, 20);
  command.fragment = fragment;
  EXPECT_THAT(ErrorFor(command),
              AllOf(HasSubstr(profile.string() + ": fitting orders up to 20 needs at least 2*20+1 = 41 points"),
                    HasSubstr("got 5")));
  EXPECT_EQ(ReadText(fragment), "kept\n") << "a refused fit must leave an existing fragment alone";
}

// Micrometres under deviation_mm: the scene refuses them against its ring; `ringtol fit`
// alone, with no ring, against the largest form a deviation export can hold. The fragment
// is left as it was.
TEST(RunFit, RefusesMicrometresUnderDeviationMm) {
  const std::filesystem::path folder = TestFolder();
  std::vector<Harmonic> in_micrometres = kTruth;
  for (Harmonic& h : in_micrometres) h.amplitude *= 1e3;  // 20 um written as 20 "mm"
  const std::filesystem::path profile = WriteProfile(folder / "deviations.csv", "deviation_mm", 1e-3, 0.0, in_micrometres);
  const std::filesystem::path fragment = folder / "ring.toml";
  std::ofstream(fragment) << "kept\n";
  FitCommand command = Command(profile, kOrders);
  command.fragment = fragment;
  EXPECT_THAT(ErrorFor(command), AllOf(HasSubstr(profile.string() + ": deviation_mm: a form of 43 mm"),
                                       HasSubstr("deviation_um for micrometres")));
  EXPECT_EQ(ReadText(fragment), "kept\n");
}

TEST(RunFit, RefusesAFragmentThatCannotBeWrittenNamingIt) {
  const std::filesystem::path folder = TestFolder();
  FitCommand command = Command(WriteRadii(folder), kOrders);
  command.fragment = folder / "no_such_folder" / "ring.toml";
  EXPECT_THAT(ErrorFor(command),
              AllOf(HasSubstr("--fragment " + command.fragment.string()), HasSubstr("cannot open for writing")));
  command.fragment = command.profile;
  EXPECT_THAT(ErrorFor(command), HasSubstr("the profile itself"));
}

TEST(RunFit, RefusesOrdersOutOfRangeAndUnreadableFiles) {
  const std::filesystem::path folder = TestFolder();
  const std::filesystem::path profile = WriteRadii(folder);
  EXPECT_EQ(ErrorFor(Command(profile, 0)), "--orders 0: out of range; allowed: an integer >= 1 and <= 1000");
  EXPECT_THAT(ErrorFor(Command(profile, 1001)), HasSubstr("--orders 1001: out of range"));
  const std::filesystem::path missing = folder / "missing.csv";
  EXPECT_THAT(ErrorFor(Command(missing, kOrders)), AllOf(HasSubstr(missing.string()), HasSubstr("no such file")));
}

// The example export is synthetic: orders 2, 3, 5 and 8 of stated amplitudes and phases,
// an eccentricity, and Gaussian noise of 1 um. Each fitted amplitude lies within 5 of its
// standard errors of the stated one (two-sided 5.7e-7 per value for Gaussian noise; the
// file is fixed, so the outcome is too), and a phase within 5 standard errors / C [rad].
TEST(RunFit, RecoversTheStatedHarmonicsOfTheExampleExport) {
  constexpr double kStandardErrors = 5.0;
  const nlohmann::json j = JsonOutput(Command(kExampleProfile, 12));
  EXPECT_EQ(j["points"], kPoints);
  EXPECT_NEAR(j["largest_gap_deg"].get<double>(), 30.0, 2.0 * kEps * 360.0);
  // sigma = 1 um noise: the residual rms estimates it; (points - unknowns) / points = 0.92
  // of it, within a few per cent from 331 samples.
  EXPECT_GT(j["residual_rms_um"].get<double>(), 0.8);
  EXPECT_LT(j["residual_rms_um"].get<double>(), 1.2);
  const std::vector<Harmonic> stated = {{1, 4.0, -35.0}, {2, 35.0, 20.0}, {3, 22.0, -75.0}, {5, 12.0, 140.0},
                                        {8, 10.0, 60.0}};  // um, deg
  for (const Harmonic& s : stated) {
    SCOPED_TRACE("order " + std::to_string(s.order));
    const nlohmann::json& h = j["harmonics"][static_cast<std::size_t>(s.order - 1)];
    const double error = h["standard_error_um"].get<double>();
    EXPECT_NEAR(h["amplitude_um"].get<double>(), s.amplitude, kStandardErrors * error);
    EXPECT_NEAR(AngleDifferenceDeg(h["phase_deg"].get<double>(), s.phase), 0.0,
                kStandardErrors * error / s.amplitude * kDegPerRad);
  }
}

}  // namespace
}  // namespace ringtol::jobs
