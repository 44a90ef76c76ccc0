// The assembly ringtol simulates (docs/model.md §1–§4), in SI units. Conventions are in
// engine/conventions.h. A Scene is a plain value: the input reader in jobs/ fills it and
// validates every field; solvers take it by const reference and never keep it.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/conventions.h"
#include "engine/motion_law.h"
#include "engine/profile.h"
#include "engine/error_motion.h"
#include "engine/sensor.h"

namespace ringtol::engine {

// What a body is made of, as its contact needs it. Only the contact law a scene file
// derives when it states none reads it (engine/line_contact.h, docs/model.md §4); the
// solvers never do. The defaults are steel.
struct Material {
  double youngs_modulus = 210e9;  // [Pa] E > 0
  double poisson_ratio = 0.3;     // [-] nu in [0, 0.5]

  bool operator==(const Material&) const = default;
};

struct Ring {
  PolarProfile inner;          // inner (running) surface in the ring frame; radius() = R [m]
  double outer_radius = 0.0;   // [m]
  double thickness = 0.0;      // [m] axial
  double mass = 0.0;           // [kg]
  double spin_inertia = 0.0;   // [kg m^2] about z through the centre
  Material material;

  bool operator==(const Ring&) const = default;
};

enum class RollerMount { kFixed, kSpring };

struct Spring {
  double stiffness = 0.0;     // [N/m] k_b >= 0
  double preload = 0.0;       // [N] > 0, force at zero travel, pushing the roller along +axis
  double axis_angle = 0.0;    // [rad] global angle of the travel axis u
  double travel_limit = 0.0;  // [m] > 0; |travel| beyond it means the assembly cannot close

  bool operator==(const Spring&) const = default;
};

struct Roller {
  std::string name;
  double angle = 0.0;               // [rad] nominal angle of the centre
  double centre_radius = 0.0;       // [m] nominal radius of the centre circle (R - r_b)
  double radial_offset = 0.0;       // [m] own position error, outward
  double tangential_offset = 0.0;   // [m] own position error, counter-clockwise
  PolarProfile outline;             // outer surface in the roller frame; radius() = r_b
  ShapePhaseReference phase_reference = ShapePhaseReference::kRadial;
  double spin_phase = 0.0;          // [rad] extra body rotation at psi = 0
  RollerMount mount = RollerMount::kFixed;
  Spring spring;                    // used when mount == kSpring
  double mass = 0.0;                // [kg]
  double spin_inertia = 0.0;        // [kg m^2]
  // [m] axial length as the scene file gives it: only a mass computed from density uses
  // it, and a scene written back keeps it; 0 where no file gave one.
  double width = 0.0;
  Material material;

  bool operator==(const Roller&) const = default;
};

// Normal contact law, docs/model.md §4: F = k delta^e + STEP(delta, 0, 0, d, c_max) delta'.
// The defaults are the article's (its Table 4, Adams IMPACT), which a scene built in code
// keeps; a scene file that states neither k nor e gets the Hertzian line-contact law of
// its materials instead (engine/line_contact.h).
struct ContactLaw {
  enum class Model { kRigid, kPenalty };
  Model model = Model::kPenalty;
  double stiffness = 1.0e7;                 // [N/m^e] k
  double exponent = 1.5;                    // [-] e >= 1
  double max_damping = 1.0e5;               // [N s/m] c_max
  double full_damping_penetration = 1e-6;   // [m] d

  bool operator==(const ContactLaw&) const = default;
};

// Coulomb friction with stiction, docs/model.md §4 (used by the dynamic solver).
// What the dynamic solver models beyond the ring's (x, y). Each reduction drops states and
// stiffness a scene may not need (docs/model.md §4).
struct DynamicModel {
  // Coulomb friction with stiction at the contacts. Off, nothing turns the rollers:
  // combine with rolling_without_slip unless still rollers are what is meant. Safe when
  // tangential forces do not move the centre, as for round rollers at steady speed.
  bool friction = true;
  // Rollers turn at exactly R / r_b times the ring's rate: no spin states, no stiction
  // dynamics, no tangential force. Safe away from starts, stops and reversals, once the
  // rollers have spun up (they do within a millisecond of a step to 270 deg/s).
  bool rolling_without_slip = false;
  // Spring rollers without mass: their travel follows from the force balance of spring,
  // contact stiffness and contact damping, with no inertia. Removes the fastest mode
  // (grams against c_max, near -4e7 1/s). Safe while the roller's own natural frequency
  // (kHz) is far above every excitation, which holds for every speed the article uses.
  bool massless_spring_rollers = false;

  bool operator==(const DynamicModel&) const = default;
};

struct Friction {
  double static_coefficient = 0.61;   // [-] mu_s
  double dynamic_coefficient = 0.47;  // [-] mu_d
  double stiction_velocity = 0.010;   // [m/s] v_s
  double transition_velocity = 0.050; // [m/s] v_d > v_s

  bool operator==(const Friction&) const = default;
};

struct Scene {
  Ring ring;
  std::vector<Roller> rollers;
  // The paper's form of roller position errors: a radial series evaluated at each
  // roller's nominal angle on the centre circle, added to each roller's own offsets.
  // Its radius() is unused (only mean_deviation and harmonics).
  PolarProfile roller_positions{1.0, 0.0, {}};
  ContactLaw contact;
  Friction friction;
  double sensor_angle = 0.0;  // [rad] global direction in which the runout sensor looks
  SwingRule sensor_swing;     // how that sensor's peak-to-valley swing is read
  // How the axis's error motion is filtered before its values are read.
  ErrorMotionFilter error_motion_filter;
  // The imposed rotation psi(t) and what of the bodies' dynamics to keep; only the
  // dynamic solver reads them (the others follow psi quasi-statically).
  MotionLaw motion = ArticleLaw();
  DynamicModel dynamics;
  // Over the stage's life (docs/model.md §9): whether the rollers keep the relative phases
  // their spin ratios give them (geared together, say), so that the revolutions repeat
  // where the ratios are commensurate. False: each roller's phase is its own, set at
  // assembly and moved by slip, and the life takes every phase of each.
  bool phase_locked_rollers = false;

  bool operator==(const Scene&) const = default;
};

// Unit vector at angle a.
inline Eigen::Vector2d Direction(double a) { return {std::cos(a), std::sin(a)}; }

// Radial position error of roller i: own offset plus the scene's series at its angle [m].
double RadialPositionError(const Scene& scene, int i);

// Centre of roller i at zero spring travel, position errors included [m].
Eigen::Vector2d RollerCentre(const Scene& scene, int i);

// Spin ratio R / r_b of roller i: radians of roller spin per radian of ring rotation, R and
// r_b the rolling radii (nominal plus mean deviation: a roller's drawn size changes how
// fast it turns, so rollers of one class drift in phase against each other).
double SpinRatio(const Scene& scene, int i);

// Global angle of roller i's body x axis when the ring has turned by psi [rad].
double RollerBodyAngle(const Scene& scene, int i, double psi);

// Travel axis of roller i (spring rollers), unit vector.
Eigen::Vector2d SpringAxis(const Scene& scene, int i);

int SpringRollerCount(const Scene& scene);
int FixedRollerCount(const Scene& scene);

// The same assembly with every shape and position error removed: the reference for the
// static offset, so the contact compliance of a perfect assembly is not counted as error.
Scene WithoutErrors(const Scene& scene);

// WithoutErrors(a) == WithoutErrors(b), found without building either: a solver's nominal
// cache asks it of every sample, where building the error-free scene and comparing it
// whole costs more than the lookup saves. Error-free profiles are circles, equal when
// their radii are.
bool SameWithoutErrors(const Scene& a, const Scene& b);

// !(WithoutErrors(scene) == scene), found without building it: whether any shape or
// position error is present.
bool HasErrors(const Scene& scene);

// Fastest undulation rate the centre path can contain [cycles per ring revolution]:
// ring orders pass at their order, roller orders at order * R / r_b.
double FastestHarmonicRate(const Scene& scene);

// The term FastestHarmonicRate finds, for messages: its rate, and whose highest order it is.
struct FastestHarmonic {
  double rate = 0.0;  // [cycles per ring revolution]
  int roller = -1;    // the roller whose order it is, or -1 for the ring's
  int order = 0;      // 0 when the scene has no harmonics
};
FastestHarmonic FindFastestHarmonic(const Scene& scene);

// The fewest angles per revolution that sample a term of `rate` undulations per revolution
// more than twice a period (Nyquist): at fewer, the term aliases onto a slower one, and at
// n angles an order-n ring reads as standing still (D_trajectory 0). A step count a user
// gives must reach this for the scene's fastest term: it has no error budget. The
// automatic rule (solvers::ChooseSteps) may leave fast terms unresolved only within its
// path tolerance, which counts an aliased term at its full size.
int MinimumSteps(double rate);

// What stops a scene from being simulated at all, found from geometry alone.
enum class GeometryIssue {
  kNone,
  kRingNotConvex,     // the ring's bore has an inward bump: contact is not unique
  kRollerNotConvex,   // a roller's outline has a dent
  kRollerDoesNotFit,  // a roller reaches beyond the ring's bore or through its own centre
  kRollersOverlap,    // two rollers' bodies cut through each other
};
struct GeometryCheck {
  GeometryIssue issue = GeometryIssue::kNone;
  int roller = -1;        // the roller concerned, or -1
  int other_roller = -1;  // kRollersOverlap: the earlier roller of the two, else -1
  double overlap = 0.0;   // [m] kRollersOverlap: sum of the largest radii less the centres' distance
  std::string message;    // human-readable reason with numbers in mm
};
GeometryCheck CheckGeometry(const Scene& scene);

}  // namespace ringtol::engine
