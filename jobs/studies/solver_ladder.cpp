#include "jobs/studies/solver_ladder.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "analysis/order_statistics.h"
#include "jobs/inputs/input_error.h"
#include "jobs/report/svg_chart.h"
#include "solvers/dynamic.h"
#include "solvers/linear.h"
#include "solvers/quasistatic.h"
#include "solvers/simulation.h"
#include "engine/units.h"

namespace ringtol::jobs {
namespace {

using solvers::Rung;

constexpr double kMs = 1e3;
constexpr double kWithin = 1e-6;  // [m] "within 1 um"

struct Case {
  std::string name;
  engine::Scene scene;
  int steps = 0;
  double reference = 0.0;              // [m] dynamic full model at 1e-10
  double penalty_reference = 0.0;      // [m] quasistatic penalty at 20x steps
  double rigid_reference = 0.0;        // [m] quasistatic rigid at 20x steps
};

// One setting of one rung: how it changes the case's scene and which solver it runs.
struct Method {
  std::string name;
  solvers::Rung rung;
  std::function<void(engine::Scene&)> adapt;
  std::shared_ptr<const solvers::Solver> solver;
  double steps_factor = 1.0;  // of the case's steps
  bool slow = false;          // time once instead of `repeats` times
  std::string only_case;      // non-empty: run on this case only
};

// The article's order and amplitude studies on the scene's nominal assembly.
std::vector<Case> Cases(const engine::Scene& scene, const LadderOptions& options) {
  std::vector<Case> cases;
  auto add = [&](int order, double amplitude) {
    Case c;
    c.name = fmt::format("n={} C={:.2f}mm", order, amplitude * units::kMillimetresPerMetre);
    c.scene = engine::WithoutErrors(scene);
    c.scene.ring.inner = engine::PolarProfile(scene.ring.inner.radius(), 0.0, {{order, amplitude, 45.0 * units::kRadiansPerDegree}});
    c.steps = solvers::ChooseSteps(c.scene, {});
    cases.push_back(std::move(c));
  };
  if (options.cases == "orders" || options.cases == "all") {
    for (const int order : {2, 3, 4, 5, 6, 7, 8, 9, 10, 12, 15, 17, 20}) add(order, 0.14e-3);
  }
  if (options.cases == "amplitudes" || options.cases == "all") {
    for (const int order : {2, 6}) {
      for (int k = 1; k <= 10; ++k) add(order, 0.07e-3 * k);
    }
  }
  if (options.max_cases > 0 && cases.size() > static_cast<std::size_t>(options.max_cases)) {
    cases.resize(static_cast<std::size_t>(options.max_cases));
  }
  return cases;
}

std::shared_ptr<const solvers::Solver> Dynamic(double tolerance, solvers::DynamicMethod method = solvers::DynamicMethod::kImplicitBdf,
                                               double step = 0.0) {
  solvers::DynamicOptions options;
  // The article's start: the reference is its quantity, the first revolution after its settle.
  options.start = solvers::DynamicStart::kArticleSettle;
  options.steady_revolution = 0;
  options.relative_tolerance = tolerance;
  options.method = method;
  options.explicit_step = step;
  return std::make_shared<solvers::DynamicSolver>(options);
}

void Reduce(engine::Scene& scene, bool massless, bool rolling) {
  scene.dynamics.massless_spring_rollers = massless;
  scene.dynamics.rolling_without_slip = rolling;
  scene.dynamics.friction = !rolling;
}

// The ladder chart's colour of each rung (ColorBrewer Dark2).
const char* RungColour(solvers::Rung rung) {
  switch (rung) {
    case Rung::kLinear: return "#1b9e77";
    case Rung::kQuasistatic: return "#d95f02";
    case Rung::kDynamic: return "#7570b3";
    case Rung::kAuto: return "#e7298a";
  }
  return "#7570b3";
}

std::vector<Method> Methods(const LadderOptions& options) {
  auto keep = [](engine::Scene&) {};
  auto rigid = [](engine::Scene& scene) { scene.contact.model = engine::ContactLaw::Model::kRigid; };
  std::vector<Method> methods;
  methods.push_back({"linear", Rung::kLinear, keep, std::make_shared<solvers::LinearSolver>(), 1.0, false, {}});
  for (const double factor : {0.25, 1.0, 4.0}) {
    const std::string steps = factor == 1.0 ? "S" : fmt::format("{:g}S", factor);
    methods.push_back({"quasistatic rigid, " + steps + " steps", Rung::kQuasistatic, rigid,
                       std::make_shared<solvers::QuasistaticSolver>(), factor, false, {}});
    methods.push_back({"quasistatic penalty, " + steps + " steps", Rung::kQuasistatic, keep,
                       std::make_shared<solvers::QuasistaticSolver>(), factor, false, {}});
  }
  for (const double tolerance : {1e-4, 1e-5, 1e-6, 1e-7, 1e-8}) {
    methods.push_back({fmt::format("dynamic BDF rtol {:g}", tolerance), Rung::kDynamic, keep, Dynamic(tolerance), 1.0, false, {}});
  }
  methods.push_back({"dynamic BDF rtol 1e-05, massless spring roller", Rung::kDynamic,
                     [](engine::Scene& s) { Reduce(s, true, false); }, Dynamic(1e-5), 1.0, false, {}});
  methods.push_back({"dynamic BDF rtol 1e-05, rolling without slip", Rung::kDynamic,
                     [](engine::Scene& s) { Reduce(s, false, true); }, Dynamic(1e-5), 1.0, false, {}});
  methods.push_back({"dynamic BDF rtol 1e-05, both reduced", Rung::kDynamic, [](engine::Scene& s) { Reduce(s, true, true); },
                     Dynamic(1e-5), 1.0, false, {}});
  for (const double step : {40e-6, 20e-6, 10e-6}) {
    // Below the stability limit each run takes seconds.
    if (options.skip_slow && step < 40e-6) continue;
    methods.push_back({fmt::format("dynamic explicit RK4 h={:g}us, both reduced", step * 1e6), Rung::kDynamic,
                       [](engine::Scene& s) { Reduce(s, true, true); },
                       Dynamic(1e-6, solvers::DynamicMethod::kExplicitRungeKutta, step), 1.0, true, {}});
  }
  if (options.explicit_full_model) {
    methods.push_back({"dynamic explicit RK4 h=65ns, full model", Rung::kDynamic, keep,
                       Dynamic(1e-6, solvers::DynamicMethod::kExplicitRungeKutta, 65e-9), 1.0, true,
                       "n=2 C=0.14mm"});
  }
  return methods;
}

struct Timed {
  solvers::SimulationResult result;
  double seconds = 0.0;  // median
};

Timed TimedRun(const engine::Scene& scene, const solvers::Solver& solver, int steps, int repeats) {
  solvers::SimulationOptions options;
  options.steps = steps;
  std::vector<double> times;
  Timed timed;
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    timed.result = solvers::Simulate(scene, solver, options);
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  timed.seconds = analysis::Median(times);
  return timed;
}

}  // namespace

LadderResult RunLadder(const engine::Scene& scene, const LadderOptions& options, std::ostream* progress) {
  if (options.cases != "orders" && options.cases != "amplitudes" && options.cases != "all") {
    throw InputError("--cases " + options.cases + ": allowed: orders, amplitudes, all");
  }
  if (options.repeats < 1) throw InputError("--repeats " + std::to_string(options.repeats) + ": allowed: >= 1");
  std::vector<Case> cases = Cases(scene, options);
  LadderResult result;
  result.cases = static_cast<int>(cases.size());
  const auto reference = Dynamic(1e-10);
  const solvers::QuasistaticSolver quasistatic;
  std::vector<double> reference_times;
  for (Case& c : cases) {
    if (progress != nullptr) fmt::print(*progress, "reference {}\n", c.name);
    const Timed run = TimedRun(c.scene, *reference, c.steps, 1);
    if (run.result.status != solvers::Status::kOk) {
      throw InputError(fmt::format("the reference run of case {} failed ({}: {}); the ladder needs it", c.name,
                                   solvers::StatusName(run.result.status), run.result.message));
    }
    c.reference = run.result.d_trajectory;
    reference_times.push_back(run.seconds);
    c.penalty_reference = TimedRun(c.scene, quasistatic, 20 * c.steps, 1).result.d_trajectory;
    engine::Scene rigid = c.scene;
    rigid.contact.model = engine::ContactLaw::Model::kRigid;
    c.rigid_reference = TimedRun(rigid, quasistatic, 20 * c.steps, 1).result.d_trajectory;
  }
  result.reference_time = analysis::Median(reference_times);

  for (const Method& method : Methods(options)) {
    if (progress != nullptr) fmt::print(*progress, "{}\n", method.name);
    LadderRow row;
    row.method = method.name;
    row.rung = method.rung;
    std::vector<double> times;
    double numerical = 0.0;
    for (const Case& c : cases) {
      // The order and amplitude studies share a case: a method meant for one case runs
      // on its first occurrence only.
      if (!method.only_case.empty() && (c.name != method.only_case || row.cases_run > 0)) continue;
      engine::Scene scene_for_method = c.scene;
      method.adapt(scene_for_method);
      const int steps = std::max(1, static_cast<int>(std::lround(method.steps_factor * c.steps)));
      const Timed run = TimedRun(scene_for_method, *method.solver, steps, method.slow ? 1 : options.repeats);
      ++row.cases_run;
      if (run.result.status != solvers::Status::kOk) {
        if (row.cases_failed++ == 0) {
          row.first_failure =
              fmt::format("{}: {}: {}", c.name, solvers::StatusName(run.result.status), run.result.message);
        }
        continue;
      }
      times.push_back(run.seconds);
      row.error = std::max(row.error, std::abs(run.result.d_trajectory - c.reference));
      const bool rigid = scene_for_method.contact.model == engine::ContactLaw::Model::kRigid;
      numerical = std::max(numerical,
                           std::abs(run.result.d_trajectory - (rigid ? c.rigid_reference : c.penalty_reference)));
    }
    row.time = analysis::Median(times);
    if (method.rung != Rung::kDynamic) row.numerical_error = numerical;
    if (row.cases_failed == row.cases_run) row.error = std::numeric_limits<double>::quiet_NaN();
    result.rows.push_back(row);
  }
  for (std::size_t i = 0; i < result.rows.size(); ++i) {
    const LadderRow& row = result.rows[i];
    if (row.cases_failed > 0 || !(row.error <= kWithin)) continue;
    if (result.fastest_within < 0 || row.time < result.rows[static_cast<std::size_t>(result.fastest_within)].time) {
      result.fastest_within = static_cast<int>(i);
    }
  }
  return result;
}

void WriteLadderCsv(std::ostream& out, const LadderResult& result) {
  fmt::print(out, "method,rung,cases_run,cases_failed,time_ms,error_um,numerical_error_um,first_failure\n");
  auto number = [](double value, double scale) { return std::isnan(value) ? std::string() : fmt::format("{:.6g}", value * scale); };
  for (const LadderRow& row : result.rows) {
    std::string failure = "\"";
    for (const char c : row.first_failure) failure += c == '"' ? std::string("\"\"") : std::string(1, c);
    failure += "\"";
    fmt::print(out, "\"{}\",{},{},{},{},{},{},{}\n", row.method, NameOf(solvers::kRungNames, row.rung), row.cases_run, row.cases_failed,
               number(row.time, kMs), number(row.error, units::kMicrometresPerMetre),
               row.numerical_error < 0.0 ? std::string() : number(row.numerical_error, units::kMicrometresPerMetre), failure);
  }
}

void PrintLadder(std::ostream& out, const LadderResult& result) {
  fmt::print(out, "{} cases; reference (dynamic, rtol 1e-10): {:.1f} ms per revolution\n", result.cases,
             result.reference_time * kMs);
  fmt::print(out, "{:<48} {:>12} {:>12} {:>14} {:>7}\n", "method", "time ms", "error um", "numerical um", "failed");
  for (std::size_t i = 0; i < result.rows.size(); ++i) {
    const LadderRow& row = result.rows[i];
    fmt::print(out, "{:<48} {:>12.4g} {:>12.4g} {:>14} {:>3}/{:<3}{}\n", row.method, row.time * kMs, row.error * units::kMicrometresPerMetre,
               row.numerical_error < 0.0 ? std::string("-") : fmt::format("{:.4g}", row.numerical_error * units::kMicrometresPerMetre),
               row.cases_failed, row.cases_run, static_cast<int>(i) == result.fastest_within ? "  <- fastest within 1 um" : "");
    if (!row.first_failure.empty()) fmt::print(out, "    first failure: {}\n", row.first_failure);
  }
}

void WriteLadderSvg(std::ostream& out, const LadderResult& result) {
  constexpr double kErrorFloor = 1e-3;  // [um] where errors below are drawn
  const auto drawable = [](const LadderRow& row) { return row.time > 0.0 && !std::isnan(row.error); };
  // Whole decades that hold every point.
  double t_min = 1e300, t_max = 0.0, e_max = 1.0;
  for (const LadderRow& row : result.rows) {
    if (!drawable(row)) continue;
    t_min = std::min(t_min, row.time * kMs);
    t_max = std::max(t_max, row.time * kMs);
    e_max = std::max(e_max, row.error * units::kMicrometresPerMetre);
  }
  if (t_max == 0.0) t_min = 1e-3, t_max = 1.0;
  svg::Chart chart;
  chart.title =
      fmt::format("ringtol solver ladder: error in D_trajectory against time per revolution ({} cases)", result.cases);
  chart.x = {.label = "wall time per revolution [ms], settle included for the dynamic rung",
             .log10 = true,
             .min = std::pow(10.0, std::floor(std::log10(t_min))),
             .max = std::pow(10.0, std::ceil(std::log10(t_max)) + (t_max == t_min ? 1.0 : 0.0))};
  chart.y = {.label = "max |D - D_reference| [um] (below 1e-3 drawn at 1e-3)",
             .log10 = true,
             .min = kErrorFloor,
             .max = std::pow(10.0, std::ceil(std::log10(e_max)))};
  chart.width = 900.0;
  chart.height = 800.0;  // the legend names every method
  chart.lines.push_back({svg::ReferenceLine::Direction::kHorizontal, kWithin * units::kMicrometresPerMetre, "1 um"});
  // One series per method, numbered in the legend and beside its marker, coloured by rung.
  for (std::size_t i = 0; i < result.rows.size(); ++i) {
    const LadderRow& row = result.rows[i];
    svg::Series series;
    series.name = fmt::format("{}. {}{}", i + 1, row.method, drawable(row) ? "" : " (failed)");
    series.style = svg::Series::Style::kPoints;
    series.custom_colour = RungColour(row.rung);
    if (drawable(row)) {
      series.x = {row.time * kMs};
      series.y = {std::max(row.error * units::kMicrometresPerMetre, kErrorFloor)};
      series.labels = {fmt::format("{}", i + 1)};
    }
    chart.series.push_back(std::move(series));
  }
  if (result.fastest_within >= 0) {
    const std::size_t best = static_cast<std::size_t>(result.fastest_within);
    svg::Series ring{.name = "fastest within 1 um: " + result.rows[best].method,
                     .x = chart.series[best].x,
                     .y = chart.series[best].y,
                     .style = svg::Series::Style::kRings,
                     .custom_colour = "red"};
    chart.series.push_back(std::move(ring));
  }
  out << svg::RenderChart(chart);
}

}  // namespace ringtol::jobs
