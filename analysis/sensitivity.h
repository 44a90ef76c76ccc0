// Which tolerances matter: variance-based sensitivity of a campaign output to its inputs.
//
//   - Sobol' indices from a pick-and-freeze (Saltelli) design, sampling/design.h's
//     kSaltelli: rows j of A_j, B_j and, for every group g, AB_g,j = A_j with group g's
//     coordinates taken from B_j. The first-order index S_g = Var(E[Y | X_g]) / Var(Y) is
//     what fixing group g at its true value would remove from the output variance; the
//     total index ST_g = 1 - Var(E[Y | X_~g]) / Var(Y) is what would remain if only group g
//     varied, interactions included. ST_g ~ 0 means the group's tolerance can be loosened.
//   - Screening of a plain Monte Carlo or QMC campaign (no pick-and-freeze): standardised
//     regression coefficients on values and ranks, and a given-data estimate of each
//     input's first-order index.
//
// Error bars come from the bootstrap over rows (samples), which assumes independent rows:
// they are honest for a Monte Carlo base and conservative for a randomised Sobol' base.
// Every result is a pure function of the outputs and the options (the bootstrap draws from
// its own seeded generator).
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "analysis/order_statistics.h"
#include "engine/enum_names.h"

namespace ringtol::analysis {

// ---------------------------------------------------------------------------------------
// Sobol' indices from a pick-and-freeze design.

// Model outputs of a pick-and-freeze design, aligned by row j = 0..N-1. A row with any
// non-finite output (a failed sample) is excluded whole: its partners are useless alone.
struct PickFreezeOutputs {
  std::vector<double> a;                // f(A_j), N values
  std::vector<double> b;                // f(B_j), N values
  std::vector<std::vector<double>> ab;  // ab[g][j] = f(AB_g,j), N values for each of G >= 1 groups
};

// The estimators, all written with y = f - mean (the mean of every used output of every
// matrix, as SALib and OpenTURNS centre) and V = (1/2N) sum over A and B rows (y - ybar)^2:
//   kSaltelliJansen  S_g  = (1/N) sum y(B) (y(AB_g) - y(A)) / V      Saltelli et al. 2010, table 2
//                    ST_g = (1/2N) sum (y(A) - y(AB_g))^2 / V         Jansen 1999 (also in that table)
//   kJanon           S_g  = [(1/N) sum y(B) y(AB_g) - m^2] / [(1/2N) sum (y(B)^2 + y(AB_g)^2) - m^2],
//                           m = (1/2N) sum (y(B) + y(AB_g)): the pair B, AB_g shares group g's
//                           coordinates; its own mean and variance make the estimator
//                           asymptotically efficient (Janon et al. 2014, eq. for T_N)
//                    ST_g = Jansen's, as above
//   kMartinez        S_g  = corr(y(B), y(AB_g)),  ST_g = 1 - corr(y(A), y(AB_g))   Martinez 2011
// (Pearson correlations over the rows). OpenTURNS' MartinezSensitivityAlgorithm computes the
// same numbers; its Jansen total and Mauntz-Kucherenko first order are ours times
// (2N)/(2N-1), resp. N/(N-1), and V / Var_unbiased(f(A)) (it divides by the variance of A
// alone); see tests/analysis/openturns_sobol.py.
enum class SobolEstimator { kSaltelliJansen, kJanon, kMartinez };

inline constexpr NameTable<SobolEstimator, 3> kSobolEstimatorNames = {{{SobolEstimator::kSaltelliJansen, "saltelli2010-jansen"},
                                                                      {SobolEstimator::kJanon, "janon"},
                                                                      {SobolEstimator::kMartinez, "martinez"}}};
constexpr std::string_view SobolEstimatorName(SobolEstimator estimator) { return NameOf(kSobolEstimatorNames, estimator); }

struct SobolOptions {
  SobolEstimator estimator = SobolEstimator::kSaltelliJansen;
  // Bootstrap resamples of the rows for the error bars: 0 (no error bars: conf and interval
  // are NaN) or >= 2. Every resample draws N rows with replacement, the same rows for all
  // groups, and applies the estimator to them.
  int bootstrap_resamples = 1000;
  // Two-sided level of conf and interval, in (0, 1) [-].
  double confidence = 0.95;
  // Seed of the bootstrap's generator (boost::random::mt19937_64).
  std::uint64_t bootstrap_seed = 1;
};

struct SobolIndex {
  double value = std::numeric_limits<double>::quiet_NaN();  // the estimate on all used rows [-]
  // SALib's *_conf: z_{(1+confidence)/2} x the standard deviation of the bootstrap
  // estimates, a half-width under a normal approximation [-].
  double conf = std::numeric_limits<double>::quiet_NaN();
  // Percentile bootstrap interval: the (1 -/+ confidence)/2 quantiles of the bootstrap
  // estimates (type 7). Not centred on value when the estimator is skewed or biased.
  Interval interval{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
};

struct SobolIndices {
  SobolEstimator estimator = SobolEstimator::kSaltelliJansen;
  std::vector<SobolIndex> first_order;  // per group
  std::vector<SobolIndex> total_order;  // per group
  double mean = 0.0;                    // of the output over the used A and B rows [output unit]
  double variance = 0.0;                // V above: (1/2N) sum (f - mean)^2 over the used A and B rows [output unit^2]
  std::int64_t rows = 0;                // rows used, N
  std::int64_t rows_excluded = 0;       // rows with a non-finite output in a, b or any ab[g]
  // Pearson correlation of f(A) and f(B) over the used rows: the design needs A and B
  // independent, and |r| beyond about 3 / sqrt(N) says they are not (a Sobol' base in more
  // dimensions than it has points repeats coordinates), which biases every index. NaN when
  // either does not vary.
  double ab_correlation = std::numeric_limits<double>::quiet_NaN();
};

// Throws std::invalid_argument, with a message naming the quantity and its allowed range,
// for: no groups, a, b or some ab[g] of a different length, fewer than 2 usable rows, zero
// output variance over A and B (or, for kJanon and kMartinez, within a pair a correlation
// needs), and options out of range.
SobolIndices EstimateSobolIndices(const PickFreezeOutputs& outputs, const SobolOptions& options = {});

// Rows that would shrink the widest total-order conf of `indices` to target_conf, from
// conf ~ 1/sqrt(N): ceil(N (conf_max / target_conf)^2), at least 2, saturating at
// INT64_MAX. Total-order indices decide which tolerances can be loosened, hence their
// precision. Throws std::invalid_argument for target_conf <= 0 or not finite, and for
// indices without bootstrap error bars.
std::int64_t RowsForSobolPrecision(const SobolIndices& indices, double target_conf);

// ---------------------------------------------------------------------------------------
// Screening of a plain Monte Carlo or QMC sample.

struct ScreeningOptions {
  // Classes of the given-data estimator: 0 = automatic, floor(sqrt(n)) clamped to [2, 50];
  // otherwise >= 2 and fewer than the usable samples.
  int classes = 0;
  // Whether the samples are independent draws (Monte Carlo). The given-data estimate's bias
  // correction assumes they are: the class means then carry iid noise. In a stratified
  // design (Sobol' net, Latin hypercube) every class of one input is balanced in all the
  // others, its means carry almost none, and the correction would push an unused input to
  // about -(M - 1)/(n - 1): false leaves the estimate uncorrected.
  bool independent_samples = true;
  // Bootstrap resamples of the samples for the first-order error bars: 0 or >= 2.
  int bootstrap_resamples = 200;
  // Two-sided level of conf and interval, in (0, 1) [-].
  double confidence = 0.95;
  std::uint64_t bootstrap_seed = 1;
  // Worker threads of the sorting, the two regressions and the given-data estimate with its
  // bootstrap: 0 = one per core (std::thread::hardware_concurrency), else >= 1. The results
  // do not depend on it: each number is computed by one thread, in one order.
  int threads = 0;
};

struct InputScreening {
  // Standardised regression coefficients beta_k s_k / s_y of one least-squares fit of y on
  // all inputs with an intercept (src), and of the same fit on ranks (srrc) [-]. For
  // independent inputs and a linear (monotone) model, src^2 (srrc^2) is the input's share of
  // the variance (of the rank variance). An input of zero spread gets 0; collinear inputs
  // share their effect (minimum-norm solution). NaN when there are fewer than d + 2 samples.
  double src = std::numeric_limits<double>::quiet_NaN();
  double srrc = std::numeric_limits<double>::quiet_NaN();
  // Given-data first-order index: the samples sorted by this input are cut into M classes
  // of equal count, and Var(E[Y | X_k]) is the variance of the class means; bias-corrected
  // for the noise of the class means, with bootstrap error bars. Unlike src it sees
  // non-monotone effects (y = x^2 on a symmetric x has src ~ 0 but a first order near 1).
  SobolIndex first_order;
};

struct Screening {
  std::vector<InputScreening> inputs;
  // Coefficients of determination of the value and rank regressions [-]. The SRC^2 (SRRC^2)
  // sum to them for independent inputs; the coefficients mean something only when r2
  // (rank_r2) is near 1. rank_r2 > r2 hints at a monotone nonlinear model; both low at a
  // non-monotone one or at interactions (then read first_order). NaN as src.
  double r2 = std::numeric_limits<double>::quiet_NaN();
  double rank_r2 = std::numeric_limits<double>::quiet_NaN();
  int classes = 0;                    // M used by the given-data estimator
  std::int64_t samples = 0;           // samples used
  std::int64_t samples_excluded = 0;  // samples with a non-finite output
};

// x: row-major n x d input values (sample i is x[i d .. i d + d - 1]), y: the n outputs.
// Samples with a non-finite y are excluded. Throws std::invalid_argument for d < 1, x of a
// size other than n d, a non-finite input of a used sample, fewer used samples than
// max(3, classes + 1), more than 2^24 of them, zero output variance, and options out of
// range.
//
// Cost: the given-data estimate walks each input's sorted order once for up to 256 lanes
// (the full sample and the B resamples), adding count x y for every output at once: about
// n d (B + 1) (outputs + 2) multiply-adds, spread over `threads`. Memory, besides x: at
// most about 7 n d doubles (the inputs, their ranks, the sorted orders, and both
// regressions' standardised copies and decompositions, which run side by side) and
// 8 n (B + 1) bytes of resample counts (briefly twice): for n = 16,384, d = 157 and
// B = 200 about 170 MB, whatever the size of the file the samples came from.
//
// Against the estimator as first written (one input, one resample, one copy of a sample at
// a time) the class sums add count x y instead of y count times, and the mean and SST of a
// resample are summed in sample order instead of in each input's order: the same numbers
// to rounding (tests/analysis/sensitivity_test.cpp keeps that estimator and compares).
Screening ScreenInputs(std::span<const double> x, int d, std::span<const double> y,
                       const ScreeningOptions& options = {});

// Several outputs of the same samples: element o is ScreenInputs(x, d, ys[o], options),
// with what depends on the inputs alone (sorting, ranks, the regressions' decompositions,
// the bootstrap draws, the walk over each input's order) done once for all outputs whose
// non-finite values fall on the same samples. Throws as ScreenInputs, for the first output
// that fails.
std::vector<Screening> ScreenInputs(std::span<const double> x, int d, std::span<const std::span<const double>> ys,
                                    const ScreeningOptions& options = {});

// Ranks 1..n of `values`, ties sharing the average of their ranks ({3, 1, 3, 2} ->
// {3.5, 1, 3.5, 2}). Exposed for tests.
std::vector<double> AverageRanks(std::span<const double> values);

}  // namespace ringtol::analysis
