// What makes two runs the same campaign, and the spec a campaign judges its samples by:
// the campaign's own vocabulary, which the results file (jobs/store/campaign_store.h)
// persists and the report reads back. Plain data; no I/O.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "jobs/campaign/sample_record.h"
#include "sampling/assembly_sampler.h"
#include "sampling/design.h"
#include "solvers/simulation.h"

namespace ringtol::jobs {

// An upper specification limit on one output (runout is one-sided).
struct SpecLimit {
  std::string output;  // one of kOutputNames (jobs/campaign/sample_record.h)
  double upper = 0.0;  // in the output's unit
};

// Resume refuses a file whose identity differs in any field but campaign_path.
struct CampaignIdentity {
  std::string ringtol_version;
  std::string catalogue_version;
  std::string campaign_path;  // provenance only
  std::string campaign_file;  // the campaign file's text
  std::string base_scene;     // the base scene as a scene file
  std::string design;         // sampling::DesignName
  std::string solver;         // solver name
  std::uint64_t seed = 0;
  std::vector<sampling::SampledInput> inputs;  // the design's coordinates, in order
  // The base scene's rollers by name, in its order: what SampleRecord::off_bore's entries
  // are. Not compared, since base_scene holds them.
  std::vector<std::string> rollers;
  // The measured parts the campaign draws from (SamplingPlan::population); empty without.
  std::string population;
  std::vector<SpecLimit> spec;
  // Whether the samples computed the life outputs (IsLifeOutput): the campaign file's
  // [outputs] life. A results file without them holds none of their columns.
  bool life = true;
  // What the samples traded of the outputs' definition for speed: the campaign file's
  // solver.accuracy (solvers::Accuracy), also named in `solver` when not full. Files
  // written before the setting are full.
  solvers::Accuracy accuracy = solvers::Accuracy::kFull;
  // How the sensor's swing was read: the base scene's [sensor] table, so already compared
  // through base_scene; the results file states it beside /outputs/swing_mm.
  engine::SwingRule swing;
  // How the error motion was filtered, likewise: stated beside each error_motion_* column.
  engine::ErrorMotionFilter error_motion_filter;
  // What the sampler's calibration of the form spectra came to (AssemblySampler::scales()):
  // not compared, since it follows from the fields above, but stored, so that a campaign
  // rebuilt from its results file draws with the same scales without calibrating again.
  // Empty in files written before it was stored (they calibrate).
  std::vector<sampling::ComponentScale> calibrations;
};

// Whether a summary or report shows `output` (one of kOutputNames) for this campaign: the
// dynamic rung's own revolutions (OutputSpan::kDynamicRevolution) only where that rung
// ran, since the time-free rungs give them the revolution's value.
inline bool ShowsOutput(const CampaignIdentity& identity, std::string_view output) {
  return OutputNamed(output).span != OutputSpan::kDynamicRevolution || identity.solver.starts_with("dynamic");
}

// Whether --samples may grow a campaign of this design: a Latin hypercube's strata are its
// whole size, so a larger one is another design, whose first samples are not the ones
// already drawn; every other design's sample i is the same whatever the size.
inline bool DesignCanGrow(const CampaignIdentity& identity) {
  return identity.design != sampling::DesignName(sampling::DesignKind::kLatinHypercube);
}

}  // namespace ringtol::jobs
