// Campaign files: a sampling file (jobs/inputs/sampling_file.h: scene, seed, [design],
// [tolerances.*], [catalogue]) plus how to simulate each sample and what counts as good.
// examples/campaigns/default.toml is the reference.
//
//   [solver]                       optional
//     name = "quasistatic"         "linear", "quasistatic" or "dynamic"
//     steps = 0                    integer >= 0: angles per revolution; 0 = automatic
//     path_tolerance_um = 1.0      >= 0: budget of the automatic resolution for the sampling
//                                  error of D_trajectory (solvers/simulation.h,
//                                  SamplingErrorBound); 0 resolves every undulation.
//                                  The quasistatic solver then converges each angle to
//                                  1 % of it (Campaign::MakeSolver), else to 1 pm
//     relative_tolerance = 1e-6    > 0 and < 1: the dynamic solver's integration tolerance
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

namespace ringtol::jobs {

struct CampaignSolver {
  std::string name = "quasistatic";
  int steps = 0;
  double path_tolerance = 1e-6;     // [m]
  double relative_tolerance = 1e-6;  // [-] dynamic only
};

struct CampaignPlan {
  std::filesystem::path file;
  SamplingPlan sampling;
  CampaignSolver solver;
  std::vector<SpecLimit> spec;  // in the order of kOutputNames
};

// The root tables a campaign file adds to a sampling file.
inline constexpr std::array<std::string_view, 2> kCampaignTables = {"solver", "spec"};

// `stored`: see ReadSamplingFile.
CampaignPlan ReadCampaignFile(const std::filesystem::path& file, const StoredSampling* stored = nullptr);

}  // namespace ringtol::jobs
