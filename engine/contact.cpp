#include "engine/contact.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <boost/math/tools/minima.hpp>
#include <numbers>

namespace ringtol::engine {
namespace {

struct GapDerivatives {
  double g, dg, ddg;
  SupportPoint ring, roller;
};

GapDerivatives Evaluate(const PolarProfile& ring, const BodyPose& ring_pose, const PolarProfile& roller,
                        const BodyPose& roller_pose, double phi, double ring_guess, double roller_guess) {
  const Eigen::Vector2d n(std::cos(phi), std::sin(phi));
  const Eigen::Vector2d t(-n.y(), n.x());
  const Eigen::Vector2d offset = ring_pose.centre - roller_pose.centre;
  const SupportPoint a = ring.Support(phi - ring_pose.angle, ring_guess);
  const SupportPoint b = roller.Support(phi - roller_pose.angle, roller_guess);
  const double g = offset.dot(n) + a.h - b.h;
  return {g, offset.dot(t) + a.dh - b.dh, a.curvature_radius - b.curvature_radius - g, a, b};
}

}  // namespace

double GapAlong(const PolarProfile& ring, const BodyPose& ring_pose, const PolarProfile& roller,
                const BodyPose& roller_pose, double phi) {
  return Evaluate(ring, ring_pose, roller, roller_pose, phi, phi - ring_pose.angle, phi - roller_pose.angle).g;
}

Contact FindContact(const PolarProfile& ring, const BodyPose& ring_pose, const PolarProfile& roller,
                    const BodyPose& roller_pose, const ContactGuess* guess) {
  constexpr double kHalfPi = std::numbers::pi / 2.0;
  // g' carries the round-off of the bore's support point: its body angle is resolved to
  // 1e-14 rad at a 0.3 m radius, ~3e-15 m. Stop at three times that.
  constexpr double kTangentialTolerance = 1e-14;  // [m]
  // A Newton update this small changes g by g'' dphi^2 / 2 < 1e-26 m and turns the normal
  // by a relative 1e-13: both far below anything a force balance can feel.
  constexpr double kAngleTolerance = 1e-13;       // [rad]
  constexpr int kMaxIterations = 100;

  double phi;
  double ring_theta;
  double roller_theta;
  if (guess != nullptr) {
    phi = guess->normal_angle;
    ring_theta = guess->ring_theta;
    roller_theta = guess->roller_theta;
  } else {
    const Eigen::Vector2d towards = roller_pose.centre - ring_pose.centre;
    phi = std::atan2(towards.y(), towards.x());
    ring_theta = phi - ring_pose.angle;
    roller_theta = phi - roller_pose.angle;
  }
  // g' < 0 at the low end and > 0 at the high end of this bracket whenever the roller is
  // small against the bore: (ring - roller centre) . t dominates the support terms there.
  double lo = phi - kHalfPi;
  double hi = phi + kHalfPi;
  Contact contact;
  GapDerivatives d{};
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    d = Evaluate(ring, ring_pose, roller, roller_pose, phi, ring_theta, roller_theta);
    ring_theta = d.ring.theta;
    roller_theta = d.roller.theta;
    if (std::abs(d.dg) <= kTangentialTolerance) {
      contact.converged = true;
      break;
    }
    if (d.dg < 0.0) lo = phi; else hi = phi;
    const double step = -d.dg / d.ddg;
    if (d.ddg > 0.0 && (std::abs(step) <= kAngleTolerance || hi - lo <= kAngleTolerance)) {
      // The remaining step moves g by ~g'' step^2 / 2 < 1e-28 m: keep the evaluated point.
      contact.converged = true;
      break;
    }
    double next = phi + step;
    // Round-off can put a converging Newton point on the wrong side of the bracket, so
    // bisect only when the step really leaves it.
    if (!(d.ddg > 0.0) || !(next > lo && next < hi)) next = 0.5 * (lo + hi);
    phi = next;
  }
  contact.gap = d.g;
  contact.normal_angle = phi;
  contact.normal = Eigen::Vector2d(std::cos(phi), std::sin(phi));
  contact.tangent = Eigen::Vector2d(-contact.normal.y(), contact.normal.x());
  contact.ring_point = ring_pose.centre + d.ring.h * contact.normal + d.ring.dh * contact.tangent;
  contact.roller_point = roller_pose.centre + d.roller.h * contact.normal + d.roller.dh * contact.tangent;
  contact.gap_curvature = d.ddg;
  contact.ring_theta = d.ring.theta;
  contact.roller_theta = d.roller.theta;
  if (!(std::isfinite(contact.gap) && contact.gap_curvature > 0.0)) contact.converged = false;
  return contact;
}

bool IsSinglePoint(const PolarProfile& ring, const BodyPose& ring_pose, const PolarProfile& roller,
                   const BodyPose& roller_pose, const Contact& contact, double tolerance, int samples) {
  const double touching = std::max(contact.gap, 0.0) + tolerance;
  const double width = std::numbers::pi;
  const double step = width / samples;
  auto gap_at = [&](double offset) { return GapAlong(ring, ring_pose, roller, roller_pose, contact.normal_angle + offset); };
  // A grid value misses its basin's minimum by up to g'' (step/2)^2 / 2 (~1e-7 m here), far
  // more than a tight tolerance: refine every candidate with Brent's method, whose
  // minimum value is exact to second order in its sqrt(eps) placement.
  auto refined_minimum = [&](double centre) {
    return boost::math::tools::brent_find_minima(gap_at, centre - step, centre + step,
                                                 std::numeric_limits<double>::digits)
        .second;
  };
  // Exclude the contact's own basin: the samples nearest to it always read ~its gap.
  const double own_basin = 2.0 * step;
  double previous = gap_at(-width / 2.0);
  double current = gap_at(-width / 2.0 + step);
  for (int k = 2; k <= samples; ++k) {
    const double offset = -width / 2.0 + k * step;
    const double next = gap_at(offset);
    const double centre_offset = offset - step;
    if (current < contact.gap - tolerance) return false;
    const bool local_minimum = current <= previous && current <= next;
    if (local_minimum && std::abs(centre_offset) > own_basin && refined_minimum(centre_offset) <= touching) {
      return false;
    }
    previous = current;
    current = next;
  }
  return true;
}

}  // namespace ringtol::engine
