#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "jobs/inputs/input_error.h"
#include "jobs/inputs/scene_file.h"
#include "jobs/studies/solver_ladder.h"

namespace ringtol::jobs {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

engine::Scene PaperScene() { return ReadScene(RINGTOL_SOURCE_DIR "/examples/paper/scene.toml"); }

// One case (order 2), one repeat, no multi-second explicit runs: the whole ladder in ~1 s.
const LadderResult& Quick() {
  static const LadderResult result = [] {
    LadderOptions options;
    options.cases = "orders";
    options.repeats = 1;
    options.max_cases = 1;
    options.skip_slow = true;
    return RunLadder(PaperScene(), options, nullptr);
  }();
  return result;
}

const LadderRow& Row(const std::string& method) {
  const auto& rows = Quick().rows;
  const auto it = std::find_if(rows.begin(), rows.end(), [&](const LadderRow& r) { return r.method == method; });
  if (it == rows.end()) throw std::logic_error("no ladder row " + method);
  return *it;
}

TEST(SolverLadder, RejectsUnknownCasesAndNoRepeats) {
  LadderOptions cases;
  cases.cases = "everything";
  EXPECT_THROW(RunLadder(PaperScene(), cases, nullptr), InputError);
  LadderOptions repeats;
  repeats.repeats = 0;
  EXPECT_THROW(RunLadder(PaperScene(), repeats, nullptr), InputError);
}

// The reference is the dynamic BDF at 1e-10; the same integrator at 1e-8 must land within
// its own tolerance of it (measured 0.002 um), while the quasi-static rungs miss by the
// start transient the article's 0.5 s settle leaves (~47 um for order 2).
TEST(SolverLadder, ErrorsSeparateTheRungsAsThePhysicsSays) {
  constexpr double kTightBdf = 0.1e-6;      // [m] fifty times the measured error at 1e-8
  constexpr double kStartTransient = 10e-6;  // [m] a fifth of the measured transient share
  EXPECT_LT(Row("dynamic BDF rtol 1e-08").error, kTightBdf);
  EXPECT_GT(Row("quasistatic penalty, S steps").error, kStartTransient);
  EXPECT_GT(Row("linear").error, kStartTransient);
  // Numerically the quasistatic rung converges with its steps.
  EXPECT_LT(Row("quasistatic penalty, 4S steps").numerical_error, Row("quasistatic penalty, 0.25S steps").numerical_error);
  EXPECT_LT(Row("dynamic BDF rtol 1e-05").time, Row("dynamic BDF rtol 1e-08").time);
}

TEST(SolverLadder, AnUnstableExplicitStepIsAFailureWithItsReason) {
  const LadderRow& row = Row("dynamic explicit RK4 h=40us, both reduced");
  EXPECT_EQ(row.cases_failed, 1);
  EXPECT_THAT(row.first_failure, HasSubstr("stability limit"));
  EXPECT_TRUE(std::isnan(row.error));
}

TEST(SolverLadder, CsvAndSvgCarryEveryMethodAndTheHighlight) {
  const LadderResult& result = Quick();
  ASSERT_GE(result.fastest_within, 0);
  std::ostringstream csv;
  WriteLadderCsv(csv, result);
  std::istringstream lines(csv.str());
  std::string header;
  std::getline(lines, header);
  EXPECT_EQ(header, "method,rung,cases_run,cases_failed,time_ms,error_um,numerical_error_um,first_failure");
  int rows = 0;
  for (std::string line; std::getline(lines, line);) ++rows;
  EXPECT_EQ(rows, static_cast<int>(result.rows.size()));
  std::ostringstream svg;
  WriteLadderSvg(svg, result);
  const std::string text = svg.str();
  EXPECT_THAT(text, StartsWith("<svg"));
  EXPECT_THAT(text, HasSubstr("</svg>"));
  EXPECT_THAT(text, HasSubstr("fastest within 1 um: " +
                              result.rows[static_cast<std::size_t>(result.fastest_within)].method));
  // Every method that ran gets a marker (a filled series of one point); the refused explicit
  // step has none. The ring around the fastest is drawn unfilled.
  const std::string marker = "<g class=\"series\" fill=\"#";
  std::size_t markers = 0;
  for (std::size_t at = text.find(marker); at != std::string::npos; at = text.find(marker, at + 1)) ++markers;
  EXPECT_EQ(markers, result.rows.size() - 1);
}

}  // namespace
}  // namespace ringtol::jobs
