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
// for a file or a header that cannot be read, text that is not UTF-8 (jobs/inputs/text_encoding.h),
// columns separated by semicolons or tabs, an unknown column name (the message lists the
// allowed ones), a row with the wrong number of fields, a value that is not a number or not
// finite, a radius <= 0, and a file without data rows; and, once fitted, for numbers whose
// units cannot be what the columns say (CheckMeasuredFit).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/enum_names.h"
#include "engine/profile.h"
#include "sampling/profile_fit.h"

namespace ringtol::jobs {

enum class ProfileQuantity {
  kRadius,     // sample values are radii [m], > 0
  kDeviation,  // sample values are radial deviations from the nominal radius [m]
};

struct MeasuredProfile {
  ProfileQuantity quantity = ProfileQuantity::kRadius;
  std::string_view angle_column;  // the header's name for it: "angle_deg" or "angle_rad"
  std::string_view value_column;  // "radius_mm", "deviation_mm" or "deviation_um"
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

// What a measured profile's numbers must show before its fit stands for the part
// (docs/inputs.md, "Profile CSV files"). Each rule catches a unit other than the column
// names, which otherwise gives a fit, and a runout, that is silently wrong.
//
// Angles: a whole turn in the other unit. Readings under angle_deg that all lie within
// 2 pi degrees are radians: no roundness profile covers only 6.3 degrees.
inline constexpr double kOneTurnInDegrees = 360.0;
// The fit explains little: R^2 below kMinRSquared leaves most of the readings' variance in
// the residual. That is refused where the residual is not noise: where neighbouring
// readings' residuals (in the file's order, the order a tester takes them along the
// outline) correlate above kMaxNoiseCorrelation, the residual is outline that the fit did
// not take in: degrees under angle_rad (each reading wrapped to a far-away angle), or form
// at orders above those fitted. A ring as round as the tester's noise is measured as
// noise: its residuals do not correlate (about +-1/sqrt(readings) for white noise), and
// its fit is accepted however low its R^2.
inline constexpr double kMinRSquared = 0.5;
inline constexpr double kMaxNoiseCorrelation = 0.5;
// Size: a form (sum of the amplitudes of orders 2 and up) larger than kSameRingShare of the
// ring's radius is not a ring's form: deviations in another unit. The radius is the scene's
// inner radius, or a radius file's own mean radius for `ringtol fit`. A deviation file's
// form is also held to kMaxDeviationForm, the one bound `ringtol fit` has for it: five
// times the loosest circularity class of the catalogue (waterjet, 0.2 mm), where
// micrometres written under deviation_mm land for every ring but the roundest.
inline constexpr double kSameRingShare = 0.01;
inline constexpr double kMaxDeviationForm = 1e-3;  // [m]

// Reads `file`, fits orders 0..orders and holds the fit to the rules above. ring_radius
// [m]: the nominal radius of the ring the profile is for, when known. Throws InputError:
// ReadProfileCsv's; the fit's refusal (sampling::FitFourierSeries: orders < 1, too few
// distinct angles, a gap too wide for the orders) as "<file>: <reason>"; or a rule's, as
// "<file>: <what the numbers show>: <likely cause>; allowed: ...", naming the angles' span,
// the fit's R^2 or the form's size. A form as large as the radius (a fit gone wild across a
// gap) is left to the caller, whose message can blame the orders.
// `part` names what the export is a profile of in messages: "ring" or "roller".
MeasuredFit FitProfileFile(const std::filesystem::path& file, int orders, std::optional<double> ring_radius = {},
                           std::string_view part = "ring");

// The fit's harmonics that describe the part: orders 2..N, or 1..N when
// keep_eccentricity; in order, amplitudes [m] and phases [rad] as fitted.
std::vector<engine::Harmonic> FormHarmonics(const sampling::FourierFit& fit, bool keep_eccentricity);

// The export a file key names (a string at `site`), resolved against `folder` (an absolute
// path stays as it is). InputError naming the key when it is not an existing file;
// `allowed` words what the key takes.
struct Site;
std::filesystem::path ReadProfilePath(const Site& site, const std::filesystem::path& folder, std::string_view allowed);

// What a measured part's export is held to (a scene's ring.measured_profile or
// rollers[].measured_profile, a campaign's [population.ring]):
//   kNominal (the default): the export's own size counts: a radius file's mean radius less
//     the ring's nominal inner radius, or a deviation file's mean deviation, becomes the
//     ring's mean deviation; a size more than kSameRingShare of the radius from nominal is
//     a profile of another part, refused as such (OtherPartReason);
//   kOwnMean: the form alone, about the export's own mean: its harmonics on a ring of any
//     nominal size (a measured 302 mm ring's form on a 150 mm design).
enum class ProfileReference { kNominal, kOwnMean };
inline constexpr NameTable<ProfileReference, 2> kProfileReferenceNames = {
    {{ProfileReference::kNominal, "nominal"}, {ProfileReference::kOwnMean, "own_mean"}}};

// [m] The export's size about a ring of nominal inner radius `ring_radius`: a radius file's
// mean radius less it, a deviation file's mean deviation.
double MeanDeviation(const MeasuredFit& measured, double ring_radius);
// Why `file`'s export cannot be a profile of that part (`part`: "ring", "roller") held to its
// nominal size, whose key `radius_key` names: "its mean radius 310 mm lies 8 mm from
// ring.inner_radius_mm = 302 mm, more than 1 %: a profile of another ring (or deviations in
// another unit)"; empty when it can be one.
std::string OtherPartReason(const MeasuredFit& measured, double ring_radius, const std::string& file,
                            std::string_view radius_key = "ring.inner_radius_mm", std::string_view part = "ring");

}  // namespace ringtol::jobs
