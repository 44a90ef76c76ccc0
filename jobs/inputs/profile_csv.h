// A roundness tester's export, read and fitted: the measured outline a scene file names
// (ring.measured_profile) and `ringtol fit` shows, through the same two functions
// (FitProfileFile, FormHarmonics), so that both routes give the same harmonics.
//
// The file (docs/inputs.md, "Profile CSV files"): comma-separated readings under a header
// whose first column names the angle (`angle_deg`, `angle_rad`) and whose second names the
// quantity (`radius_mm`, `deviation_mm`, `deviation_um`). Values are converted to SI here:
// the rest of ringtol sees metres and radians only.
//
// Everything here throws InputError (jobs/inputs/input_error.h) and nothing else (std::bad_alloc
// aside), with messages in its form, e.g.
//   ring.csv:7: radius_mm = abc: not a number; allowed: a finite number > 0
// for a file or a header that cannot be read, an unknown column name (the message lists
// the allowed ones), a row with the wrong number of fields, a value that is not a number
// or not finite, a radius <= 0, and a file without data rows.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "engine/profile.h"
#include "sampling/profile_fit.h"

namespace ringtol::jobs {

enum class ProfileQuantity {
  kRadius,     // sample values are radii [m], > 0
  kDeviation,  // sample values are radial deviations from the nominal radius [m]
};

struct MeasuredProfile {
  ProfileQuantity quantity = ProfileQuantity::kRadius;
  std::vector<sampling::ProfileSample> samples;  // in file order; angle [rad], value [m]
};

// Reads and parses `file`; messages name it as given.
MeasuredProfile ReadProfileCsv(const std::filesystem::path& file);
// Parses the text of a file; `source_name` stands for the file in messages.
MeasuredProfile ParseProfileCsv(std::string_view text, const std::string& source_name);

// A measured outline and its fit.
struct MeasuredFit {
  ProfileQuantity quantity = ProfileQuantity::kRadius;  // what fit.mean is: a radius or a mean deviation
  sampling::FourierFit fit;
};

// Reads `file` and fits orders 0..orders. Throws InputError: ReadProfileCsv's, or the
// fit's refusal (sampling::FitFourierSeries: orders < 1, too few distinct angles, a gap
// too wide for the orders) as "<file>: <reason>".
MeasuredFit FitProfileFile(const std::filesystem::path& file, int orders);

// The fit's harmonics that describe the part: orders 2..N, or 1..N when
// keep_eccentricity; in order, amplitudes [m] and phases [rad] as fitted.
std::vector<engine::Harmonic> FormHarmonics(const sampling::FourierFit& fit, bool keep_eccentricity);

}  // namespace ringtol::jobs
