// Campaign files: a sampling file (jobs/inputs/sampling_file.h) plus how to simulate each
// sample ([solver]), which outputs to compute ([outputs]) and what counts as good ([spec]). The format, key by key, is
// docs/inputs.md, "Campaign files"; examples/campaigns/default.toml is the default campaign.
//
// Failure: InputError naming the file, key, value and allowed range, for everything
// ReadSamplingFile refuses and for the keys of [solver], [outputs] and [spec] (a limit on an
// output the campaign does not compute among them).
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string_view>
#include <string>
#include <vector>

#include "jobs/campaign/campaign_identity.h"
#include "jobs/campaign/sample_record.h"
#include "jobs/inputs/sampling_file.h"
#include "solvers/simulation.h"

namespace ringtol::jobs {

// A campaign's defaults differ from a single run's in three fields: the auto rung, a
// sampling budget of 1 um (path_tolerance_um), where `ringtol simulate` runs the
// quasistatic rung and resolves every undulation, and the life values, which every
// campaign's sample reads (the life outputs of kOutputNames) unless its file says
// `[outputs] life = false`, and a single run only when asked (--revolutions).
inline constexpr double kCampaignPathTolerance = 1e-6;  // [m]
inline solvers::SolverSettings CampaignSolverDefaults() {
  solvers::SolverSettings settings;
  settings.rung = solvers::Rung::kAuto;
  settings.simulation.path_tolerance = kCampaignPathTolerance;
  settings.simulation.life = true;
  return settings;
}

// [disposition]: the verdict on the measured part a campaign's scene holds (docs/usage.md,
// "Disposition of a measured part"): pass when the share of assemblies within every [spec]
// limit is at least `required_yield` at `confidence`, fail when it is surely below, else
// undecided (analysis::JudgeYield).
struct DispositionRule {
  double required_yield = 0.0;  // (0, 1): the file's required_yield_percent
  double confidence = 0.95;     // (0, 1): the file's confidence_percent
};

struct CampaignPlan {
  std::filesystem::path file;
  SamplingPlan sampling;
  // [solver], and in `simulation.life` the [outputs] table's choice of the life outputs.
  solvers::SolverSettings solver = CampaignSolverDefaults();
  std::vector<SpecLimit> spec;  // in the order of kOutputNames
  std::optional<DispositionRule> disposition;  // [disposition]; needs a [spec]
};

// The root tables a campaign file adds to a sampling file.
inline constexpr std::array<std::string_view, 4> kCampaignTables = {"solver", "outputs", "spec", "disposition"};

// The keys of a [solver] table (above), read from the table's reader: a campaign's and an
// allocation file's (jobs/allocation/allocation_file.h). Throws InputError.
class TableReader;
solvers::SolverSettings ReadSolverTable(const TableReader& table);

// A [solver] steps given by the user has no error budget (engine::MinimumSteps): refuses
// one that does not resolve `fastest`, the fastest term any sample can draw from `base`
// (sampling::FastestDrawnHarmonic), naming the minimum. Throws InputError.
void RequireEnoughSteps(const TableReader& solver_table, int steps, const engine::Scene& base,
                        const engine::FastestHarmonic& fastest);

// `stored`: see ReadSamplingFile.
CampaignPlan ReadCampaignFile(const std::filesystem::path& file, const StoredSampling* stored = nullptr);

}  // namespace ringtol::jobs
