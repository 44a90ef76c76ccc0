#include "jobs/cli/results_output.h"

#include <algorithm>
#include <numbers>
#include <string>
#include <utility>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "engine/units.h"
#include "jobs/inputs/input_error.h"

namespace ringtol::jobs {
namespace {


// The columns of the sweep table and CSV, in order, with their display format.
struct Column {
  const char* key;
  const char* header;
  int width;
  int decimals;
};
constexpr Column kColumns[] = {
    {"d_trajectory_mm", "D_traj mm", 10, 4},   {"dist_init_mm", "Dist_init mm", 12, 4},
    {"static_offset_mm", "offset mm", 10, 4},  {"runout_mm", "runout mm", 10, 4},
    {"min_contact_force_N", "min F N", 8, 3},
};

std::string Cell(const nlohmann::json& value, int decimals) {
  if (value.is_null()) return "-";
  if (value.is_number()) return fmt::format("{:.{}f}", value.get<double>(), decimals);
  if (value.is_string()) return value.get<std::string>();
  return value.dump();
}

}  // namespace

namespace {

std::string DescribeSwingRule(const engine::SwingRule& rule) {
  const std::string resolution = fmt::format("resolution {:g} um", rule.resolution * units::kMicrometresPerMetre);
  if (!(rule.cutoff_upr > 0.0)) return resolution + ", unfiltered";
  return fmt::format("{}, Gaussian filter at {:g} undulations per revolution", resolution, rule.cutoff_upr);
}

// The metric keys of one revolution (shared by the result and its steady revolution).
void PutMetrics(nlohmann::json& j, const engine::Scene& scene, const solvers::SimulationResult& result) {
  j["status"] = std::string(solvers::StatusName(result.status));
  if (result.status != solvers::Status::kOk) j["message"] = result.message;
  const bool ok = result.status == solvers::Status::kOk;
  auto metric = [&](double value, double scale) { return ok ? nlohmann::json(value * scale) : nlohmann::json(); };
  j["d_trajectory_mm"] = metric(result.d_trajectory, units::kMillimetresPerMetre);
  j["dist_init_mm"] = metric(result.dist_init, units::kMillimetresPerMetre);
  j["static_offset_mm"] = metric(result.static_offset, units::kMillimetresPerMetre);
  j["runout_mm"] = metric(result.runout, units::kMillimetresPerMetre);
  j["swing_mm"] = metric(result.swing, units::kMillimetresPerMetre);
  j["min_contact_force_N"] = metric(result.min_contact_force, 1.0);
  nlohmann::json forces = nlohmann::json::array();
  if (ok) {
    for (std::size_t i = 0; i < scene.rollers.size(); ++i) {
      forces.push_back({{"roller", scene.rollers[i].name},
                        {"min", result.contact_force[i].min},
                        {"max", result.contact_force[i].max},
                        {"off_bore_percent", units::kPercentPerFraction * result.contact_force[i].off_bore}});
    }
  }
  j["contact_force_N"] = forces;
}

// Whether any sweep row ran on the dynamic rung (and so has a start and two revolutions).
bool AnyDynamic(const std::vector<nlohmann::json>& rows) {
  return std::any_of(rows.begin(), rows.end(), [](const nlohmann::json& row) { return row.contains("dynamic_start"); });
}

// D_trajectory of the first and of the steady revolution [mm], null where not usable. A
// time-free rung's path does not depend on time, so both are its one D_trajectory; the
// dynamic rung's steady one is its later revolution (null when it failed or the law
// stopped before it).
std::pair<nlohmann::json, nlohmann::json> FirstAndSteady(const solvers::SimulationResult& result, bool dynamic) {
  if (result.status != solvers::Status::kOk) return {nlohmann::json(), nlohmann::json()};
  const double first = result.d_trajectory * units::kMillimetresPerMetre;
  if (!dynamic) return {first, first};
  const bool steady = result.steady && result.steady->status == solvers::Status::kOk;
  return {first, steady ? nlohmann::json(result.steady->d_trajectory * units::kMillimetresPerMetre) : nlohmann::json()};
}

std::string CsvNumber(const nlohmann::json& value) {
  return value.is_null() ? "" : fmt::format("{:.9g}", value.get<double>());
}

// The lines the first and the steady revolution share: status, then the reason it failed or
// its distances; false if it failed. Names fill one column of 18 characters, so that the
// steady revolution's, `indent`ed, line up under the first's.
bool PrintStatusAndDistances(std::ostream& out, std::string_view status, std::string_view indent,
                             const solvers::SimulationResult& result) {
  constexpr std::size_t kColumn = 18;
  const std::size_t width = kColumn - indent.size();
  fmt::print(out, "{:<{}}{}\n", status, kColumn, solvers::StatusName(result.status));
  if (result.status != solvers::Status::kOk) {
    fmt::print(out, "{}{:<{}}{}\n", indent, "reason", width, result.message);
    return false;
  }
  fmt::print(out, "{}{:<{}}{:.4f} mm\n", indent, "D_trajectory", width, result.d_trajectory * units::kMillimetresPerMetre);
  fmt::print(out, "{}{:<{}}{:.4f} mm\n", indent, "Dist_init", width, result.dist_init * units::kMillimetresPerMetre);
  return true;
}

}  // namespace

nlohmann::json ResultJson(const engine::Scene& scene, const solvers::SimulationResult& result,
                          const solvers::SolverSettings& solver, double solve_seconds, const std::string& case_name) {
  nlohmann::json j;
  if (!case_name.empty()) j["case"] = case_name;
  j["solver"] = std::string(NameOf(solvers::kRungNames, solver.rung));
  if (result.trajectory.rung) j["rung"] = std::string(NameOf(solvers::kRungNames, *result.trajectory.rung));
  const bool dynamic = solver.rung == solvers::Rung::kDynamic || result.trajectory.rung == solvers::Rung::kDynamic;
  if (dynamic) j["dynamic_start"] = std::string(NameOf(solvers::kDynamicStartNames, solver.dynamic_start));
  if (solver.simulation.accuracy != solvers::Accuracy::kFull) {
    j["accuracy"] = std::string(NameOf(solvers::kAccuracyNames, solver.simulation.accuracy));
  }
  PutMetrics(j, scene, result);
  const auto [first_diameter, steady_diameter] = FirstAndSteady(result, dynamic);
  j["d_trajectory_first_mm"] = first_diameter;
  j["d_trajectory_steady_mm"] = steady_diameter;
  j["steps"] = result.steps;
  if (result.steady) {
    nlohmann::json steady;
    PutMetrics(steady, scene, *result.steady);
    j["steady"] = steady;
  }
  j["solve_time_ms"] = solve_seconds * 1e3;
  return j;
}

void PrintResult(std::ostream& out, const engine::Scene& scene, const solvers::SimulationResult& result,
                 const solvers::SolverSettings& solver, double solve_seconds) {
  const bool chose = solver.rung == solvers::Rung::kAuto && result.trajectory.rung;
  fmt::print(out, "solver            {}{} ({} steps, {:.3f} ms)\n", solvers::SolverDescription(solver),
             chose ? fmt::format(": {}", NameOf(solvers::kRungNames, *result.trajectory.rung)) : std::string(),
             result.steps, solve_seconds * 1e3);
  if (!PrintStatusAndDistances(out, "status", "", result)) return;
  if (solver.rung == solvers::Rung::kDynamic || result.trajectory.rung == solvers::Rung::kDynamic) {
    const auto [first, steady] = FirstAndSteady(result, true);
    fmt::print(out, "revolutions       D_trajectory first {} mm, steady {} mm\n", Cell(first, 4), Cell(steady, 4));
  }
  fmt::print(out, "static offset     {:.4f} mm\n", result.static_offset * units::kMillimetresPerMetre);
  fmt::print(out, "runout            {:.4f} mm max - min (sensor at {:g} deg)\n", result.runout * units::kMillimetresPerMetre,
             scene.sensor_angle * units::kDegreesPerRadian);
  fmt::print(out, "swing             {:.4f} mm peak to valley, {}\n", result.swing * units::kMillimetresPerMetre,
             DescribeSwingRule(scene.sensor_swing));
  for (std::size_t i = 0; i < scene.rollers.size(); ++i) {
    const solvers::RollerForceRange& range = result.contact_force[i];
    fmt::print(out, "contact force     {:<10} {:.3f} .. {:.3f} N{}\n", scene.rollers[i].name, range.min, range.max,
               range.off_bore > 0.0 ? fmt::format(", off the bore over {:.1f} % of the turn", units::kPercentPerFraction * range.off_bore)
                                    : std::string());
  }
  if (!result.steady) return;
  const solvers::SimulationResult& steady = *result.steady;
  if (!PrintStatusAndDistances(out, "steady revolution", "  ", steady)) return;
  fmt::print(out, "  runout          {:.4f} mm max - min, swing {:.4f} mm\n", steady.runout * units::kMillimetresPerMetre,
             steady.swing * units::kMillimetresPerMetre);
  fmt::print(out, "  min contact     {:.3f} N\n", steady.min_contact_force);
}

void PrintSweepTable(std::ostream& out, const std::vector<nlohmann::json>& rows) {
  std::size_t case_width = 4;
  for (const nlohmann::json& row : rows) case_width = std::max(case_width, row.value("case", std::string()).size());
  const bool dynamic = AnyDynamic(rows);
  fmt::print(out, "{:<{}}  {:<10}", "case", case_width, "status");
  for (const Column& c : kColumns) fmt::print(out, "  {:>{}}", c.header, c.width);
  if (dynamic) fmt::print(out, "  {:>11}  {:>11}", "D_first mm", "D_steady mm");
  fmt::print(out, "\n");
  for (const nlohmann::json& row : rows) {
    fmt::print(out, "{:<{}}  {:<10}", row.value("case", std::string()), case_width, row["status"].get<std::string>());
    for (const Column& c : kColumns) fmt::print(out, "  {:>{}}", Cell(row[c.key], c.decimals), c.width);
    if (dynamic) {
      fmt::print(out, "  {:>11}  {:>11}", Cell(row["d_trajectory_first_mm"], 4), Cell(row["d_trajectory_steady_mm"], 4));
    }
    if (row.contains("message")) fmt::print(out, "  {}", row["message"].get<std::string>());
    fmt::print(out, "\n");
  }
}

void WriteSweepCsv(std::ostream& out, const std::vector<nlohmann::json>& rows) {
  fmt::print(out, "case,solver,status,steps");
  for (const Column& c : kColumns) fmt::print(out, ",{}", c.key);
  fmt::print(out, ",swing_mm,solve_time_ms,message,d_trajectory_first_mm,d_trajectory_steady_mm,dynamic_start\n");
  auto quoted = [](const std::string& s) {
    std::string q = "\"";
    for (char ch : s) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
    return q + "\"";
  };
  for (const nlohmann::json& row : rows) {
    fmt::print(out, "{},{},{},{}", quoted(row.value("case", std::string())), row["solver"].get<std::string>(),
               row["status"].get<std::string>(), row["steps"].get<int>());
    for (const Column& c : kColumns) fmt::print(out, ",{}", row[c.key].is_null() ? "" : fmt::format("{:.9g}", row[c.key].get<double>()));
    fmt::print(out, ",{},{:.6g},{}",
               row["swing_mm"].is_null() ? "" : fmt::format("{:.9g}", row["swing_mm"].get<double>()),
               row["solve_time_ms"].get<double>(), quoted(row.value("message", std::string())));
    fmt::print(out, ",{},{},{}\n", CsvNumber(row["d_trajectory_first_mm"]), CsvNumber(row["d_trajectory_steady_mm"]),
               row.value("dynamic_start", std::string()));
  }
}

void WriteTrajectoryCsv(std::ostream& out, const engine::Scene& scene, const solvers::SimulationResult& result) {
  const solvers::Trajectory& path = result.trajectory;
  const std::size_t z = scene.rollers.size();
  fmt::print(out, "psi_deg,x_mm,y_mm,sensor_mm");
  for (const engine::Roller& r : scene.rollers) {
    if (r.mount == engine::RollerMount::kSpring) fmt::print(out, ",travel_{}_mm", r.name);
  }
  for (const engine::Roller& r : scene.rollers) fmt::print(out, ",force_{}_N", r.name);
  fmt::print(out, "\n");
  for (std::size_t k = 0; k < path.psi.size(); ++k) {
    fmt::print(out, "{:.9g},{:.9g},{:.9g},{:.9g}", path.psi[k] * units::kDegreesPerRadian, path.centre[k].x() * units::kMillimetresPerMetre,
               path.centre[k].y() * units::kMillimetresPerMetre, k < result.sensor.size() ? result.sensor[k] * units::kMillimetresPerMetre : 0.0);
    for (std::size_t i = 0; i < z; ++i) {
      if (scene.rollers[i].mount == engine::RollerMount::kSpring) fmt::print(out, ",{:.9g}", path.travel[k * z + i] * units::kMillimetresPerMetre);
    }
    for (std::size_t i = 0; i < z; ++i) fmt::print(out, ",{:.9g}", path.contact_force[k * z + i]);
    fmt::print(out, "\n");
  }
}

void WriteHistoryCsv(std::ostream& out, const engine::Scene& scene, const solvers::DynamicHistory& history) {
  fmt::print(out, "time_s,psi_deg,x_um,y_um");
  for (const engine::Roller& r : scene.rollers) {
    fmt::print(out, ",{0}_travel_um,{0}_spin_deg,{0}_spin_rate_deg_per_s,{0}_normal_N,{0}_friction_N,{0}_slip_mm_per_s",
               r.name);
  }
  fmt::print(out, "\n");
  for (const solvers::DynamicSample& s : history.samples) {
    fmt::print(out, "{:.9g},{:.9g},{:.9g},{:.9g}", s.time, s.psi * units::kDegreesPerRadian, s.centre.x() * units::kMicrometresPerMetre, s.centre.y() * units::kMicrometresPerMetre);
    for (std::size_t i = 0; i < scene.rollers.size(); ++i) {
      fmt::print(out, ",{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}", s.travel[i] * units::kMicrometresPerMetre, s.spin_angle[i] * units::kDegreesPerRadian,
                 s.spin_rate[i] * units::kDegreesPerRadian, s.normal_force[i], s.friction_force[i], s.slip[i] * units::kMillimetresPerMetre);
    }
    fmt::print(out, "\n");
  }
}

std::ofstream OpenOutput(const std::filesystem::path& file, const char* option) {
  std::ofstream out(file);
  if (!out) throw InputError(std::string(option) + " " + file.string() + ": cannot open for writing");
  return out;
}

std::ofstream OpenOptionalOutput(const std::filesystem::path& file, const char* option) {
  return file.empty() ? std::ofstream() : OpenOutput(file, option);
}

}  // namespace ringtol::jobs
