// The tolerance catalogue as a file: jobs/inputs/catalogue.toml, built into the executable, and
// the same tables under [catalogue] in a sampling (campaign) file, which add classes or
// replace shipped ones of the same name. The format, key by key, is docs/inputs.md,
// "Tolerance catalogue"; the shipped file also has `version`, kept with every campaign's
// results.
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
