// The one exception type of ringtol's first failure tier (docs/architecture.md, "Failure"): bad input, found at
// the boundary before any simulation starts.
//
// InputError is thrown for bad input files and options: a file that is missing,
// unreadable or not valid TOML, an unknown or missing key, a value of the wrong type, a
// number that is not finite or out of range, and a geometry that cannot be assembled (a
// roller that does not fit in the ring). Its message is meant for the person who wrote
// the file and always names
//   - the file, followed by line:column when the parser knows the position,
//   - the key path, e.g. `rollers[2].radius_mm` (array indices are 0-based as in the file),
//   - the offending value as written (in the file's units),
//   - the allowed range or the allowed values,
// in the form
//   <file>:<line>:<col>: <key path> = <value>: <what is wrong>; allowed: <range or values>
// and for unknown keys
//   <file>:<line>:<col>: unknown key '<key path>'; valid keys here: a, b, c
// Numerical outcomes of a valid input (no convergence, lift-off) are never InputErrors:
// they are statuses in the solvers' results.
#pragma once

#include <stdexcept>

namespace ringtol::jobs {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace ringtol::jobs
