// Scene files written from a Scene: the inverse of jobs/inputs/scene_file.h, so that any
// assembly, a Monte Carlo sample's above all, can be saved and replayed with
// `ringtol simulate`.
//
// The text is a complete, standalone scene file: every key ReadScene reads is written,
// nothing is left to a default, in the units of the key names (mm, deg, mm/s, deg/s,
// deg/s^2; s, N, N/m, N/m^e, N s/m, kg, kg m^2 as in SI). Each number is the shortest
// decimal that the reader converts back to the scene's value exactly; where no decimal
// does (a unit conversion skips some doubles: about 2 % of values in mm, 9 % in
// degrees), it is value / unit written to round-trip, which reads back within two
// roundings. So a scene read from a file writes back that file's numbers (those of up
// to 15 significant digits), and
//   ParseScene(WriteScene(scene), name) == scene
// field by field up to |relative error| <= 4 DBL_EPSILON in a converted number (two
// roundings for a unit, six for the article law's span); numbers in SI units, text,
// choices, flags and harmonic orders are exact.
//
// What a Scene does not hold is written so that it reads back the same:
//   - masses and spin inertias as mass_kg and spin_inertia_kg_m2, never a density; the
//     rollers' width_mm, required by the format but used only with a density, is set to
//     the ring's thickness_mm and has no effect;
//   - [roller_positions] only when its mean deviation or harmonics are non-zero (its
//     radius is unused and reads back as 1 m);
//   - [motion] as law = "test_bench" when the segments are exactly TestBenchLaw(settle),
//     as "article" when they have its form (an optional rest, then a constant non-zero
//     rate: settle_s, rate_deg_per_s, revolutions = span * |rate| / 2 pi), and otherwise
//     as "piecewise" segments; each is the same law;
//   - a fixed roller's spring is not written (the format forbids it) and reads back as
//     the default Spring;
//   - [contact] always states the penalty law's k and e, so the materials written beside
//     them (which derive a law only for a file that states none) never change it.
//
// Precondition: a scene the format can express, as ReadScene returns it or a sampler
// derives from one (values in the ranges of jobs/inputs/scene_file.h, unique non-empty roller
// names, at least 3 rollers). Anything else is written as it is, and reading the file
// fails with the InputError that names the offending key.
#pragma once

#include <filesystem>
#include <string>

#include "engine/scene.h"

namespace ringtol::jobs {

// The scene file (jobs/inputs/scene_file.h format) that reads back as `scene`, starting with a
// comment saying ringtol wrote it. Does not throw (std::bad_alloc aside).
std::string WriteScene(const engine::Scene& scene);

// Writes WriteScene(scene) to `file`, replacing it. Throws InputError naming the file
// when it cannot be opened for writing (a missing folder, a directory, no permission) or
// the write fails; a failed write may leave a partial file.
void WriteSceneFile(const engine::Scene& scene, const std::filesystem::path& file);

}  // namespace ringtol::jobs
