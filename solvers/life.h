// What the ring does over its life, not over one revolution (docs/model.md §9). A roller
// of rolling radius r in a bore of rolling radius R turns R/r times a revolution
// (engine::SpinRatio), a ratio no real assembly makes rational, so every revolution meets
// the rollers' lobes at new phases: revolution k is the first one with roller i turned on
// by 2 pi k R/r_i. The life metrics are the one-revolution metrics taken over the union of
// such revolutions, and the axis's radial error motion as ISO 230-7 reads it
// (engine/error_motion.h) in the sensor's fixed direction:
//   d_trajectory  diameter of the smallest circle enclosing every revolution's centre path;
//   runout        the sensor signal's max - min over every revolution;
//   error_motion  total, synchronous and asynchronous values of the axis motion, the
//                 centre's component along the sensor's ray: the bore's own form, which the
//                 sensor also reads, is the artefact, which a reversal would separate, and
//                 is reported apart (`artefact`).
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "engine/error_motion.h"
#include "engine/scene.h"
#include "solvers/linear.h"
#include "solvers/simulation.h"
#include "solvers/solver.h"

namespace ringtol::solvers {

struct LifeResult {
  Status status = Status::kOk;  // the first failing revolution's, with its message
  std::string message;
  int steps = 0;         // angles a revolution
  int revolutions = 0;   // simulated
  LifeValues values;     // over the revolutions
  // Over every revolution the assembly will ever turn (LinearLife only): over every phase
  // of each roller, unless the scene locks the rollers' phases (Scene::
  // phase_locked_rollers); then the rollers whose spin ratios are rational with small
  // denominators (kLongestCycle) over the cycle after which their phases repeat, with
  // every phase of the others.
  std::optional<LifeValues> asymptotic;
  int cycle = 0;  // revolutions after which they repeat; 0 when they never do
  // [m] LinearLife: the largest share of the second-order correction that the rollers'
  // lobes make on the first revolution (the path less the same assembly's with round
  // rollers, less the lobes' first order), and an allowance for the asymptotic values'
  // error against the exact model: the linear rung's own estimate plus four times that
  // share (the asymptotic values carry the first revolution's correction to every phase;
  // the share that depends on the phases differs between two of them by at most twice its
  // size, and a diameter or a range counts a point's error twice). An allowance, not a
  // proven bound: the share's largest size over every phase is taken as the first
  // revolution's.
  double correction = 0.0;
  double error_estimate = 0.0;
  // [m] the axis motion the error motion was read from: the centre's component along the
  // sensor's ray through the scene's filter, at the `steps` angles of each of the
  // `revolutions`, revolution-major (engine::MeasureErrorMotion's layout).
  std::vector<double> motion;
  // [m] the bore's own form as the sensor reads it, fundamental removed: max - min of
  // r(theta_s - psi) - R less its once-per-revolution part (the artefact's roundness as a
  // reversal would report it).
  double artefact = 0.0;
};

// The scene as it starts revolution k: each roller turned on by 2 pi k SpinRatio(i).
engine::Scene AtRevolution(const engine::Scene& scene, int k);

// Simulates `revolutions` >= 1 successive revolutions with `solver`, each at the dense
// angles of options' step rule (the same for every revolution: it does not depend on
// phases), and reads the life values over them. Any rung; the reference the linear
// rung's closed form is tested against. A filtered error motion also solves the
// filter's margin of revolutions before and after them
// (engine::ErrorMotionFilter::MarginRevolutions), whose motion the filter reads, as an
// analyser recording on would. Never throws for numerical outcomes.
LifeResult SimulateLife(const engine::Scene& scene, const Solver& solver, const SimulationOptions& options,
                        int revolutions);

// How much looser Accuracy::kFast samples the rollers' lobe curves than kFull: their
// chords may stray this many times further (solvers/life.cpp), with
// 1 / sqrt(kFastCurveLooseness) of the samples. On 16,384 default samples 5 moves the life
// D_trajectory by at most 0.041 um and 10 by 0.078 um (the Hermite bound's 0.025 included),
// against a 1 um path tolerance.
inline constexpr double kFastCurveLooseness = 5.0;

// Revolutions after which phase-locked rollers with rational spin ratios repeat, at most:
// a longer cycle is counted as never repeating, since its revolutions already cover every
// phase to within (pi m / cycle)^2 / 2 of a lobe's amplitude.
inline constexpr int kLongestCycle = 1000;

// The linear rung's life. The `revolutions` values are SimulateLife's with the linear
// rung (each revolution its own path, second order included). The asymptotic ones come
// from its phasors: its first-order path is a sum of terms, and a roller's terms turn
// with that roller's own phase alone, so the centre is
//   c(psi) = s(psi) + sum_i G_i(theta_i),
// s the bore's terms, the constant and the second-order correction, G_i roller i's lobes
// as a closed curve in its own phase theta_i. Slip and assembly set each roller's phase,
// whatever its size, so over the life every theta_i occurs at every psi: the union of
// the paths is the Minkowski sum of s's path and each curve, whose convex hull (and so
// its enclosing circle) is the sum of their hulls, and the signal's range and the error
// motion add the curves' ranges along the sensor's ray:
//   runout = TIR of the signal less its lobes + sum_i range(e_s . G_i),
//   asynchronous = sum_i range(e_s . G_i),  synchronous = that of e_s . s,
//   total = synchronous + asynchronous.
// Phase-locked rollers (Scene::phase_locked_rollers) turn at SpinRatio psi from their
// drawn phases: the rollers of one ratio are one curve, and those whose ratios repeat
// within kLongestCycle revolutions are summed at their phases over that cycle (no solve),
// the other curves added as above around each of its revolutions. Statuses as
// SimulateLife.
LifeResult LinearLife(const engine::Scene& scene, const LinearSolver& linear, const SimulationOptions& options,
                      int revolutions);

// LinearLife's every-revolution values around a revolution already solved (`one`, at
// the dense angles of its steps, status ok: any rung's path stands for the path less its
// lobes plus the lobes at their drawn phases), the lobes' curves from the linear rung's
// phasors of the same scene (LinearSolver::Phasors, usable). No solve: what a campaign's
// sample adds. `cycle` as LifeResult::cycle. Throws std::invalid_argument otherwise.
// Accuracy::kFast samples the lobes' curves kFastCurveLooseness times looser (fewer points
// to hull and sum), widening the hull, the ranges and the error motion by the larger
// straying: the values stay upper bounds on the sampled life's, a little wider.
LifeValues EveryRevolution(const engine::Scene& scene, const SimulationResult& one, const PhasorSum& sum, int& cycle,
                           Accuracy accuracy = Accuracy::kFull);
// The same from the centre and the sensor signal less the rollers' lobes [m] at psi_k =
// 2 pi k / size, k = 0 .. size - 1 (size >= 3, both alike), as the spectral evaluation has
// them.
LifeValues EveryRevolutionFromRest(const engine::Scene& scene, std::span<const Eigen::Vector2d> rest,
                                   std::span<const double> signal_rest, const PhasorSum& sum, int& cycle,
                                   Accuracy accuracy = Accuracy::kFull);

// The artefact value of `scene` over `steps` angles (LifeResult::artefact).
double ArtefactForm(const engine::Scene& scene, int steps);

}  // namespace ringtol::solvers
