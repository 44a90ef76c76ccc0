#include "jobs/report/campaign_report.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <set>
#include <span>
#include <utility>

#include <fmt/format.h>

#include "jobs/campaign/campaign.h"
#include "jobs/report/campaign_summary.h"
#include "jobs/report/report_text.h"
#include "jobs/campaign/sample_record.h"
#include "jobs/report/svg_chart.h"
#include "solvers/quasistatic.h"
#include "solvers/simulation.h"
#include "engine/units.h"

namespace ringtol::jobs {
namespace {

// The output whose largest value picks the sample whose error motion is drawn.
const std::string_view kErrorMotionTotal = ErrorMotionColumn(ErrorMotionValue::kTotal);
// Drawn values are read 65,536 samples at a time: 8 bytes x inputs each.
constexpr std::int64_t kValuesBlock = std::int64_t{1} << 16;
constexpr std::size_t kFailedListed = 20;
constexpr double kSobolTargetConf = 0.05;  // "rows needed" aims the widest ST half-width here

std::optional<double> SpecOf(const CampaignIdentity& identity, std::string_view output) {
  for (const SpecLimit& limit : identity.spec) {
    if (limit.output == output) return limit.upper;
  }
  return std::nullopt;
}

// The category of one input at an aggregation level: what a designer sets one tolerance
// class for (source), or the harmonic order it belongs to.
std::string Category(const sampling::SampledInput& input, std::string_view level) {
  if (level == "source") return std::string(sampling::ErrorSourceName(input.source));
  if (input.order > 0) return fmt::format("order {}", input.order);
  if (input.source == sampling::ErrorSource::kRollerShape) return "roller size";
  return std::string(sampling::ErrorSourceName(input.source));
}

// What the entries of a group have in common.
void Describe(SensitivityEntry& entry, const std::vector<sampling::SampledInput>& inputs,
              std::span<const int> members) {
  std::set<std::string> sources;
  std::set<int> orders;
  for (const int k : members) {
    sources.emplace(sampling::ErrorSourceName(inputs[static_cast<std::size_t>(k)].source));
    orders.insert(inputs[static_cast<std::size_t>(k)].order);
  }
  entry.source = sources.size() == 1 ? *sources.begin() : "";
  entry.order = orders.size() == 1 ? *orders.begin() : 0;
}

void SortLargestFirst(std::vector<SensitivityEntry>& entries) {
  std::stable_sort(entries.begin(), entries.end(),
                   [](const SensitivityEntry& a, const SensitivityEntry& b) { return a.ranking > b.ranking; });
}

// Sums of the entries of `finest` (each inside one category) per category of `level`. The
// sum's half-width adds the parts' in quadrature, as if their bootstrap errors were
// independent; they are not quite (one bootstrap), so it is a guide, not an interval.
std::optional<SensitivityLevel> Aggregate(const std::vector<SensitivityEntry>& finest,
                                          const std::vector<std::vector<int>>& members,
                                          const std::vector<sampling::SampledInput>& inputs, std::string_view level) {
  std::vector<std::string> order_of_categories;
  std::map<std::string, std::vector<std::size_t>> parts;
  for (std::size_t g = 0; g < finest.size(); ++g) {
    std::set<std::string> categories;
    for (const int k : members[g]) categories.insert(Category(inputs[static_cast<std::size_t>(k)], level));
    if (categories.size() != 1) return std::nullopt;  // a design group spans categories: no sum says anything
    const std::string& category = *categories.begin();
    if (!parts.contains(category)) order_of_categories.push_back(category);
    parts[category].push_back(g);
  }
  SensitivityLevel out;
  out.level = std::string(level);
  out.aggregation = Aggregation::kExact;
  const bool sobol = finest.front().total_order.has_value();
  for (const std::string& category : order_of_categories) {
    const std::vector<std::size_t>& part = parts[category];
    std::vector<int> all_members;
    for (const std::size_t g : part) all_members.insert(all_members.end(), members[g].begin(), members[g].end());
    SensitivityEntry sum;
    if (part.size() == 1) {
      sum = finest[part.front()];  // the design froze exactly this category
    } else {
      out.aggregation = Aggregation::kBounds;
      // Sums of intervals are not intervals of the sum: the estimate and the quadrature
      // half-width are kept.
      std::vector<analysis::SobolIndex> first, total;
      for (const std::size_t g : part) {
        const SensitivityEntry& e = finest[g];
        first.push_back(e.first_order);
        if (sobol) total.push_back(*e.total_order);
        sum.src += e.src * e.src;
        sum.srrc += e.srrc * e.srrc;
      }
      sum.first_order = SumOfIndices(first, false);
      if (sobol) sum.total_order = SumOfIndices(total, true);
    }
    if (!sobol) {
      // Given-data estimates carry a bias of order (M - 1)/(n - 1) each (its sign depends on
      // how stratified the design is); summed over a hundred inputs it swamps the signal.
      // A screened group is measured by its regression shares alone.
      sum.first_order = analysis::SobolIndex{};
      if (part.size() == 1) {
        sum.src *= sum.src;
        sum.srrc *= sum.srrc;
      }
    }
    sum.name = category;
    Describe(sum, inputs, all_members);
    if (level == "source") sum.order = 0;
    sum.ranking = sobol ? sum.total_order->value : sum.src;
    out.entries.push_back(std::move(sum));
  }
  if (out.entries.size() < 2) return std::nullopt;  // one category holds everything: its share is 1
  SortLargestFirst(out.entries);
  return out;
}

void AddAggregates(OutputSensitivity& out, const std::vector<SensitivityEntry>& finest,
                   const std::vector<std::vector<int>>& members, const std::vector<sampling::SampledInput>& inputs) {
  for (const char* level : {"source", "order"}) {
    if (std::optional<SensitivityLevel> aggregated = Aggregate(finest, members, inputs, level)) {
      out.levels.push_back(std::move(*aggregated));
    }
  }
}

// `y` and `status` cover the first whole rows of the campaign's `samples`; the rows beyond
// are pending.
OutputSensitivity SobolSensitivity(const std::string& output, const std::vector<double>& y,
                                   const std::vector<SampleStatus>& status, std::int64_t samples,
                                   const sampling::Design& design,
                                   const sampling::InputGroups& groups,
                                   const std::vector<sampling::SampledInput>& inputs, const ReportOptions& options) {
  const int per_row = design.samples_per_row();
  const std::int64_t rows = static_cast<std::int64_t>(y.size()) / per_row;
  const std::size_t group_count = groups.names.size();
  analysis::PickFreezeOutputs pick;
  pick.ab.resize(group_count);
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::int64_t pending_rows = samples / per_row - rows;
  for (std::int64_t row = 0; row < rows; ++row) {
    const auto at = [&](int matrix) {
      const auto i = static_cast<std::size_t>(row * per_row + matrix);
      return status[i] == SampleStatus::kOk ? y[i] : kNaN;
    };
    bool pending = false;
    for (int m = 0; m < per_row; ++m) {
      pending = pending || status[static_cast<std::size_t>(row * per_row + m)] == SampleStatus::kPending;
    }
    if (pending) {
      ++pending_rows;
      continue;
    }
    pick.a.push_back(at(0));
    pick.b.push_back(at(1));
    for (std::size_t g = 0; g < group_count; ++g) pick.ab[g].push_back(at(2 + static_cast<int>(g)));
  }
  OutputSensitivity out;
  out.output = output;
  out.method = "sobol";
  out.estimator = analysis::SobolEstimatorName(options.estimator);
  analysis::SobolOptions sobol;
  sobol.estimator = options.estimator;
  sobol.bootstrap_resamples = options.bootstrap_resamples;
  sobol.confidence = options.confidence;
  const analysis::SobolIndices indices = analysis::EstimateSobolIndices(pick, sobol);
  out.rows = indices.rows;
  out.rows_excluded = indices.rows_excluded;
  out.rows_pending = pending_rows;
  out.variance = indices.variance;
  if (std::isfinite(indices.ab_correlation)) out.ab_correlation = indices.ab_correlation;
  if (options.bootstrap_resamples > 0)
    out.rows_for_precision = analysis::RowsForSobolPrecision(indices, kSobolTargetConf);
  std::vector<SensitivityEntry> finest(group_count);
  for (std::size_t g = 0; g < group_count; ++g) {
    finest[g].name = groups.names[g];
    finest[g].first_order = indices.first_order[g];
    finest[g].total_order = indices.total_order[g];
    finest[g].ranking = indices.total_order[g].value;
    Describe(finest[g], inputs, groups.coordinates[g]);
  }
  SensitivityLevel design_level{"design", Aggregation::kExact, finest};
  SortLargestFirst(design_level.entries);
  out.levels.push_back(std::move(design_level));
  AddAggregates(out, finest, groups.coordinates, inputs);
  return out;
}

}  // namespace

std::vector<OutputSensitivity> ScreenOutputs(std::span<const std::string> outputs,
                                             std::span<const std::span<const double>> ys_used,
                                             std::span<const double> x_used, int d,
                                             const std::vector<sampling::SampledInput>& inputs,
                                             const ReportOptions& options) {
  analysis::ScreeningOptions screening;
  screening.bootstrap_resamples = std::max(0, options.bootstrap_resamples / 5);
  screening.confidence = options.confidence;
  const std::vector<analysis::Screening> results = analysis::ScreenInputs(x_used, d, ys_used, screening);
  std::vector<OutputSensitivity> screened;
  for (std::size_t o = 0; o < results.size(); ++o) {
    const analysis::Screening& result = results[o];
    OutputSensitivity& out = screened.emplace_back();
    out.output = outputs[o];
    out.method = "screening";
    out.estimator = "SRC, SRRC and a given-data first-order estimate";
    out.rows = result.samples;
    out.rows_excluded = result.samples_excluded;
    if (std::isfinite(result.r2)) out.r2 = result.r2;
    if (std::isfinite(result.rank_r2)) out.rank_r2 = result.rank_r2;
    std::vector<SensitivityEntry> finest(static_cast<std::size_t>(d));
    std::vector<std::vector<int>> members(static_cast<std::size_t>(d));
    for (std::size_t k = 0; k < finest.size(); ++k) {
      finest[k].name = inputs[k].name;
      finest[k].first_order = result.inputs[k].first_order;
      finest[k].src = std::isfinite(result.inputs[k].src) ? result.inputs[k].src : 0.0;
      finest[k].srrc = std::isfinite(result.inputs[k].srrc) ? result.inputs[k].srrc : 0.0;
      finest[k].ranking = finest[k].first_order.value;
      members[k] = {static_cast<int>(k)};
      Describe(finest[k], inputs, members[k]);
    }
    SensitivityLevel input_level{"input", Aggregation::kExact, finest};
    SortLargestFirst(input_level.entries);
    out.levels.push_back(std::move(input_level));
    AddAggregates(out, finest, members, inputs);
  }
  return screened;
}

OutputSensitivity ScreenOutput(const std::string& output, std::span<const double> y_used,
                               std::span<const double> x_used, int d,
                               const std::vector<sampling::SampledInput>& inputs, const ReportOptions& options) {
  const std::string names[] = {output};
  const std::span<const double> ys[] = {y_used};
  return std::move(ScreenOutputs(names, ys, x_used, d, inputs, options).front());
}

namespace {

// The kept points of a curve, in place.
void KeepPoints(std::vector<double>& values, const std::vector<std::size_t>& kept) {
  std::vector<double> picked;
  picked.reserve(kept.size());
  for (const std::size_t i : kept) picked.push_back(values[i]);
  values = std::move(picked);
}

// The orbit of one sample as the campaign's solver computes it now, drawn only when it
// reproduces the stored D_trajectory.
ReplayedTrajectory Replay(const Campaign& campaign, const CampaignReader& reader, std::string label, std::string by,
                          std::int64_t index) {
  const SampleRecord stored = reader.ReadSample(index);
  ReplayedTrajectory out;
  out.label = std::move(label);
  out.by = std::move(by);
  out.stored_by = stored.outputs[OutputIndex(out.by)];
  out.index = index;
  out.stored_d_trajectory_mm = stored.outputs[OutputIndex("d_trajectory_mm")];
  out.tolerance_mm = ReplayTolerance(campaign.plan().solver) * units::kMillimetresPerMetre;
  solvers::SimulationResult result;
  try {
    const sampling::SampledAssembly assembly = campaign.sampling().sampler.Realise(index, stored.u);
    const std::unique_ptr<solvers::Solver> solver = campaign.MakeSolver();
    // The pictures draw the path and the signal at every angle: replay on the dense grid,
    // whose D_trajectory and status the sparse angle modes reproduce.
    solvers::SimulationOptions options = campaign.simulation();
    options.angles = solvers::AngleMode::kDense;
    result = solvers::Simulate(assembly.scene, *solver, options);
  } catch (const std::exception& e) {
    out.status = SampleStatusName(SampleStatus::kException);
    out.message = e.what();
    return out;
  }
  out.status = solvers::StatusName(result.status);
  out.message = result.message;
  out.steps = result.steps;
  if (result.status != solvers::Status::kOk) return out;
  out.d_trajectory_mm = result.d_trajectory * units::kMillimetresPerMetre;
  out.reproduced = std::abs(out.d_trajectory_mm - out.stored_d_trajectory_mm) <= out.tolerance_mm;
  if (!out.reproduced) return out;

  constexpr double um = units::kMicrometresPerMetre;
  const Eigen::Vector2d circle = result.enclosing_circle.centre;
  for (const Eigen::Vector2d& c : result.trajectory.centre) {
    out.x_um.push_back(c.x() * um);
    out.y_um.push_back(c.y() * um);
  }
  out.circle_x_um = circle.x() * um;
  out.circle_y_um = circle.y() * um;
  out.circle_radius_um = result.enclosing_circle.radius * um;
  out.static_x_um = result.trajectory.initial.centre.x() * um;
  out.static_y_um = result.trajectory.initial.centre.y() * um;
  const std::vector<std::size_t> path =
      svg::DecimateCurve(out.x_um, out.y_um, kDrawnPoints, std::array{out.circle_x_um, out.circle_y_um});
  KeepPoints(out.x_um, path);
  KeepPoints(out.y_um, path);

  const std::vector<double>& sensor = result.sensor;
  if (sensor.empty()) return out;
  const auto [lowest, highest] = std::minmax_element(sensor.begin(), sensor.end());
  const auto angle_of = [&](auto at) {
    return result.trajectory.psi[static_cast<std::size_t>(at - sensor.begin())] * units::kDegreesPerRadian;
  };
  out.tir_um = (*highest - *lowest) * um;
  out.max_angle_deg = angle_of(highest);
  out.min_angle_deg = angle_of(lowest);
  for (std::size_t k = 0; k < sensor.size(); ++k) {
    out.angle_deg.push_back(result.trajectory.psi[k] * units::kDegreesPerRadian);
    out.sensor_um.push_back((sensor[k] - *lowest) * um);
  }
  const std::vector<std::size_t> signal = svg::DecimateCurve(out.angle_deg, out.sensor_um, kDrawnPoints);
  KeepPoints(out.angle_deg, signal);
  KeepPoints(out.sensor_um, signal);
  return out;
}

// The sample's error motion over `revolutions`, as the campaign's solver computes it now.
ErrorMotionPlot ReplayErrorMotion(const Campaign& campaign, const CampaignReader& reader, std::int64_t index,
                                  double stored_total_mm, int revolutions) {
  const SampleRecord stored = reader.ReadSample(index);
  ErrorMotionPlot plot;
  try {
    const sampling::SampledAssembly assembly = campaign.sampling().sampler.Realise(index, stored.u);
    const std::unique_ptr<solvers::Solver> solver = campaign.MakeSolver();
    plot = PlotErrorMotion(assembly.scene, *solver, campaign.simulation(), revolutions);
  } catch (const std::exception& e) {
    plot.status = SampleStatusName(SampleStatus::kException);
    plot.message = e.what();
  }
  plot.index = index;
  plot.stored_total_mm = stored_total_mm;
  return plot;
}

}  // namespace

OutputReport DescribeOutput(std::string name, std::optional<double> upper_spec_limit, std::span<const double> ok_values,
                            std::int64_t failed, std::span<const double> probabilities, const ReportOptions& options) {
  OutputReport out;
  out.name = std::move(name);
  out.upper_spec_limit = upper_spec_limit;
  out.count = static_cast<std::int64_t>(ok_values.size());
  if (ok_values.empty()) return out;
  analysis::SpecLimits limits;
  limits.upper = upper_spec_limit;
  out.distribution = analysis::Describe(ok_values, probabilities, limits, options.confidence);
  out.convergence = analysis::TraceConvergence(ok_values, kReportQuantile, limits, options.confidence);
  for (const analysis::QuantileEstimate& q : out.distribution->quantiles) {
    if (q.probability != kReportQuantile || !(q.value > 0.0)) continue;
    out.samples_for_quantile =
        analysis::SamplesForQuantilePrecision(q, out.count, options.quantile_precision * std::abs(q.value));
  }
  if (const std::optional<analysis::ProportionEstimate>& within = out.distribution->within_spec) {
    out.samples_for_yield =
        analysis::SamplesForProportionPrecision(within->value, options.yield_precision, options.confidence);
    out.within_spec_counting_failures =
        analysis::EstimateProportion(within->successes, within->trials + failed, options.confidence);
  }
  return out;
}

CampaignReport BuildReport(const std::filesystem::path& results, const ReportOptions& options) {
  CampaignReport report;
  report.options = options;
  report.results = results;
  const CampaignReader reader(results);
  report.identity = reader.identity();
  report.schema_note = SchemaNote(reader);
  report.design = report.identity.design;
  report.samples = reader.samples();
  const Campaign campaign(report.identity, report.samples);
  const sampling::Design& design = campaign.sampling().design;
  const bool saltelli = design.options().kind == sampling::DesignKind::kSaltelli;
  report.rollers = static_cast<int>(campaign.sampling().sampler.base().rollers.size());
  report.populations = ViewPopulations(campaign.plan().sampling);
  const std::vector<sampling::SampledInput>& inputs = report.identity.inputs;
  const int d = static_cast<int>(inputs.size());

  // Samples are read up to the file's written end only, rounded up to whole Saltelli rows:
  // every one beyond is pending, so a campaign of 2^40 samples stopped early reads in the
  // time of what it finished.
  const std::int64_t per_row = design.samples_per_row();
  const std::int64_t read_end = std::min(report.samples, (reader.written_end() + per_row - 1) / per_row * per_row);
  const std::vector<SampleStatus> status = ReadInBlocks<SampleStatus>(
      read_end, [&](std::int64_t begin, std::int64_t count) { return reader.ReadStatus(begin, count); });
  const std::vector<std::int32_t> redraws = ReadInBlocks<std::int32_t>(
      read_end, [&](std::int64_t begin, std::int64_t count) { return reader.ReadRedraws(begin, count); });
  const std::int64_t unread = campaign.IndependentDraws(report.samples) - campaign.IndependentDraws(read_end);
  report.used = unread;
  report.pending = unread;
  std::vector<std::int64_t> used_ok;  // independent ok samples, in design order
  std::vector<bool> used(status.size());
  for (std::int64_t i = 0; i < read_end; ++i) {
    const auto s = static_cast<std::size_t>(i);
    used[s] = campaign.IndependentDraw(i);
    if (!used[s]) continue;
    ++report.used;
    if (redraws[s] > 0) ++report.redrawn;
    if (status[s] == SampleStatus::kPending) {
      ++report.pending;
      continue;
    }
    ++report.done;
    if (status[s] == SampleStatus::kOk) {
      ++report.ok;
      used_ok.push_back(i);
      continue;
    }
    ++report.failures[std::string(SampleStatusName(status[s]))];
    if (report.failed.size() < kFailedListed) {
      const SampleRecord record = reader.ReadSample(i);
      report.failed.push_back({i, std::string(SampleStatusName(status[s])), record.message});
    }
  }

  report.settled_by = CountRungs(reader, status, used);
  report.openings = CountOpenings(reader, status, used, options.confidence);

  report.primary_output = "d_trajectory_mm";
  for (const char* name : kOutputNames) {
    if (SpecOf(report.identity, name)) {
      report.primary_output = name;
      break;
    }
  }

  // Screening inputs: the drawn values of the first independent ok samples.
  std::vector<double> x_screen;
  std::vector<std::int64_t> screened;
  if (!saltelli && !used_ok.empty()) {
    const std::int64_t take =
        std::min<std::int64_t>(options.screening_samples, static_cast<std::int64_t>(used_ok.size()));
    screened.assign(used_ok.begin(), used_ok.begin() + take);
    const std::int64_t last = screened.back() + 1;
    x_screen.reserve(static_cast<std::size_t>(take) * static_cast<std::size_t>(d));
    std::size_t next = 0;
    for (std::int64_t begin = 0; begin < last && next < screened.size(); begin += kValuesBlock) {
      const std::int64_t count = std::min(kValuesBlock, last - begin);
      const std::vector<double> block = reader.ReadValues(begin, count);
      while (next < screened.size() && screened[next] < begin + count) {
        const auto row = static_cast<std::size_t>(screened[next] - begin) * static_cast<std::size_t>(d);
        x_screen.insert(x_screen.end(), block.begin() + static_cast<std::ptrdiff_t>(row),
                        block.begin() + static_cast<std::ptrdiff_t>(row) + d);
        ++next;
      }
    }
  }

  const sampling::InputGroups groups =
      saltelli ? campaign.sampling().sampler.Groups(campaign.plan().sampling.grouping) : sampling::InputGroups{};
  report.samples_per_draw = saltelli ? design.samples_per_row() / 2.0 : 1.0;
  // The outputs the orbits are picked by: each one the spec constrains, else D_trajectory;
  // their values are kept from the loop.
  std::vector<std::string> ranked_by;
  for (const char* name : kOutputNames) {
    if (SpecOf(report.identity, name)) ranked_by.emplace_back(name);
  }
  if (ranked_by.empty()) ranked_by.emplace_back("d_trajectory_mm");
  std::map<std::string, std::vector<double>, std::less<>> ranking_values;
  // The used ok samples' values of the life comparisons' columns and of the error motion, in
  // used_ok order.
  std::map<std::string, std::vector<double>, std::less<>> life_values;
  // Whether each used ok sample is within every spec limit, in used_ok order.
  std::vector<bool> within_every_limit(used_ok.size(), true);
  std::vector<std::string> screened_names;  // outputs to screen, and their values on the screened samples
  std::vector<std::vector<double>> y_screens;
  for (const char* name : kOutputNames) {
    if (!reader.HasOutput(name) || !ShowsOutput(report.identity, name)) continue;
    std::vector<double> all = ReadInBlocks<double>(
        read_end, [&](std::int64_t begin, std::int64_t count) { return reader.ReadOutput(name, begin, count); });
    std::vector<double> values;  // in used_ok order, NaN where an ok sample has none (a life output)
    values.reserve(used_ok.size());
    for (const std::int64_t i : used_ok) values.push_back(all[static_cast<std::size_t>(i)]);
    const std::optional<double> limit = SpecOf(report.identity, name);
    for (std::size_t k = 0; k < values.size() && limit; ++k) {
      if (!(values[k] <= *limit)) within_every_limit[k] = false;
    }
    std::vector<double> finite;
    std::copy_if(values.begin(), values.end(), std::back_inserter(finite), [](double v) { return std::isfinite(v); });
    OutputReport out =
        DescribeOutput(name, limit, finite, report.done - report.ok, kSummaryProbabilities, options);
    // Sensitivities need spread: an output that never varies (or no ok sample) has none.
    if (out.distribution && out.distribution->standard_deviation > 0.0) {
      if (saltelli) {
        report.sensitivities.push_back(SobolSensitivity(name, all, status, report.samples, design, groups, inputs, options));
      } else if (screened.size() >= 2 &&
                 std::all_of(screened.begin(), screened.end(),
                             [&](std::int64_t i) { return std::isfinite(all[static_cast<std::size_t>(i)]); })) {
        // The screening shares its samples' inputs across outputs: an output some of them
        // lack (a life output where a roller left the bore) is not screened.
        screened_names.emplace_back(name);
        std::vector<double>& y_screen = y_screens.emplace_back();
        y_screen.reserve(screened.size());
        for (const std::int64_t i : screened) y_screen.push_back(all[static_cast<std::size_t>(i)]);
      }
    }
    report.outputs.push_back(std::move(out));
    if (IsLifeOutput(OutputIndex(name))) report.life_missing = CountNotFinite(values);
    if (IsErrorMotionColumn(name) || IsLifeColumn(name)) life_values[name] = std::move(values);
    if (std::find(ranked_by.begin(), ranked_by.end(), name) != ranked_by.end()) ranking_values[name] = std::move(all);
  }
  report.life_gaps = LifeGaps(life_values);
  report.life_error_motion = LifeErrorMotionOf(life_values);
  if (!report.identity.spec.empty() && !used_ok.empty()) {
    const auto within = static_cast<std::int64_t>(std::count(within_every_limit.begin(), within_every_limit.end(), true));
    report.within_every_limit = analysis::EstimateProportion(within, report.ok, options.confidence);
    report.within_every_limit_counting_failures = analysis::EstimateProportion(within, report.done, options.confidence);
    if (const std::optional<DispositionRule>& rule = campaign.plan().disposition) {
      report.disposition = Dispose(*rule, within, report.done);
    }
  }
  // Every output's screening at once: they share the inputs' sorting, decompositions and
  // bootstrap draws.
  if (!screened_names.empty()) {
    const std::vector<std::span<const double>> ys(y_screens.begin(), y_screens.end());
    for (OutputSensitivity& screening : ScreenOutputs(screened_names, ys, x_screen, d, inputs, options))
      report.sensitivities.push_back(std::move(screening));
  }

  if (!options.replay) {
    report.replay_problem = "replays were not asked for";
  } else if (used_ok.empty()) {
    report.replay_problem = "no sample finished ok";
  } else {
    for (const std::string& output : ranked_by) {
      const auto found = ranking_values.find(output);
      if (found == ranking_values.end()) continue;  // a column this file lacks
      const std::vector<double>& value = found->second;
      std::vector<std::int64_t> ranked;
      std::copy_if(used_ok.begin(), used_ok.end(), std::back_inserter(ranked),
                   [&](std::int64_t i) { return std::isfinite(value[static_cast<std::size_t>(i)]); });
      if (ranked.empty()) continue;
      std::sort(ranked.begin(), ranked.end(), [&](std::int64_t a, std::int64_t b) {
        const double va = value[static_cast<std::size_t>(a)], vb = value[static_cast<std::size_t>(b)];
        return va != vb ? va < vb : a < b;
      });
      // Of an even count the lower of the two middle samples: both are as near the median.
      const std::int64_t median = ranked[(ranked.size() - 1) / 2];
      report.trajectories.push_back(Replay(campaign, reader, "worst", output, ranked.back()));
      if (median != ranked.back()) report.trajectories.push_back(Replay(campaign, reader, "median", output, median));
    }
  }

  if (const auto total = life_values.find(kErrorMotionTotal); total != life_values.end()) {
    // The largest finite value, the first sample of equal ones.
    std::optional<std::size_t> worst;
    for (std::size_t k = 0; k < total->second.size(); ++k) {
      if (std::isfinite(total->second[k]) && (!worst || total->second[k] > total->second[*worst])) worst = k;
    }
    if (!options.replay) {
      report.error_motion_problem = "replays were not asked for";
    } else if (!worst) {
      report.error_motion_problem = "no ok sample has a total error motion";
    } else {
      report.error_motion = ReplayErrorMotion(campaign, reader, used_ok[*worst], total->second[*worst],
                                              options.error_motion_revolutions);
    }
  }
  return report;
}

double ReplayTolerance(const solvers::SolverSettings& settings) {
  // The multiple of a position tolerance, and the dynamic rung's absolute position
  // tolerance per unit of relative tolerance [m] (solvers/dynamic.h: 1e-11 m at 1e-8).
  constexpr double kRuns = 4.0;
  constexpr double kDynamicPositionPerRelative = 1e-11 / 1e-8;
  switch (settings.rung) {
    case solvers::Rung::kDynamic:
      return kRuns * kDynamicPositionPerRelative * settings.relative_tolerance;
    case solvers::Rung::kQuasistatic:
    case solvers::Rung::kAuto:  // its exact-model samples are quasistatic ones; its linear ones replay exactly
      if (settings.simulation.path_tolerance > 0.0) {
        return kRuns * solvers::kAngleShareOfPathTolerance * settings.simulation.path_tolerance;
      }
      break;
    case solvers::Rung::kLinear:
      break;
  }
  return kRuns * solvers::QuasistaticOptions{}.position_tolerance;
}

std::vector<std::size_t> OrdersCarryingVariance(std::span<const double> ranking, double cumulative, double single) {
  std::vector<double> carried(ranking.size());
  double sum = 0.0;
  for (std::size_t k = 0; k < ranking.size(); ++k) {
    carried[k] = ranking[k] > 0.0 ? ranking[k] : 0.0;  // NaN and negative estimates carry nothing
    sum += carried[k];
  }
  std::vector<std::size_t> kept(ranking.size());
  std::iota(kept.begin(), kept.end(), std::size_t{0});
  if (!(sum > 0.0)) return kept;
  std::stable_sort(kept.begin(), kept.end(), [&](std::size_t a, std::size_t b) { return carried[a] > carried[b]; });
  double reached = 0.0;
  std::size_t count = 0;
  for (; count < kept.size(); ++count) {
    const double share = carried[kept[count]] / sum;
    if (reached >= cumulative && share < single) break;
    reached += share;
  }
  kept.resize(count);
  std::sort(kept.begin(), kept.end());
  return kept;
}

analysis::SobolIndex SumOfIndices(std::span<const analysis::SobolIndex> parts, bool total) {
  double value = 0.0, conf2 = 0.0;
  for (const analysis::SobolIndex& part : parts) {
    value += part.value;
    conf2 += part.conf * part.conf;
  }
  const double conf = std::sqrt(conf2);
  if (total) value = std::min(value, 1.0);
  return {value, conf, {value - conf, total ? std::min(1.0, value + conf) : value + conf}};
}

nlohmann::json JsonNumber(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr); }

nlohmann::json Json(const analysis::Interval& interval) {
  return nlohmann::json::array({JsonNumber(interval.lower), JsonNumber(interval.upper)});
}

nlohmann::json Json(const analysis::QuantileEstimate& q) {
  return {{"probability", q.probability}, {"value", JsonNumber(q.value)}, {"interval", Json(q.interval)}};
}

nlohmann::json Json(const analysis::ProportionEstimate& p) {
  return {{"value", JsonNumber(p.value)}, {"interval", Json(p.interval)}, {"successes", p.successes}, {"trials", p.trials}};
}

namespace {

nlohmann::json Optional(const std::optional<double>& value) { return value ? JsonNumber(*value) : nlohmann::json(nullptr); }

template <typename T>
nlohmann::json OptionalInteger(const std::optional<T>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

}  // namespace

nlohmann::json OutputJson(const OutputReport& out, double samples_per_draw) {
  nlohmann::json j;
  j["count"] = out.count;
  j["upper_spec_limit"] = Optional(out.upper_spec_limit);
  if (!out.distribution) return j;
  const analysis::DistributionSummary& d = *out.distribution;
  j["mean"] = JsonNumber(d.mean);
  j["std"] = JsonNumber(d.standard_deviation);
  j["min"] = JsonNumber(d.min);
  j["max"] = JsonNumber(d.max);
  j["quantiles"] = nlohmann::json::array();
  for (const analysis::QuantileEstimate& q : d.quantiles) j["quantiles"].push_back(Json(q));
  j["histogram"] = {{"lower", d.histogram.lower}, {"bin_width", d.histogram.bin_width}, {"counts", d.histogram.counts}};
  nlohmann::json ecdf = nlohmann::json::array();
  for (const analysis::EcdfPoint& p : d.ecdf) ecdf.push_back({p.value, p.probability});
  j["ecdf"] = std::move(ecdf);
  j["capability"] = {{"Cp", Optional(d.capability.cp)},
                     {"Cpk", Optional(d.capability.cpk)},
                     {"Cpu", Optional(d.capability.cpu)},
                     {"Cpl", Optional(d.capability.cpl)},
                     {"Cpk_percentile", Optional(d.capability.cpk_percentile)},
                     {"percentile_extrapolated", d.capability.percentile_extrapolated}};
  j["yield"] = d.within_spec ? Json(*d.within_spec) : nlohmann::json(nullptr);
  j["yield_counting_failures"] =
      out.within_spec_counting_failures ? Json(*out.within_spec_counting_failures) : nlohmann::json(nullptr);
  nlohmann::json convergence = nlohmann::json::array();
  for (const analysis::ConvergencePoint& p : out.convergence) {
    nlohmann::json point = {{"samples", p.samples}, {"quantile", Json(p.quantile)}};
    point["yield"] = p.within_spec ? Json(*p.within_spec) : nlohmann::json(nullptr);
    convergence.push_back(std::move(point));
  }
  j["convergence"] = std::move(convergence);
  const auto campaign_samples = [&](const std::optional<std::int64_t>& draws) {
    return draws ? nlohmann::json(static_cast<std::int64_t>(std::ceil(static_cast<double>(*draws) * samples_per_draw)))
                 : nlohmann::json(nullptr);
  };
  j["samples_needed"] = {{"quantile",
                          {{"probability", kReportQuantile},
                           {"draws", OptionalInteger(out.samples_for_quantile)},
                           {"campaign_samples", campaign_samples(out.samples_for_quantile)}}},
                         {"yield",
                          {{"draws", OptionalInteger(out.samples_for_yield)},
                           {"campaign_samples", campaign_samples(out.samples_for_yield)}}}};
  return j;
}

namespace {

nlohmann::json EntryJson(const SensitivityEntry& e) {
  nlohmann::json j = {{"name", e.name}, {"source", e.source}, {"order", e.order}};
  j["S1"] = JsonNumber(e.first_order.value);
  j["S1_conf"] = JsonNumber(e.first_order.conf);
  j["S1_interval"] = Json(e.first_order.interval);
  if (e.total_order) {
    j["ST"] = JsonNumber(e.total_order->value);
    j["ST_conf"] = JsonNumber(e.total_order->conf);
    j["ST_interval"] = Json(e.total_order->interval);
  } else {
    j["SRC"] = JsonNumber(e.src);
    j["SRRC"] = JsonNumber(e.srrc);
  }
  return j;
}

}  // namespace

nlohmann::json SensitivityJson(const OutputSensitivity& s) {
  nlohmann::json o = {{"method", s.method},
                      {"estimator", s.estimator},
                      {"rows", s.rows},
                      {"rows_excluded", s.rows_excluded},
                      {"rows_pending", s.rows_pending},
                      {"variance", JsonNumber(s.variance)},
                      {"rows_for_precision", OptionalInteger(s.rows_for_precision)}};
  o["r2"] = Optional(s.r2);
  o["ab_correlation"] = Optional(s.ab_correlation);
  o["rank_r2"] = Optional(s.rank_r2);
  for (const SensitivityLevel& level : s.levels) {
    nlohmann::json entries = nlohmann::json::array();
    for (const SensitivityEntry& e : level.entries) entries.push_back(EntryJson(e));
    o[level.level] = {{"aggregation", level.aggregation == Aggregation::kExact ? "exact" : "sum of parts"},
                      {"entries", std::move(entries)}};
  }
  return o;
}

nlohmann::json ReportJson(const CampaignReport& report) {
  nlohmann::json j;
  j["format"] = "ringtol report";
  j["schema_version"] = 1;
  j["results"] = report.results.string();
  j["campaign"] = {{"path", report.identity.campaign_path},
                   {"ringtol_version", report.identity.ringtol_version},
                   {"catalogue_version", report.identity.catalogue_version},
                   {"design", report.design},
                   {"solver", report.identity.solver},
                   {"seed", report.identity.seed},
                   {"rollers", report.rollers}};
  j["confidence"] = report.options.confidence;
  if (!report.schema_note.empty()) j["schema_note"] = report.schema_note;
  j["samples"] = {{"campaign", report.samples},
                  {"used", report.used},
                  {"done", report.done},
                  {"ok", report.ok},
                  {"pending", report.pending},
                  {"failed", report.done - report.ok},
                  {"redrawn", report.redrawn},
                  {"failures", report.failures},
                  {"samples_per_draw", report.samples_per_draw}};
  nlohmann::json failed = nlohmann::json::array();
  for (const FailedSample& f : report.failed)
    failed.push_back({{"index", f.index}, {"status", f.status}, {"message", f.message}});
  j["failed_samples"] = std::move(failed);
  if (RungsRan(report.settled_by) > 0) j["rungs"] = RungsJson(report.settled_by);
  if (report.openings) j["contacts"] = OpeningsJson(*report.openings);
  j["primary_output"] = report.primary_output;
  const auto proportion = [](const std::optional<analysis::ProportionEstimate>& p) {
    return p ? Json(*p) : nlohmann::json(nullptr);
  };
  j["within_every_limit"] = proportion(report.within_every_limit);
  j["within_every_limit_counting_failures"] = proportion(report.within_every_limit_counting_failures);
  if (report.disposition) j["disposition"] = DispositionJson(*report.disposition);
  nlohmann::json populations = nlohmann::json::array();
  for (const PopulationView& view : report.populations) populations.push_back(PopulationJson(view));
  j["populations"] = std::move(populations);
  nlohmann::json outputs = nlohmann::json::object();
  for (const OutputReport& out : report.outputs) outputs[out.name] = OutputJson(out, report.samples_per_draw);
  j["outputs"] = std::move(outputs);
  nlohmann::json sensitivity = nlohmann::json::object();
  for (const OutputSensitivity& s : report.sensitivities) sensitivity[s.output] = SensitivityJson(s);
  j["sensitivity"] = std::move(sensitivity);
  nlohmann::json trajectories = nlohmann::json::array();
  for (const ReplayedTrajectory& t : report.trajectories) {
    nlohmann::json entry = {{"label", t.label},
                            {"by", t.by},
                            {"stored_by", JsonNumber(t.stored_by)},
                            {"index", t.index},
                            {"status", t.status},
                            {"message", t.message},
                            {"steps", t.steps},
                            {"stored_d_trajectory_mm", JsonNumber(t.stored_d_trajectory_mm)},
                            {"d_trajectory_mm", JsonNumber(t.d_trajectory_mm)},
                            {"tolerance_mm", JsonNumber(t.tolerance_mm)},
                            {"reproduced", t.reproduced}};
    if (t.reproduced) {
      entry["x_um"] = t.x_um;
      entry["y_um"] = t.y_um;
      entry["circle"] = {{"x_um", t.circle_x_um}, {"y_um", t.circle_y_um}, {"radius_um", t.circle_radius_um}};
      entry["static_equilibrium"] = {{"x_um", t.static_x_um}, {"y_um", t.static_y_um}};
      entry["sensor"] = {{"angle_deg", t.angle_deg},
                         {"above_min_um", t.sensor_um},
                         {"tir_um", t.tir_um},
                         {"max_angle_deg", t.max_angle_deg},
                         {"min_angle_deg", t.min_angle_deg}};
    }
    trajectories.push_back(std::move(entry));
  }
  j["trajectories"] = std::move(trajectories);
  j["replay_problem"] = report.replay_problem ? nlohmann::json(*report.replay_problem) : nlohmann::json(nullptr);
  if (nlohmann::json life = LifeJson(report.identity.life, report.life_gaps, report.life_error_motion,
                                     report.identity.error_motion_filter, report.life_missing);
      !life.is_null()) {
    j["life"] = std::move(life);
  }
  if (report.error_motion_problem) j["error_motion_problem"] = *report.error_motion_problem;
  if (const std::optional<ErrorMotionPlot>& p = report.error_motion) {
    nlohmann::json plot = {{"index", p->index},
                           {"stored_total_mm", JsonNumber(p->stored_total_mm)},
                           {"status", p->status},
                           {"message", p->message},
                           {"revolutions", p->revolutions},
                           {"steps", p->steps}};
    if (p->status == "ok") {
      plot["total_um"] = p->total_um;
      plot["synchronous_um"] = p->synchronous_um;
      plot["asynchronous_um"] = p->asynchronous_um;
      plot["fundamental_um"] = p->fundamental_um;
      plot["circles_um"] = {{"total", {p->total_inner_um, p->total_outer_um}},
                            {"synchronous", {p->synchronous_inner_um, p->synchronous_outer_um}}};
      plot["angle_deg"] = p->angle_deg;
      plot["lowest_um"] = p->lowest_um;
      plot["highest_um"] = p->highest_um;
      plot["average_um"] = p->average_um;
    }
    j["error_motion"] = std::move(plot);
  }
  return j;
}

}  // namespace ringtol::jobs
