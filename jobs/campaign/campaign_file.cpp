#include "jobs/campaign/campaign_file.h"

#include <algorithm>
#include <array>
#include <optional>
#include <string_view>

#include "jobs/inputs/toml_fields.h"
#include "engine/scene.h"
#include "engine/units.h"
#include "sampling/assembly_sampler.h"
#include "solvers/dynamic.h"
#include "solvers/simulation.h"
#include "solvers/solver.h"

namespace ringtol::jobs {
namespace {

// The condition of a limit on a life output, as messages and docs/inputs.md word it.
constexpr std::string_view kLifeOn = "outputs.life = true";

struct SpecInput {
  std::array<std::optional<double>, kOutputCount> upper;
};

}  // namespace

void RequireEnoughSteps(const TableReader& solver_table, int steps, const engine::Scene& base,
                        const engine::FastestHarmonic& fastest) {
  if (steps == 0 || steps >= engine::MinimumSteps(fastest.rate)) return;
  solver_table.Fail("steps", "too few for the fastest undulation a sample can draw", StepsRule(base, fastest));
}

// The [solver] keys of the settings' fields a file sets, for SolverSettings::IsValid's report.
constexpr std::array<OptionName, 3> kSolverKeys{{
    {"simulation.steps", "steps"},
    {"simulation.path_tolerance", "path_tolerance_um", units::kMetresPerMicrometre},
    {"relative_tolerance", "relative_tolerance"},
}};

solvers::SolverSettings ReadSolverTable(const TableReader& table) {
  struct SolverInput {
    solvers::Rung rung = CampaignSolverDefaults().rung;
    int steps = 0;
    double path_tolerance = kCampaignPathTolerance;
    double relative_tolerance = solvers::SolverSettings{}.relative_tolerance;
    solvers::DynamicStart start = solvers::SolverSettings{}.dynamic_start;
    solvers::AngleMode angles = CampaignSolverDefaults().simulation.angles;
    solvers::Accuracy accuracy = CampaignSolverDefaults().simulation.accuracy;
  };
  SolverInput solver;
  const std::vector<Field<SolverInput>> solver_fields{
      Choice("name", Presence::kOptional, solvers::kRungNames, &SolverInput::rung),
      OptionInteger("steps", Presence::kOptional, solvers::SimulationOptions::kStepsRange, &SolverInput::steps),
      OptionNumber("path_tolerance_um", Presence::kOptional, units::kMetresPerMicrometre,
                   InFileUnits(solvers::SimulationOptions::kPathToleranceRange, units::kMetresPerMicrometre),
                   &SolverInput::path_tolerance),
      OptionNumber("relative_tolerance", Presence::kOptional, kSameUnit,
                   solvers::DynamicOptions::kRelativeToleranceRange, &SolverInput::relative_tolerance),
      Choice("start", Presence::kOptional, solvers::kDynamicStartNames, &SolverInput::start),
      Choice("angles", Presence::kOptional, solvers::kAngleModeNames, &SolverInput::angles),
      Choice("accuracy", Presence::kOptional, solvers::kAccuracyNames, &SolverInput::accuracy),
  };
  table.Read(solver_fields, solver);
  solvers::SolverSettings settings = CampaignSolverDefaults();
  settings.rung = solver.rung;
  settings.simulation.steps = solver.steps;
  settings.simulation.path_tolerance = solver.path_tolerance;
  settings.simulation.angles = solver.angles;
  settings.simulation.accuracy = solver.accuracy;
  settings.relative_tolerance = solver.relative_tolerance;
  settings.dynamic_start = solver.start;
  if (InvalidOption invalid; !settings.IsValid(&invalid)) table.FailOption(invalid, kSolverKeys);
  return settings;
}

CampaignPlan ReadCampaignFile(const std::filesystem::path& file, const StoredSampling* stored) {
  CampaignPlan plan;
  plan.file = file;
  plan.sampling = ReadSamplingFile(file, kCampaignTables, stored);

  const std::string source = file.string();
  const toml::table document = ParseToml(plan.sampling.text, source);
  const TableReader root(document, "", source);

  // [outputs]: the life outputs add 40 % to a default sample's cost; a campaign that asks
  // nothing of them leaves them out, as an allocation whose constraints name none does.
  struct OutputsInput {
    bool life = CampaignSolverDefaults().simulation.life;
  };
  const std::vector<Field<OutputsInput>> outputs_fields{
      Flag("life", Presence::kOptional, &OutputsInput::life),
  };
  bool& life = plan.solver.simulation.life;

  SpecInput spec;
  std::vector<Field<SpecInput>> spec_fields;
  for (std::size_t k = 0; k < kOutputCount; ++k) {
    Field<SpecInput> field{kOutputNames[k], Presence::kOptional, "> 0", [k](const Site& site, SpecInput& target) {
                             target.upper[k] = ReadNumber(site, Above(0));
                           }, {}, {}};
    // [outputs] is read first (the fields below are in that order).
    if (IsLifeOutput(k)) field = std::move(field).When([&life](const SpecInput&) { return life; }, kLifeOn);
    spec_fields.push_back(std::move(field));
  }
  // A verdict at 100 % or at certainty would need every assembly or infinitely many samples.
  const std::vector<Field<DispositionRule>> disposition_fields{
      Number("required_yield_percent", Presence::kRequired, units::kFractionPerPercent, Range{0, true, 100, true},
             &DispositionRule::required_yield),
      Number("confidence_percent", Presence::kOptional, units::kFractionPerPercent, Range{50, false, 100, true},
             &DispositionRule::confidence),
  };
  struct Root {};
  Root unused;
  std::vector<Field<Root>> fields{
      Section<Root>("solver", Presence::kOptional,
                    [&](const TableReader& t, Root&) {
                      plan.solver = ReadSolverTable(t);
                      RequireEnoughSteps(
                          t, plan.solver.simulation.steps, plan.sampling.scene,
                          sampling::FastestDrawnHarmonic(plan.sampling.scene, plan.sampling.tolerances));
                    }),
      Section<Root>("outputs", Presence::kOptional,
                    [&](const TableReader& t, Root&) {
                      OutputsInput outputs;
                      t.Read(outputs_fields, outputs);
                      life = outputs.life;
                    }),
      Section<Root>("spec", Presence::kOptional, [&](const TableReader& t, Root&) { t.Read(spec_fields, spec); }),
      Section<Root>("disposition", Presence::kOptional,
                    [&](const TableReader& t, Root&) {
                      DispositionRule rule;
                      t.Read(disposition_fields, rule);
                      // [spec] is read first (the fields are in that order).
                      if (std::none_of(spec.upper.begin(), spec.upper.end(), [](const auto& u) { return u.has_value(); })) {
                        t.Fail("required_yield_percent", "judges the share of assemblies within [spec], and the file sets no [spec] limit",
                               "a [spec] table with at least one limit");
                      }
                      plan.disposition = rule;
                    }),
  };
  // The sampling half was read and checked above; here only the campaign's own tables.
  for (const auto& [key, node] : document) {
    if (std::find(kCampaignTables.begin(), kCampaignTables.end(), key.str()) == kCampaignTables.end()) {
      fields.push_back({key.str(), Presence::kOptional, "", [](const Site&, Root&) {}, {}, {}});
    }
  }
  root.Read(fields, unused);

  for (std::size_t k = 0; k < kOutputCount; ++k) {
    if (spec.upper[k]) plan.spec.push_back({kOutputNames[k], *spec.upper[k]});
  }
  return plan;
}

}  // namespace ringtol::jobs
