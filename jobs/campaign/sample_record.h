// One simulated sample of a campaign as it travels from the rank that computed it to the
// results file: its identity, its inputs (enough to replay it alone) and its outputs.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/check.h"
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

// What an output is read over: the revolution a sample simulates; one of the dynamic rung's
// own revolutions, its first or its steady one (solvers::DynamicOptions::steady_revolution),
// which the time-free rungs, whose path is steady by construction, give as the revolution's
// value; or every revolution the assembly will turn (solvers::LifeValues, docs/model.md
// §9), which a campaign may leave out (CampaignIdentity::life) and an allocation computes
// only when a constraint names it.
enum class OutputSpan { kRevolution, kDynamicRevolution, kLife };

// One per-sample output: its name (its unit the suffix, as every key of ringtol's files
// carries it), its unit, how summaries and reports label it, what it is read over, the
// first results schema that stores it (jobs/store/campaign_store.h; older files read it as
// NaN) and what it is, in one line. Adding an output: compute it and fill it in
// SampleEvaluator::Evaluate (jobs/campaign/campaign.cpp), add its row here, at the end
// (stored columns follow this order), and document it (docs/architecture.md, "An output").
struct OutputDescription {
  const char* name;
  const char* unit;  // "mm", "N": the allocation's limit key (upper_<unit>) and the reports' units
  const char* label;
  OutputSpan span;
  int first_schema;
  const char* definition;
};

// The per-sample outputs.
inline constexpr auto kOutputs = std::to_array<OutputDescription>({
    {"d_trajectory_mm", "mm", "D_trajectory", OutputSpan::kRevolution, 1, "diameter of the smallest circle enclosing the centre's path"},
    {"dist_init_mm", "mm", "Dist_init", OutputSpan::kRevolution, 1, "distance from the static equilibrium to that circle's centre"},
    {"static_offset_mm", "mm", "static offset", OutputSpan::kRevolution, 1, "distance from the nominal centre to the static equilibrium"},
    {"runout_mm", "mm", "runout (max - min)", OutputSpan::kRevolution, 1, "max - min of the sensor's reading"},
    {"swing_mm", "mm", "swing", OutputSpan::kRevolution, 2, "largest peak-to-valley swing of the reading at its resolution"},
    {"min_contact_force_N", "N", "min contact force", OutputSpan::kRevolution, 1, "smallest contact force of any roller"},
    {"max_contact_force_N", "N", "max contact force", OutputSpan::kRevolution, 1, "largest contact force of any roller"},
    {"d_trajectory_first_mm", "mm", "d trajectory first", OutputSpan::kDynamicRevolution, 2, "D_trajectory over the first revolution"},
    {"d_trajectory_steady_mm", "mm", "d trajectory steady", OutputSpan::kDynamicRevolution, 2, "D_trajectory over the steady revolution"},
    {"life_d_trajectory_mm", "mm", "D_trajectory over the life", OutputSpan::kLife, 4, "D_trajectory over every revolution of the life"},
    {"life_runout_mm", "mm", "runout (max - min) over the life", OutputSpan::kLife, 4, "the sensor's max - min over every revolution"},
    {"error_motion_total_mm", "mm", "total error motion", OutputSpan::kLife, 4, "ISO 230-7 total radial error motion value"},
    {"error_motion_synchronous_mm", "mm", "synchronous error motion", OutputSpan::kLife, 4, "ISO 230-7 synchronous radial error motion value"},
    {"error_motion_asynchronous_mm", "mm", "asynchronous error motion", OutputSpan::kLife, 4, "ISO 230-7 asynchronous radial error motion value"},
#ifdef RINGTOL_TEST_OUTPUT
    // Only tests/jobs/fake_output compiles this row in: an output added as a new one would
    // be, to show that its row is all the store, the summary, the report and the
    // allocation need (its value: SampleEvaluator::Evaluate's one test-only line).
    {"test_output_mm", "mm", "test output", OutputSpan::kRevolution, 6, "twice D_trajectory"},
#endif
});
inline constexpr std::array<const char*, kOutputs.size()> kOutputNames = [] {
  std::array<const char*, kOutputs.size()> names{};
  for (std::size_t k = 0; k < kOutputs.size(); ++k) names[k] = kOutputs[k].name;
  return names;
}();
// Every name ends in "_" and its unit, as the keys of ringtol's files do.
static_assert([] {
  for (const OutputDescription& output : kOutputs) {
    const std::string_view name = output.name, unit = output.unit;
    if (!name.ends_with(unit) || name.size() <= unit.size() || name[name.size() - unit.size() - 1] != '_') return false;
  }
  return true;
}(), "an output's name must end in _<its unit>");
inline constexpr bool IsLifeOutput(std::size_t output) { return kOutputs[output].span == OutputSpan::kLife; }
inline constexpr std::size_t kOutputCount = kOutputNames.size();
// Where the output named `name` is in kOutputs; kOutputCount when no output has that name.
constexpr std::size_t OutputIndex(std::string_view name) {
  std::size_t k = 0;
  while (k < kOutputCount && name != kOutputs[k].name) ++k;
  return k;
}
// The row of the output named `name`, which must be one (RINGTOL_CHECK: callers hold names
// checked against the table, a campaign's spec or an allocation's constraints).
inline const OutputDescription& OutputNamed(std::string_view name) {
  const std::size_t output = OutputIndex(name);
  RINGTOL_CHECK(output < kOutputCount, name);
  return kOutputs[output];
}
// Whether `output` is one of the three error-motion values, which the error motion's filter
// reads (engine::ErrorMotionFilter) and whose datasets state it.
constexpr bool IsErrorMotionOutput(std::string_view output) { return output.starts_with("error_motion_"); }

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
  // [%] for each roller of the scene, in its order: the share of the revolution's angles
  // at which it carried nothing, off the bore with the ring resting on the others
  // (solvers::RollerForceRange::off_bore); empty when status != kOk.
  std::vector<double> off_bore;
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
