// The report's view of measured populations: parts of a known single lobe, written here as
// roundness exports, must come back with their amplitude and form; the class they are
// compared with must be the file's, else the tightest every part meets; and the class's
// column must be what the sampler draws from that class.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "analysis/order_statistics.h"
#include "engine/units.h"
#include "jobs/campaign/campaign.h"
#include "jobs/cli/report_command.h"
#include "jobs/inputs/input_error.h"
#include "jobs/inputs/sampling_file.h"
#include "jobs/report/campaign_report.h"
#include "jobs/report/population_view.h"
#include "jobs/report/report_html.h"
#include "jobs/report/report_text.h"
#include "sampling/assembly_sampler.h"
#include "sampling/design.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Not;

constexpr double kPi = 3.14159265358979323846;
// The fit of exports written to a nanometre's millionth recovers a lobe to far better than this.
constexpr double kFitUm = 1e-4;

const std::filesystem::path kScene = std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/paper/scene.toml";

class PopulationViewTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = ringtol::testing::FreshTestFolder("population_view_test"); }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  struct Lobe {
    int order = 0;
    double amplitude_um = 0.0;
    double phase_rad = 0.0;
  };

  // An export of a part of nominal radius `radius_mm`, `size_um` above it, with `lobes`: a
  // reading every degree.
  void WritePart(const std::string& name, double radius_mm, double size_um, const std::vector<Lobe>& lobes) {
    std::string text = "angle_deg, radius_mm\n";
    for (int step = 0; step < 360; ++step) {
      const double theta = step * kPi / 180.0;
      double deviation_um = size_um;
      for (const Lobe& lobe : lobes) deviation_um += lobe.amplitude_um * std::cos(lobe.order * theta + lobe.phase_rad);
      text += fmt::format("{}, {:.10f}\n", step, radius_mm + deviation_um * 1e-3);
    }
    ringtol::testing::WriteText(dir_ / name, text);
  }

  // Rings of the paper's scene (bore 604 mm), each a lobe of order 3: RONt twice its amplitude.
  void WriteRings(const std::vector<double>& amplitudes_um) {
    for (std::size_t k = 0; k < amplitudes_um.size(); ++k) {
      WritePart(fmt::format("ring_{}.csv", k + 1), 302.0, 3.0 + static_cast<double>(k),
                {{3, amplitudes_um[k], 0.4 * static_cast<double>(k)}});
    }
  }

  // A sampling file drawing `table` ([population.ring] or [population.rollers]) from the parts written.
  SamplingPlan Plan(const std::string& table, const std::string& keys) {
    ringtol::testing::WriteText(dir_ / "sampling.toml",
                                fmt::format("scene = \"{}\"\n[population.{}]\n{}", kScene.string(), table, keys));
    return ReadSamplingFile(dir_ / "sampling.toml");
  }

  static PopulationViewOptions Quick() {
    PopulationViewOptions options;
    options.class_parts = 1024;
    return options;
  }

  std::filesystem::path dir_;
};

TEST_F(PopulationViewTest, ASingleLobeComesBackAsEachPartsAmplitudeAndTheMedianOfThem) {
  WriteRings({9.0, 10.0, 13.0});
  const SamplingPlan plan =
      Plan("ring", "profiles = [\"ring_1.csv\", \"ring_2.csv\", \"ring_3.csv\"]\norders = 5\nclass = \"IT7/2\"\n");
  const std::vector<PopulationView> views = ViewPopulations(plan, Quick());
  ASSERT_EQ(views.size(), 1u);
  const PopulationView& view = views.front();
  ASSERT_EQ(view.orders.size(), 4u);  // 2..5: the tester's centring (order 1) is dropped
  EXPECT_EQ(view.orders[1].order, 3);
  EXPECT_NEAR(view.orders[1].measured_median_um, 10.0, kFitUm);
  EXPECT_NEAR(view.orders[1].measured_max_um, 13.0, kFitUm);
  for (const std::size_t k : {0u, 2u, 3u}) EXPECT_NEAR(view.orders[k].measured_max_um, 0.0, kFitUm);
  ASSERT_EQ(view.parts.size(), 3u);
  const double amplitudes[] = {9.0, 10.0, 13.0};
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(view.parts[k].name, fmt::format("ring_{}.csv", k + 1));
    EXPECT_NEAR(view.parts[k].amplitudes_um[1], amplitudes[k], kFitUm);
    EXPECT_NEAR(view.parts[k].roundness_um, 2.0 * amplitudes[k], kFitUm);
    EXPECT_NEAR(view.parts[k].form_um, 2.0 * amplitudes[k], kFitUm);
    ASSERT_TRUE(view.parts[k].size_deviation_um.has_value());
    EXPECT_NEAR(*view.parts[k].size_deviation_um, 3.0 + static_cast<double>(k), kFitUm);
  }
  EXPECT_EQ(view.class_name, "IT7/2");
  EXPECT_FALSE(view.class_chosen);
  EXPECT_DOUBLE_EQ(view.class_limit_um, 35.0);
  EXPECT_EQ(PartsWithinClass(view), 3);
  EXPECT_THAT(PopulationLine(view),
              AllOf(HasSubstr("ring population: 3 measured parts, resampled; against IT7/2: 3 of 3 within RONt 35 µm"),
                    HasSubstr("order 3 median 10 µm against the class's"), Not(HasSubstr("outside"))));
}

// Drawn again here with another seed, the class's median and 95th percentile of every order
// agree with the view's to the draws' precision (about 1.5 % for either at 4096 parts); an
// order the class does not draw (a ring's order 1) has no class column, and the line quotes
// the largest order the class draws rather than the tester's centring.
TEST_F(PopulationViewTest, TheClassColumnIsWhatTheSamplerDrawsFromTheClass) {
  WriteRings({9.0, 10.0, 13.0});
  for (const char* name : {"ring_1.csv", "ring_2.csv", "ring_3.csv"}) {
    WritePart(name, 302.0, 0.0, {{1, 40.0, 0.0}, {3, 10.0, 0.0}});
  }
  const SamplingPlan plan =
      Plan("ring", "profiles = [\"ring_1.csv\", \"ring_2.csv\", \"ring_3.csv\"]\norders = 6\nkeep_eccentricity = true\n"
                   "class = \"IT7/2\"\nmode = \"inspected\"\n");
  const PopulationView view = ViewPopulations(plan).front();
  EXPECT_EQ(view.class_parts_drawn, 4096);
  ASSERT_EQ(view.orders.size(), 6u);
  EXPECT_FALSE(view.orders[0].class_median_um.has_value());
  EXPECT_NEAR(view.orders[0].measured_median_um, 40.0, kFitUm);
  EXPECT_THAT(PopulationLine(view), HasSubstr("order 3 median 10 µm against the class's"));

  const sampling::AssemblyTolerances tolerances =
      ToleranceOfClass(plan, sampling::ErrorSource::kRingShape, "IT7/2", sampling::ToleranceMode::kInspected);
  sampling::AssemblySamplerOptions sampler_options;
  sampler_options.seed = 99;
  const sampling::AssemblySampler sampler(plan.scene, tolerances, sampler_options);
  sampling::DesignOptions design_options;
  design_options.seed = 99;
  sampling::Design design(sampler.dimension(), design_options);
  std::map<int, std::vector<double>> drawn;
  for (std::int64_t i = 0; i < 4096; ++i) {
    const sampling::SampledAssembly assembly = sampler.Sample(design, i);
    for (std::size_t k = 0; k < sampler.inputs().size(); ++k) {
      if (sampler.inputs()[k].name == fmt::format("ring.order{}.amplitude_um", sampler.inputs()[k].order)) {
        drawn[sampler.inputs()[k].order].push_back(assembly.values[k]);
      }
    }
  }
  for (std::size_t k = 1; k < view.orders.size(); ++k) {
    const OrderComparison& order = view.orders[k];
    std::vector<double>& values = drawn[order.order];
    ASSERT_EQ(values.size(), 4096u) << "order " << order.order;
    std::sort(values.begin(), values.end());
    ASSERT_TRUE(order.class_median_um.has_value() && order.class_q95_um.has_value());
    EXPECT_NEAR(*order.class_median_um / analysis::Median(values), 1.0, 0.05) << "order " << order.order;
    EXPECT_NEAR(*order.class_q95_um / analysis::EstimateQuantile(values, 0.95).value, 1.0, 0.05)
        << "order " << order.order;
  }
  // The spectrum falls as 1/n: the class's median of order 2 is thrice that of order 6.
  EXPECT_NEAR(*view.orders[1].class_median_um / *view.orders[5].class_median_um, 3.0, 0.2);
}

// Parts of RONt 18, 20 and 26 µm at 604 mm: IT6/2 (22 µm) holds two of them, IT7/2 (35 µm)
// all three, so IT7/2 is the default, and naming IT6/2 counts and names the third as outside.
TEST_F(PopulationViewTest, WithoutAClassTheTightestEveryPartMeetsIsChosenAndATighterOneNamesThePartOutside) {
  WriteRings({9.0, 10.0, 13.0});
  const std::string parts = "profiles = [\"ring_1.csv\", \"ring_2.csv\", \"ring_3.csv\"]\norders = 4\n";
  const PopulationView chosen = ViewPopulations(Plan("ring", parts), Quick()).front();
  EXPECT_EQ(chosen.class_name, "IT7/2");
  EXPECT_TRUE(chosen.class_chosen);
  EXPECT_EQ(PartsWithinClass(chosen), 3);
  EXPECT_THAT(PopulationLine(chosen),
              HasSubstr("against IT7/2, the tightest class every part meets at 604 mm: 3 of 3"));

  const PopulationView tighter = ViewPopulations(Plan("ring", parts + "class = \"IT6/2\"\n"), Quick()).front();
  EXPECT_DOUBLE_EQ(tighter.class_limit_um, 22.0);
  EXPECT_EQ(PartsWithinClass(tighter), 2);
  EXPECT_TRUE(tighter.parts[0].within_class);
  EXPECT_FALSE(tighter.parts[2].within_class);
  EXPECT_THAT(PopulationLine(tighter), HasSubstr("2 of 3 within RONt 22 µm (outside: ring_3.csv)"));
  const nlohmann::json json = PopulationJson(tighter);
  EXPECT_EQ(json["class"]["parts_within"], 2);
  EXPECT_EQ(json["parts"][2]["within_class"], false);
}

// Parts no class holds are compared with the loosest class at their diameter, which says so.
TEST_F(PopulationViewTest, PartsNoClassHoldsAreComparedWithTheLoosestAndTheLineSaysSo) {
  WriteRings({10.0, 300.0});
  const PopulationView view =
      ViewPopulations(Plan("ring", "profiles = [\"ring_1.csv\", \"ring_2.csv\"]\norders = 4\n"), Quick()).front();
  EXPECT_EQ(view.class_name, "ISO2768-L");
  EXPECT_EQ(PartsWithinClass(view), 1);
  EXPECT_THAT(PopulationLine(view), AllOf(HasSubstr("the loosest class at 604 mm (none holds every part)"),
                                          HasSubstr("(outside: ring_2.csv)")));
}

// Rollers of radius 5 mm with one lobe of order 2 (two-point variation four times the
// amplitude, RONt twice it), a diameter 2 µm under nominal: at 10 mm class 6 allows VDsp
// 9 µm and class 5 5 µm, so of VDsp 4, 4.4 and 8 µm class 6 is the tightest all meet.
TEST_F(PopulationViewTest, RollersAreJudgedOnTheirTwoPointVariationAgainstVdsp) {
  const double amplitudes[] = {1.0, 1.1, 2.0};
  for (std::size_t k = 0; k < 3; ++k) {
    WritePart(fmt::format("roller_{}.csv", k + 1), 5.0, -1.0, {{2, amplitudes[k], 0.3 * static_cast<double>(k)}});
  }
  const std::string parts = "profiles = [\"roller_1.csv\", \"roller_2.csv\", \"roller_3.csv\"]\norders = 3\n";
  const PopulationView view = ViewPopulations(Plan("rollers", parts), Quick()).front();
  EXPECT_FALSE(view.ring);
  EXPECT_EQ(view.measure, sampling::FormMeasure::kTwoPointVariation);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_NEAR(view.parts[k].form_um, 4.0 * amplitudes[k], kFitUm);
    EXPECT_NEAR(view.parts[k].roundness_um, 2.0 * amplitudes[k], kFitUm);
    EXPECT_NEAR(*view.parts[k].size_deviation_um, -2.0, kFitUm);  // a mean diameter, as ΔDmp states it
  }
  EXPECT_EQ(view.class_name, "6");
  EXPECT_TRUE(view.class_chosen);
  EXPECT_NEAR(view.orders[0].measured_median_um, 1.1, kFitUm);
  // Three rollers an assembly: 342 assemblies give the 1024 parts asked for, and two more.
  EXPECT_EQ(view.class_parts_drawn, 1026);
  EXPECT_TRUE(view.orders[0].class_median_um.has_value());

  const PopulationView tighter = ViewPopulations(Plan("rollers", parts + "class = \"5\"\n"), Quick()).front();
  EXPECT_THAT(PopulationLine(tighter),
              AllOf(HasSubstr("roller population: 3 measured parts, resampled without replacement; against 5: 2 of 3 "
                              "within VDsp 5 µm (outside: roller_3.csv)")));
}

// The line of a view built by hand: a model's words, at most five parts named outside, an
// order the class does not draw, and a population compared with no class.
TEST(PopulationLine, NamesFiveOutsidePartsCountsTheRestAndSaysWhyNoClassWasCompared) {
  PopulationView view;
  view.draw = sampling::PopulationDraw::kModel;
  view.class_name = "IT5/2";
  view.class_limit_um = 16.0;
  view.mode = sampling::ToleranceMode::kInspected;
  for (int k = 1; k <= 8; ++k) view.parts.push_back({fmt::format("p{}.csv", k), std::nullopt, 20.0, 20.0, false, {}});
  view.parts.front().within_class = true;
  view.orders.push_back({2, 4.0, 5.0, std::nullopt, std::nullopt});
  EXPECT_EQ(PopulationLine(view),
            "ring population: 8 measured parts, drawn from a law fitted to them; against IT5/2 (inspected): 1 of 8 "
            "within RONt 16 µm (outside: p2.csv, p3.csv, p4.csv, p5.csv, p6.csv and 2 more); order 2 median 4 µm "
            "against nothing the class draws");
  view.class_name.clear();
  view.class_problem = "no class of the catalogue has a row at this diameter";
  EXPECT_EQ(PopulationLine(view),
            "ring population: 8 measured parts, drawn from a law fitted to them; not compared with a class: no class "
            "of the catalogue has a row at this diameter");
}

TEST_F(PopulationViewTest, AnUnknownClassIsRefusedNamingTheKey) {
  WriteRings({9.0});
  const std::string message = ringtol::testing::MessageOf<InputError>(
      [&] { Plan("ring", "profiles = [\"ring_1.csv\"]\norders = 4\nclass = \"IT9/2\"\n"); });
  EXPECT_THAT(message, AllOf(HasSubstr("population.ring.class"), HasSubstr("IT9/2")));
}

// Through a results file: the report, its JSON and `ringtol report`'s lines show the view.
TEST_F(PopulationViewTest, TheReportItsJsonAndTheCommandShowTheMeasuredParts) {
  WriteRings({9.0, 10.0, 13.0});
  ringtol::testing::WriteText(
      dir_ / "campaign.toml",
      fmt::format("scene = \"{}\"\nseed = 1\n[design]\nkind = \"monte_carlo\"\nsamples = 4\n"
                  "[population.ring]\nprofiles = [\"ring_1.csv\", \"ring_2.csv\", \"ring_3.csv\"]\norders = 4\n"
                  "class = \"IT6/2\"\n[solver]\nname = \"quasistatic\"\n[spec]\nd_trajectory_mm = 0.25\n",
                  kScene.string()));
  const Campaign campaign(dir_ / "campaign.toml", std::nullopt, std::nullopt);
  SampleEvaluator evaluator(campaign);
  const std::filesystem::path results = dir_ / "results.h5";
  CampaignStore store = CampaignStore::Create(results, campaign.identity(), campaign.samples());
  for (std::int64_t i = 0; i < campaign.samples(); ++i) store.Add(evaluator.Evaluate(i));
  store.Commit();

  ReportCommand command;
  command.results = results;
  command.out = dir_ / "report.html";
  command.json = dir_ / "report.json";
  command.options.bootstrap_resamples = 0;
  command.options.replay = false;
  std::ostringstream out;
  ASSERT_EQ(RunReport(command, out), 0);
  EXPECT_THAT(out.str(), HasSubstr("ring population: 3 measured parts, resampled; against IT6/2: 2 of 3 within RONt "
                                   "22 µm (outside: ring_3.csv); order 3 median 10 µm against the class's "));
  const std::string html = ringtol::testing::ReadText(command.out);
  EXPECT_THAT(html, AllOf(HasSubstr("<h2 id=\"measured-parts\">Measured parts</h2>"), HasSubstr("ring_3.csv"),
                          HasSubstr("class: 95th percentile"), HasSubstr("<b>no</b>")));
  const nlohmann::json json = nlohmann::json::parse(ringtol::testing::ReadText(*command.json));
  ASSERT_EQ(json["populations"].size(), 1u);
  EXPECT_EQ(json["populations"][0]["class"]["name"], "IT6/2");
  EXPECT_NEAR(json["populations"][0]["orders"][1]["measured_median_um"].get<double>(), 10.0, kFitUm);
  EXPECT_GT(json["populations"][0]["orders"][1]["class_q95_um"].get<double>(),
            json["populations"][0]["orders"][1]["class_median_um"].get<double>());
}

}  // namespace
}  // namespace ringtol::jobs
