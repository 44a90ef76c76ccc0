// The contact law's warning on the shipped examples, and what it stands for: how far the
// law moves D_trajectory from rigid contact's (docs/model.md §4, "When the law matters").
#include "jobs/cli/contact_warning.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "engine/units.h"
#include "jobs/inputs/scene_file.h"
#include "solvers/contact_compliance.h"
#include "solvers/quasistatic.h"
#include "solvers/simulation.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

const std::string kExamples = RINGTOL_SOURCE_DIR "/examples/";

// The 800 mm table as shipped (the law of its materials), and under the article's law.
engine::Scene Table() { return ReadScene(kExamples + "rotary_table/scene.toml"); }
engine::Scene TableUnderTheArticlesLaw() {
  const std::string text = testing::ReplaceOnce(testing::ReadText(kExamples + "rotary_table/scene.toml"),
                                                "law = \"penalty\"",
                                                "law = \"penalty\"\nstiffness_N_per_m_e = 1.0e7\nexponent = 1.5");
  return ParseScene(text, "table_article_law.toml");
}

engine::Scene Rigid(engine::Scene scene) {
  scene.contact.model = engine::ContactLaw::Model::kRigid;
  return scene;
}

double DTrajectory(const engine::Scene& scene) {
  const solvers::SimulationResult result = solvers::Simulate(scene, solvers::QuasistaticSolver());
  EXPECT_EQ(result.status, solvers::Status::kOk) << result.message;
  return result.d_trajectory;
}

// (D_rigid - D_law) / D_rigid.
double Understatement(const engine::Scene& scene) {
  const double rigid = DTrajectory(Rigid(scene));
  return (rigid - DTrajectory(scene)) / rigid;
}

TEST(ContactLawWarning, NamesThePenetrationTheLawAndWhatToSetOnTheTableUnderTheArticlesLaw) {
  const engine::Scene scene = TableUnderTheArticlesLaw();
  const solvers::ContactCompliance compliance = solvers::AssessContactCompliance(scene);
  const std::optional<std::string> warning = ContactLawWarning(scene, std::nullopt);
  ASSERT_TRUE(warning.has_value());
  EXPECT_THAT(*warning,
              AllOf(HasSubstr("ringtol: warning: the contact law F = 1e+07 delta^1.5"),
                    HasSubstr(fmt::format("{:.3g} um at {:.4g} N",
                                          compliance.penetration * units::kMicrometresPerMetre, compliance.force)),
                    HasSubstr(fmt::format("by up to {:.3g} %", 100.0 * compliance.response_change)),
                    HasSubstr("remove stiffness_N_per_m_e and exponent from [contact]"),
                    HasSubstr("youngs_modulus_GPa and poisson_ratio")));
  // The issue's table: more than half a millimetre, against tolerances of 10 and 20 um.
  EXPECT_GT(compliance.penetration, 0.5e-3);
}

TEST(ContactLawWarning, SaysNothingOfTheTablesLawOfTheMaterialsOrOfRigidContact) {
  EXPECT_EQ(ContactLawWarning(Table(), std::nullopt), std::nullopt);
  EXPECT_EQ(ContactLawWarning(Rigid(TableUnderTheArticlesLaw()), std::nullopt), std::nullopt);
}

TEST(ContactLawWarning, WarnsOnTheArticlesOwnRig) {
  EXPECT_THAT(ContactLawWarning(ReadScene(kExamples + "paper/order3.toml"), std::nullopt),
              ::testing::Optional(HasSubstr("ringtol: warning: the contact law F = 1e+07 delta^1.5")));
}

// A law the scene file states is the user's choice: one line, a note, naming the file and
// its keys, the penetration and the share, and the materials' law beside it.
TEST(ContactLawWarning, ALawTheSceneFileStatesIsANoteOfOneLineNamingTheFileAndItsKeys) {
  const engine::Scene scene = TableUnderTheArticlesLaw();
  const solvers::ContactCompliance compliance = solvers::AssessContactCompliance(scene);
  const std::optional<std::string> note = ContactLawWarning(scene, "table_article_law.toml");
  ASSERT_TRUE(note.has_value());
  EXPECT_THAT(*note, AllOf(::testing::StartsWith("ringtol: note: the contact law F = 1e+07 delta^1.5"),
                           HasSubstr("that table_article_law.toml states ([contact] stiffness_N_per_m_e and exponent)"),
                           HasSubstr(fmt::format("{:.3g} um at {:.4g} N",
                                                 compliance.penetration * units::kMicrometresPerMetre, compliance.force)),
                           HasSubstr(fmt::format("by up to {:.3g} %", 100.0 * compliance.response_change)),
                           HasSubstr("the materials' law, F = "), ::testing::Not(HasSubstr("warning"))));
  EXPECT_EQ(note->find('\n'), note->size() - 1) << *note;
  EXPECT_EQ(ContactLawWarning(Table(), "scene.toml"), std::nullopt);
}

TEST(ContactLawWarning, TheTablesLawOfTheMaterialsKeepsDTrajectoryWithinATenthOfAPercentOfRigid) {
  // The law's share on the table is about k_b delta / (e F) x 2.3 = 1e-4 (0.4 um of
  // penetration, a 20,000 N/m spring, 200 N; docs/model.md §4): ten times that.
  constexpr double kMaterialsAgainstRigid = 1e-3;
  EXPECT_LT(std::abs(Understatement(Table())), kMaterialsAgainstRigid);
  // The issue: the article's law understates the same table's D_trajectory by 12 %.
  constexpr double kIssuesUnderstatement = 0.10;
  EXPECT_GT(Understatement(TableUnderTheArticlesLaw()), kIssuesUnderstatement);
}

TEST(ContactLawWarning, ItsShareIsHowFarTheLawMovesDTrajectoryFromRigidContact) {
  // The share bounds every error pattern's change against the largest response
  // (solvers/contact_compliance.h); a ring order that is a multiple of 3 changes every gap
  // alike, a pattern whose response is 1/1.22 of the largest on three rollers 120 deg
  // apart, so its relative change may exceed the share by that factor, and the path's
  // second-order terms move D a little more. Within half the share either way.
  constexpr double kShareAgainstD = 0.5;
  for (const engine::Scene& scene :
       {TableUnderTheArticlesLaw(), ReadScene(kExamples + "paper/order3.toml"), Table()}) {
    const double share = solvers::AssessContactCompliance(scene).response_change;
    EXPECT_NEAR(Understatement(scene), share, kShareAgainstD * share) << fmt::format("k = {}", scene.contact.stiffness);
  }
}

}  // namespace
}  // namespace ringtol::jobs
