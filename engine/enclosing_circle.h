// Smallest circle containing a finite set of 2-D points (minimum enclosing circle, MEC),
// used to reduce a sampled path, such as the ring centre's, to one centre and radius.
//
// Exact algorithm, not an approximation: Welzl's randomized incremental construction in
// its iterative three-nested-loop form, expected O(n) for points in random order. The
// points are shuffled with a hand-written generator and a fixed seed, so the result is
// deterministic and identical on every platform. The MEC is unique, so the result does not
// depend on the input order beyond rounding.
//
// Units: any consistent length unit; the centre and radius come back in the input's.
// Ownership: the points are only read; one internal copy is made for the shuffle.
// Guarantee: radius is the largest distance from the returned centre to an input point,
// computed as (p - centre).norm() in a final pass, so every point is inside the returned
// circle without tolerance. The radius exceeds the exact MEC radius by at most ~1e-13 of
// the set's extent (the round-off slack of the inside test) plus coordinate rounding.
// Failure modes: std::invalid_argument for an empty set or a non-finite coordinate.
// Coordinates whose squared differences overflow a double are not supported.
#pragma once

#include <span>

#include <Eigen/Core>

namespace ringtol::engine {

struct Circle {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // [m]
  double radius = 0.0;                               // [m], >= 0
};

Circle MinimumEnclosingCircle(std::span<const Eigen::Vector2d> points);

}  // namespace ringtol::engine
