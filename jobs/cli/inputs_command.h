// `ringtol inputs RESULTS.h5 --samples FIRST[:END]`: the design point and drawn values of
// chosen samples of a campaign's results file as CSV, whether the file keeps them or
// replays them (a file keeps the first kStoredInputSamples samples' inputs unless it was
// written with --store-inputs; jobs/store/campaign_store.h). A replay is checked against
// the draw checksum the file keeps of every finished sample.
//
// Failure: InputError naming the file for a file that is not a campaign's results file or
// is damaged, naming --samples and the allowed range for samples outside the file, and
// naming the sample whose replay no longer matches its checksum (another ringtol's sampler).
#pragma once

#include <cstdint>
#include <filesystem>
#include <ostream>
#include <string>

namespace ringtol::jobs {

struct InputsCommand {
  std::filesystem::path results;
  std::string samples;  // "FIRST" or "FIRST:END" (END excluded), sample indices
};

// Prints one CSV row per sample: sample, status, u_0 ... u_{d-1}, then the drawn values under
// their input names (units in the names); a pending sample's numbers are empty.
int RunInputs(const InputsCommand& command, std::ostream& out);

}  // namespace ringtol::jobs
