// The first rung: first-order kinematics. The force balance of solvers/equilibrium.h is
// linearised once about the static equilibrium of the error-free assembly; every error
// source then enters as an additive change of a contact's gap,
//   dg_i(psi) = dr_ring(phi_i - psi) - dr_roller_i(phi_i - gamma_i(psi)) - dp_i . n_i,
// and the centre, travels and forces respond as y(psi) = y0 + Y dg(psi). Each error term
// is a rotating phasor, so the path is a sum of phasors evaluated in closed form at every
// angle: exact to first order in amplitude / radius, with a second-order error, which the
// rung estimates from the same phasors (the profiles' slopes, the centre's motion across
// each contact normal, the penalty law's curvature; solvers/linear.cpp ErrorEstimate)
// and returns as Trajectory::error_estimate; beyond LinearOptions' limit it refuses.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "solvers/nominal_cache.h"
#include "solvers/path_kernels.h"
#include "solvers/quasistatic.h"
#include "solvers/solver.h"

namespace ringtol::solvers {

struct LinearOptions {
  // Options of the quasistatic solve of the error-free assembly that is linearised.
  QuasistaticOptions nominal;
  // The path is refused (Status::kBeyondLinearRange) when its estimated second-order
  // error in D_trajectory (Trajectory::error_estimate) exceeds
  //   max(max_relative_error * reach, min_error_limit),
  // reach [m] the path's largest distance from its start (between D_trajectory / 2 and
  // D_trajectory). The error grows as amplitude^2 while the path grows as amplitude, so a
  // relative limit is a limit on amplitude / size: 1 % [-] in (0, 1]. The absolute floor
  // [m] >= 0 keeps a nearly still path, whose relative error is meaningless, from being
  // refused over errors far below any tolerance studied (1 nm).
  double max_relative_error = 0.01;
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
// (the bore's at contact i, then the roller's). SolveRevolution sums it in another order
// (solvers/linear.cpp EvaluatePath); this form is the reference it is tested against.
struct PhasorSum {
  bool usable = false;         // false when the error-free assembly cannot be linearised
  Eigen::VectorXd offset;
  Eigen::MatrixXd cosine;      // outputs x terms
  Eigen::MatrixXd sine;        // outputs x terms
  std::vector<double> rates;   // [rad of phase per rad of ring angle]
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
    std::vector<Eigen::Vector2d> centre;        // [m] the first-order centre
    std::vector<double> travel;                 // [m] k-major, one per roller (0 for fixed)
    std::vector<double> contact_force;          // [N] k-major, one per roller
    std::vector<Eigen::Vector2d> centre_error;  // [m] the neglected second-order terms' centre
                                                //     error there (SolveRevolution's estimate)
    // What those terms are squares of, per angle and roller: the bore's and the roller's
    // gap slopes [m/rad], the gap function's slope [m/rad] and the penetration change [m]
    // (kFactors values a roller, angle-major).
    static constexpr std::size_t kFactors = 4;
    std::vector<double> factors;
    // [m] the sensor's reading of the first-order centre: engine::ReadSensor's to second
    // order in the centre's and the bore form's size,
    //   e_s . c + r - r' t + r'' t^2 / 2 - c_t t / 2,   t = c_t / r,
    // r, r', r'' the bore's at theta_s - psi and c_t the centre across the ray; the rest is
    // about r''' t^3 / 6, below 1e-10 m for any part studied.
    std::vector<double> signal;
    void clear();
    std::size_t size() const { return index.size(); }
  };

  // Bounds over the whole revolution for chords dpsi [rad] apart (ChordStraying, plus the
  // second-order terms' own): how far each output between two angles can stray from the
  // chord through its values there.
  struct Straying {
    double centre = 0.0;                // [m]
    double signal_rest = 0.0;           // [m] of signal - e_s . c - r(theta_s - psi): the sensor's second-order terms
    std::vector<double> travel;         // [m] per roller
    std::vector<double> contact_force;  // [N] per roller
    // Per roller and factor (Samples::factors' layout): the factor's first-order chord
    // bound, and the weight [1/m] its square has in |centre_error|.
    std::vector<double> factor;
    std::vector<double> factor_weight;

    // [m] How far Samples::centre_error can stray between samples a and b (dpsi apart)
    // from its chord: each second-order term is a weighted square f^2 whose chord f
    // follows to within its bound s, so f^2 strays by at most
    //   (f_b - f_a)^2 / 4 + 2 max(|f_a|, |f_b|) s + s^2
    // (the chord of f squared lies below the chord of f^2 by at most the first; the rest
    // is what f's own straying adds).
    double CentreErrorBetween(const Samples& samples, std::size_t a, std::size_t b) const;
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
  int coarse_stride() const { return stride_; }
  // The coarse angles' indices, ascending (their last is steps).
  const std::vector<int>& coarse() const { return coarse_; }
  // Appends the outputs at every dense angle strictly between coarse angles j and j + 1.
  void Refine(int j, Samples& samples);
  // e_s . c + r(theta_s - psi) [m] at every angle k = 0 .. steps: the sensor signal's
  // first-order part, for the reductions that need every angle (the swing). The same
  // vectorised sums as SolveRevolution.
  void FirstOrderSignal(std::vector<double>& signal) const;
  Straying StrayingAt(double dpsi) const;

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

 private:
  std::shared_ptr<const NominalResponse> Nominal(const engine::Scene& scene) const;

  LinearOptions options_;
  NominalCache<NominalResponse> nominal_;
};

}  // namespace ringtol::solvers
