// Sweep files: one base scene and the error patterns to run on it, the form of the
// article's studies (docs/model.md §6; examples/paper/orders.toml, amplitudes.toml,
// combinations.toml). The format, key by key, is docs/inputs.md, "Sweep files".
//
// Each case's scene is the base scene with the harmonics of its target(s) replaced, not
// added to; cases of a [study] are named "<target> n=<order> C=<amplitude>mm".
//
// Failure: InputError for every key as in scene files, and for a case whose scene fails
// the scene file's geometry checks (deviations below the radius, each roller fits in the
// ring): the message names the sweep file, the key that produced the case and the case's
// name. Problems in the base scene are reported by ReadScene against the scene file itself.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "engine/scene.h"

namespace ringtol::jobs {

struct SweepCase {
  std::string name;     // unique within the sweep
  engine::Scene scene;  // the base scene with this case's harmonics, SI units
};

struct Sweep {
  std::filesystem::path scene_file;  // the base scene: the sweep file's folder / `scene`
  std::vector<SweepCase> cases;      // in the order described above; never empty
};

// Reads and validates a sweep file and the scene file it names; builds every case.
// Throws InputError (jobs/inputs/input_error.h) for any bad input in either file.
Sweep ReadSweep(const std::filesystem::path& file);

}  // namespace ringtol::jobs
