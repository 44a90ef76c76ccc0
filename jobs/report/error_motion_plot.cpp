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
  options.angles = solvers::AngleMode::kDense;
  ErrorMotionPlot plot;
  plot.revolutions = revolutions;
  const Eigen::Vector2d ray = engine::Direction(scene.sensor_angle);
  std::vector<double> motion;  // revolution-major, as engine::MeasureErrorMotion reads it
  for (int k = 0; k < revolutions; ++k) {
    const solvers::SimulationResult result = solvers::Simulate(solvers::AtRevolution(scene, k), solver, options);
    if (result.status != solvers::Status::kOk) {
      plot.status = solvers::StatusName(result.status);
      plot.message =
          "revolution " + std::to_string(k + 1) + " of " + std::to_string(revolutions) + ": " + result.message;
      return plot;
    }
    // Every revolution at the first one's angles, as the error motion is read: the step
    // rule would choose the same count (it reads amplitudes and orders, not phases), and
    // fixing it makes sure.
    if (k == 0) options.steps = plot.steps = result.steps;
    const auto steps = static_cast<std::size_t>(plot.steps);
    if (result.steps != plot.steps || result.trajectory.centre.size() < steps) {
      throw std::logic_error("PlotErrorMotion: a revolution came back at other angles than the first");
    }
    for (std::size_t j = 0; j < steps; ++j) motion.push_back(ray.dot(result.trajectory.centre[j]));
  }

  const auto n = static_cast<std::size_t>(plot.steps);
  engine::ErrorMotionBand band = engine::ErrorMotionBandOf(motion, plot.steps);
  std::vector<double>& lowest = band.lowest;
  std::vector<double>& highest = band.highest;
  std::vector<double>& average = band.average;
  plot.fundamental_um = band.fundamental * units::kMicrometresPerMetre;
  double mean = 0.0;
  for (const double x : average) mean += x / static_cast<double>(n);

  constexpr double um = units::kMicrometresPerMetre;
  std::vector<double> angle_deg(n);
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
    plot.asynchronous_um = std::max(plot.asynchronous_um, highest[j] - lowest[j]);
  }
  plot.total_um = plot.total_outer_um - plot.total_inner_um;
  plot.synchronous_um = plot.synchronous_outer_um - plot.synchronous_inner_um;

  // One set of angles for the three curves: the union of what each keeps.
  std::vector<bool> keep(n, false);
  for (const std::vector<double>* curve : {&lowest, &highest, &average}) {
    for (const std::size_t j : svg::DecimateCurve(angle_deg, *curve, kDrawnPoints / 3)) keep[j] = true;
  }
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
