#include "solvers/spectral.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

#include "engine/enclosing_circle.h"
#include "engine/sensor.h"
#include "solvers/validity.h"

namespace ringtol::solvers {

namespace {

// How far a coarse stretch's unevaluated angles can be from the line through its ends:
// its evaluated ends (the chord bound), or with Accuracy::kFast once tightened those less
// LinearPath::StretchStraying's shifts for the centre, the travels and the forces.
struct StretchBound {
  std::array<Eigen::Vector2d, 2> centre_end;  // [m] the line's ends for the corrected centre
  double centre = 0.0;  // [m] the corrected centre
  double correction = 0.0;  // [m] of the chord bound's, the second-order correction's: its bound plus the ends'
  // [m] the chord bound's centre, about the chord through the evaluated ends: what the
  // margins the auto rung weighs read (the farthest reach behind the estimate), so that
  // its verdicts do not depend on the accuracy setting.
  double chord_centre = 0.0;
  double signal = 0.0;  // [m] the signal's rest beyond its first-order part
};

// Coarse stretches the first bound of the second-order correction covers (64 dense
// angles at the default stride): one a stretch cost a third of a default-campaign sample.
constexpr std::size_t kStretchesARun = 8;

// Adds to dense[k], k = 0 .. steps, a rest known at the evaluated angles only, linearly
// interpolated between them: `order` the evaluated samples by angle (the first at k = 0,
// the last at k = steps), `index` each sample's k, rest_of(s) sample s's rest, read before
// anything is added at its angle.
template <typename Value, typename RestOf>
void AddInterpolated(const std::vector<std::size_t>& order, const std::vector<int>& index, RestOf rest_of,
                     std::vector<Value>& dense) {
  std::size_t previous = order.front();
  Value previous_rest = rest_of(previous);
  dense.front() += previous_rest;
  for (std::size_t o = 1; o < order.size(); ++o) {
    const std::size_t s = order[o];
    const int a = index[previous];
    const int b = index[s];
    const Value rest = rest_of(s);
    for (int k = a + 1; k <= b; ++k) {
      const double t = static_cast<double>(k - a) / (b - a);
      dense[static_cast<std::size_t>(k)] += (1.0 - t) * previous_rest + t * rest;
    }
    previous = s;
    previous_rest = rest;
  }
}

}  // namespace

std::optional<SpectralResult> SimulateSpectral(const engine::Scene& scene, const LinearSolver& linear, int steps,
                                               int stride, double estimate_target, bool life,
                                               bool keep_trajectory, Accuracy accuracy) {
  const ValidityCheck validity(scene);
  const std::size_t z = scene.rollers.size();
  if (stride < 2 || steps < 4 * stride) return std::nullopt;
  // Penetrating contacts have gaps <= 0, so a roller that needs no two-point search at a
  // zero gap needs none anywhere.
  for (std::size_t i = 0; i < z; ++i) {
    if (validity.NeedsTwoPointSearch(static_cast<int>(i), 0.0)) return std::nullopt;
  }
  LinearPath path = linear.Path(scene, steps);
  if (path.status() != Status::kOk) return std::nullopt;

  const double dpsi = 2.0 * std::numbers::pi / steps;
  LinearPath::Samples samples;
  path.EvaluateCoarse(stride, samples);
  const std::vector<int>& coarse = path.coarse();
  const std::size_t segments = coarse.size() - 1;
  const LinearPath::Straying straying = path.StrayingAt(dpsi * stride);
  // Accuracy::kFast also tries the Hermite bound on a stretch the chord bound leaves open.
  const bool hermite = accuracy == Accuracy::kFast;
  if (hermite) path.KeepStretchRows();
  std::vector<char> refined(segments, 0);
  std::vector<std::size_t> first_inner(segments, 0);  // where a refined stretch's samples start
  std::size_t checked = 0;  // samples passed through the validity check
  std::string message;
  const auto refine = [&](std::size_t j) {
    refined[j] = 1;
    first_inner[j] = samples.size();
    path.Refine(static_cast<int>(j), samples);
  };
  // Every evaluated angle must pass the validity check; the dense evaluation states the
  // first failure otherwise.
  const auto valid = [&]() {
    for (; checked < samples.size(); ++checked) {
      const std::span<const double> travel(samples.travel.data() + checked * z, z);
      const std::span<const double> force(samples.contact_force.data() + checked * z, z);
      const double psi = dpsi * samples.index[checked];
      if (validity.Check(psi, samples.centre[checked], travel, force, message) != Status::kOk) return false;
    }
    return true;
  };
  if (!valid()) return std::nullopt;

  // Each coarse stretch's unevaluated angles, bounded: the first-order outputs lie within
  // their chord bounds of the chord through the stretch's ends, so SecondOrderTerms::Over
  // bounds the correction and its remainder there; a corrected output then lies within its
  // chord bound, plus the correction's bound, plus the larger correction at the ends, of
  // the chord through the corrected ends. Over runs of kStretchesARun stretches first (a
  // bound per stretch costs more than the angles it saves); a run whose remainder bound
  // alone would break the estimate's target is bounded again stretch by stretch.
  const std::size_t width = path.FirstOrderWidth();
  std::vector<StretchBound> bounds(segments);
  // Per stretch and roller [m, N], stretch-major; the lines' ends per stretch, end and
  // roller.
  std::vector<double> travel_bound(segments * z), force_bound(segments * z);
  std::vector<double> travel_end(2 * segments * z), force_end(2 * segments * z);
  std::vector<double> travel_chord_bound(segments * z);  // the chord bound's, for the margins
  // With the Hermite bound: what the correction adds to each stretch's bound, per stretch
  // (the centre) and per stretch and roller, and whether the stretch reads it already.
  std::vector<double> centre_extra(segments), travel_extra(segments * z), force_extra(segments * z);
  std::vector<char> tightened(segments, 0);
  thread_local FirstOrderRange range;
  thread_local SecondOrderRange over;
  const LinearPath::StretchStraying chord{straying.centre,
                                          {Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()},
                                          straying.travel,
                                          straying.contact_force,
                                          std::vector<double>(2 * z, 0.0),
                                          std::vector<double>(2 * z, 0.0)};
  const auto bound_stretches = [&](std::size_t first, std::size_t last) {
    path.RangeOver(samples, first, last, straying, range);
    path.second_order().Over(range, over);
    for (std::size_t j = first; j < last; ++j) {
      StretchBound& bound = bounds[j];
      tightened[j] = 0;
      const std::size_t a = j;
      const std::size_t b = j + 1;
      // The correction at the ends: the corrected outputs less At's first-order inputs.
      const double* first_a = samples.first_order.data() + a * width;
      const double* first_b = samples.first_order.data() + b * width;
      const double end_correction = std::max((samples.centre[a] - Eigen::Vector2d(first_a[0], first_a[1])).norm(),
                                             (samples.centre[b] - Eigen::Vector2d(first_b[0], first_b[1])).norm());
      bound.centre = chord.centre + over.centre + end_correction;
      bound.correction = bound.centre - chord.centre;
      bound.chord_centre = straying.centre + over.centre + end_correction;
      bound.centre_end = {samples.centre[a] - chord.centre_shift[0], samples.centre[b] - chord.centre_shift[1]};
      bound.signal = straying.signal_rest + over.centre + end_correction;
      for (std::size_t i = 0; i < z; ++i) {
        const auto end = [&](const std::vector<double>& corrected, std::size_t offset) {
          return std::max(std::abs(corrected[a * z + i] - first_a[offset + i]),
                          std::abs(corrected[b * z + i] - first_b[offset + i]));
        };
        travel_bound[j * z + i] = chord.travel[i] + over.travel[i] + end(samples.travel, 2);
        travel_chord_bound[j * z + i] = straying.travel[i] + over.travel[i] + end(samples.travel, 2);
        force_bound[j * z + i] = chord.contact_force[i] + over.contact_force[i] + end(samples.contact_force, 2 + z);
        for (std::size_t side = 0; side < 2; ++side) {
          const std::size_t at = (j + side) * z + i;
          travel_end[(2 * j + side) * z + i] = samples.travel[at] - chord.travel_shift[side * z + i];
          force_end[(2 * j + side) * z + i] = samples.contact_force[at] - chord.force_shift[side * z + i];
        }
        travel_extra[j * z + i] = over.travel[i] + end(samples.travel, 2);
        force_extra[j * z + i] = over.contact_force[i] + end(samples.contact_force, 2 + z);
      }
      centre_extra[j] = over.centre + end_correction;
    }
    return over.remainder;
  };
  // Accuracy::kFast: a stretch the chord bound leaves open is bounded again by
  // LinearPath::StrayingOver (the smaller of the chord and the Hermite bound per output,
  // about the line through the ends less the fast lobes there) plus the same correction;
  // false if it already was. Only the decisions on the domain and the extremes read it:
  // the estimate and the auto rung's margins keep the chord bound.
  thread_local LinearPath::StretchStraying tight;
  const auto tighten = [&](std::size_t j) {
    if (!hermite || tightened[j]) return false;
    tightened[j] = 1;
    path.StrayingOver(samples, j, straying, tight);
    StretchBound& bound = bounds[j];
    bound.centre = tight.centre + centre_extra[j];
    bound.centre_end = {samples.centre[j] - tight.centre_shift[0], samples.centre[j + 1] - tight.centre_shift[1]};
    for (std::size_t i = 0; i < z; ++i) {
      travel_bound[j * z + i] = tight.travel[i] + travel_extra[j * z + i];
      force_bound[j * z + i] = tight.contact_force[i] + force_extra[j * z + i];
      for (std::size_t side = 0; side < 2; ++side) {
        const std::size_t at = (j + side) * z + i;
        travel_end[(2 * j + side) * z + i] = samples.travel[at] - tight.travel_shift[side * z + i];
        force_end[(2 * j + side) * z + i] = samples.contact_force[at] - tight.force_shift[side * z + i];
      }
    }
    return true;
  };
  const std::size_t runs = (segments + kStretchesARun - 1) / kStretchesARun;
  std::vector<double> run_remainder(runs);  // [m] Over's bound on each run
  for (std::size_t r = 0; r < runs; ++r) {
    run_remainder[r] = bound_stretches(r * kStretchesARun, std::min((r + 1) * kStretchesARun, segments));
  }

  // The estimate, as SolveRevolution forms it, from the remainder's bounds over the runs
  // (which cover every angle, so it does not depend on which stretches the extremes
  // evaluate) and the farthest the path can reach; where a bound exceeds the target's
  // share, from the bounds a level finer and at last At's own remainder at every angle,
  // each level's count floored at the share (the header says why).
  double farthest = 0.0;
  for (std::size_t j = 0; j < segments; ++j) {
    farthest =
        std::max(farthest, std::max(samples.centre[j].norm(), samples.centre[j + 1].norm()) + bounds[j].chord_centre);
  }
  // The linear rung's own limit (LinearRangeRefusal) at the coarse angles' reach, below the
  // dense path's: a target no decision lies under.
  double coarse_reach = 0.0;
  for (std::size_t j = 0; j <= segments; ++j) {
    coarse_reach = std::max(coarse_reach, (samples.centre[j] - samples.centre.front()).norm());
  }
  const LinearOptions& limits = linear.options();
  const double target =
      std::min(estimate_target, std::max(limits.max_relative_error * coarse_reach, limits.min_error_limit));
  const double share = target / path.EstimateFrom(1.0, farthest);  // [m] of remainder
  // max() would drop a NaN: the estimate must carry it. A NaN bound gives way to a finer one.
  const auto raise = [](double& largest, double value) {
    if (!std::isnan(largest) && !(value <= largest)) largest = value;
  };
  const auto floored = [&](double bound, double finer) {
    double count = share;
    raise(count, std::fmin(bound, finer));
    return count;
  };
  double largest_remainder = 0.0;
  for (std::size_t r = 0; r < runs; ++r) {
    double remainder = run_remainder[r];
    if (!(remainder <= share) && std::isfinite(share)) {
      double finer = 0.0;
      for (std::size_t j = r * kStretchesARun; j < std::min((r + 1) * kStretchesARun, segments); ++j) {
        double stretch = bound_stretches(j, j + 1);
        if (!(stretch <= share)) {
          if (!refined[j]) refine(j);
          double evaluated = samples.remainder[j];
          raise(evaluated, samples.remainder[j + 1]);
          const auto inner = static_cast<std::size_t>(coarse[j + 1] - coarse[j] - 1);
          for (std::size_t q = 0; q < inner; ++q) raise(evaluated, samples.remainder[first_inner[j] + q]);
          stretch = floored(stretch, evaluated);
        }
        raise(finer, stretch);
      }
      remainder = floored(remainder, finer);
    }
    raise(largest_remainder, remainder);
  }
  if (!valid()) return std::nullopt;
  const double error_estimate = path.EstimateFrom(largest_remainder, farthest);

  // The domain: a force above its bound and a travel inside its limit by more than its
  // bound at both ends of a stretch cannot fail between them.
  const auto in_domain = [&](std::size_t j) {
    bool certain = true;
    for (std::size_t i = 0; i < z && certain; ++i) {
      const double force_a = force_end[2 * j * z + i];
      const double force_b = force_end[(2 * j + 1) * z + i];
      certain = std::min(force_a, force_b) > force_bound[j * z + i];
      if (scene.rollers[i].mount != engine::RollerMount::kFixed) {
        const double travel = std::max(std::abs(travel_end[2 * j * z + i]), std::abs(travel_end[(2 * j + 1) * z + i]));
        certain = certain && travel + travel_bound[j * z + i] <= scene.rollers[i].spring.travel_limit;
      }
    }
    return certain;
  };
  for (std::size_t j = 0; j < segments; ++j) {
    if (refined[j]) continue;
    if (!in_domain(j) && !(tighten(j) && in_domain(j))) refine(j);
  }
  if (!valid()) return std::nullopt;

  // The extremes: each pass refines the stretches whose ends, widened by their bounds,
  // reach beyond what the evaluated angles give; the extremes only grow, so it ends when
  // none is left. What campaigns record of the forces is certified: the smallest over
  // every contact and the largest; each roller's own range is read at the evaluated angles.
  // With_reach: also the path's largest distance from its start.
  engine::Circle circle;
  double smallest_force = 0.0;
  double largest_force = 0.0;
  double reach = 0.0;
  const Eigen::Vector2d start = samples.centre.front();
  const auto refine_open = [&](bool with_reach) {
    for (bool changed = true; changed;) {
      circle = engine::MinimumEnclosingCircle(samples.centre);
      const auto [low, high] = std::minmax_element(samples.contact_force.begin(), samples.contact_force.end());
      smallest_force = *low;
      largest_force = *high;
      reach = 0.0;
      for (const Eigen::Vector2d& c : samples.centre) reach = std::max(reach, (c - start).norm());
      std::vector<std::size_t> wanted;
      const auto open = [&](std::size_t j) {
        const auto beyond = [&](const Eigen::Vector2d& from, double radius) {
          return std::max((bounds[j].centre_end[0] - from).norm(), (bounds[j].centre_end[1] - from).norm()) + bounds[j].centre >
                 radius;
        };
        bool is_open = beyond(circle.centre, circle.radius) || (with_reach && beyond(start, reach));
        for (std::size_t i = 0; i < z && !is_open; ++i) {
          const double force_a = force_end[2 * j * z + i];
          const double force_b = force_end[(2 * j + 1) * z + i];
          is_open = std::min(force_a, force_b) - force_bound[j * z + i] < smallest_force ||
                    std::max(force_a, force_b) + force_bound[j * z + i] > largest_force;
        }
        return is_open;
      };
      for (std::size_t j = 0; j < segments; ++j) {
        if (refined[j]) continue;
        if (open(j) && !(tighten(j) && !open(j))) wanted.push_back(j);
      }
      changed = !wanted.empty();
      for (const std::size_t j : wanted) refine(j);
      if (!valid()) return false;
    }
    return true;
  };

  if (!refine_open(false)) return std::nullopt;

  // The linear rung's own limit on the dense path's reach: the evaluated reach is a lower
  // bound of it; where that leaves the verdict open, the reach is refined until exact.
  if (!LinearRangeRefusal(linear.options(), error_estimate, reach).empty() && !refine_open(true)) return std::nullopt;

  SpectralResult spectral;
  SimulationResult& result = spectral.result;
  result.steps = steps;
  spectral.evaluated = static_cast<int>(samples.size());
  // The evaluated angles in order: each coarse angle, then its stretch's when refined.
  std::vector<std::size_t> order;
  order.reserve(samples.size());
  for (std::size_t j = 0; j < segments; ++j) {
    order.push_back(j);
    if (!refined[j]) continue;
    const auto inner = static_cast<std::size_t>(coarse[j + 1] - coarse[j] - 1);
    for (std::size_t q = 0; q < inner; ++q) order.push_back(first_inner[j] + q);
  }
  order.push_back(segments);
  Trajectory& kept = result.trajectory;
  kept.rung = Rung::kLinear;
  kept.initial.centre = start;
  kept.initial.travel.assign(samples.travel.begin(), samples.travel.begin() + static_cast<std::ptrdiff_t>(z));
  kept.initial.contact_force.assign(samples.contact_force.begin(),
                                    samples.contact_force.begin() + static_cast<std::ptrdiff_t>(z));
  kept.error_estimate = error_estimate;
  std::vector<RollerForceRange> forces(z, {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()});
  std::vector<double> largest_travel(z, 0.0);
  for (const std::size_t s : order) {
    if (keep_trajectory) {
      kept.psi.push_back(dpsi * samples.index[s]);
      kept.centre.push_back(samples.centre[s]);
      kept.travel.insert(kept.travel.end(), samples.travel.begin() + static_cast<std::ptrdiff_t>(s * z),
                         samples.travel.begin() + static_cast<std::ptrdiff_t>((s + 1) * z));
      kept.contact_force.insert(kept.contact_force.end(), samples.contact_force.begin() + static_cast<std::ptrdiff_t>(s * z),
                                samples.contact_force.begin() + static_cast<std::ptrdiff_t>((s + 1) * z));
      result.sensor.push_back(samples.signal[s]);
    }
    for (std::size_t i = 0; i < z; ++i) {
      forces[i].min = std::min(forces[i].min, samples.contact_force[s * z + i]);
      forces[i].max = std::max(forces[i].max, samples.contact_force[s * z + i]);
      largest_travel[i] = std::max(largest_travel[i], std::abs(samples.travel[s * z + i]));
    }
  }

  const std::string refusal = LinearRangeRefusal(linear.options(), kept.error_estimate, reach);
  if (!refusal.empty()) {
    result.status = kept.status = Status::kBeyondLinearRange;
    result.message = kept.message = refusal;
    return spectral;
  }

  result.enclosing_circle = circle;
  result.d_trajectory = 2.0 * circle.radius;
  result.dist_init = (start - circle.centre).norm();
  result.contact_force = forces;
  result.min_contact_force = smallest_force;

  // The signal at every angle: its first-order part summed there, the rest (the sensor's
  // second-order terms and the centre's correction along the ray) interpolated between
  // the evaluated angles (which straddle every angle, the coarse grid's ends being 0 and
  // steps).
  thread_local std::vector<double> signal, signal_second;
  path.FirstOrderSignal(signal);
  signal_second.resize(samples.index.size());
  for (std::size_t s = 0; s < signal_second.size(); ++s) {
    signal_second[s] = samples.signal[s] - signal[static_cast<std::size_t>(samples.index[s])];
  }
  AddInterpolated(order, samples.index, [&](std::size_t s) { return signal_second[s]; }, signal);
  const engine::Runout runout = engine::MeasureRunout(signal, scene.sensor_swing);
  result.runout = runout.total;
  result.swing = runout.swing;

  if (life) {
    // The centre and the signal less their lobes at every angle: their first order there,
    // plus the second order (the corrected centre less At's first-order input; the signal's
    // as above) interpolated between the evaluated angles.
    thread_local std::vector<Eigen::Vector2d> centre;
    thread_local std::vector<double> signal_rest;
    path.FirstOrderWithoutLobes(centre, signal_rest);
    AddInterpolated(order, samples.index, [&](std::size_t s) {
      const double* first = samples.first_order.data() + s * width;
      return Eigen::Vector2d(samples.centre[s] - Eigen::Vector2d(first[0], first[1]));
    }, centre);
    AddInterpolated(order, samples.index, [&](std::size_t s) { return signal_second[s]; }, signal_rest);
    for (std::size_t j = 0; j < segments; ++j) {
      if (!refined[j]) spectral.centre_error = std::max(spectral.centre_error, bounds[j].correction);
    }
    const auto dense = static_cast<std::size_t>(steps);
    spectral.life = EveryRevolutionFromRest(scene, std::span<const Eigen::Vector2d>(centre).first(dense),
                                            std::span<const double>(signal_rest).first(dense), path.Phasors(),
                                            spectral.life_cycle, accuracy);
  }

  spectral.margins.error_estimate = kept.error_estimate;
  spectral.margins.smallest_force = result.min_contact_force;
  spectral.margins.largest_force = largest_force;
  spectral.margins.reach = reach;
  for (std::size_t j = 0; j < segments; ++j) {
    if (refined[j]) continue;
    spectral.signal_error = std::max(spectral.signal_error, bounds[j].signal);
    for (std::size_t i = 0; i < z; ++i) {
      const double end = std::max(std::abs(samples.travel[j * z + i]), std::abs(samples.travel[(j + 1) * z + i]));
      largest_travel[i] = std::max(largest_travel[i], end + travel_chord_bound[j * z + i]);
    }
  }
  spectral.margins.largest_travel = std::move(largest_travel);
  return spectral;
}

}  // namespace ringtol::solvers
