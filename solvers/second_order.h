// The linear rung's second order (docs/model.md §7): what the first-order path of
// solvers/linear.h misses to second order in the errors, added at one angle (At), with a
// bound on what the corrected outputs still miss of the exact quasistatic model there (of
// third order), and bounds of both over every angle of a set (Over), for the spectral
// evaluation's stretches between evaluated angles.
//
// Units SI: lengths [m], forces [N], angles [rad]. LinearSolver makes SecondOrderTerms from
// a scene's linearisation (LinearSolver::SecondOrder, LinearPath::second_order); it shares
// an immutable SecondOrderScene, so copies are cheap and every method is thread-safe. At
// evaluates one angle, AtEach a block of angles in SIMD lanes, with the same bits; neither
// nor Over touches the heap once a thread has called it, for up to 8 rollers.
// Failure modes, none thrown: where a premise of the expansion fails at an angle (a reach
// or the gap's curvature not positive) At keeps the first-order curvatures and its
// remainder is infinite; where only a premise of the remainder bound fails, only the
// remainder is infinite. Over's bounds are all infinite where a premise of the expansion
// may fail anywhere in its range, and its remainder where one of the bound's may.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace ringtol::solvers {
// One angle of the first-order path, in PhasorSum's rows: what the second-order
// correction reads. travel and contact_force hold Z values (travel 0 for a fixed roller),
// slopes and curvatures 2Z each (the bore's part at contact i, then the roller's).
struct FirstOrderAngle {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // [m]
  std::span<const double> travel;                    // [m]
  std::span<const double> contact_force;             // [N]
  std::span<const double> slopes;                    // [m/rad]
  std::span<const double> curvatures;                // [m/rad^2]
};

// What the second-order terms add to one angle's first-order outputs, and a bound on what
// the corrected outputs still miss of the exact quasistatic model there.
struct SecondOrderAngle {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // [m] to add to the centre
  std::vector<double> travel;                        // [m] per roller, to add (0 for fixed)
  std::vector<double> contact_force;                 // [N] per roller, to add
  // [m] >= 0 (infinite where the bound's premises fail): |exact centre - corrected centre|
  // at this angle is at most this (docs/model.md §7, "The linear rung's error estimate").
  double remainder = 0.0;
};

// Bounds on the first-order inputs of SecondOrderTerms::At that hold at every angle of a
// set (a stretch between two evaluated angles), in FirstOrderAngle's layout.
struct FirstOrderRange {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // [m] the centre lies within centre_radius of this
  double centre_radius = 0.0;                        // [m] >= 0
  std::vector<double> travel_low, travel_high;       // [m] Z each (0, 0 for a fixed roller)
  std::vector<double> force_low, force_high;         // [N] Z each
  std::vector<double> slope_low, slope_high;         // [m/rad] 2Z each, bore's then roller's
  std::vector<double> curvature_low, curvature_high; // [m/rad^2] 2Z each, likewise
};

// Bounds on what SecondOrderTerms::At returns at every angle whose inputs lie in a
// FirstOrderRange: every field infinite where a premise of At's expansion or of its
// remainder may fail somewhere in the range.
struct SecondOrderRange {
  double centre = 0.0;                // [m] >= |SecondOrderAngle::centre|
  std::vector<double> travel;         // [m] per roller, >= |SecondOrderAngle::travel| (0 for fixed)
  std::vector<double> contact_force;  // [N] per roller, >= |SecondOrderAngle::contact_force|
  double remainder = 0.0;             // [m] >= SecondOrderAngle::remainder
};

// A block of angles of the first-order path, structure of arrays (what SecondOrderTerms::
// AtEach vectorises over): field f of angle j at rows[f * stride + j], j < count <= stride,
// fields in FirstOrderAngle's order: centre x, y [m]; travel [m] (Z, 0 for fixed rollers);
// contact force [N] (Z); slopes [m/rad] (2Z); curvatures [m/rad^2] (2Z): 2 + 6Z rows.
// A view: the caller owns the rows.
struct FirstOrderAngles {
  const double* rows = nullptr;
  std::size_t stride = 0;
  std::size_t count = 0;
};

// SecondOrderAngle for a block of angles, likewise: rows centre x, y [m] to add; travel [m]
// to add (Z, 0 for fixed rollers); contact force [N] to add (Z); remainder [m]: 3 + 2Z rows
// of a FirstOrderAngles' count angles at rows[f * stride + j]. A view: the caller owns the
// rows.
struct SecondOrderAngles {
  double* rows = nullptr;
  std::size_t stride = 0;
};

// One scene as the second-order terms read it: its error-free assembly's static
// equilibrium and first-order response (LinearSolver's linearisation), and the sizes of
// the scene's errors that the remainder bound needs. Z contacts, one per roller.
struct SecondOrderScene {
  struct Contact {
    // At the error-free assembly's equilibrium.
    Eigen::Vector2d normal = Eigen::Vector2d::Zero();   // [-] unit, outward from the ring's centre
    Eigen::Vector2d tangent = Eigen::Vector2d::Zero();  // [-] the normal turned by +90 deg
    double gap_curvature = 0.0;       // [m] g'' of the gap along the normal's angle (> 0: isolated)
    double roller_radius = 0.0;       // [m] r_i, nominal
    bool spring = false;              // a spring roller (travels along axis), else fixed
    double travel0 = 0.0;             // [m] nominal travel (spring rollers)
    double force0 = 0.0;              // [N] nominal contact force
    double penetration = 0.0;         // [m] delta (penalty law; 0 for the rigid law)
    double force_stiffness = 0.0;     // [N/m] dF/d delta there (penalty law; 0 rigid)
    double law_scale = 0.0;           // [m^(e-1)] delta^(e - 1) (penalty law)
    double gap_gain = 0.0;            // [-] |the centre's response to a unit gap change|
    double normal_force_gain = 0.0;   // [m/N] |the centre's response to a unit force along the normal|
    double tangent_force_gain = 0.0;  // [m/N] likewise along the tangent
    // The scene's own.
    Eigen::Vector2d axis = Eigen::Vector2d::Zero();   // [-] unit spring axis (spring rollers)
    Eigen::Vector2d shift = Eigen::Vector2d::Zero();  // [m] the roller centre's position error
    double roller_value = 0.0;        // [m] |dr0| + sum |c_m| of the roller: bounds |dr|
    double roller_jerk = 0.0;         // [m] sum m^3 |c_m|: bounds |dr'''|
  };
  std::vector<Contact> contacts;
  Eigen::Vector2d centre0 = Eigen::Vector2d::Zero();  // [m] the ring centre at the equilibrium
  double ring_radius = 0.0;         // [m] R, the bore's nominal
  double exponent = 1.0;            // [-] e of the penalty law
  // The first-order response of the outputs, rows centre x, y [m], travel [m] per roller
  // (zero rows for fixed rollers), contact force [N] per roller (2 + 2Z rows), to each
  // contact's gap change [m] (columns 0 .. Z-1), to an extra force [N] there along its
  // normal (Z .. 2Z-1) and along its tangent (2Z .. 3Z-1).
  Eigen::MatrixXd response;
  double ring_value = 0.0;          // [m] |dr0| + sum |C_n| of the bore: bounds |dr|
  double ring_jerk = 0.0;           // [m] sum n^3 |C_n|: bounds |dr'''|
  double ring_slope_sum = 0.0;      // [m] sum n |C_n|: bounds |dr'|
};

// The second-order correction of one scene, angle by angle (solvers/second_order.cpp
// SecondOrderTerms::At). Cheap to copy; thread-safe; shares the scene it was made from.
class SecondOrderTerms {
 public:
  SecondOrderTerms() = default;  // not usable()
  explicit SecondOrderTerms(SecondOrderScene scene);
  bool usable() const { return scene_ != nullptr; }
  // `first` one angle of this scene's first-order path (LinearSolver::Phasors summed there,
  // or SolveRevolution's path before correction); `out` is resized to the scene's rollers
  // (allocates only the first time: reuse it across angles). Requires usable().
  void At(const FirstOrderAngle& first, SecondOrderAngle& out) const;
  // At at every angle of a block, two angles at a time in SIMD lanes: the same operations
  // in the same order, so the same bits as At angle by angle. For a caller with many
  // angles (a revolution's, a coarse grid's); `out` spans first.count angles of 3 + 2Z
  // rows. Allocates only the first time on a thread. Requires usable().
  void AtEach(const FirstOrderAngles& first, const SecondOrderAngles& out) const;
  // Bounds At's results over every angle whose inputs lie in `range` (vectors sized as
  // At's): At mirrored term by term in interval arithmetic (solvers/second_order.cpp). `out` is
  // resized to the scene's rollers. Requires usable().
  void Over(const FirstOrderRange& range, SecondOrderRange& out) const;
  // [m] Trajectory::error_estimate from the largest remainder [m] over the angles and the
  // path's reach [m] (largest distance of the centre from its start): twice the remainder
  // (every point moves by at most it, so the enclosing circle's radius and the sensor's
  // max and min each by at most it), times the sensor's gain to centre motion.
  double EstimateFrom(double largest_remainder, double reach) const;

 private:
  std::shared_ptr<const SecondOrderScene> scene_;
};

}  // namespace ringtol::solvers
