// The polar plot of a ring's radial error motion as ISO 230-7 draws it (docs/model.md §9,
// engine/error_motion.h), from revolutions solved one after the other: what the campaign
// report shows for the sample with the largest total error motion.
//
// Revolution k is solvers::AtRevolution(scene, k), simulated at the dense angles of the
// first revolution's step count, so every revolution is read at the same angles
// psi_j = 2 pi j / steps. The axis motion is the centre's component along the sensor's
// ray, m_k(psi_j) = e_s . c_k(psi_j). The fundamental of its synchronous average (which a
// fixed sensitive direction cannot tell from the artefact's centring) is removed from
// every revolution, and so is the average's mean, which only moves the plot along its
// radii: what remains is drawn about the base circle of the polar plot, whose centre is
// then its least-squares centre. Read there:
//   total          the two concentric circles that just enclose every revolution: inner at
//                  the least value over all revolutions, outer at the greatest;
//   synchronous    the two that just enclose the synchronous average;
//   asynchronous   the widest the band of revolutions is along one radial line.
// These are engine::MeasureErrorMotion's values of the same revolutions, through the
// scene's error-motion filter (engine::FilterErrorMotion: the revolutions as one record).
//
// The plot's revolutions read at most the stored value, and usually less: a results file
// stores the limit over every revolution of the life, every phase of each roller, and a
// few successive revolutions meet only a few of those phases.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "engine/scene.h"
#include "solvers/simulation.h"
#include "solvers/solver.h"

namespace ringtol::jobs {

struct ErrorMotionPlot {
  std::int64_t index = 0;  // the campaign sample replayed (BuildReport)
  // [mm] its error_motion_total_mm as the campaign stored it (over the life the campaign
  // read; the plot's revolutions may reach less of it); NaN outside a report.
  double stored_total_mm = std::numeric_limits<double>::quiet_NaN();
  std::string status = "ok";  // the first failing revolution's ("exception" when realising or solving threw)
  std::string message;        // why, when status is not ok; nothing below is drawn then
  int revolutions = 0;        // asked for
  int steps = 0;              // angles per revolution
  engine::ErrorMotionFilter filter;  // the scene's, through which the motion was read
  double total_um = 0.0, synchronous_um = 0.0, asynchronous_um = 0.0;  // the error motion values [µm]
  double fundamental_um = 0.0;  // amplitude of the once-per-revolution part removed [µm]
  // The curves about the base circle [µm], at ring angles psi [deg]: each angle's least
  // and greatest value over the revolutions (the band) and the synchronous average.
  // Decimated to at most kDrawnPoints angles, every curve's extremes kept.
  std::vector<double> angle_deg, lowest_um, highest_um, average_um;
  // The enclosing circles' radii less the base circle's [µm]: total_outer_um -
  // total_inner_um = total_um, and the same for the synchronous ones.
  double total_inner_um = 0.0, total_outer_um = 0.0;
  double synchronous_inner_um = 0.0, synchronous_outer_um = 0.0;
  // [deg] the angle at which the band is widest, where asynchronous_um is read (kept
  // among the drawn angles).
  double asynchronous_angle_deg = 0.0;
};

// Solves `revolutions` >= 1 revolutions of `scene` with `solver` (options' step rule and
// tolerances; its angle mode is replaced by the dense one) and draws their error motion.
// A revolution whose status is not ok ends it: its status and message are returned and
// nothing is drawn. Throws std::invalid_argument for revolutions < 1.
ErrorMotionPlot PlotErrorMotion(const engine::Scene& scene, const solvers::Solver& solver,
                                solvers::SimulationOptions options, int revolutions);

}  // namespace ringtol::jobs
