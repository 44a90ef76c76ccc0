// Sweep files: one base scene and the error patterns to run on it, the form of the
// article's studies (docs/model.md §6; examples/paper/orders.toml, amplitudes.toml,
// combinations.toml). Keys are validated as in scene files (jobs/inputs/scene_file.h): unknown,
// missing, wrongly typed or non-finite values are InputErrors.
//
//   scene = "scene.toml"      required: the base scene, relative to this file's folder
//                             (an absolute path is used as is)
//
// then exactly one of
//
//   [study]                   a grid of single-harmonic cases
//     target = "ring" | "roller_positions" | "roller_shape"     required
//     orders = [2, 3]         required, non-empty, integers 1..1000
//     amplitudes_mm = [0.14]  required, non-empty, each >= 0
//     phase_deg = 45.0        default 0
//   One case per (order, amplitude), orders in the outer loop, amplitudes in the inner,
//   named "<target> n=<order> C=<amplitude>mm" (amplitude to 6 significant digits, e.g.
//   "ring n=3 C=0.14mm"). Orders must be distinct, and so must the amplitudes.
//
//   [[cases]]                 explicit cases, in file order
//     name = "case1"          required, unique
//     ring = [...]            optional harmonic arrays, as in scene files:
//     roller_positions = [...]    [{ order = 2, amplitude_mm = 0.14, phase_deg = 45.0 }]
//     roller_shape = [...]
//
// Each case's scene is the base scene with the harmonics of its target(s) replaced, not
// added to: "ring" is the ring's inner surface, "roller_positions" the position series
// on the centre circle, "roller_shape" every roller's outline (the same harmonics on all
// rollers). Mean deviations and whatever a case does not list stay as in the base scene;
// an empty array removes that target's harmonics.
//
// Every case's scene passes the scene file's geometry checks (deviations below the radius,
// each roller fits in the ring); otherwise InputError names the sweep file, the key that
// produced the case and the case's name. Problems in the base scene are reported by
// ReadScene against the scene file itself.
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
