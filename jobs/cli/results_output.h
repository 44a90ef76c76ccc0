// How simulation results leave ringtol: JSON objects (the stable interface for scripts),
// aligned text tables for people, and CSV files. Output units are mm, N and degrees,
// with the unit in every key name.
#pragma once

#include <filesystem>
#include <fstream>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/scene.h"
#include "solvers/dynamic.h"
#include "solvers/simulation.h"

namespace ringtol::jobs {

// One simulation as a JSON object: solver (the rung's name), status (and message when not
// "ok"), steps, d_trajectory_mm, dist_init_mm, static_offset_mm, runout_mm
// (max - min), swing_mm, min_contact_force_N, contact_force_N (per roller min/max),
// d_trajectory_first_mm and d_trajectory_steady_mm, solve_time_ms. Metrics are null when
// the status is not "ok". `case_name` adds a "case" key when non-empty. The dynamic rung
// adds "dynamic_start" (solvers::kDynamicStartNames); its d_trajectory_first_mm is
// d_trajectory_mm (the first revolution after rotation starts), its
// d_trajectory_steady_mm the later revolution's (null when that failed or the law stopped
// before it), and a result with that revolution adds "steady": an object with the same
// status and metric keys for it. For the time-free rungs, whose path is steady by
// construction, both equal d_trajectory_mm.
nlohmann::json ResultJson(const engine::Scene& scene, const solvers::SimulationResult& result,
                          const solvers::SolverSettings& solver, double solve_seconds, const std::string& case_name = "");

// Human-readable block for `ringtol simulate`; the dynamic rung's adds its start and the
// first and steady revolutions' D_trajectory.
void PrintResult(std::ostream& out, const engine::Scene& scene, const solvers::SimulationResult& result,
                 const solvers::SolverSettings& solver, double solve_seconds);

// An output file opened up front, so that a bad path fails before any work is done.
// Throws InputError naming `option` and the file. The optional form leaves the stream
// closed when `file` is empty (the option was not given).
std::ofstream OpenOutput(const std::filesystem::path& file, const char* option);
std::ofstream OpenOptionalOutput(const std::filesystem::path& file, const char* option);

// Aligned table, one row per sweep case; D_first and D_steady columns when a row is dynamic.
void PrintSweepTable(std::ostream& out, const std::vector<nlohmann::json>& rows);

// CSV with one row per sweep case and the JSON keys as columns, ending in
// d_trajectory_first_mm, d_trajectory_steady_mm and dynamic_start (empty for the time-free rungs).
void WriteSweepCsv(std::ostream& out, const std::vector<nlohmann::json>& rows);

// The path over the revolution: psi_deg, x_mm, y_mm, sensor_mm, then travel_<roller>_mm
// for spring rollers and force_<roller>_N for every roller.
void WriteTrajectoryCsv(std::ostream& out, const engine::Scene& scene, const solvers::SimulationResult& result);

// The dynamic solver's time history: time_s, psi_deg, x_um, y_um, then per roller
// <name>_travel_um, _spin_deg, _spin_rate_deg_per_s, _normal_N, _friction_N (on the ring,
// along the contact tangent) and _slip_mm_per_s. Every sample computed is written, also
// when the history stopped early.
void WriteHistoryCsv(std::ostream& out, const engine::Scene& scene, const solvers::DynamicHistory& history);

}  // namespace ringtol::jobs
