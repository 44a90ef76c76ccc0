// `ringtol match`: which rollers of a measured batch to install with a measured ring.
//
// The campaign file names the ring (its scene, with ring.measured_profile) and the batch
// ([population.rollers], draw = "resample"). Every assignment of batch parts to the roller
// slots the batch fills is fitted to the scene as it stands (`draws` = 0: the match is for
// the parts in hand), or to each of the first `draws` assemblies the file's other
// tolerances draw (the same for every assignment: roller positions and springs not yet
// measured), and simulated with the campaign's [solver]; assignments rank by the mean
// output over those assemblies, fewer failed ones first.
// Exhaustive where the assignments number at most `exhaustive_limit` (B! / (B - Z)! for B
// parts and Z rollers); beyond it, a stated heuristic: `budget` assignments drawn at random,
// then, from the best, swaps of one slot's part for another (a part left in the batch or
// another slot's) while one lowers the output.
//
// Throws InputError (jobs/inputs/input_error.h) for a bad file or option before any
// simulation; an assembly that fails is reported with its status, never ranked.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>

namespace ringtol::jobs {

struct MatchCommand {
  std::filesystem::path file;  // campaign file with [population.rollers]
  // The output to lower (kOutputNames): by default the first the campaign's [spec] limits,
  // else d_trajectory_mm.
  std::optional<std::string> output;
  std::int64_t exhaustive_limit = 20000;  // >= 1: the most assignments searched exhaustively
  std::int64_t budget = 2000;             // >= 1: the random assignments of the heuristic
  int top = 5;                            // >= 1: assignments listed
  std::int64_t draws = 0;                 // >= 0, <= the file's samples: 0 fits the scene as it stands
  int threads = 0;                        // >= 0: simulating threads, 0 one per core (results do not depend on it)
  bool json = false;
};

// Prints the search, the best assignment, what a random choice from the batch gives (the
// distribution over every assignment searched) and the gain. Returns 0.
int RunMatch(const MatchCommand& command, std::ostream& out);

}  // namespace ringtol::jobs
