// The conventions every part of ringtol shares, stated once (docs/model.md §1 explains them).
//
// Frame and angles
//   Global frame: x, y span the ring's plane, z points at the viewer. Angles are measured
//   from +x, counter-clockwise positive, in radians inside the code and in degrees in
//   files (`*_deg` keys). The ring turns by psi about its own centre, counter-clockwise
//   positive; a ring body angle theta sits at global angle theta + psi.
//
// Profiles (docs/model.md §3)
//   Every surface is a polar series about its body's centre in its body's frame:
//     r(theta) = r_nominal + dr0 + sum_n C_n cos(n theta + phi_n),
//   amplitudes C_n are radial deviations, positive outward. Order 1 is an eccentricity.
//
// Contact
//   The gap g > 0 is clearance; the penetration delta = -g > 0 is overlap. The contact
//   normal n points from the ring's centre outward through the contact, so the force of a
//   roller on the ring is +F n with F >= 0.
//
// Rollers
//   A roller inside a ring turns the same way as the ring. Rolling without slip on the
//   nominal radii gives its spin angle gamma = gamma_0 + (R / r_b) psi.
//   gamma_0, the body-frame phase reference of a roller's shape harmonics, is settable
//   per roller because it changes results by tens of micrometres when every roller has
//   the same shape error:
//     kRadial (default): at psi = 0 the roller's body x axis points along its nominal
//       outward radial direction, i.e. body angle 0 faces the ring; identical rollers
//       mounted identically then present the same phase to the ring.
//     kGlobal: at psi = 0 the roller's body x axis is the global +x axis.
//   plus an optional extra spin phase.
//   Position errors: a positive radial offset moves a roller's centre outward, a positive
//   tangential offset moves it counter-clockwise along the centre circle.
//
// Spring rollers
//   A spring roller slides along a unit axis u (default: its outward radial direction).
//   Its travel s along u is zero where the spring force equals the preload; the spring
//   pushes the roller along +u with F_spring = preload - stiffness * s.
#pragma once

namespace ringtol::engine {

enum class ShapePhaseReference {
  kRadial,  // roller body angle 0 faces the ring at psi = 0
  kGlobal,  // roller body angle 0 is global +x at psi = 0
};

}  // namespace ringtol::engine
