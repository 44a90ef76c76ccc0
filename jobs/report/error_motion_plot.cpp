#include "jobs/report/error_motion_plot.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "engine/error_motion.h"
#include "engine/units.h"
#include "jobs/report/campaign_report.h"
#include "jobs/report/svg_chart.h"
#include "solvers/life.h"

namespace ringtol::jobs {

ErrorMotionPlot PlotErrorMotion(const engine::Scene& scene, const solvers::Solver& solver,
                                solvers::SimulationOptions options, int revolutions) {
  if (revolutions < 1) throw std::invalid_argument("PlotErrorMotion: revolutions must be at least 1");
  ErrorMotionPlot plot;
  plot.revolutions = revolutions;
  const solvers::LifeResult life = solvers::SimulateLife(scene, solver, options, revolutions);
  if (life.status != solvers::Status::kOk) {
    plot.status = solvers::StatusName(life.status);
    plot.message = life.message;
    return plot;
  }
  plot.steps = life.steps;
  const auto n = static_cast<std::size_t>(plot.steps);
  plot.filter = scene.error_motion_filter;
  engine::ErrorMotionBand band = engine::ErrorMotionBandOf(life.motion, plot.steps);
  std::vector<double>& lowest = band.lowest;
  std::vector<double>& highest = band.highest;
  std::vector<double>& average = band.average;
  plot.fundamental_um = band.fundamental * units::kMicrometresPerMetre;
  double mean = 0.0;
  for (const double x : average) mean += x / static_cast<double>(n);

  constexpr double um = units::kMicrometresPerMetre;
  std::vector<double> angle_deg(n);
  std::size_t widest = 0;
  plot.total_inner_um = plot.synchronous_inner_um = std::numeric_limits<double>::infinity();
  plot.total_outer_um = plot.synchronous_outer_um = -std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j < n; ++j) {
    angle_deg[j] = 360.0 * static_cast<double>(j) / plot.steps;
    lowest[j] = (lowest[j] - mean) * um;
    highest[j] = (highest[j] - mean) * um;
    average[j] = (average[j] - mean) * um;
    plot.total_inner_um = std::min(plot.total_inner_um, lowest[j]);
    plot.total_outer_um = std::max(plot.total_outer_um, highest[j]);
    plot.synchronous_inner_um = std::min(plot.synchronous_inner_um, average[j]);
    plot.synchronous_outer_um = std::max(plot.synchronous_outer_um, average[j]);
    if (highest[j] - lowest[j] > plot.asynchronous_um) {
      plot.asynchronous_um = highest[j] - lowest[j];
      widest = j;
    }
  }
  plot.asynchronous_angle_deg = angle_deg[widest];
  plot.total_um = plot.total_outer_um - plot.total_inner_um;
  plot.synchronous_um = plot.synchronous_outer_um - plot.synchronous_inner_um;

  // One set of angles for the three curves: the union of what each keeps.
  std::vector<bool> keep(n, false);
  for (const std::vector<double>* curve : {&lowest, &highest, &average}) {
    for (const std::size_t j : svg::DecimateCurve(angle_deg, *curve, kDrawnPoints / 3)) keep[j] = true;
  }
  keep[widest] = true;
  for (std::size_t j = 0; j < n; ++j) {
    if (!keep[j]) continue;
    plot.angle_deg.push_back(angle_deg[j]);
    plot.lowest_um.push_back(lowest[j]);
    plot.highest_um.push_back(highest[j]);
    plot.average_um.push_back(average[j]);
  }
  return plot;
}

}  // namespace ringtol::jobs
