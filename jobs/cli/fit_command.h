// `ringtol fit PROFILE.csv --orders N [--keep-eccentricity] [--fragment ring.toml] [--json]`:
// a roundness tester's export (jobs/inputs/profile_csv.h) fitted with a Fourier series of orders
// 0..N (sampling/profile_fit.h), shown as a table or one JSON object, and optionally
// written as the [ring] keys of a scene file (jobs/inputs/scene_file.h). Scene files can also
// name the export directly (ring.measured_profile); both use FitProfileFile and
// FormHarmonics (jobs/inputs/profile_csv.h), so the two routes give the same harmonics.
//
// Order 1 of a measured outline is the tester's set-up eccentricity (the part was not
// centred exactly on the spindle), not a property of the part: it is shown, but left out
// of the harmonics handed to a scene unless keep_eccentricity asks for it.
//
// Output units: mm for radii, um for deviations, amplitudes and residuals, degrees for
// angles and phases (phi_n in C_n cos(n theta + phi_n), engine/conventions.h).
#pragma once

#include <filesystem>
#include <ostream>
#include <vector>

#include "jobs/inputs/profile_csv.h"

namespace ringtol::jobs {

struct FitCommand {
  std::filesystem::path profile;      // roundness tester export (CSV, jobs/inputs/profile_csv.h)
  int orders = 0;                     // highest order fitted, 1..kMaxHarmonicOrder (jobs/inputs/toml_fields.h)
  bool keep_eccentricity = false;     // keep order 1 in the fragment
  std::filesystem::path fragment;     // [ring] keys written here as TOML; empty: none
  bool json = false;                  // one JSON object instead of text
};

// Prints the fit: points, largest gap, condition number, mean (radius or deviation, as
// the file holds), R^2, residual rms and max, and per order the amplitude, phase and
// standard error (order 1 marked as set-up eccentricity). As JSON the keys are points,
// largest_gap_deg, condition_number, mean_radius_mm or mean_deviation_um, r_squared,
// residual_rms_um, residual_max_um, harmonics: [{ order, amplitude_um, phase_deg,
// standard_error_um (null when the fit leaves no residual), set_up_eccentricity }].
// With a fragment, writes it after the fit succeeded (a refused fit leaves an existing
// file untouched): a comment header, then [ring] with inner_radius_mm = the fitted mean
// (radius files) or mean_deviation_mm = the fitted mean (deviation files), and
// harmonics = FormHarmonics(fit, keep_eccentricity) in mm and degrees, each number the
// shortest text that reads back as the same double.
// Returns 0. Throws InputError for orders outside 1..kMaxHarmonicOrder, a CSV that
// cannot be read (jobs/inputs/profile_csv.h), a fit the samples cannot support, numbers
// that break the rules of FitProfileFile (jobs/inputs/profile_csv.h: angles or deviations
// in another unit than the columns name, a fit whose residual is outline, not noise), and a
// fragment that cannot be opened or written or is the profile itself; the message names the
// file.
int RunFit(const FitCommand& command, std::ostream& out);

}  // namespace ringtol::jobs
