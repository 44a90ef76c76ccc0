// One simulated sample of a campaign as it travels from the rank that computed it to the
// results file: its identity, its inputs (enough to replay it alone) and its outputs.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "solvers/solver.h"

namespace ringtol::jobs {

// A sample's outcome. Values 0..kLastSolverStatus are solvers::Status (same numbers, same names); the
// campaign adds its own failures and the marker of a sample not yet on disk.
enum class SampleStatus : std::int8_t {
  kPending = -1,          // not computed (the results file's fill value)
  kOk = 0,
  // 1..kLastSolverStatus: the remaining solvers::Status values, in their order
  kException = 64,        // the sample threw (message: what()); the campaign goes on
  kNonFiniteOutput = 65,  // the solver said ok but an output is NaN or infinite
  kSamplingFailed = 66,   // the sampler could not realise the assembly (message says why)
};

// The solver's statuses keep their numbers and names; the campaign's own lie above them.
inline constexpr int kLastSolverStatus = static_cast<int>(solvers::kStatusNames.back().value);
static_assert(static_cast<int>(SampleStatus::kOk) == static_cast<int>(solvers::Status::kOk));
static_assert(kLastSolverStatus < static_cast<int>(SampleStatus::kException),
              "a new solvers::Status would collide with the campaign's own statuses: renumber those");
inline constexpr NameTable<SampleStatus, 4> kCampaignStatusNames = {{{SampleStatus::kPending, "pending"},
                                                                     {SampleStatus::kException, "exception"},
                                                                     {SampleStatus::kNonFiniteOutput, "non_finite_output"},
                                                                     {SampleStatus::kSamplingFailed, "sampling_failed"}}};

SampleStatus FromSolverStatus(solvers::Status status);
// "pending", "ok", the solvers::StatusName of 1..kLastSolverStatus, "exception", "non_finite_output",
// "sampling_failed".
std::string_view SampleStatusName(SampleStatus status);
// Every status, pending first, for enumerations in output files.
const std::vector<SampleStatus>& AllSampleStatuses();

// The per-sample outputs, in the order of kOutputNames (units in the names). The first
// nine are over one revolution from the drawn phases of the rollers; d_trajectory_first_mm
// and d_trajectory_steady_mm are D_trajectory over the dynamic rung's first and steady
// revolutions (solvers::DynamicOptions::steady_revolution); the time-free rungs' path is
// steady by construction, so for them both equal d_trajectory_mm. The last five are over
// every revolution the assembly will turn (solvers::LifeValues, docs/model.md §9):
// D_trajectory and runout over the union of the revolutions, and ISO 230-7's total,
// synchronous and asynchronous radial error motion values along the sensor's direction.
inline constexpr std::array<const char*, 14> kOutputNames = {
    "d_trajectory_mm",     "dist_init_mm",        "static_offset_mm",      "runout_mm",
    "swing_mm",            "min_contact_force_N", "max_contact_force_N",   "d_trajectory_first_mm",
    "d_trajectory_steady_mm", "life_d_trajectory_mm", "life_runout_mm", "error_motion_total_mm",
    "error_motion_synchronous_mm", "error_motion_asynchronous_mm"};
// Where the life outputs start in kOutputNames: files of schema 3 and before end there.
inline constexpr std::size_t kFirstLifeOutput = 9;
inline constexpr std::size_t kOutputCount = kOutputNames.size();
// Whether `output` is one of the three error-motion values, which the error motion's filter
// reads (engine::ErrorMotionFilter) and whose datasets state it.
inline bool IsErrorMotionOutput(std::string_view output) { return output.starts_with("error_motion_"); }

inline constexpr std::int8_t kNoRung = -1;

struct SampleRecord {
  std::int64_t index = 0;
  SampleStatus status = SampleStatus::kPending;
  std::string message;                   // why, when status != kOk; empty otherwise
  std::vector<double> u;                 // the design point (before inspection redraws): the replay key
  std::vector<double> values;            // drawn values per sampler input, in the units of their names
  std::int32_t redraws = 0;              // inspected parts rejected and drawn again
  std::int32_t steps = 0;                // angles per revolution the solver used
  std::array<double, kOutputCount> outputs{};  // NaN when status != kOk
  // [mm] the rung's own bound on its error in d_trajectory_mm against the exact model
  // (solvers::Trajectory::error_estimate: the linear rung's bound on what its second-order
  // path misses, 0 for the rungs that solve the exact model); NaN when status != kOk.
  double d_trajectory_error = 0.0;
  // The rung whose path the outputs are (solvers::Rung's number: 0 linear, 1 quasistatic,
  // 2 dynamic; the auto rung picks one per sample); kNoRung when no rung ran.
  std::int8_t rung = kNoRung;
  double solve_time = 0.0;               // [s] wall time of realise + simulate
  // DrawChecksum of this record, when whoever drew it computed it (SampleDrawer does, on
  // the computing thread, so that the writer need not): empty otherwise.
  std::optional<std::uint32_t> draw_checksum;
};

// A checksum of a sample's draw as a results file stores it: CRC-32 (zlib's) of the bits
// of u, of the values rounded to float32, and of the redraws. A file that keeps only the
// first samples' inputs keeps this of every sample, so a replay (SampleDrawer) that no
// longer reproduces a draw (another sampler, another catalogue) is caught, not trusted.
std::uint32_t DrawChecksum(const SampleRecord& record);

}  // namespace ringtol::jobs
