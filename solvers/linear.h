// The first rung: kinematics to second order. The force balance of solvers/equilibrium.h
// is linearised once about the static equilibrium of the error-free assembly; every error
// source then enters as an additive change of a contact's gap,
//   dg_i(psi) = dr_ring(phi_i - psi) - dr_roller_i(phi_i - gamma_i(psi)) - dp_i . n_i,
// and the centre, travels and forces respond as y(psi) = y0 + Y dg(psi). Each error term
// is a rotating phasor, so this first-order path is a sum of phasors evaluated in closed
// form at every angle. From the same phasors (the gap's slopes and curvatures at each
// contact) the rung adds the second-order terms at every angle (SecondOrderTerms), and
// bounds what that path still misses, of third order, as Trajectory::error_estimate;
// beyond LinearOptions' limit it refuses.
#pragma once

#include <array>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "solvers/nominal_cache.h"
#include "solvers/path_kernels.h"
#include "solvers/quasistatic.h"
#include "solvers/second_order.h"
#include "solvers/solver.h"

namespace ringtol::solvers {

struct LinearOptions {
  // Options of the quasistatic solve of the error-free assembly that is linearised.
  QuasistaticOptions nominal;
  // The path is refused (Status::kBeyondLinearRange) when the bound on its error in
  // D_trajectory (Trajectory::error_estimate, infinite where the expansion's premises
  // fail) exceeds
  //   max(max_relative_error * reach, min_error_limit),
  // reach [m] the path's largest distance from its start (between D_trajectory / 2 and
  // D_trajectory). The error grows as amplitude^3 while the path grows as amplitude, so a
  // relative limit is a limit on amplitude / size: 5 % [-] in (0, 1]. The bound is a worst
  // case over phases and angles, at least 14 times the true error on every validated draw
  // (docs/model.md §7), so 5 % of the bound keeps the true error well below the 1 % the
  // rung allowed its second-order estimate, and still admits the article's orders up to
  // 20 at 0.14 mm (2.7 %). The absolute floor [m] >= 0 keeps a nearly still path, whose
  // relative error is meaningless, from being refused over errors far below any tolerance
  // studied (1 nm).
  double max_relative_error = 0.05;
  double min_error_limit = 1e-9;
  // The build of the path sums' inner loops (solvers/path_kernels.h). Every build gives
  // the same bits, so this changes speed only; it is not read from any file and exists so
  // that tests can run both builds.
  path_kernels::Isa kernels = path_kernels::Isa::kBest;
};

// The first-order path in closed form: output o at ring angle psi [rad] is
//   offset[o] + sum_p cosine(o, p) cos(rates[p] psi) + sine(o, p) sin(rates[p] psi),
// rows: centre x, y [m]; travel [m] of each spring roller (travel_row[i], -1 for a fixed
// roller); contact force [N] of roller i (first_force_row + i); then 2Z gap slopes [m/rad]
// (the bore's at contact i, then the roller's) and 2Z gap curvatures [m/rad^2] (likewise),
// which only the second order reads (SecondOrderTerms). These are the first-order path;
// SolveRevolution adds the second order. SolveRevolution sums it in another order
// (solvers/linear.cpp EvaluatePath); this form is the reference it is tested against.
struct PhasorSum {
  bool usable = false;         // false when the error-free assembly cannot be linearised
  Eigen::VectorXd offset;
  Eigen::MatrixXd cosine;      // outputs x terms
  Eigen::MatrixXd sine;        // outputs x terms
  std::vector<double> rates;   // [rad of phase per rad of ring angle]
  // Per term: the roller whose lobe it is (-1: the bore's form), and the harmonic's order
  // n or m; a roller's term turns at m engine::SpinRatio of the ring's rate.
  std::vector<int> roller;
  std::vector<int> order;
  std::vector<int> travel_row;
  int first_force_row = 0;
};

struct NominalResponse;

// First-order bounds on how far a revolution's outputs stray from the chord through their
// values at two angles dpsi apart: each error term moves an output as a sinusoid of
// amplitude a (its row of the linearisation) at rate w per revolution, which strays from
// its chord by at most min(2, w^2 dpsi^2 / 8) a; the bounds are the sums over the terms.
// Exact bounds for the linear rung's own path; for the exact model, first order.
struct ChordStraying {
  bool usable = false;                // false when the error-free assembly cannot be linearised
  double centre = 0.0;                // [m] the ring centre's distance from its chord
  double signal = 0.0;                // [m] the sensor reading's: the centre along the ray plus the bore's form
  std::vector<double> travel;         // [m] per roller (0 for fixed)
  std::vector<double> contact_force;  // [N] per roller
};

struct Linearisation;

// The linear rung's path over one revolution of `steps` angles, psi_k = 2 pi k / steps,
// held in closed form and read only where its caller asks: the spectral evaluation
// (solvers/spectral.h) reads a coarse grid, then the stretches between its angles that a
// bound cannot settle. Every output it gives at angle k is the dense path's (the one
// SolveRevolution returns) at k, to round-off: the same phasors, summed in another order.
// Made by LinearSolver::Path; owns everything it reads (the scene may go). Not
// thread-safe: one per thread.
class LinearPath {
 public:
  // Outputs at a set of angles, appended in the order they were asked for.
  struct Samples {
    std::vector<int> index;                     // k of each angle
    // The outputs of SolveRevolution's path there: the first order with its second-order
    // correction (SecondOrderTerms::At).
    std::vector<Eigen::Vector2d> centre;        // [m]
    std::vector<double> travel;                 // [m] k-major, one per roller (0 for fixed)
    std::vector<double> contact_force;          // [N] k-major, one per roller
    std::vector<double> remainder;              // [m] SecondOrderAngle::remainder there
    // [m] the sensor's reading of that centre: engine::ReadSensor's to second
    // order in the centre's and the bore form's size,
    //   e_s . c + r - r' t + r'' t^2 / 2 - c_t t / 2,   t = c_t / r,
    // r, r', r'' the bore's at theta_s - psi and c_t the centre across the ray; the rest is
    // about r''' t^3 / 6, below 1e-10 m for any part studied.
    std::vector<double> signal;
    // At's inputs there (the first-order outputs, before the correction), FirstOrderWidth()
    // an angle, angle-major: centre x, y [m]; travel [m] (Z, 0 for fixed); contact force [N]
    // (Z); 2Z slopes [m/rad]; 2Z curvatures [m/rad^2] (FirstOrderAngle's layout).
    std::vector<double> first_order;
    void clear();
    std::size_t size() const { return index.size(); }
  };

  // Bounds over the whole revolution for chords dpsi [rad] apart (ChordStraying): how far
  // each first-order output between two angles can stray from the chord through its values
  // there. What the second-order correction adds between angles, SecondOrderTerms::Over
  // bounds from RangeOver.
  struct Straying {
    double centre = 0.0;                // [m]
    double signal_rest = 0.0;           // [m] of signal - e_s . c - r(theta_s - psi): the sensor's second-order terms
    std::vector<double> travel;         // [m] per roller
    std::vector<double> contact_force;  // [N] per roller
    std::vector<double> slopes;         // [m/rad] 2Z, FirstOrderAngle's layout
    std::vector<double> curvatures;     // [m/rad^2] 2Z, likewise
    // The largest |slope| and |curvature| anywhere, the sums of their terms' amplitudes:
    // for a roller's fast lobes, which turn by more than a radian between coarse angles,
    // tighter than a chord and its bound.
    std::vector<double> slope_reach;     // [m/rad] 2Z
    std::vector<double> curvature_reach; // [m/rad^2] 2Z
  };

  // Bounds on how far the first-order centre, travels and forces stray over one coarse
  // stretch from the line through their values at its ends less the shifts there (zero,
  // or the rollers' fast lobes' values: see StrayingOver).
  struct StretchStraying {
    double centre = 0.0;                          // [m]
    std::array<Eigen::Vector2d, 2> centre_shift;  // [m] at the stretch's start, then its end
    std::vector<double> travel;                   // [m] per roller (0 for fixed)
    std::vector<double> contact_force;            // [N] per roller
    std::vector<double> travel_shift;             // [m] 2Z: Z at the start, then Z at the end
    std::vector<double> force_shift;              // [N] 2Z, likewise
  };

  LinearPath(LinearPath&&) noexcept;
  LinearPath& operator=(LinearPath&&) noexcept;
  ~LinearPath();

  // kOk, or why the path has no numbers (the error-free assembly cannot be linearised, or
  // the linearisation is not finite), with the reason in message().
  Status status() const { return status_; }
  const std::string& message() const { return message_; }
  int steps() const { return steps_; }
  int rollers() const;

  // Appends the outputs at k = 0, stride, 2 stride, ... and at k = steps (the coarse grid,
  // stride >= 1), and keeps the phasors there for Refine. Call once, first.
  void EvaluateCoarse(int stride, Samples& samples);
  // Prepares what StrayingOver reads at the coarse angles: the first-order outputs' slopes
  // there and the rollers' fast lobes' values (one more sum over the kept phasors, at an
  // angle the first time a stretch ending there asks). Call once, after EvaluateCoarse.
  void KeepStretchRows();
  int coarse_stride() const { return stride_; }
  // The coarse angles' indices, ascending (their last is steps).
  const std::vector<int>& coarse() const { return coarse_; }
  // Appends the outputs at every dense angle strictly between coarse angles j and j + 1.
  void Refine(int j, Samples& samples);
  // e_s . c + r(theta_s - psi) [m] at every angle k = 0 .. steps: the sensor signal's
  // first-order part, for the reductions that need every angle (the swing). The same
  // vectorised sums as SolveRevolution.
  void FirstOrderSignal(std::vector<double>& signal) const;
  // The centre's and the signal's first order [m] less the rollers' lobes (PhasorSum::roller
  // >= 0) at every angle k = 0 .. steps, by the same sums: what the life values
  // (solvers/life.h) add the lobes' curves to. The bore's terms turn at whole rates, so the
  // sums fold.
  void FirstOrderWithoutLobes(std::vector<Eigen::Vector2d>& centre, std::vector<double>& signal) const;
  // The first-order terms, as LinearSolver::Phasors gives them for this scene.
  PhasorSum Phasors() const;
  Straying StrayingAt(double dpsi) const;
  // How far the first-order centre, travels and forces stray over the stretch between
  // coarse angles j and j + 1 (samples j and j + 1, as EvaluateCoarse appends them;
  // `straying` from StrayingAt(coarse_stride() 2 pi / steps)). Per output, the smaller of
  // two bounds: the chord bound (shifts zero), or the cubic Hermite bound, which splits the
  // terms into slow ones and the rollers' fast lobes (more than 2 sqrt(2) rad a stretch):
  // the slow part strays from its cubic through its values and slopes at the ends, kept by
  // KeepStretchRows (call it first), by its fourth-derivative remainder, the cubic from the slow part's chord
  // by what its slopes say; the fast part by at most its amplitudes from zero; the line is
  // then the chord through the ends less the fast part there, which the shifts hold
  // (solvers/linear.cpp, docs/model.md §5). `out` is resized. Sums the slopes at the
  // stretch's ends on first use: one path, one thread.
  void StrayingOver(const Samples& samples, std::size_t j, const Straying& straying, StretchStraying& out) const;
  // Doubles an angle in Samples::first_order: 2 + 6Z.
  std::size_t FirstOrderWidth() const;
  // Bounds on At's inputs at every angle between samples first and last (a run of adjacent
  // coarse angles, each stretch between them `straying`'s dpsi apart): each output lies
  // within its straying of the chord through its values at a stretch's ends, so within
  // [min - straying, max + straying] over the run, a gap derivative also within +-its
  // reach, and the centre within its straying of the circle enclosing the run's centres
  // (for one stretch, a disc about the chord's midpoint). `range` is overwritten, its
  // buffers reused.
  void RangeOver(const Samples& samples, std::size_t first, std::size_t last, const Straying& straying,
                 FirstOrderRange& range) const;
  // Trajectory::error_estimate from the largest remainder over the angles and the path's
  // farthest point from the origin (SecondOrderTerms::EstimateFrom).
  double EstimateFrom(double largest_remainder, double farthest) const;
  // The second-order correction the path's outputs carry (SecondOrderTerms::At), for bounds
  // over the angles between samples (SecondOrderTerms::Over).
  const SecondOrderTerms& second_order() const;

 private:
  friend class LinearSolver;
  LinearPath();

  Status status_ = Status::kOk;
  std::string message_;
  int steps_ = 0;
  int stride_ = 0;
  std::unique_ptr<Linearisation> lin_;
  struct Parts;
  std::unique_ptr<Parts> parts_;
  std::vector<int> coarse_;
};

// Why the linear rung refuses a path (Status::kBeyondLinearRange) whose error estimate
// [m] exceeds max(options.max_relative_error reach, options.min_error_limit), reach [m] its
// largest distance from its start; empty when it does not.
std::string LinearRangeRefusal(const LinearOptions& options, double error_estimate, double reach);

// Thread-safe. Keeps the linearisation of the last error-free assembly it saw (a static
// solve and a factorisation, about a third of a revolution's cost) and reuses it while
// the scene without its errors stays the same, as it does for every sample of a campaign.
class LinearSolver final : public Solver {
 public:
  explicit LinearSolver(LinearOptions options = {}) : options_(options) {}
  std::string_view name() const override { return "linear"; }
  Equilibrium SolveStatic(const engine::Scene& scene) const override;
  Trajectory SolveRevolution(const engine::Scene& scene, int steps) const override;
  // dpsi [rad] > 0.
  ChordStraying ChordStrayingAt(const engine::Scene& scene, double dpsi) const;
  PhasorSum Phasors(const engine::Scene& scene) const;
  // The path of SolveRevolution(scene, steps) in closed form (steps >= 1), for the spectral
  // evaluation; a failed status where SolveRevolution would fail before its first angle.
  // Validity and the range limit are the caller's.
  LinearPath Path(const engine::Scene& scene, int steps) const;
  const LinearOptions& options() const { return options_; }
  // The per-angle second-order correction that SolveRevolution applies at every angle,
  // for a caller that sums the first-order path (Phasors) at angles of its own.
  SecondOrderTerms SecondOrder(const engine::Scene& scene) const;

 private:
  std::shared_ptr<const NominalResponse> Nominal(const engine::Scene& scene) const;
  static SecondOrderTerms SecondOrderOf(const engine::Scene& scene, std::shared_ptr<const NominalResponse> nominal);

  LinearOptions options_;
  NominalCache<NominalResponse> nominal_;
};

}  // namespace ringtol::solvers
