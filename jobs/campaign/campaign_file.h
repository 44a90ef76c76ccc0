// Campaign files: a sampling file (jobs/inputs/sampling_file.h: scene, seed, [design],
// [tolerances.*], [catalogue]) plus how to simulate each sample and what counts as good.
// examples/campaigns/default.toml is the reference.
//
//   [solver]                       optional
//     name = "auto"                "auto", "linear", "quasistatic" or "dynamic": auto picks
//                                  per sample the cheapest whose error fits half the
//                                  path_tolerance (solvers/auto.h)
//     steps = 0                    0..solvers::kMaxSteps: angles per revolution; 0 = automatic
//     path_tolerance_um = 1.0      >= 0: budget of the automatic resolution for the sampling
//                                  error of D_trajectory (solvers/simulation.h,
//                                  SamplingErrorBound); 0 resolves every undulation.
//                                  The quasistatic solver then converges each angle to
//                                  1 % of it (solvers::SolverSettings), else to 1 pm
//     angles = "dense"             "refined" or "spectral": evaluate every angle, or every
//                                  eighth and only the stretches that can move D_trajectory,
//                                  runout or the status (refined: linear and quasistatic
//                                  rungs; spectral: the linear rung, alone or as auto's
//                                  first step, read from its phasors; solvers::AngleMode)
//     relative_tolerance = 1e-6    > 0 and < 1: the dynamic solver's integration tolerance
//     start = "quasistatic_equilibrium"  or "article_settle": where the dynamic solver
//                                  starts (solvers::DynamicStart); the other rungs ignore it
//   [spec]                         optional: upper specification limits (one-sided)
//     d_trajectory_mm = 0.30       any output of jobs/campaign/sample_record.h, > 0 (mm or N)
//
// Failure: InputError naming the file, key, value and allowed range, for everything
// ReadSamplingFile refuses and for the keys above.
#pragma once

#include <array>
#include <filesystem>
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
// campaign's sample reads (the life outputs of kOutputNames) and a single run only when
// asked (--revolutions).
inline constexpr double kCampaignPathTolerance = 1e-6;  // [m]
inline solvers::SolverSettings CampaignSolverDefaults() {
  solvers::SolverSettings settings;
  settings.rung = solvers::Rung::kAuto;
  settings.simulation.path_tolerance = kCampaignPathTolerance;
  settings.simulation.life = true;
  return settings;
}

struct CampaignPlan {
  std::filesystem::path file;
  SamplingPlan sampling;
  solvers::SolverSettings solver = CampaignSolverDefaults();
  std::vector<SpecLimit> spec;  // in the order of kOutputNames
};

// The root tables a campaign file adds to a sampling file.
inline constexpr std::array<std::string_view, 2> kCampaignTables = {"solver", "spec"};

// The keys of a [solver] table (above), read from the table's reader: a campaign's and an
// allocation file's (jobs/allocation/allocation_file.h). Throws InputError.
class TableReader;
solvers::SolverSettings ReadSolverTable(const TableReader& table);

// `stored`: see ReadSamplingFile.
CampaignPlan ReadCampaignFile(const std::filesystem::path& file, const StoredSampling* stored = nullptr);

}  // namespace ringtol::jobs
