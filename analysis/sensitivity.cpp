#include "analysis/sensitivity.h"

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <boost/math/distributions/normal.hpp>
#include <boost/random/mersenne_twister.hpp>
#include <boost/random/uniform_int_distribution.hpp>
#include <cmath>
#include <cstddef>
#include <exception>
#include <limits>
#include <mutex>
#include <numeric>
#include <stdexcept>
#include <string>
#include <thread>
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

namespace {

// Average ranks of `values` given the positions in increasing order (a stable sort's).
std::vector<double> AverageRanksInOrder(std::span<const double> values, std::span<const std::size_t> order) {
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

std::vector<std::size_t> IncreasingOrder(std::span<const double> values) {
  std::vector<std::size_t> order(values.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return values[i] < values[j]; });
  return order;
}

}  // namespace

std::vector<double> AverageRanks(std::span<const double> values) {
  return AverageRanksInOrder(values, IncreasingOrder(values));
}

namespace {

// Centring a constant column leaves rounding noise of a few eps times its magnitude; a
// spread below 50 eps of the magnitude is that noise, not an input that varies.
constexpr double kFlatColumn = 1e-14;

// Bootstrap multiplicities are kept as float: exact integers up to 2^24, half the bytes of
// a double, and the count of a sample never exceeds the samples.
constexpr std::size_t kMaxScreeningSamples = std::size_t{1} << 24;

// Lanes (the full sample and the bootstrap resamples) per pass of the given-data kernel:
// the default 201 in one pass, so that each sample's counts are fetched once per input; the
// running class sums (8 bytes x outputs per lane) stay in the first-level cache.
constexpr std::size_t kLaneBatch = 256;

// The kernel visits samples in each input's order, at random in memory: it asks for the
// counts and outputs of the sample this many places ahead while it adds up the current one.
constexpr std::size_t kPrefetchAhead = 8;
constexpr std::size_t kCacheLine = 64;

#if defined(__x86_64__) && defined(__GNUC__)
#define RINGTOL_LANE_KERNEL __attribute__((target_clones("avx2", "default")))
#else
#define RINGTOL_LANE_KERNEL
#endif

// Calls body(item, worker) once for every item in [0, items), on `workers` threads (the
// calling one among them), each taking the next item in turn; worker < workers names the
// thread's scratch. Every caller makes an item's result a function of the item alone, so
// nothing depends on the number of threads or on which thread ran what. The first
// exception a body throws is rethrown once every thread has stopped.
template <typename Body>
void ParallelFor(std::size_t items, std::size_t workers, Body&& body) {
  if (workers <= 1 || items <= 1) {
    for (std::size_t item = 0; item < items; ++item) body(item, std::size_t{0});
    return;
  }
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  const auto work = [&](std::size_t worker) {
    try {
      for (std::size_t item; (item = next.fetch_add(1)) < items;) body(item, worker);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(failure_mutex);
      if (!failure) failure = std::current_exception();
      next = items;
    }
  };
  {
    std::vector<std::jthread> pool;
    pool.reserve(workers - 1);
    for (std::size_t worker = 1; worker < workers; ++worker) pool.emplace_back(work, worker);
    work(0);
  }
  if (failure) std::rethrow_exception(failure);
}

std::size_t Workers(int threads, std::size_t items) {
  const std::size_t wanted =
      threads > 0 ? static_cast<std::size_t>(threads) : std::max(1u, std::thread::hardware_concurrency());
  return std::max<std::size_t>(1, std::min(wanted, items));
}

struct RegressionFit {
  std::vector<double> coefficients;  // standardised
  double r2 = kNaN;
};

// Least squares of each standardised column of y on the standardised columns of x (n x d,
// column major), from one decomposition of x. Centring every column and y is the
// intercept; scaling makes the coefficients standardised. A column of zero spread becomes
// a zero column, whose coefficient is set to 0; the complete orthogonal decomposition gives
// the minimum-norm solution, which shares an effect evenly among collinear columns instead
// of failing on them.
std::vector<RegressionFit> StandardisedRegressions(const Eigen::MatrixXd& x, const Eigen::MatrixXd& y) {
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
  Eigen::MatrixXd zy = y.rowwise() - y.colwise().mean();
  for (Eigen::Index o = 0; o < zy.cols(); ++o) zy.col(o) /= std::sqrt(zy.col(o).squaredNorm() / n);
  const Eigen::MatrixXd beta = z.completeOrthogonalDecomposition().solve(zy);
  std::vector<RegressionFit> fits(static_cast<std::size_t>(y.cols()));
  for (Eigen::Index o = 0; o < zy.cols(); ++o) {
    RegressionFit& fit = fits[static_cast<std::size_t>(o)];
    fit.coefficients.resize(static_cast<std::size_t>(x.cols()));
    for (Eigen::Index k = 0; k < z.cols(); ++k) {
      fit.coefficients[static_cast<std::size_t>(k)] = constant[static_cast<std::size_t>(k)] ? 0.0 : beta(k, o);
    }
    fit.r2 = 1.0 - (zy.col(o) - z * beta.col(o)).squaredNorm() / zy.col(o).squaredNorm();
  }
  return fits;
}

// What the given-data estimate works on: the used samples' outputs and, per lane, a
// multiplicity of every sample. Lane 0 is the full sample (every count 1); the others are
// bootstrap resamples, n draws with replacement each.
struct GivenDataLanes {
  std::size_t n = 0, outputs = 0, lanes = 0;
  std::vector<double> y;       // [n][outputs]
  std::vector<float> counts;   // [n][lanes]
  std::vector<double> mean;    // [outputs][lanes]: sum over samples of count y, over n
  std::vector<double> sst;     // [outputs][lanes]: sum over samples of count (y - mean)^2
  // Per output: the lanes that are its estimates, lane 0 and then one per resample.
  std::vector<std::vector<std::size_t>> lanes_of;
};

// The lanes for `resamples` bootstrap resamples of every output, drawn as one generator
// stream: n picks per resample, as ScreenInputs has always drawn them. A resample whose
// drawn outputs do not vary (sst not > 0) leaves the estimate undefined and is drawn again
// for that output; since every output sees the same stream, a lane serves every output
// for which it is defined, and the outputs share all lanes unless one of them needs a
// redraw.
GivenDataLanes DrawLanes(std::vector<double> y, std::size_t n, std::size_t outputs, std::size_t resamples,
                         std::uint64_t seed, const std::string& who) {
  GivenDataLanes data;
  data.n = n;
  data.outputs = outputs;
  data.y = std::move(y);
  std::vector<std::vector<float>> columns;
  std::vector<std::vector<double>> means(outputs), ssts(outputs);
  std::vector<double> mean(outputs), sst(outputs);
  const auto moments = [&](const std::vector<float>& count) {
    std::fill(mean.begin(), mean.end(), 0.0);
    std::fill(sst.begin(), sst.end(), 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t o = 0; o < outputs; ++o) mean[o] += static_cast<double>(count[i]) * data.y[i * outputs + o];
    }
    for (double& m : mean) m /= static_cast<double>(n);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t o = 0; o < outputs; ++o) {
        const double deviation = data.y[i * outputs + o] - mean[o];
        sst[o] += static_cast<double>(count[i]) * deviation * deviation;
      }
    }
  };
  const auto keep = [&](std::vector<float> count) {
    columns.push_back(std::move(count));
    for (std::size_t o = 0; o < outputs; ++o) {
      means[o].push_back(mean[o]);
      ssts[o].push_back(sst[o]);
    }
  };
  std::vector<float> count(n, 1.0F);
  moments(count);
  keep(count);
  data.lanes_of.assign(outputs, std::vector<std::size_t>{0});

  boost::random::mt19937_64 engine(seed);
  boost::random::uniform_int_distribution<std::size_t> pick(0, n - 1);
  std::vector<int> misses(outputs, 0);
  const auto short_of = [&] {
    return std::any_of(data.lanes_of.begin(), data.lanes_of.end(),
                       [&](const std::vector<std::size_t>& lanes) { return lanes.size() < resamples + 1; });
  };
  while (resamples > 0 && short_of()) {
    std::fill(count.begin(), count.end(), 0.0F);
    for (std::size_t i = 0; i < n; ++i) count[pick(engine)] += 1.0F;
    moments(count);
    bool kept = false;
    for (std::size_t o = 0; o < outputs; ++o) {
      if (data.lanes_of[o].size() == resamples + 1) continue;
      if (sst[o] > 0.0) {
        data.lanes_of[o].push_back(columns.size());
        misses[o] = 0;
        kept = true;
      } else if (++misses[o] == kMaxRedraws) {
        throw std::invalid_argument(who + ": " + std::to_string(kMaxRedraws) +
                                    " bootstrap resamples in a row had a constant output; it barely varies");
      }
    }
    if (kept) keep(count);
  }

  data.lanes = columns.size();
  data.counts.resize(n * data.lanes);
  for (std::size_t l = 0; l < data.lanes; ++l) {
    for (std::size_t i = 0; i < n; ++i) data.counts[i * data.lanes + l] = columns[l][i];
  }
  data.mean.reserve(outputs * data.lanes);
  data.sst.reserve(outputs * data.lanes);
  for (std::size_t o = 0; o < outputs; ++o) {
    data.mean.insert(data.mean.end(), means[o].begin(), means[o].end());
    data.sst.insert(data.sst.end(), ssts[o].begin(), ssts[o].end());
  }
  return data;
}

struct KernelScratch {
  std::vector<double> position, next, take, rest, sum, ssb;
  std::vector<std::size_t> cls;
};

// Given-data first order of one input, for every output in lanes [first, first + width),
// into estimate[o * lanes + lane]: the samples in increasing order of the input (`order`),
// each repeated as often as the lane counts it, are cut into classes by position, position
// p (0-based, of n) in class floor(p M / n), so that class c holds positions starts[c] to
// starts[c + 1] - 1, starts[c] = ceil(c n / M): counts differ by at most one, and they do
// not depend on the lane. A sample whose copies straddle a class boundary is split there.
//
// Bias correction: the between-class sum of squares SSB = sum_m n_m (ybar_m - ybar)^2 takes
// up, besides the signal, the noise of the class means: within-class variance
// (1 - S) Var Y times M - 1 degrees of freedom. So E[SSB / SST] ~ S + k (1 - S) with
// k = (M - 1) / (n - 1) (at S = 0 the null expectation, exact for normal noise, where
// SSB / SST is Beta distributed), and S ~ (eta^2 - k) / (1 - k), Kelley's epsilon^2.
// Left uncorrected, an unused input would show k ~ 1/sqrt(n), a few percent; subtracting k
// alone would shrink a real effect by the factor 1 - k. What remains is the variation of
// E[Y | X] inside a class, which shrinks like 1/M^2 for a smooth dependence.
//
// One walk over the order serves every lane and output of the batch: per sample, the
// lanes' counts are split into what fits the current class (take) and what spills into the
// next (rest, rare: M boundaries in n samples), and the class sums of all outputs grow by
// take x y, a loop over lanes without a branch or a division. On x86-64 it is built for the baseline and
// for AVX2 (chosen at run time): the loops over lanes only add and multiply lane by lane,
// without fused multiply-adds (AVX2 alone does not enable them), so both give the same bits.
RINGTOL_LANE_KERNEL void GivenDataFirstOrders(const GivenDataLanes& data, std::span<const std::size_t> order,
                          std::span<const double> starts, std::size_t first, std::size_t width, bool correct,
                          KernelScratch& scratch, double* estimate) {
  const std::size_t outputs = data.outputs;
  const std::size_t lanes = data.lanes;
  scratch.position.assign(width, 0.0);
  scratch.next.assign(width, starts[1]);
  scratch.take.assign(width, 0.0);
  scratch.rest.assign(width, 0.0);
  scratch.sum.assign(outputs * width, 0.0);
  scratch.ssb.assign(outputs * width, 0.0);
  scratch.cls.assign(width, 0);
  double* const position = scratch.position.data();
  double* const next = scratch.next.data();
  double* const take = scratch.take.data();
  double* const rest = scratch.rest.data();
  double* const sum = scratch.sum.data();
  double* const ssb = scratch.ssb.data();
  const double* const mean = data.mean.data() + first;

  // Class cls[l] of lane l is complete: its mean's deviation enters SSB.
  const auto close_class = [&](std::size_t l) {
    const std::size_t c = scratch.cls[l];
    const double members = starts[c + 1] - starts[c];
    for (std::size_t o = 0; o < outputs; ++o) {
      const double deviation = sum[o * width + l] / members - mean[o * lanes + l];
      ssb[o * width + l] += members * deviation * deviation;
    }
  };

  for (std::size_t place = 0; place < order.size(); ++place) {
    if (place + kPrefetchAhead < order.size()) {
      const std::size_t ahead = order[place + kPrefetchAhead];
      const auto* row = reinterpret_cast<const char*>(data.counts.data() + ahead * lanes + first);
      for (std::size_t byte = 0; byte < width * sizeof(float); byte += kCacheLine) __builtin_prefetch(row + byte);
      __builtin_prefetch(data.y.data() + ahead * outputs);
    }
    const std::size_t i = order[place];
    const float* const count = data.counts.data() + i * lanes + first;
    const double* const y = data.y.data() + i * outputs;
    int spills = 0;
    for (std::size_t l = 0; l < width; ++l) {
      const double copies = count[l];
      const double room = next[l] - position[l];
      const double fits = copies < room ? copies : room;
      take[l] = fits;
      rest[l] = copies - fits;
      position[l] += copies;
      spills |= static_cast<int>(copies > room);
    }
    for (std::size_t o = 0; o < outputs; ++o) {
      const double value = y[o];
      double* const class_sum = sum + o * width;
      for (std::size_t l = 0; l < width; ++l) class_sum[l] += take[l] * value;
    }
    if (spills == 0) continue;
    for (std::size_t l = 0; l < width; ++l) {
      if (!(rest[l] > 0.0)) continue;
      double left = rest[l];
      std::size_t c = scratch.cls[l];
      while (left > 0.0) {
        close_class(l);
        scratch.cls[l] = ++c;
        const double fits = std::min(left, starts[c + 1] - starts[c]);
        for (std::size_t o = 0; o < outputs; ++o) sum[o * width + l] = fits * y[o];
        left -= fits;
      }
      next[l] = starts[c + 1];
    }
  }

  const std::size_t classes = starts.size() - 1;
  const double k = (static_cast<double>(classes) - 1.0) / (static_cast<double>(data.n) - 1.0);
  for (std::size_t l = 0; l < width; ++l) close_class(l);
  for (std::size_t o = 0; o < outputs; ++o) {
    for (std::size_t l = 0; l < width; ++l) {
      const double sst = data.sst[o * lanes + first + l];
      double value = kNaN;
      if (sst > 0.0) {
        const double eta2 = ssb[o * width + l] / sst;
        value = correct ? (eta2 - k) / (1.0 - k) : eta2;
      }
      estimate[o * lanes + first + l] = value;
    }
  }
}

// ScreenInputs of the outputs `which` of ys, whose non-finite outputs fall on the same
// samples.
void ScreenGroup(std::span<const double> x, std::size_t dims, std::span<const std::span<const double>> ys,
                 std::span<const std::size_t> which, const ScreeningOptions& options, const std::string& who,
                 std::vector<Screening>& results) {
  const std::span<const double> first_y = ys[which.front()];
  std::vector<std::size_t> used;
  used.reserve(first_y.size());
  for (std::size_t i = 0; i < first_y.size(); ++i) {
    if (!std::isfinite(first_y[i])) continue;
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
    throw std::invalid_argument(who + ": " + std::to_string(n) + " usable samples of " + std::to_string(first_y.size()) +
                                " (non-finite outputs are excluded) for " + std::to_string(classes) +
                                " classes; need at least max(3, classes + 1)");
  }
  if (n > kMaxScreeningSamples) {
    throw std::invalid_argument(who + ": " + std::to_string(n) + " usable samples; at most " +
                                std::to_string(kMaxScreeningSamples) + " can be screened");
  }

  const std::size_t outputs = which.size();
  const auto rows = static_cast<Eigen::Index>(n);
  Eigen::MatrixXd xs(rows, static_cast<Eigen::Index>(dims));
  Eigen::MatrixXd ys_used(rows, static_cast<Eigen::Index>(outputs));
  for (std::size_t r = 0; r < n; ++r) {
    for (std::size_t k = 0; k < dims; ++k)
      xs(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(k)) = x[used[r] * dims + k];
    for (std::size_t o = 0; o < outputs; ++o)
      ys_used(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(o)) = ys[which[o]][used[r]];
  }
  for (std::size_t o = 0; o < outputs; ++o) {
    const auto column = ys_used.col(static_cast<Eigen::Index>(o));
    if (!((column.array() - column.mean()).square().sum() > 0.0)) {
      throw std::invalid_argument(who + ": the output does not vary over the " + std::to_string(n) +
                                  " usable samples; its sensitivities are undefined");
    }
  }
  for (std::size_t o = 0; o < outputs; ++o) {
    Screening& result = results[which[o]];
    result.classes = classes;
    result.samples = static_cast<std::int64_t>(n);
    result.samples_excluded = static_cast<std::int64_t>(first_y.size() - n);
    result.inputs.resize(dims);
  }

  // Every input's increasing order, once: the ranks and every lane of the given-data
  // estimate walk it.
  std::vector<std::vector<std::size_t>> orders(dims);
  ParallelFor(dims, Workers(options.threads, dims), [&](std::size_t k, std::size_t) {
    orders[k] = IncreasingOrder(std::span<const double>(xs.col(static_cast<Eigen::Index>(k)).data(), n));
  });

  // One residual degree of freedom at least: with n <= d + 1 the fit is exact whatever
  // the model, and the coefficients are not identifiable. The value and the rank
  // regressions decompose their inputs once for every output, side by side.
  if (n >= dims + 2) {
    Eigen::MatrixXd xr(rows, static_cast<Eigen::Index>(dims));
    Eigen::MatrixXd yr(rows, static_cast<Eigen::Index>(outputs));
    ParallelFor(dims + outputs, Workers(options.threads, dims + outputs), [&](std::size_t item, std::size_t) {
      const bool input = item < dims;
      const auto column = static_cast<Eigen::Index>(input ? item : item - dims);
      const std::span<const double> values(input ? xs.col(column).data() : ys_used.col(column).data(), n);
      const std::vector<double> r =
          input ? AverageRanksInOrder(values, orders[item]) : AverageRanksInOrder(values, IncreasingOrder(values));
      (input ? xr.col(column) : yr.col(column)) = Eigen::Map<const Eigen::VectorXd>(r.data(), rows);
    });
    std::vector<RegressionFit> fits[2];
    ParallelFor(2, Workers(options.threads, 2), [&](std::size_t item, std::size_t) {
      fits[item] = item == 0 ? StandardisedRegressions(xs, ys_used) : StandardisedRegressions(xr, yr);
    });
    for (std::size_t o = 0; o < outputs; ++o) {
      Screening& result = results[which[o]];
      for (std::size_t k = 0; k < dims; ++k) {
        result.inputs[k].src = fits[0][o].coefficients[k];
        result.inputs[k].srrc = fits[1][o].coefficients[k];
      }
      result.r2 = fits[0][o].r2;
      result.rank_r2 = fits[1][o].r2;
    }
  }

  // Given-data first order: estimates[(k outputs + o) lanes + lane] for input k, from work
  // items of one input and one batch of lanes.
  std::vector<double> y_rows(n * outputs);
  for (std::size_t r = 0; r < n; ++r) {
    for (std::size_t o = 0; o < outputs; ++o)
      y_rows[r * outputs + o] = ys_used(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(o));
  }
  const GivenDataLanes data = DrawLanes(std::move(y_rows), n, outputs,
                                        static_cast<std::size_t>(options.bootstrap_resamples), options.bootstrap_seed, who);
  const auto m = static_cast<std::size_t>(classes);
  std::vector<double> starts(m + 1);
  for (std::size_t c = 0; c <= m; ++c) starts[c] = static_cast<double>((c * n + m - 1) / m);
  const std::size_t batches = (data.lanes + kLaneBatch - 1) / kLaneBatch;
  std::vector<double> estimates(dims * outputs * data.lanes);
  const std::size_t workers = Workers(options.threads, dims * batches);
  std::vector<KernelScratch> scratch(workers);
  ParallelFor(dims * batches, workers, [&](std::size_t item, std::size_t worker) {
    const std::size_t k = item / batches;
    const std::size_t first = (item % batches) * kLaneBatch;
    GivenDataFirstOrders(data, orders[k], starts, first, std::min(kLaneBatch, data.lanes - first),
                         options.independent_samples, scratch[worker], estimates.data() + k * outputs * data.lanes);
  });

  for (std::size_t o = 0; o < outputs; ++o) {
    Screening& result = results[which[o]];
    const std::vector<std::size_t>& lanes = data.lanes_of[o];
    for (std::size_t k = 0; k < dims; ++k) {
      const double* estimate = estimates.data() + (k * outputs + o) * data.lanes;
      result.inputs[k].first_order.value = estimate[0];
      if (lanes.size() < 2) continue;
      std::vector<double> boot(lanes.size() - 1);
      for (std::size_t b = 1; b < lanes.size(); ++b) boot[b - 1] = estimate[lanes[b]];
      SummariseBootstrap(std::move(boot), options.confidence, result.inputs[k].first_order);
    }
  }
}

}  // namespace

std::vector<Screening> ScreenInputs(std::span<const double> x, int d, std::span<const std::span<const double>> ys,
                                    const ScreeningOptions& options) {
  const std::string who = "ScreenInputs";
  if (d < 1) throw std::invalid_argument(who + ": d = " + std::to_string(d) + " inputs; allowed >= 1");
  const auto dims = static_cast<std::size_t>(d);
  for (const std::span<const double> y : ys) {
    if (x.size() != y.size() * dims) {
      throw std::invalid_argument(who + ": " + std::to_string(x.size()) + " input values for " +
                                  std::to_string(y.size()) + " outputs and d = " + std::to_string(d) +
                                  "; expected n d = " + std::to_string(y.size() * dims));
    }
  }
  if (options.classes < 0 || options.classes == 1) {
    throw std::invalid_argument(who + ": classes = " + std::to_string(options.classes) +
                                ": allowed 0 (automatic) or >= 2");
  }
  CheckBootstrapOptions(options.bootstrap_resamples, options.confidence, who.c_str());
  if (options.threads < 0) {
    throw std::invalid_argument(who + ": threads = " + std::to_string(options.threads) +
                                ": allowed 0 (one per core) or >= 1");
  }

  // Outputs that failed on the same samples use the same samples: they share the work.
  std::vector<Screening> results(ys.size());
  std::vector<bool> screened(ys.size(), false);
  const auto same_samples = [](std::span<const double> a, std::span<const double> b) {
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (std::isfinite(a[i]) != std::isfinite(b[i])) return false;
    }
    return true;
  };
  for (std::size_t o = 0; o < ys.size(); ++o) {
    if (screened[o]) continue;
    std::vector<std::size_t> which;
    for (std::size_t p = o; p < ys.size(); ++p) {
      if (!screened[p] && same_samples(ys[o], ys[p])) {
        which.push_back(p);
        screened[p] = true;
      }
    }
    ScreenGroup(x, dims, ys, which, options, who, results);
  }
  return results;
}

Screening ScreenInputs(std::span<const double> x, int d, std::span<const double> y, const ScreeningOptions& options) {
  const std::span<const double> one[] = {y};
  return ScreenInputs(x, d, one, options).front();
}

}  // namespace ringtol::analysis
