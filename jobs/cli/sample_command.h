// `ringtol sample`: a sampling file's assemblies, drawn but not simulated.
//
// Reads and validates every input and opens every output file before the first
// simulation; throws InputError (jobs/inputs/input_error.h) when one is bad. Simulation
// failures are statuses in the output, not errors.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>

namespace ringtol::jobs {

// `ringtol sample`: draw the assemblies of a sampling file (jobs/inputs/sampling_file.h) without
// simulating them, to inspect what the tolerances produce and to replay one sample.
struct SampleCommand {
  std::filesystem::path file;            // sampling file
  std::optional<std::int64_t> samples;   // overrides design.samples
  std::optional<std::uint64_t> seed;     // overrides seed
  std::filesystem::path csv;             // one row per sample: its drawn inputs; empty: none
  std::optional<std::int64_t> index;     // with `scene`: the sample to write
  std::filesystem::path scene;           // the assembly of sample `index` as a scene file
};

// Prints the design, the calibrated scales and how many drawn parts meet their
// tolerances; writes the CSV and the replayed scene. Returns 0; throws InputError for a
// bad file or option before anything is written.
int RunSample(const SampleCommand& command, std::ostream& out);

}  // namespace ringtol::jobs
