// `ringtol classes`: the built-in tolerance catalogue (jobs/inputs/catalogue.toml).
#pragma once

#include <ostream>

namespace ringtol::jobs {

// The catalogue's classes, one line each with their source, or (toml) the catalogue file
// itself. Returns 0.
int RunClasses(bool toml, std::ostream& out);

}  // namespace ringtol::jobs
