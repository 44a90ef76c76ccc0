// `ringtol join RESULTS.h5 [--out FILE]`: one self-contained results file from a results
// file that is an index of shards (what `mpirun ... ringtol campaign` writes), for a user
// who wants one file to move. Without --out the joined file replaces the index and the
// shards are removed once it has; with --out the index and its shards stay as they are.
// Chunks are copied as stored (checksums included) where they can be.
//
// Failure: InputError naming the file for a file that keeps its samples itself (nothing to
// join), a shard that is missing or of another campaign, and an --out that exists.
#pragma once

#include <filesystem>
#include <optional>
#include <ostream>

namespace ringtol::jobs {

struct JoinCommand {
  std::filesystem::path results;
  std::optional<std::filesystem::path> out;  // empty: replace `results`
};

// Prints what was joined: samples, of which in whole chunks, and the file written.
int RunJoin(const JoinCommand& command, std::ostream& out);

}  // namespace ringtol::jobs
