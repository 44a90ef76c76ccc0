#include "analysis/sensitivity.h"

#include <Eigen/Dense>
#include <algorithm>
#include <boost/math/distributions/normal.hpp>
#include <boost/random/mersenne_twister.hpp>
#include <boost/random/uniform_int_distribution.hpp>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace ringtol::analysis {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A bootstrap resample whose estimate is undefined (every drawn row alike, so a variance
// is zero) is drawn again. It takes a handful of rows for that to happen at all; the cap
// only stops an endless loop on data that passed the full-sample checks by a hair.
constexpr int kMaxRedraws = 1000;

// Automatic classes of the given-data estimator.
constexpr int kMinClasses = 2;
constexpr int kMaxClasses = 50;

void CheckBootstrapOptions(int resamples, double confidence, const char* who) {
  if (resamples < 0 || resamples == 1) {
    throw std::invalid_argument(std::string(who) + ": bootstrap_resamples = " + std::to_string(resamples) +
                                ": allowed 0 (no error bars) or >= 2");
  }
  if (!(confidence > 0.0 && confidence < 1.0)) {
    throw std::invalid_argument(std::string(who) + ": confidence = " + std::to_string(confidence) + ": allowed (0, 1)");
  }
}

// Hyndman & Fan type 7 (linear between order statistics), as EstimateQuantile.
double SortedQuantile(const std::vector<double>& sorted, double p) {
  const double h = (static_cast<double>(sorted.size()) - 1.0) * p;
  const auto below = static_cast<std::size_t>(std::floor(h));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  return sorted[below] + (h - static_cast<double>(below)) * (sorted[above] - sorted[below]);
}

// conf and the percentile interval of `index` from its bootstrap estimates.
void SummariseBootstrap(std::vector<double> estimates, double confidence, SobolIndex& index) {
  if (estimates.size() < 2) return;
  const double n = static_cast<double>(estimates.size());
  const double mean = std::accumulate(estimates.begin(), estimates.end(), 0.0) / n;
  double squares = 0.0;
  for (const double e : estimates) squares += (e - mean) * (e - mean);
  // Unbiased (n - 1) standard deviation and the normal quantile, as SALib's Z * std(ddof=1).
  const double z = boost::math::quantile(boost::math::normal_distribution<double>(), 0.5 * (1.0 + confidence));
  index.conf = z * std::sqrt(squares / (n - 1.0));
  std::sort(estimates.begin(), estimates.end());
  index.interval.lower = SortedQuantile(estimates, 0.5 * (1.0 - confidence));
  index.interval.upper = SortedQuantile(estimates, 0.5 * (1.0 + confidence));
}

// ---------------------------------------------------------------------------------------
// Sobol' indices.

// Centred outputs of the used rows.
struct PickFreezeColumns {
  std::vector<double> a, b;
  std::vector<std::vector<double>> ab;
};

// Pearson correlation of x and y over `rows`; NaN when either has zero spread.
double Correlation(const std::vector<double>& x, const std::vector<double>& y, std::span<const std::size_t> rows) {
  const double n = static_cast<double>(rows.size());
  double mx = 0.0, my = 0.0;
  for (const std::size_t r : rows) {
    mx += x[r];
    my += y[r];
  }
  mx /= n;
  my /= n;
  double sxy = 0.0, sxx = 0.0, syy = 0.0;
  for (const std::size_t r : rows) {
    const double dx = x[r] - mx, dy = y[r] - my;
    sxy += dx * dy;
    sxx += dx * dx;
    syy += dy * dy;
  }
  if (!(sxx > 0.0 && syy > 0.0)) return kNaN;
  return sxy / std::sqrt(sxx * syy);
}

// The estimator on the rows `rows` (a multiset for a bootstrap resample) into first[g] and
// total[g]. Returns an empty string, or why an estimate is undefined.
std::string EstimateOnRows(const PickFreezeColumns& y, std::span<const std::size_t> rows, SobolEstimator estimator,
                           std::vector<double>& first, std::vector<double>& total) {
  const double n = static_cast<double>(rows.size());
  double mean = 0.0;
  for (const std::size_t r : rows) mean += y.a[r] + y.b[r];
  mean /= 2.0 * n;
  double variance = 0.0;
  for (const std::size_t r : rows) variance += (y.a[r] - mean) * (y.a[r] - mean) + (y.b[r] - mean) * (y.b[r] - mean);
  variance /= 2.0 * n;
  if (!(variance > 0.0)) return "the output variance over the A and B rows is zero";

  for (std::size_t g = 0; g < y.ab.size(); ++g) {
    const std::vector<double>& ab = y.ab[g];
    switch (estimator) {
      case SobolEstimator::kSaltelliJansen:
      case SobolEstimator::kJanon: {
        double jansen = 0.0;
        for (const std::size_t r : rows) jansen += (y.a[r] - ab[r]) * (y.a[r] - ab[r]);
        total[g] = jansen / (2.0 * n) / variance;
        if (estimator == SobolEstimator::kSaltelliJansen) {
          double saltelli = 0.0;
          for (const std::size_t r : rows) saltelli += y.b[r] * (ab[r] - y.a[r]);
          first[g] = saltelli / n / variance;
        } else {
          // Written around the pair's own mean m: (1/N) sum (y_B - m)(y_AB - m) is algebraically
          // (1/N) sum y_B y_AB - m^2, without the cancellation.
          double m = 0.0;
          for (const std::size_t r : rows) m += y.b[r] + ab[r];
          m /= 2.0 * n;
          double cross = 0.0, squares = 0.0;
          for (const std::size_t r : rows) {
            const double db = y.b[r] - m, dab = ab[r] - m;
            cross += db * dab;
            squares += db * db + dab * dab;
          }
          if (!(squares > 0.0)) return "the outputs of B and AB_" + std::to_string(g) + " do not vary";
          first[g] = (cross / n) / (squares / (2.0 * n));
        }
        break;
      }
      case SobolEstimator::kMartinez: {
        const double rho_b = Correlation(y.b, ab, rows);
        const double rho_a = Correlation(y.a, ab, rows);
        if (std::isnan(rho_b) || std::isnan(rho_a)) {
          return "the outputs of A, B or AB_" + std::to_string(g) + " do not vary, so a correlation is undefined";
        }
        first[g] = rho_b;
        total[g] = 1.0 - rho_a;
        break;
      }
    }
  }
  return "";
}

}  // namespace

SobolIndices EstimateSobolIndices(const PickFreezeOutputs& outputs, const SobolOptions& options) {
  const std::string who = "EstimateSobolIndices";
  switch (options.estimator) {
    case SobolEstimator::kSaltelliJansen:
    case SobolEstimator::kJanon:
    case SobolEstimator::kMartinez:
      break;
    default:
      throw std::invalid_argument(who + ": unknown estimator " + std::to_string(static_cast<int>(options.estimator)));
  }
  CheckBootstrapOptions(options.bootstrap_resamples, options.confidence, who.c_str());
  const std::size_t groups = outputs.ab.size();
  if (groups == 0) throw std::invalid_argument(who + ": no groups (outputs.ab is empty)");
  const std::size_t n_all = outputs.a.size();
  if (outputs.b.size() != n_all) {
    throw std::invalid_argument(who + ": " + std::to_string(outputs.b.size()) + " outputs of B for " +
                                std::to_string(n_all) + " of A; each matrix needs one output per row");
  }
  for (std::size_t g = 0; g < groups; ++g) {
    if (outputs.ab[g].size() != n_all) {
      throw std::invalid_argument(who + ": " + std::to_string(outputs.ab[g].size()) + " outputs of AB_" +
                                  std::to_string(g) + " for " + std::to_string(n_all) +
                                  " of A; each matrix needs one output per row");
    }
  }

  // A row is usable only whole: its A, B and AB outputs enter every estimator together.
  std::vector<std::size_t> used;
  used.reserve(n_all);
  for (std::size_t j = 0; j < n_all; ++j) {
    bool finite = std::isfinite(outputs.a[j]) && std::isfinite(outputs.b[j]);
    for (std::size_t g = 0; g < groups && finite; ++g) finite = std::isfinite(outputs.ab[g][j]);
    if (finite) used.push_back(j);
  }
  const std::size_t n = used.size();
  if (n < 2) {
    throw std::invalid_argument(who + ": " + std::to_string(n) + " usable rows of " + std::to_string(n_all) +
                                " (rows with a non-finite output are excluded); at least 2 needed");
  }

  SobolIndices result;
  result.estimator = options.estimator;
  result.rows = static_cast<std::int64_t>(n);
  result.rows_excluded = static_cast<std::int64_t>(n_all - n);

  // Centre once on the mean of every used output: every matrix samples the law of Y, and
  // Saltelli's first-order sum is not invariant to a shift (a constant c adds
  // c (1/N) sum (f(AB) - f(A)) / V), so an uncentred output far from zero would drown it.
  double grand = 0.0;
  for (const std::size_t j : used) {
    grand += outputs.a[j] + outputs.b[j];
    for (std::size_t g = 0; g < groups; ++g) grand += outputs.ab[g][j];
  }
  grand /= static_cast<double>(n * (groups + 2));
  PickFreezeColumns y;
  y.a.resize(n);
  y.b.resize(n);
  y.ab.assign(groups, std::vector<double>(n));
  for (std::size_t r = 0; r < n; ++r) {
    y.a[r] = outputs.a[used[r]] - grand;
    y.b[r] = outputs.b[used[r]] - grand;
    for (std::size_t g = 0; g < groups; ++g) y.ab[g][r] = outputs.ab[g][used[r]] - grand;
  }
  double mean = 0.0;
  for (std::size_t r = 0; r < n; ++r) mean += y.a[r] + y.b[r];
  mean /= 2.0 * static_cast<double>(n);
  double variance = 0.0;
  for (std::size_t r = 0; r < n; ++r) variance += (y.a[r] - mean) * (y.a[r] - mean) + (y.b[r] - mean) * (y.b[r] - mean);
  result.mean = mean + grand;
  result.variance = variance / (2.0 * static_cast<double>(n));

  std::vector<std::size_t> rows(n);
  std::iota(rows.begin(), rows.end(), std::size_t{0});
  result.ab_correlation = Correlation(y.a, y.b, rows);
  std::vector<double> first(groups), total(groups);
  const std::string undefined = EstimateOnRows(y, rows, options.estimator, first, total);
  if (!undefined.empty()) {
    throw std::invalid_argument(who + " (" + std::string(SobolEstimatorName(options.estimator)) + "): " + undefined + " over " +
                                std::to_string(n) + " rows; the indices are undefined");
  }
  result.first_order.resize(groups);
  result.total_order.resize(groups);
  for (std::size_t g = 0; g < groups; ++g) {
    result.first_order[g].value = first[g];
    result.total_order[g].value = total[g];
  }
  if (options.bootstrap_resamples == 0) return result;

  const auto resamples = static_cast<std::size_t>(options.bootstrap_resamples);
  std::vector<std::vector<double>> first_boot(groups, std::vector<double>(resamples));
  std::vector<std::vector<double>> total_boot(groups, std::vector<double>(resamples));
  boost::random::mt19937_64 engine(options.bootstrap_seed);
  boost::random::uniform_int_distribution<std::size_t> pick(0, n - 1);
  for (std::size_t k = 0; k < resamples; ++k) {
    for (int attempt = 0;; ++attempt) {
      if (attempt == kMaxRedraws) {
        throw std::invalid_argument(who + ": " + std::to_string(kMaxRedraws) +
                                    " bootstrap resamples in a row had undefined indices; the outputs barely vary");
      }
      for (std::size_t& r : rows) r = pick(engine);
      if (EstimateOnRows(y, rows, options.estimator, first, total).empty()) break;
    }
    for (std::size_t g = 0; g < groups; ++g) {
      first_boot[g][k] = first[g];
      total_boot[g][k] = total[g];
    }
  }
  for (std::size_t g = 0; g < groups; ++g) {
    SummariseBootstrap(std::move(first_boot[g]), options.confidence, result.first_order[g]);
    SummariseBootstrap(std::move(total_boot[g]), options.confidence, result.total_order[g]);
  }
  return result;
}

std::int64_t RowsForSobolPrecision(const SobolIndices& indices, double target_conf) {
  if (!(target_conf > 0.0 && std::isfinite(target_conf))) {
    throw std::invalid_argument("RowsForSobolPrecision: target_conf = " + std::to_string(target_conf) +
                                ": allowed > 0 and finite");
  }
  if (indices.total_order.empty()) throw std::invalid_argument("RowsForSobolPrecision: no total-order indices");
  double widest = 0.0;
  for (const SobolIndex& index : indices.total_order) {
    if (!std::isfinite(index.conf)) {
      throw std::invalid_argument(
          "RowsForSobolPrecision: the indices have no bootstrap conf; estimate them with bootstrap_resamples >= 2");
    }
    widest = std::max(widest, index.conf);
  }
  const double ratio = widest / target_conf;
  const double rows = std::ceil(static_cast<double>(indices.rows) * ratio * ratio);
  // 2^63 is exactly representable; anything at or above it does not fit.
  if (!(rows < 0x1p63)) return std::numeric_limits<std::int64_t>::max();
  return std::max<std::int64_t>(2, static_cast<std::int64_t>(rows));
}

// ---------------------------------------------------------------------------------------
// Screening.

std::vector<double> AverageRanks(std::span<const double> values) {
  std::vector<std::size_t> order(values.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return values[i] < values[j]; });
  std::vector<double> ranks(values.size());
  for (std::size_t start = 0; start < order.size();) {
    std::size_t end = start + 1;
    while (end < order.size() && values[order[end]] == values[order[start]]) ++end;
    // Positions start..end-1 hold ranks start+1..end; each gets their mean.
    const double rank = 0.5 * static_cast<double>(start + 1 + end);
    for (std::size_t p = start; p < end; ++p) ranks[order[p]] = rank;
    start = end;
  }
  return ranks;
}

namespace {

// Centring a constant column leaves rounding noise of a few eps times its magnitude; a
// spread below 50 eps of the magnitude is that noise, not an input that varies.
constexpr double kFlatColumn = 1e-14;

struct RegressionFit {
  std::vector<double> coefficients;  // standardised
  double r2 = kNaN;
};

// Least squares of the standardised y on the standardised columns of x (n x d, column
// major). Centring every column and y is the intercept; scaling makes the coefficients
// standardised. A column of zero spread becomes a zero column, whose coefficient is set to
// 0; the complete orthogonal decomposition gives the minimum-norm solution, which shares an
// effect evenly among collinear columns instead of failing on them.
RegressionFit StandardisedRegression(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) {
  const auto n = static_cast<double>(x.rows());
  Eigen::MatrixXd z = x.rowwise() - x.colwise().mean();
  std::vector<bool> constant(static_cast<std::size_t>(x.cols()));
  for (Eigen::Index k = 0; k < z.cols(); ++k) {
    const double spread = std::sqrt(z.col(k).squaredNorm() / n);
    const bool flat = !(spread > 0.0) || spread <= kFlatColumn * x.col(k).cwiseAbs().maxCoeff();
    constant[static_cast<std::size_t>(k)] = flat;
    if (flat) {
      z.col(k).setZero();
    } else {
      z.col(k) /= spread;
    }
  }
  Eigen::VectorXd zy = y.array() - y.mean();
  zy /= std::sqrt(zy.squaredNorm() / n);
  const Eigen::VectorXd beta = z.completeOrthogonalDecomposition().solve(zy);
  RegressionFit fit;
  fit.coefficients.resize(static_cast<std::size_t>(x.cols()));
  for (Eigen::Index k = 0; k < z.cols(); ++k) {
    fit.coefficients[static_cast<std::size_t>(k)] = constant[static_cast<std::size_t>(k)] ? 0.0 : beta(k);
  }
  fit.r2 = 1.0 - (zy - z * beta).squaredNorm() / zy.squaredNorm();
  return fit;
}

// Given-data first order of one input from the samples in increasing order of that input,
// each repeated `count` times (1 for the full sample, the bootstrap multiplicity otherwise).
// Class of sorted position p (0-based, of total n): floor(p M / n), so counts differ by at
// most one.
//
// Bias correction: the between-class sum of squares SSB = sum_m n_m (ybar_m - ybar)^2 takes
// up, besides the signal, the noise of the class means: within-class variance
// (1 - S) Var Y times M - 1 degrees of freedom. So E[SSB / SST] ~ S + k (1 - S) with
// k = (M - 1) / (n - 1) (at S = 0 the null expectation, exact for normal noise, where
// SSB / SST is Beta distributed), and S ~ (eta^2 - k) / (1 - k), Kelley's epsilon^2.
// Left uncorrected, an unused input would show k ~ 1/sqrt(n), a few percent; subtracting k
// alone would shrink a real effect by the factor 1 - k. What remains is the variation of
// E[Y | X] inside a class, which shrinks like 1/M^2 for a smooth dependence.
double GivenDataFirstOrder(std::span<const std::size_t> order, std::span<const std::size_t> count,
                           std::span<const double> y, int classes, bool correct, std::vector<double>& class_sum,
                           std::vector<double>& class_count) {
  std::fill(class_sum.begin(), class_sum.end(), 0.0);
  std::fill(class_count.begin(), class_count.end(), 0.0);
  std::size_t n = 0;
  for (const std::size_t i : order) n += count[i];
  const auto m = static_cast<std::size_t>(classes);
  double total = 0.0;
  std::size_t p = 0;
  for (const std::size_t i : order) {
    for (std::size_t c = 0; c < count[i]; ++c, ++p) {
      const std::size_t cls = p * m / n;
      class_sum[cls] += y[i];
      class_count[cls] += 1.0;
    }
    total += static_cast<double>(count[i]) * y[i];
  }
  const double nd = static_cast<double>(n);
  const double mean = total / nd;
  double sst = 0.0;
  for (const std::size_t i : order) sst += static_cast<double>(count[i]) * (y[i] - mean) * (y[i] - mean);
  if (!(sst > 0.0)) return kNaN;
  double ssb = 0.0;
  for (std::size_t c = 0; c < m; ++c) {
    if (class_count[c] > 0.0) {
      const double d = class_sum[c] / class_count[c] - mean;
      ssb += class_count[c] * d * d;
    }
  }
  if (!correct) return ssb / sst;
  const double k = (static_cast<double>(classes) - 1.0) / (nd - 1.0);
  return (ssb / sst - k) / (1.0 - k);
}

}  // namespace

Screening ScreenInputs(std::span<const double> x, int d, std::span<const double> y, const ScreeningOptions& options) {
  const std::string who = "ScreenInputs";
  if (d < 1) throw std::invalid_argument(who + ": d = " + std::to_string(d) + " inputs; allowed >= 1");
  const auto dims = static_cast<std::size_t>(d);
  if (x.size() != y.size() * dims) {
    throw std::invalid_argument(who + ": " + std::to_string(x.size()) + " input values for " +
                                std::to_string(y.size()) + " outputs and d = " + std::to_string(d) +
                                "; expected n d = " + std::to_string(y.size() * dims));
  }
  if (options.classes < 0 || options.classes == 1) {
    throw std::invalid_argument(who + ": classes = " + std::to_string(options.classes) +
                                ": allowed 0 (automatic) or >= 2");
  }
  CheckBootstrapOptions(options.bootstrap_resamples, options.confidence, who.c_str());

  std::vector<std::size_t> used;
  used.reserve(y.size());
  for (std::size_t i = 0; i < y.size(); ++i) {
    if (!std::isfinite(y[i])) continue;
    for (std::size_t k = 0; k < dims; ++k) {
      if (!std::isfinite(x[i * dims + k])) {
        throw std::invalid_argument(who + ": input " + std::to_string(k) + " of sample " + std::to_string(i) +
                                    " is not finite");
      }
    }
    used.push_back(i);
  }
  const std::size_t n = used.size();
  const int classes = options.classes > 0 ? options.classes
                                          : std::clamp(static_cast<int>(std::floor(std::sqrt(static_cast<double>(n)))),
                                                       kMinClasses, kMaxClasses);
  if (n < 3 || n <= static_cast<std::size_t>(classes)) {
    throw std::invalid_argument(who + ": " + std::to_string(n) + " usable samples of " + std::to_string(y.size()) +
                                " (non-finite outputs are excluded) for " + std::to_string(classes) +
                                " classes; need at least max(3, classes + 1)");
  }

  Screening result;
  result.classes = classes;
  result.samples = static_cast<std::int64_t>(n);
  result.samples_excluded = static_cast<std::int64_t>(y.size() - n);
  result.inputs.resize(dims);

  const auto rows = static_cast<Eigen::Index>(n);
  Eigen::MatrixXd xs(rows, d);
  Eigen::VectorXd ys(rows);
  for (std::size_t r = 0; r < n; ++r) {
    ys(static_cast<Eigen::Index>(r)) = y[used[r]];
    for (std::size_t k = 0; k < dims; ++k)
      xs(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(k)) = x[used[r] * dims + k];
  }
  const double y_mean = ys.mean();
  if (!((ys.array() - y_mean).square().sum() > 0.0)) {
    throw std::invalid_argument(who + ": the output does not vary over the " + std::to_string(n) +
                                " usable samples; its sensitivities are undefined");
  }

  // One residual degree of freedom at least: with n <= d + 1 the fit is exact whatever
  // the model, and the coefficients are not identifiable.
  if (n >= dims + 2) {
    const RegressionFit values = StandardisedRegression(xs, ys);
    Eigen::MatrixXd xr(rows, d);
    for (Eigen::Index k = 0; k < xs.cols(); ++k) {
      const std::vector<double> r = AverageRanks(std::span<const double>(xs.col(k).data(), n));
      xr.col(k) = Eigen::Map<const Eigen::VectorXd>(r.data(), rows);
    }
    const std::vector<double> y_ranks = AverageRanks(std::span<const double>(ys.data(), n));
    const RegressionFit ranks = StandardisedRegression(xr, Eigen::Map<const Eigen::VectorXd>(y_ranks.data(), rows));
    for (std::size_t k = 0; k < dims; ++k) {
      result.inputs[k].src = values.coefficients[k];
      result.inputs[k].srrc = ranks.coefficients[k];
    }
    result.r2 = values.r2;
    result.rank_r2 = ranks.r2;
  }

  // Given-data first order: each input's sorted order once; a bootstrap resample is then a
  // multiplicity per sample, walked in that order (no re-sorting).
  const std::span<const double> yv(ys.data(), n);
  std::vector<std::vector<std::size_t>> orders(dims, std::vector<std::size_t>(n));
  for (std::size_t k = 0; k < dims; ++k) {
    std::iota(orders[k].begin(), orders[k].end(), std::size_t{0});
    const double* column = xs.col(static_cast<Eigen::Index>(k)).data();
    std::stable_sort(orders[k].begin(), orders[k].end(),
                     [&](std::size_t i, std::size_t j) { return column[i] < column[j]; });
  }
  std::vector<double> class_sum(static_cast<std::size_t>(classes)), class_count(static_cast<std::size_t>(classes));
  std::vector<std::size_t> count(n, 1);
  for (std::size_t k = 0; k < dims; ++k) {
    result.inputs[k].first_order.value =
        GivenDataFirstOrder(orders[k], count, yv, classes, options.independent_samples, class_sum, class_count);
  }
  if (options.bootstrap_resamples == 0) return result;

  const auto resamples = static_cast<std::size_t>(options.bootstrap_resamples);
  std::vector<std::vector<double>> boot(dims, std::vector<double>(resamples));
  boost::random::mt19937_64 engine(options.bootstrap_seed);
  boost::random::uniform_int_distribution<std::size_t> pick(0, n - 1);
  std::vector<double> estimates(dims);
  for (std::size_t b = 0; b < resamples; ++b) {
    for (int attempt = 0;; ++attempt) {
      if (attempt == kMaxRedraws) {
        throw std::invalid_argument(who + ": " + std::to_string(kMaxRedraws) +
                                    " bootstrap resamples in a row had a constant output; it barely varies");
      }
      std::fill(count.begin(), count.end(), std::size_t{0});
      for (std::size_t i = 0; i < n; ++i) ++count[pick(engine)];
      bool defined = true;
      for (std::size_t k = 0; k < dims && defined; ++k) {
        estimates[k] =
            GivenDataFirstOrder(orders[k], count, yv, classes, options.independent_samples, class_sum, class_count);
        defined = !std::isnan(estimates[k]);
      }
      if (defined) break;
    }
    for (std::size_t k = 0; k < dims; ++k) boot[k][b] = estimates[k];
  }
  for (std::size_t k = 0; k < dims; ++k) {
    SummariseBootstrap(std::move(boot[k]), options.confidence, result.inputs[k].first_order);
  }
  return result;
}

}  // namespace ringtol::analysis
