// A closed convex outline given as a polar Fourier series about its body's centre:
//   r(theta) = radius + mean_deviation + sum_n C_n cos(n theta + phi_n)      [m], theta [rad]
// The ring's inner surface and each roller's outer surface are PolarProfiles.
//
// Support(phi) answers the question contact geometry asks of a convex body: which point
// of the outline has its outward normal at body-frame angle phi, how far does the body
// reach in that direction (the support function h), and how curved is it there. For a
// convex outline the normal angle nu(theta) = theta - atan2(r', r) increases
// monotonically, which makes that inverse well posed and bracketed.
//
// Cost and sharing. Construction keeps the harmonics' coefficients and O(orders) bounds on
// the outline's extremes, about what drawing the harmonics costs. What costs more is built
// on first demand: the sampled table (three inverse FFTs, kSampledOrders and up) on the
// first EvaluateAt(theta, cos, sin), and the exact extremes (a scan and Brent refinement)
// on the first MinCurvature() .. MaxRadius() or a convexity question the bounds leave
// open. A PolarProfile never changes once made: every const member may be called from any
// number of threads at once, on one object or on its copies. The state built on demand is
// built once (std::call_once), by the first thread that asks while the others wait, and
// is shared by every copy of the profile, made before or after it was built; assigning a
// new profile gives fresh state. Results do not depend on which accessor came first, on
// which thread built the state, or on whether it was built at all.
#pragma once

#include <cmath>
#include <memory>
#include <vector>

namespace ringtol::engine {

struct Harmonic {
  int order = 0;           // [-] undulations per revolution, >= 1
  double amplitude = 0.0;  // [m] radial deviation C_n, >= 0
  double phase = 0.0;      // [rad] phi_n in C_n cos(n theta + phi_n)
  bool operator==(const Harmonic&) const = default;
};

// r and its first two derivatives with respect to the body angle.
struct RadiusDerivatives {
  double r = 0.0;    // [m]
  double dr = 0.0;   // [m/rad]
  double ddr = 0.0;  // [m/rad^2]
  double cos_theta = 1.0;  // [-] of the angle evaluated, reused by callers
  double sin_theta = 0.0;  // [-]
};

// The outline's reach in one direction.
struct SupportPoint {
  double theta = 0.0;             // [rad] body angle of the touching point
  double h = 0.0;                 // [m] support function: max over the outline of x . n(phi)
  double dh = 0.0;                // [m/rad] dh/dphi: the touching point's coordinate along the tangent
  double curvature_radius = 0.0;  // [m] radius of curvature at the touching point; h'' = this - h
  int evaluations = 0;            // [-] outline evaluations the search took (0 for a circle)
};

// The outline's extremes over the whole revolution, or bounds on them.
struct OutlineExtremes {
  double min_curvature = 0.0;  // [1/m] smallest signed curvature
  double max_curvature = 0.0;  // [1/m] largest signed curvature
  double min_radius = 0.0;     // [m] smallest r(theta)
  double max_radius = 0.0;     // [m] largest r(theta)
  bool operator==(const OutlineExtremes&) const = default;
};

class PolarProfile {
 public:
  PolarProfile() = default;
  // radius > 0 [m]; harmonics of equal order add up. Throws std::invalid_argument for a
  // non-positive radius or an order < 1 (callers validate input files before this).
  PolarProfile(double radius, double mean_deviation, std::vector<Harmonic> harmonics);

  double radius() const { return radius_; }  // nominal radius [m]
  double mean_deviation() const { return mean_deviation_; }
  const std::vector<Harmonic>& harmonics() const { return harmonics_; }
  int max_order() const { return static_cast<int>(cos_coefficients_.size()) - 1; }
  bool is_circle() const { return max_order() == 0; }
  // a_n and b_n of r = radius + mean + sum_n (a_n cos n theta - b_n sin n theta) [m];
  // zero for orders above max_order().
  double cos_coefficient(int n) const;
  double sin_coefficient(int n) const;

  // r and its derivatives at body angle theta, summed over the harmonics: exact to
  // round-off.
  RadiusDerivatives Evaluate(double theta) const;
  // The same at the body angle whose cosine and sine are given (from a NearbyAngle).
  RadiusDerivatives EvaluateAt(double cos_theta, double sin_theta) const;
  // The same at body angle theta whose cosine and sine the caller has: from the profile's
  // samples when it keeps them (sampled()), else summed as EvaluateAt. The cheaper of the
  // two for any profile.
  RadiusDerivatives EvaluateAt(double theta, double cos_theta, double sin_theta) const;
  // Four angles at once, in two pairs of SIMD lanes and one pass over the harmonics: the
  // same arithmetic, and the same results, as four EvaluateAt calls, whose recurrences
  // then overlap instead of waiting on each other.
  void EvaluateFourAt(const double (&cos_theta)[4], const double (&sin_theta)[4], RadiusDerivatives (&out)[4]) const;

  // Support point for the outward normal at body angle phi [rad]. theta_guess speeds up
  // the search when close (warm start along a trajectory); the answer does not depend on
  // it. Requires IsConvex(); on a non-convex outline the result is one of the points with
  // that normal, not necessarily the outermost.
  SupportPoint Support(double phi, double theta_guess) const;
  // The same search for a normal given as the unit vector (cos phi, sin phi), for callers
  // that hold the normal but not its angle. Here `theta` of the result, and the guess,
  // are the touching point's offset theta - phi, in (-pi/2, pi/2).
  SupportPoint SupportToward(double cos_phi, double sin_phi, double offset_guess) const;
  // The same for a nearly round outline, whose touching point lies delta ~ r' / r from the
  // normal: one evaluation of r and its first four derivatives along the normal, and delta
  // from the series reversion of r' cos delta - r sin delta = 0 to third order in r' / r,
  // exact to its next term, which the harmonics' moments bound. Where that bound exceeds
  // offset_tolerance [rad] (a lobed outline rather than a nearly round one) the search of
  // SupportToward finishes from the series' answer to its own 1e-14 rad. The series'
  // curvature radius leaves out r^(5) delta^3 / 6 of r'' (~1e-8 of it for a roller's
  // lobes): enough for the Newton steps that use it.
  SupportPoint SupportTowardNearlyRound(double cos_phi, double sin_phi, double offset_tolerance) const;

  // Profiles with many harmonics (kSampledOrders and up) keep r, r' and r'' sampled on a
  // uniform grid of the body angle, computed at construction by three inverse FFTs
  // (Eigen's FFT module), with as many samples as make quintic Hermite interpolation
  // between neighbours exact to kSampleTolerance in r: its error is at most
  // h^6 / 46080 * sum_n n^6 C_n for a grid step h. r' and r'' come from the same
  // interpolant, exact to O(h^5) and O(h^4) (a few pm/rad and um/rad^2 for a 50-order
  // waterjet ring), which only the Newton steps' rate feels. An evaluation then costs
  // about as much as three harmonics summed, whatever the order. The table is built on the
  // first evaluation that reads it (see the top of this file).
  static constexpr int kSampledOrders = 16;
  static constexpr double kSampleTolerance = 1e-15;  // [m]
  bool sampled() const { return max_order() >= kSampledOrders; }

  // Extremes over the whole outline, found on first demand by dense sampling (64 points
  // per undulation of the highest order) refined by Brent's method, then kept: what
  // convexity, fit and the two-point certificate ask when the bounds below cannot answer.
  double MinCurvature() const { return Extremes().min_curvature; }  // [1/m] smallest signed curvature
  double MaxCurvature() const { return Extremes().max_curvature; }  // [1/m] largest signed curvature
  double MinRadius() const { return Extremes().min_radius; }        // [m] smallest r(theta)
  double MaxRadius() const { return Extremes().max_radius; }        // [m] largest r(theta)
  // MinCurvature() > 0, from the bounds when they settle it.
  bool IsConvex() const { return bounds_.min_curvature > 0.0 || MinCurvature() > 0.0; }

  // Bounds on the extremes above from the amplitudes alone (sums of n^k C_n), made at
  // construction in O(orders): min_curvature <= MinCurvature(), max_curvature >=
  // MaxCurvature(), min_radius <= MinRadius(), max_radius >= MaxRadius(), for the values
  // those accessors return, round-off and the table's interpolation error included, so a
  // decision the bounds settle is the exact value's decision, bit for bit. Exact for a
  // circle; -inf or +inf where the amplitudes say nothing (min_curvature when
  // R + mean - sum (n^2 + 1) C_n <= 0). For a nearly round part they are loose by about
  // (sum n^2 C_n) / R, relatively: enough to settle a campaign's fit and Blaschke tests.
  const OutlineExtremes& ExtremesBounds() const { return bounds_; }

  bool operator==(const PolarProfile&) const = default;

 private:
  const OutlineExtremes& Extremes() const;
  OutlineExtremes FindExtremes() const;
  // moments[k] = sum_n n^k C_n for k = 0..3, sixth = sum_n n^6 C_n [m]
  void BoundExtremes(const double (&moments)[4], double sixth);

  double radius_ = 0.0;
  double mean_deviation_ = 0.0;
  std::vector<Harmonic> harmonics_;
  // r = radius + mean + sum_n (a_n cos n theta - b_n sin n theta), index n = 0..max_order
  std::vector<double> cos_coefficients_{0.0};
  std::vector<double> sin_coefficients_{0.0};
  // The same for n = 1..max_order with the factors n and n^2 of r' and r'' applied
  // once, here, rather than at every evaluation.
  struct Term {
    double a, b, na, nb, nna, nnb, nnna, nnnb;
    bool operator==(const Term&) const = default;
  };
  // r, its first two derivatives and (in dddr) the third at the body angle whose cosine and
  // sine are given: the support search's evaluation, from which its last step is taken by
  // series.
  RadiusDerivatives EvaluateWithThirdAt(double cos_theta, double sin_theta, double& dddr) const;
  template <bool kThird>
  RadiusDerivatives Sum(double cos_theta, double sin_theta, double& dddr) const;
  std::vector<Term> terms_;
  // Bounds over the outline of |r''' - 3 r'| (odd) and |3 r'' - r| (even) [m]: the support
  // search's certificate that its next step would be negligible.
  struct SupportBound {
    double odd = 0.0;
    double even = 0.0;
    double fourth = 0.0;  // of |r''''|: what a last step by series leaves out of r''
    // of |r^(5)| / 24 + 5 |r'''| / 12 + 5 |r'| / 24, the fourth Taylor coefficient of
    // r' cos delta - r sin delta: the nearly-round series' error bound
    double series = 0.0;
    bool operator==(const SupportBound&) const = default;
  };
  SupportBound support_bound_;
  OutlineExtremes bounds_;  // the extremes themselves for a circle
  int sample_count_ = 0;    // [-] the table's samples per revolution (a power of two), 0 unsampled
  // The table and the exact extremes, built on demand (Table(), Extremes()) for a profile
  // that is not a circle: derived from the harmonics, shared between copies, and left out
  // of comparisons (profiles with equal harmonics have equal derived state).
  struct SampleTable;
  struct Derived;
  const SampleTable& Table() const;
  struct SharedDerived {
    std::shared_ptr<Derived> state;
    bool operator==(const SharedDerived&) const { return true; }
  };
  SharedDerived derived_;
};

// cos and sin of |delta| <= NearbyAngle::kReach [rad] from their Taylor series, exact to
// round-off there; std::cos and std::sin beyond. Inline: contact steps call it for every
// contact at every iteration.
inline void CosSinOfSmallAngle(double delta, double& cos_delta, double& sin_delta);

// cos and sin of an angle that moves in small steps, as a contact's touching point does
// along a trajectory: one libm sincos at a reference angle, then the rotation of that
// reference by the offset, with cos and sin of the offset from their Taylor series. Within
// kReach of the reference the series is exact to round-off (truncation
// delta^10 / 10! < 3e-20), and the reference is exact, so nothing accumulates; a libm
// sincos costs about ten rotations.
class NearbyAngle {
 public:
  static constexpr double kReach = 0.05;  // [rad]

  void Evaluate(double theta, double& cos_theta, double& sin_theta) {
    double delta = theta - reference_;
    if (!(std::abs(delta) <= kReach)) {
      reference_ = theta;
      cos_reference_ = std::cos(theta);
      sin_reference_ = std::sin(theta);
      delta = 0.0;
    }
    double cos_delta;
    double sin_delta;
    CosSinOfSmallAngle(delta, cos_delta, sin_delta);
    cos_theta = cos_reference_ * cos_delta - sin_reference_ * sin_delta;
    sin_theta = sin_reference_ * cos_delta + cos_reference_ * sin_delta;
  }

 private:
  double reference_ = 0.0;
  double cos_reference_ = 1.0;
  double sin_reference_ = 0.0;
};

inline void CosSinOfSmallAngle(double delta, double& cos_delta, double& sin_delta) {
  if (!(std::abs(delta) <= NearbyAngle::kReach)) {
    cos_delta = std::cos(delta);
    sin_delta = std::sin(delta);
    return;
  }
  // Horner in delta^2 with the factorials' ratios as products: a division by a constant
  // that is not a power of two costs as much as the whole series.
  const double d2 = delta * delta;
  cos_delta = 1.0 - 0.5 * d2 * (1.0 - (1.0 / 12.0) * d2 * (1.0 - (1.0 / 30.0) * d2 * (1.0 - (1.0 / 56.0) * d2)));
  sin_delta =
      delta * (1.0 - (1.0 / 6.0) * d2 * (1.0 - (1.0 / 20.0) * d2 * (1.0 - (1.0 / 42.0) * d2 * (1.0 - (1.0 / 72.0) * d2))));
}

// Signed curvature of a polar curve [1/m]: (r^2 + 2 r'^2 - r r'') / (r^2 + r'^2)^(3/2).
double Curvature(const RadiusDerivatives& d);

}  // namespace ringtol::engine
