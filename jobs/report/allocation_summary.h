// What an allocation found, for the terminal and as JSON: the recommended classes, their
// cost against the reference, their margin to every limit, the alternatives, what stays
// undecided, and what the search cost. `ringtol allocate` prints it at the end of a run;
// the report (jobs/report/allocation_report.h) draws the same numbers.
#pragma once

#include <optional>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "jobs/allocation/allocation_outcome.h"

namespace ringtol::jobs {

// A class as a buyer orders it, with its mode: "5 (inspected)", "IT7/2 (process)". A
// class means other parts in another mode (inspected parts are sorted, as-made ones are
// not), so every place that names a class, on the terminal, the page and in JSON, names
// it through this.
std::string ClassWithMode(const AllocationIdentity::Option& option);
// "ring IT7/2 (process), rollers 5 (inspected), roller_positions IT8 (process), springs
// pm10 (process)".
std::string CandidateClasses(const AllocationIdentity& identity, const CandidateOutcome& candidate);
// "25.5 times", or beyond 10^4 a sentence: a ratio that large says the two candidates'
// values move together, and its digits mean nothing.
std::string CommonRandomGainText(double gain);
// "d_trajectory_mm: 99 % quantile <= 0.05 mm" or "static_offset_mm: yield >= 99.73 % within 0.03 mm".
std::string ConstraintText(const analysis::Constraint& constraint);
// How far a judged constraint is from its limit, on the safe side > 0: the limit less the
// interval's upper end (quantile, in the output's unit), or the interval's lower end less
// the least yield (yield, as a fraction).
double Margin(const analysis::Constraint& constraint, const analysis::ConstraintJudgement& judgement);

// How the error motion that a constraint names was read (ErrorMotionConditions,
// jobs/report/report_text.h); none when no constraint names one.
std::optional<std::string> ConstrainedErrorMotionReading(const AllocationIdentity& identity);

void PrintAllocation(std::ostream& out, const AllocationIdentity& identity, const AllocationOutcome& outcome);
nlohmann::json AllocationJson(const AllocationIdentity& identity, const AllocationOutcome& outcome);

}  // namespace ringtol::jobs
