// The tolerance catalogue as a file: jobs/inputs/catalogue.toml, built into the executable, and
// the same tables under [catalogue] in a sampling (campaign) file, which add classes or
// replace shipped ones of the same name.
//
//   version = "..."                     shipped file only: kept with every campaign's results
//   [[roller]]        ISO 492 outer-ring classes, rows by outside diameter D
//     name, aliases = [...], description
//     rows = [{ outside_diameter_over_mm, outside_diameter_up_to_mm, kea_um, vdsp_series_9_um,
//               vdsp_series_0_1_um, vdsp_series_2_4_um, mean_diameter_lower_um,
//               mean_diameter_upper_um, source }, ...]
//   [[ring]]          bore circularity, rows by bore diameter
//     rows = [{ diameter_over_mm, diameter_up_to_mm, circularity_mm, source }, ...]
//   [[roller_position]]   zone diameter, rows by centre-circle diameter
//     rows = [{ diameter_over_mm, diameter_up_to_mm, zone_diameter_mm, source }, ...]
//   [[spring]]        rows = [{ stiffness_percent, preload_percent, source }] (one row)
//
// Every row needs its source. Errors are InputErrors in the form of jobs/inputs/input_error.h;
// overlapping rows and negative tolerances are refused (sampling::ToleranceCatalogue::Add).
#pragma once

#include <string>

#include <toml++/toml.h>

#include "sampling/catalogue.h"

namespace ringtol::jobs {

// The shipped catalogue (jobs/inputs/catalogue.toml as built in).
sampling::ToleranceCatalogue ShippedCatalogue();
// Its text, for `ringtol classes --toml`.
const std::string& ShippedCatalogueText();

// Adds the classes of a catalogue table (a whole catalogue document, or a campaign file's
// [catalogue] table) to `catalogue`. `path` is the table's key path ("" or "catalogue").
void AddCatalogueClasses(const toml::table& table, const std::string& path, const std::string& source_name,
                         bool allow_version, sampling::ToleranceCatalogue& catalogue);

}  // namespace ringtol::jobs
