// Scene files: the TOML description of one assembly (docs/model.md §1–§4), read into an
// engine::Scene in SI units. The format, key by key, is docs/inputs.md, "Scene files",
// which tests/jobs/cli/input_reference_test.cpp holds to the field lists in scene_file.cpp.
//
// Failure: InputError (jobs/inputs/input_error.h) for a missing, unreadable or malformed file,
// an unknown or missing key (anywhere, including inside harmonic tables), a wrong type,
// a value out of range, a measured profile that is missing, unreadable, of another ring
// or in another unit, or that cannot support the orders asked for, a profile whose
// |mean_deviation| + sum of amplitudes reaches its radius (the polar form breaks down
// there), and a roller that does not fit in the ring (engine::CheckGeometry). A ring or
// roller that is not convex is NOT an input error: the solvers report it as a status, so a
// sweep can include such cases.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "engine/scene.h"

namespace ringtol::jobs {

// Reads and validates a scene file. Messages name the file as given; files it names
// (ring.measured_profile.file) are resolved against its folder.
engine::Scene ReadScene(const std::filesystem::path& file);

// Whether a scene file states its penalty contact law ([contact] stiffness_N_per_m_e and
// exponent) rather than taking its materials' (ReadScene). InputError as ReadScene for a
// file that does not read as TOML.
bool StatesContactLaw(const std::filesystem::path& file);

// The same for TOML text already in memory; source_name stands for the file in messages.
// Files the text names are resolved against the current directory.
engine::Scene ParseScene(std::string_view toml_text, const std::string& source_name);

}  // namespace ringtol::jobs
