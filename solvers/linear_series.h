// The linear rung's dense sums of series over one revolution (defined in solvers/linear.cpp,
// where EvaluatePath and LinearPath's dense signals use them), declared here for their
// tests: internal, not part of the solvers' interface.
//
// Series s at angle psi_k = 2 pi k / steps, k = 0 .. steps, is
//   sum over terms p of cosine(s, p) cos(rate_p psi_k) + sine(s, p) sin(rate_p psi_k).
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "solvers/path_kernels.h"

namespace ringtol::solvers::internal {

// How SumSeries sums the terms of integer rate. Such a term takes the same values at psi
// and 2 pi - psi up to the sign of its sine, and at psi + pi up to (-1)^rate, so part of
// the turn gives the whole: half the phasor turns and sums, or a quarter.
enum class SeriesFold {
  kNone,     // every angle: too few angles for one lane group in the folded part
  kHalf,     // odd steps: angles k = 0 .. (steps - 1) / 2 give k and steps - k
  kQuarter,  // even steps: k = 0 .. steps / 4 give k, steps - k, steps / 2 + k, steps / 2 - k
};

// The fold SumSeries uses for a revolution of `steps` >= 1 angles.
SeriesFold FoldFor(int steps);

// Each series' angles k = 0 .. steps, padded to whole lane groups: a row's length in
// SumSeries' output.
std::size_t PaddedAngles(int steps);

// The series (series_cosine and series_sine: series x terms, of equal shape; rates [rad of
// phase per rad of ring angle], one a term) at every angle of a revolution of `steps` >= 1
// angles: series s at angle k lands in series[s * PaddedAngles(steps) + k]; the padding
// lanes beyond k = steps hold no defined value. Exact to the phasor recurrence's
// round-off, ~1e-13 of a term. Thread-safe: its work buffers are per thread.
void SumSeries(const Eigen::MatrixXd& series_cosine, const Eigen::MatrixXd& series_sine, const std::vector<double>& rates,
               int steps, const path_kernels::Kernels& kernels, std::vector<double>& series);

}  // namespace ringtol::solvers::internal
