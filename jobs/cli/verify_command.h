// `ringtol verify RESULTS.h5`: reads every dataset of a results file chunk by chunk and
// says what is intact, what is damaged (the samples of each damaged chunk), what is on
// disk and which samples a --resume would compute (jobs/store/campaign_store.h,
// CheckResults). An allocation's file (ReadResultsKind) is read by CheckAllocationResults
// (jobs/store/allocation_store.h): its damaged chunks by dataset, candidate and samples.
//
// Exit status (kVerify...): 0 every dataset carries a checksum and every chunk reads; 1 a
// dataset is damaged; 2 nothing failed but some dataset has no checksum (written by an
// earlier ringtol), so damage that leaves numbers finite cannot be detected. A file that
// does not open (missing, not HDF5, damaged metadata) is an InputError naming it.
#pragma once

#include <filesystem>
#include <ostream>

namespace ringtol::jobs {

inline constexpr int kVerifyIntact = 0;
inline constexpr int kVerifyDamaged = 1;
inline constexpr int kVerifyUnchecked = 2;

struct VerifyCommand {
  std::filesystem::path results;
  bool json = false;  // one JSON object instead of the table
};

// Prints the verdict per dataset; returns one of the kVerify... exit statuses.
int RunVerify(const VerifyCommand& command, std::ostream& out);

}  // namespace ringtol::jobs
