// The allocation report from plain data: a hand-made outcome of nine candidates (three
// ring classes by three roller classes) whose verdicts, yields and intervals are known, so
// that what the page and the JSON say can be checked against what was put in; and the
// page in headless Chromium (label browser).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "jobs/report/allocation_report.h"
#include "jobs/report/allocation_summary.h"
#include "jobs/report/report_text.h"
#include "tests/support/chromium.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

constexpr int kClasses = 3;             // options per component
constexpr std::int64_t kSamples = 512;  // the recommendation's samples
constexpr double kQuantileLimitMm = 0.1;
constexpr double kYieldLimitMm = 0.2;
constexpr double kYieldLevel = 0.95;

// Candidate (ring option r, roller option l) is r * 3 + l (the last component fastest);
// option costs 1, 2, 4 for both, so candidate 4 (the current design, 1 + 1) costs 4.
constexpr double kOptionCost[kClasses] = {1.0, 2.0, 4.0};
constexpr std::int64_t kCurrent = 4;

AllocationIdentity Identity() {
  AllocationIdentity id;
  id.ringtol_version = "test";
  id.allocation_path = "allocation.toml";
  id.design = "monte_carlo";
  id.solver = "quasistatic";
  id.screen = "linear";
  id.search = "exhaustive";
  id.seed = 7;
  id.samples = 4096;
  id.first_samples = 256;
  id.confidence = 0.95;
  id.components = {"ring", "rollers"};
  id.options = {{{"waterjet", "process", 40.0, 1.0}, {"turned", "process", 20.0, 2.0}, {"ground", "process", 10.0, 4.0}},
                {{"6", "process", 15.0, 1.0}, {"5", "process", 8.0, 2.0}, {"4", "inspected", 4.0, 4.0}}};
  id.constraints = {{"d_trajectory_mm", analysis::ConstraintKind::kQuantile, 0.99, kQuantileLimitMm},
                    {"runout_mm", analysis::ConstraintKind::kYield, kYieldLevel, kYieldLimitMm}};
  id.reference = kCurrent;
  using sampling::ErrorSource;
  id.inputs = {{"ring.order2.amplitude_um", ErrorSource::kRingShape, -1, 2, "ring.order2", "ring"},
               {"ring.order3.amplitude_um", ErrorSource::kRingShape, -1, 3, "ring.order3", "ring"},
               {"roller.a.size_um", ErrorSource::kRollerShape, 0, 0, "roller.a.size", "roller.a.shape"},
               {"roller.b.size_um", ErrorSource::kRollerShape, 1, 0, "roller.b.size", "roller.b.shape"},
               {"roller.a.position.offset_um", ErrorSource::kRollerPosition, 0, 0, "roller.a.position",
                "roller.a.position"},
               {"roller.spring.stiffness_pct", ErrorSource::kSpring, 2, 0, "roller.spring.spring", "roller.spring.spring"}};
  return id;
}

analysis::ConstraintJudgement Judged(analysis::Verdict verdict, double estimate, double lower, double upper,
                                     std::int64_t samples, std::int64_t to_decide = 0) {
  return {verdict, estimate, {lower, upper}, samples, to_decide};
}

struct Made {
  analysis::Verdict verdict;
  analysis::Settlement settlement;
  std::optional<EvaluationRole> role;
  std::int64_t samples;
  double yield;  // NaN: not simulated
  double q99, q99_lower, q99_upper;  // the quantile constraint's judgement [mm]
};

// The hand-made search: the loosest three infeasible (two by the screen), candidate 3 (cost
// 3) undecided at every sample, candidate 4 (cost 4) the cheapest feasible, 2 and 6 (cost
// 5) the alternatives, the rest costlier than the recommendation. The front of cost
// against yield is then 0, 3, 4, 6: 1 has 3's cost and less yield, 2 has more cost than 4
// and less yield.
AllocationOutcome Outcome() {
  using analysis::Settlement;
  using analysis::Verdict;
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const Made made[] = {
      {Verdict::kInfeasible, Settlement::kSimulated, EvaluationRole::kScreen, 256, 0.80, 0.16, 0.15, 0.17},
      {Verdict::kInfeasible, Settlement::kSimulated, EvaluationRole::kScreen, 256, 0.90, 0.13, 0.12, 0.14},
      {Verdict::kFeasible, Settlement::kSimulated, EvaluationRole::kConfirm, 512, 0.993, 0.088, 0.082, 0.096},
      {Verdict::kUndecided, Settlement::kSimulated, EvaluationRole::kConfirm, 4096, 0.985, 0.099, 0.097, 0.101},
      {Verdict::kFeasible, Settlement::kSimulated, EvaluationRole::kConfirm, kSamples, 0.995, 0.085, 0.080, 0.094},
      {Verdict::kFeasible, Settlement::kCostlier, std::nullopt, 0, kNaN, 0, 0, 0},
      {Verdict::kFeasible, Settlement::kSimulated, EvaluationRole::kConfirm, 512, 0.999, 0.07, 0.065, 0.075},
      {Verdict::kFeasible, Settlement::kCostlier, std::nullopt, 0, kNaN, 0, 0, 0},
      {Verdict::kFeasible, Settlement::kCostlier, std::nullopt, 0, kNaN, 0, 0, 0},
  };
  AllocationOutcome outcome;
  for (int r = 0; r < kClasses; ++r) {
    for (int l = 0; l < kClasses; ++l) {
      const Made& m = made[r * kClasses + l];
      CandidateOutcome c;
      c.options = {r, l};
      c.cost = kOptionCost[r] + kOptionCost[l];
      c.relative_cost = c.cost / (kOptionCost[1] + kOptionCost[1]);
      c.verdict = m.verdict;
      c.settlement = m.settlement;
      c.settled_by = m.role;
      c.samples = m.samples;
      if (m.settlement == Settlement::kSimulated) {
        const auto within = static_cast<std::int64_t>(std::round(m.yield * static_cast<double>(m.samples)));
        c.yield = analysis::EstimateProportion(within, m.samples, 0.95);
        const Verdict q = m.q99_upper <= kQuantileLimitMm  ? Verdict::kFeasible
                          : m.q99_lower > kQuantileLimitMm ? Verdict::kInfeasible
                                                           : Verdict::kUndecided;
        c.constraints = {Judged(q, m.q99, m.q99_lower, m.q99_upper, m.samples, q == Verdict::kUndecided ? 20000 : 0),
                         Judged(c.yield.interval.lower >= kYieldLevel ? Verdict::kFeasible : Verdict::kInfeasible,
                                c.yield.value, c.yield.interval.lower, c.yield.interval.upper, m.samples)};
      }
      outcome.candidates.push_back(std::move(c));
    }
  }
  outcome.complete = true;
  outcome.recommendation = kCurrent;
  outcome.alternatives = {2, 6};
  outcome.undecided_cheaper = {3};
  outcome.front = {0, 3, 4, 6};
  outcome.common_random_numbers_gain = 7.5;
  outcome.simulated = 6;
  outcome.settled_by_screen = 2;
  outcome.samples_screen = 1536;
  outcome.samples_confirm = 5632;
  return outcome;
}

// The recommendation's samples: D_trajectory driven by the two ring inputs (u0, u1), the
// rollers, position and spring barely; runout another mix. One sample failed.
AllocationReportInput Input() {
  AllocationReportInput input;
  input.results = "allocation.h5";
  input.identity = Identity();
  input.outcome = Outcome();
  const std::size_t d = input.identity.inputs.size();
  std::mt19937_64 generator(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double>& trajectory = input.recommendation_samples["d_trajectory_mm"];
  std::vector<double>& runout = input.recommendation_samples["runout_mm"];
  for (std::int64_t i = 0; i < kSamples; ++i) {
    std::vector<double> u(d);
    for (double& x : u) x = unit(generator);
    input.design_points.insert(input.design_points.end(), u.begin(), u.end());
    trajectory.push_back(0.03 + 0.04 * u[0] + 0.03 * u[1] + 0.005 * u[2] + 0.002 * u[4]);
    runout.push_back(0.1 + 0.05 * u[3] + 0.01 * u[0]);
  }
  trajectory[17] = runout[17] = std::numeric_limits<double>::quiet_NaN();
  return input;
}

// The HTML between two markers (the second searched after the first).
std::string Between(const std::string& html, const std::string& from, const std::string& to) {
  const std::size_t begin = html.find(from);
  if (begin == std::string::npos) return "";
  const std::size_t end = html.find(to, begin);
  return html.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
}

// The table row of one candidate in a piece of the page.
std::string CandidateRow(const std::string& html, std::int64_t index) {
  return Between(html, fmt::format("data-candidate=\"{}\"", index), "</tr>");
}

// Two candidates that differ only in a component's mode read differently: every class is
// named with its mode.
TEST(AllocationSummary, CandidatesThatDifferOnlyInAModeReadDifferently) {
  AllocationIdentity identity;
  identity.components = {"rollers", "roller_positions", "springs"};
  identity.options = {{{"5", "inspected", 5e-6, 1.0}},
                      {{"IT7", "process", 70e-6, 1.0}, {"IT7", "inspected", 70e-6, 1.5}},
                      {{"pm10", "process", 0.1, 0.1}}};
  CandidateOutcome bored, reworked;
  bored.options = {0, 0, 0};
  reworked.options = {0, 1, 0};
  EXPECT_EQ(CandidateClasses(identity, bored),
            "rollers 5 (inspected), roller_positions IT7 (process), springs pm10 (process)");
  EXPECT_EQ(CandidateClasses(identity, reworked),
            "rollers 5 (inspected), roller_positions IT7 (inspected), springs pm10 (process)");
}

// Where `text` names a class of `identity`, its mode follows: "RollerSix (inspected)". The
// count of names found, so that a test can tell it looked at something.
int ExpectEveryClassCarriesItsMode(const std::string& text, const AllocationIdentity& identity,
                                   const std::string& where) {
  int found = 0;
  for (const std::vector<AllocationIdentity::Option>& options : identity.options) {
    for (const AllocationIdentity::Option& option : options) {
      const std::string named = option.class_name + " (" + option.mode + ")";
      for (std::size_t at = text.find(option.class_name); at != std::string::npos;
           at = text.find(option.class_name, at + 1)) {
        ++found;
        EXPECT_EQ(text.compare(at, named.size(), named), 0)
            << where << " names " << option.class_name << " without its mode: ..."
            << text.substr(at < 60 ? 0 : at - 60, 120) << "...";
      }
    }
  }
  return found;
}

// The same over every string of a JSON document, except the class and mode of a component's
// option, which it gives apart.
int ExpectEveryClassCarriesItsMode(const nlohmann::json& json, const AllocationIdentity& identity,
                                   const std::string& where) {
  if (json.is_string()) return ExpectEveryClassCarriesItsMode(json.get<std::string>(), identity, where);
  if (!json.is_structured()) return 0;
  int found = 0;
  const bool option = json.is_object() && json.contains("class") && json.contains("mode");
  for (auto it = json.begin(); it != json.end(); ++it) {
    if (option && (it.key() == "class" || it.key() == "mode")) continue;
    found += ExpectEveryClassCarriesItsMode(*it, identity, where);
  }
  return found;
}

// A buyer orders what the page says: every place the page, its JSON, the terminal summary
// and the summary's JSON name a class, its mode follows, for a component whose options all
// share one mode as for one whose options differ. (Class names here are distinctive, so
// that every place can be found.)
TEST(AllocationReport, EveryPlaceThatNamesAClassNamesItsMode) {
  AllocationReportInput input = Input();
  input.identity.options = {{{"WaterjetCut", "process", 40.0, 1.0},
                             {"TurnedRing", "process", 20.0, 2.0},
                             {"GroundRing", "process", 10.0, 4.0}},
                            {{"RollerSix", "inspected", 15.0, 1.0},
                             {"RollerFive", "inspected", 8.0, 2.0},
                             {"RollerFour", "inspected", 4.0, 4.0}}};
  const AllocationReport report = MakeAllocationReport(input);
  const std::string html = AllocationReportHtml(report);
  // The answer, the alternatives, the undecided candidate, the recommendation's table with
  // the current design, and both tables of the front.
  EXPECT_GE(ExpectEveryClassCarriesItsMode(html, input.identity, "the page"), 20);
  EXPECT_THAT(Between(html, "id=\"answer\"", "</div>"), HasSubstr("<b>ring TurnedRing (process), rollers RollerFive "
                                                                 "(inspected)</b>"));
  EXPECT_GE(ExpectEveryClassCarriesItsMode(AllocationReportJson(report), input.identity, "the report's JSON"), 10);
  std::ostringstream terminal;
  PrintAllocation(terminal, input.identity, input.outcome);
  EXPECT_GE(ExpectEveryClassCarriesItsMode(terminal.str(), input.identity, "the terminal summary"), 4);
  EXPECT_GE(ExpectEveryClassCarriesItsMode(AllocationJson(input.identity, input.outcome), input.identity,
                                           "the summary's JSON"),
            4);
}

// A variance ratio of ten million is exact arithmetic on two nearly equal columns, not a
// precision gain worth its digits: said in words.
TEST(AllocationSummary, AHugeCommonRandomNumbersGainIsSaidInWords) {
  EXPECT_EQ(CommonRandomGainText(25.5), "25.5 times");
  EXPECT_THAT(CommonRandomGainText(1.27e7), AllOf(HasSubstr("more than 10000 times"), ::testing::Not(HasSubstr("e+07"))));
}

TEST(AllocationReport, AnswerNamesTheRecommendedClassesTheirCostsAndTheirMargins) {
  const AllocationReport report = MakeAllocationReport(Input());
  const std::string html = AllocationReportHtml(report);
  const std::string answer = Between(html, "id=\"answer\"", "</div>");
  EXPECT_THAT(answer, HasSubstr("Recommended (candidate 4): <b>ring turned (process), rollers 5 (process)</b>"));
  // Cost 4 against the current design's 4, and twice the loosest's 2.
  EXPECT_THAT(answer, HasSubstr("Cost 1 relative to the current design, 2 times the loosest"));
  // Margins: the quantile's limit 0.1 mm less its interval's upper end 0.094 mm, in µm;
  // the yield interval's lower end less the required 95 %, in points.
  const CandidateReport& chosen = report.candidates[kCurrent];
  constexpr double kRoundOff = 1e-9;  // µm: a difference of decimals near 0.1 mm, times 1000
  EXPECT_NEAR(chosen.margins[0], 6.0, kRoundOff);
  EXPECT_EQ(report.margin_units[0], "µm");
  EXPECT_EQ(report.margin_units[1], "points");
  EXPECT_DOUBLE_EQ(chosen.margins[1], 100.0 * (chosen.outcome.yield.interval.lower - kYieldLevel));
  EXPECT_THAT(answer, HasSubstr(fmt::format("{:.4g} µm", chosen.margins[0])));
  EXPECT_THAT(answer, HasSubstr(fmt::format("{:.4g} points", chosen.margins[1])));
  // The next two, and the cheaper one still undecided with the samples that would decide it.
  EXPECT_THAT(answer, HasSubstr("candidate 2: ring waterjet (process), rollers 4 (inspected)"));
  EXPECT_THAT(answer, HasSubstr("candidate 6: ring ground (process), rollers 6 (process)"));
  EXPECT_THAT(answer, HasSubstr("candidate 3: ring turned (process), rollers 6 (process) &#8212; cost 0.75, about 20000 "
                                "samples"));
  EXPECT_THAT(answer, Not(HasSubstr("No candidate is feasible")));
  // The yield and the quantile verdicts answer different questions, and the page says so
  // beside the verdict.
  EXPECT_THAT(answer, HasSubstr("The yield counts the samples within every limit at once; each quantile constraint"));
}

// A margin of 0.6054 µm is written to the nanometre a margin means, as the allocation
// summary's is to the tenth of a micrometre: 0.605 µm, not its tenths of a nanometre.
TEST(AllocationReport, MarginsAreWrittenToTheNanometre) {
  AllocationReportInput input = Input();
  analysis::ConstraintJudgement& quantile = input.outcome.candidates[kCurrent].constraints[0];
  quantile.interval.upper = kQuantileLimitMm - 0.0006054;
  const std::string answer = Between(AllocationReportHtml(MakeAllocationReport(input)), "id=\"answer\"", "</div>");
  EXPECT_THAT(answer, HasSubstr("<td>0.605 µm</td>"));
  EXPECT_THAT(answer, Not(HasSubstr("0.6054")));
}

TEST(AllocationReport, FrontTableListsTheFrontInCostOrderWithTheRecommendationMarked) {
  const std::string html = AllocationReportHtml(MakeAllocationReport(Input()));
  const std::string front = Between(html, "The Pareto front, by cost", "<details>");
  std::vector<std::size_t> at;
  for (const std::int64_t i : {0, 3, 4, 6}) at.push_back(front.find(fmt::format("data-candidate=\"{}\"", i)));
  for (const std::size_t position : at) ASSERT_NE(position, std::string::npos);
  EXPECT_TRUE(std::is_sorted(at.begin(), at.end()));
  for (const std::int64_t off : {1, 2, 5, 7, 8}) {
    EXPECT_THAT(front, Not(HasSubstr(fmt::format("data-candidate=\"{}\"", off)))) << off;
  }
  EXPECT_THAT(CandidateRow(front, 4), HasSubstr("4 (recommended)"));
  EXPECT_THAT(CandidateRow(front, 0), HasSubstr("<td>screen</td>"));
  EXPECT_THAT(CandidateRow(front, 3), HasSubstr("<td>undecided</td><td>confirm</td><td>4096</td>"));
  // The chart draws all three verdicts and the recommendation, with a legend.
  const std::string chart = Between(html, "<svg", "</svg>");
  for (const char* entry : {"feasible", "infeasible", "undecided", "Pareto front", "recommended: 4"}) {
    EXPECT_THAT(chart, HasSubstr(entry)) << entry;
  }
}

TEST(AllocationReport, JsonHoldsTheNumbersThePageShows) {
  const AllocationReport report = MakeAllocationReport(Input());
  const std::string html = AllocationReportHtml(report);
  const nlohmann::json json = AllocationReportJson(report);
  EXPECT_EQ(json["recommendation"]["index"], kCurrent);
  ASSERT_EQ(json["front"].size(), 4u);
  const std::string front = Between(html, "The Pareto front, by cost", "<details>");
  for (const nlohmann::json& candidate : json["front"]) {
    const std::string row = CandidateRow(front, candidate["index"].get<std::int64_t>());
    EXPECT_THAT(row, HasSubstr(fmt::format("<td>{:.4g}</td>", candidate["relative_cost"].get<double>())));
    EXPECT_THAT(row, HasSubstr(YieldPercent(candidate["yield"]["value"].get<double>(),
                                            candidate["yield"]["trials"].get<std::int64_t>())));
    EXPECT_THAT(row, HasSubstr(fmt::format("{:.4g} [{:.4g}, {:.4g}]", candidate["constraints"][0]["estimate"].get<double>(),
                                           candidate["constraints"][0]["interval"][0].get<double>(),
                                           candidate["constraints"][0]["interval"][1].get<double>())));
    EXPECT_THAT(row, HasSubstr(fmt::format("<td>{}</td>", candidate["verdict"].get<std::string>())));
  }
  const std::string answer = Between(html, "id=\"answer\"", "</div>");
  for (const nlohmann::json& constraint : json["recommendation"]["constraints"]) {
    EXPECT_THAT(answer, HasSubstr(fmt::format("{:.4g}", constraint["margin"].get<double>())));
  }
  const nlohmann::json& trajectory = json["recommended_outputs"]["d_trajectory_mm"]["distribution"];
  EXPECT_EQ(trajectory["count"], kSamples - 1);  // one failed
  EXPECT_EQ(trajectory["upper_spec_limit"], kQuantileLimitMm);
  EXPECT_EQ(json["search"]["simulated"], 6);
  EXPECT_EQ(json["search"]["costlier"], 3);
  EXPECT_EQ(json["search"]["common_random_numbers_gain"], 7.5);
  EXPECT_THAT(Between(html, "id=\"search\"", "</table>"), HasSubstr("<td>7.5 times</td>"));
}

TEST(AllocationReport, NoFeasibleCandidateNamesTheBindingConstraintAndHowFarItMisses) {
  AllocationReportInput input = Input();
  AllocationOutcome& outcome = input.outcome;
  for (CandidateOutcome& c : outcome.candidates) {
    if (c.settlement == analysis::Settlement::kCostlier) {
      c.settlement = analysis::Settlement::kNotVisited;
      c.verdict = analysis::Verdict::kUnknown;
    }
    if (c.verdict == analysis::Verdict::kFeasible) c.verdict = analysis::Verdict::kInfeasible;
  }
  // The tightest (8) simulated: its 99 % quantile 0.12 mm [0.11, 0.13] against 0.1 mm.
  CandidateOutcome& tightest = outcome.candidates.back();
  tightest.settlement = analysis::Settlement::kSimulated;
  tightest.verdict = analysis::Verdict::kInfeasible;
  tightest.settled_by = EvaluationRole::kConfirm;
  tightest.samples = 512;
  tightest.yield = analysis::EstimateProportion(500, 512, 0.95);
  tightest.constraints = {Judged(analysis::Verdict::kInfeasible, 0.12, 0.11, 0.13, 512),
                          Judged(analysis::Verdict::kFeasible, tightest.yield.value, tightest.yield.interval.lower,
                                 tightest.yield.interval.upper, 512)};
  outcome.recommendation.reset();
  outcome.alternatives.clear();
  outcome.undecided_cheaper.clear();
  outcome.binding = {0};
  input.recommendation_samples.clear();
  input.design_points.clear();
  const AllocationReport report = MakeAllocationReport(input);
  const std::string html = AllocationReportHtml(report);
  const std::string answer = Between(html, "id=\"answer\"", "</div>");
  EXPECT_THAT(answer, HasSubstr("No candidate is feasible"));
  const std::string binding = Between(answer, "<li class=\"binding\">", "</li>");
  EXPECT_THAT(binding, HasSubstr("99 % quantile of D_trajectory [mm] &#8804; 0.1"));
  // The margin is the limit less the interval's upper end, 0.1 - 0.13 mm = -30 µm.
  EXPECT_THAT(binding, HasSubstr("short by 30 µm"));
  EXPECT_THAT(answer, Not(HasSubstr("runout")));  // met: not binding
  EXPECT_EQ(AllocationReportJson(report)["binding"], nlohmann::json::array({0}));
  EXPECT_TRUE(report.recommended_outputs.empty());
}

TEST(AllocationReport, AnInterruptedSearchSaysItsAnswerMayChange) {
  AllocationReportInput input = Input();
  input.outcome.complete = false;
  std::string answer = Between(AllocationReportHtml(MakeAllocationReport(input)), "id=\"answer\"", "</div>");
  EXPECT_THAT(answer, HasSubstr("Recommended (candidate 4)"));
  EXPECT_THAT(answer, HasSubstr("The search did not run to its end"));
  // Without a recommendation yet, nothing is said to be infeasible.
  input.outcome.recommendation.reset();
  const AllocationReport report = MakeAllocationReport(input);
  answer = Between(AllocationReportHtml(report), "id=\"answer\"", "</div>");
  EXPECT_THAT(answer, HasSubstr("No candidate is known to be feasible yet"));
  EXPECT_THAT(answer, Not(HasSubstr("No candidate is feasible")));
  EXPECT_FALSE(report.tightest);
}

TEST(AllocationReport, TheGroupThatDrivesTheOutputRanksFirstBySource) {
  const AllocationReport report = MakeAllocationReport(Input());
  ASSERT_EQ(report.recommended_outputs.size(), 2u);
  const RecommendedOutput& trajectory = report.recommended_outputs[0];
  ASSERT_TRUE(trajectory.sensitivity) << trajectory.sensitivity_problem;
  const SensitivityLevel* by_source = nullptr;
  for (const SensitivityLevel& level : trajectory.sensitivity->levels) {
    if (level.level == "source") by_source = &level;
  }
  ASSERT_NE(by_source, nullptr);
  ASSERT_EQ(by_source->entries.size(), 4u);
  EXPECT_EQ(by_source->entries.front().name, "ring_shape");
  // The model is linear in independent uniform inputs, so each source's share of the
  // variance is its coefficients' squares over all: ring (0.04^2 + 0.03^2) / (that +
  // 0.005^2 + 0.002^2) = 0.989. The sum of SRC^2 leaves out the cross term
  // 2 b0 b1 cov(u0, u1) / Var y = 0.96 r for the sample correlation r of u0 and u1, and
  // |r| < 3 / sqrt(n) = 0.13 at three sigma (n = 511).
  constexpr double kRingShare = (0.04 * 0.04 + 0.03 * 0.03) / (0.04 * 0.04 + 0.03 * 0.03 + 0.005 * 0.005 + 0.002 * 0.002);
  constexpr double kShareTolerance = 0.96 * 0.13;
  EXPECT_NEAR(by_source->entries.front().ranking, kRingShare, kShareTolerance);
  // Runout is driven by the second roller input: roller shape first.
  ASSERT_TRUE(report.recommended_outputs[1].sensitivity);
  for (const SensitivityLevel& level : report.recommended_outputs[1].sensitivity->levels) {
    if (level.level == "source") {
      EXPECT_EQ(level.entries.front().name, "roller_shape");
    }
  }
  const std::string html = AllocationReportHtml(report);
  EXPECT_THAT(html, HasSubstr("Tighten <b>ring shape</b> first"));
}

TEST(AllocationReport, AnOutcomeThatDoesNotMatchItsIdentityIsRefused) {
  AllocationReportInput input = Input();
  input.outcome.candidates.pop_back();
  EXPECT_THROW(MakeAllocationReport(input), std::invalid_argument);
  input = Input();
  input.design_points.pop_back();
  EXPECT_THROW(MakeAllocationReport(input), std::invalid_argument);
}

// The tests that start headless Chromium (label browser).
class AllocationReportInChromium : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = ringtol::testing::FreshTestFolder("allocation_report_test"); }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

TEST_F(AllocationReportInChromium, PageIsSelfContainedAndHeadlessChromiumPaintsItsCharts) {
  const std::filesystem::path page = dir_ / "allocation.html";
  const std::string html = AllocationReportHtml(MakeAllocationReport(Input()));
  ringtol::testing::WriteText(page, html);
  for (const char* fetch : ringtol::testing::kFetches) EXPECT_THAT(html, Not(HasSubstr(fetch))) << fetch;

  const ringtol::testing::ChromiumPage shown = ringtol::testing::RenderInChromium(page, dir_);
  ringtol::testing::ExpectPaintedWithoutErrors(shown);
  EXPECT_GE(shown.svg_count, 7u) << "the front, and per constrained output a histogram, a CDF and the sensitivity bars";
  EXPECT_THAT(shown.dom.out, HasSubstr("Recommended (candidate 4)"));
  EXPECT_THAT(shown.dom.out, HasSubstr("The Pareto front, by cost"));
}

}  // namespace
}  // namespace ringtol::jobs
