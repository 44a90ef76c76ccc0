#include "jobs/studies/campaign_speed.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <thread>

#include <fmt/format.h>

#include "analysis/order_statistics.h"
#include "engine/units.h"
#include "jobs/campaign/campaign.h"
#include "jobs/inputs/input_error.h"
#include "jobs/report/svg_chart.h"
#include "sampling/assembly_sampler.h"

namespace ringtol::jobs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Threads take this many consecutive samples at a time: enough to keep the shared counter
// off the profile, few enough that the threads finish together.
constexpr std::int64_t kSamplesPerTake = 8;
constexpr double kWithinUm = 1.0;  // the accuracy line, drawn on the chart

struct ModeRun {
  std::vector<SampleRecord> records;
  double wall_time = 0.0;  // [s]
};

ModeRun RunMode(const Campaign& campaign, std::int64_t samples, int threads) {
  ModeRun run;
  run.records.resize(static_cast<std::size_t>(samples));
  std::atomic<std::int64_t> next{0};
  const auto start = std::chrono::steady_clock::now();
  {
    std::vector<std::jthread> workers;
    for (int t = 0; t < threads; ++t) {
      workers.emplace_back([&] {
        SampleEvaluator evaluator(campaign);
        for (;;) {
          const std::int64_t begin = next.fetch_add(kSamplesPerTake);
          if (begin >= samples) return;
          for (std::int64_t i = begin; i < std::min(begin + kSamplesPerTake, samples); ++i) {
            run.records[static_cast<std::size_t>(i)] = evaluator.Evaluate(i);
          }
        }
      });
    }
  }
  run.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return run;
}

// Output columns compared, as indices into kOutputNames.
constexpr std::size_t kDTrajectory = 0, kStaticOffset = 2, kRunout = 3, kSwing = 4, kLifeDTrajectory = 9;
static_assert(std::string_view(kOutputNames[kDTrajectory]) == "d_trajectory_mm");
static_assert(std::string_view(kOutputNames[kStaticOffset]) == "static_offset_mm");
static_assert(std::string_view(kOutputNames[kRunout]) == "runout_mm");
static_assert(std::string_view(kOutputNames[kSwing]) == "swing_mm");
static_assert(std::string_view(kOutputNames[kLifeDTrajectory]) == "life_d_trajectory_mm");

CampaignModeRow Compare(const std::string& name, const solvers::SolverSettings& solver, const ModeRun& run,
                        const std::vector<SampleRecord>& reference) {
  CampaignModeRow row;
  row.name = name;
  row.solver = solvers::SolverDescription(solver);
  row.wall_time = run.wall_time;
  row.samples_per_second = static_cast<double>(run.records.size()) / run.wall_time;
  std::vector<double> times;
  times.reserve(run.records.size());
  std::array<double, kOutputCount> worst{};
  for (std::size_t i = 0; i < run.records.size(); ++i) {
    const SampleRecord& mine = run.records[i];
    const SampleRecord& theirs = reference[i];
    times.push_back(mine.solve_time);
    if (mine.status == SampleStatus::kOk) ++row.ok;
    if (mine.status != theirs.status) {
      if (row.status_mismatches++ == 0) {
        row.first_mismatch = fmt::format("sample {}: {} against {}", i, SampleStatusName(mine.status),
                                         SampleStatusName(theirs.status));
      }
      continue;
    }
    if (mine.status != SampleStatus::kOk) continue;
    ++row.compared;
    for (std::size_t k = 0; k < kOutputCount; ++k) {
      worst[k] = std::max(worst[k], std::abs(mine.outputs[k] - theirs.outputs[k]));
    }
  }
  // Outputs are in mm; the errors are reported in um.
  const auto in_um = [&](std::size_t k) { return row.compared > 0 ? worst[k] * units::kMicrometresPerMillimetre : kNaN; };
  row.max_error_d_trajectory = in_um(kDTrajectory);
  row.max_error_runout = in_um(kRunout);
  row.max_error_swing = in_um(kSwing);
  row.max_error_life_d_trajectory = solver.simulation.life ? in_um(kLifeDTrajectory) : kNaN;
  row.max_error_static_offset = in_um(kStaticOffset);
  row.median_solve_time = analysis::Median(std::move(times));
  return row;
}

// A largest error [um] as a table cell: three significant digits, "-" where none was compared.
std::string ErrorCell(double value_um) { return std::isnan(value_um) ? "-" : fmt::format("{:.3g}", value_um); }

}  // namespace

std::vector<CampaignMode> DefaultCampaignModes(const solvers::SolverSettings& campaign) {
  std::vector<CampaignMode> modes;
  modes.push_back({"campaign", campaign});
  for (const solvers::AngleMode angles :
       {solvers::AngleMode::kDense, solvers::AngleMode::kRefined, solvers::AngleMode::kSpectral}) {
    for (const solvers::Rung rung : {solvers::Rung::kLinear, solvers::Rung::kQuasistatic, solvers::Rung::kAuto}) {
      // The spectral mode reads the linear rung only: its quasistatic row would be the dense one.
      if (angles == solvers::AngleMode::kSpectral && rung == solvers::Rung::kQuasistatic) continue;
      std::string name(NameOf(solvers::kRungNames, rung));
      if (angles != solvers::AngleMode::kDense) name += std::string(", ") + std::string(NameOf(solvers::kAngleModeNames, angles));
      // The campaign's own mode is timed once, first, under the name of the mode it is.
      if (rung == campaign.rung && angles == campaign.simulation.angles &&
          campaign.simulation.accuracy == solvers::Accuracy::kFull) {
        modes.front().name = std::move(name);
        continue;
      }
      solvers::SolverSettings settings = campaign;
      settings.rung = rung;
      settings.simulation.angles = angles;
      settings.simulation.accuracy = solvers::Accuracy::kFull;
      modes.push_back({std::move(name), settings});
    }
  }
  // Below the reference's floor, the auto rung on spectral angles at accuracy fast
  // (solvers::Accuracy), with the life and, where the campaign reads it, without.
  solvers::SolverSettings fast = campaign;
  fast.rung = solvers::Rung::kAuto;
  fast.simulation.angles = solvers::AngleMode::kSpectral;
  fast.simulation.accuracy = solvers::Accuracy::kFast;
  const std::string fast_name = "auto, spectral, fast";
  const bool campaign_is_fast = campaign.rung == fast.rung && campaign.simulation.angles == fast.simulation.angles &&
                                campaign.simulation.accuracy == fast.simulation.accuracy;
  if (campaign_is_fast) modes.front().name = fast_name;
  // What the life values cost: the linear rung's modes and the campaign's own again, each
  // reading one revolution only.
  if (campaign.simulation.life) {
    const std::size_t with_life = modes.size();
    for (std::size_t m = 0; m < with_life; ++m) {
      const solvers::SolverSettings& settings = modes[m].solver;
      if (m != 0 && settings.rung != solvers::Rung::kLinear) continue;
      solvers::SolverSettings one = settings;
      one.simulation.life = false;
      modes.push_back({modes[m].name + ", one revolution", one});
    }
  }
  // The campaign's own mode, when fast, has its rows above.
  if (!campaign_is_fast) {
    modes.push_back({fast_name, fast});
    if (campaign.simulation.life) {
      fast.simulation.life = false;
      modes.push_back({fast_name + ", one revolution", fast});
    }
  }
  return modes;
}

solvers::SolverSettings FullResolutionReference(const solvers::SolverSettings& campaign) {
  solvers::SolverSettings reference = campaign;
  reference.rung = solvers::Rung::kQuasistatic;
  reference.simulation.path_tolerance = 0.0;
  reference.simulation.steps = 0;
  reference.simulation.angles = solvers::AngleMode::kDense;
  reference.simulation.accuracy = solvers::Accuracy::kFull;
  return reference;
}

CampaignSpeedResult RunCampaignSpeed(const CampaignPlan& plan, const CampaignSpeedOptions& options,
                                     std::ostream* progress) {
  if (options.threads < 0) {
    throw InputError(fmt::format("--threads = {}: allowed: >= 0 (0: one per core)", options.threads));
  }
  const std::vector<CampaignMode> modes = options.modes.empty() ? DefaultCampaignModes(plan.solver) : options.modes;
  CampaignSpeedResult result;
  result.campaign = plan.file.string();
  result.samples = plan.sampling.samples;
  result.threads = options.threads > 0 ? options.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));

  const auto calibrations = std::make_shared<sampling::CalibrationCache>();
  const auto campaign_of = [&](const solvers::SolverSettings& solver) {
    CampaignPlan mode_plan = plan;
    mode_plan.solver = solver;
    return Campaign(std::move(mode_plan), plan.file.string(), calibrations);
  };
  const auto say = [&](const std::string& line) {
    if (progress != nullptr) *progress << line << '\n' << std::flush;
  };

  const solvers::SolverSettings reference_settings = FullResolutionReference(plan.solver);
  say(fmt::format("bench campaign: reference ({} at the exact step rule), {} samples on {} threads",
                  solvers::SolverDescription(reference_settings), result.samples, result.threads));
  const ModeRun reference = RunMode(campaign_of(reference_settings), result.samples, result.threads);
  result.reference = Compare("reference", reference_settings, reference, reference.records);

  for (std::size_t m = 0; m < modes.size(); ++m) {
    say(fmt::format("bench campaign: {} ({})", modes[m].name, solvers::SolverDescription(modes[m].solver)));
    ModeRun run = RunMode(campaign_of(modes[m].solver), result.samples, result.threads);
    result.rows.push_back(Compare(modes[m].name, modes[m].solver, run, reference.records));
    if (m == 0) result.first_mode_records = std::move(run.records);
  }
  const auto quasistatic = std::find_if(result.rows.begin(), result.rows.end(),
                                        [](const CampaignModeRow& row) { return row.name == "quasistatic"; });
  if (quasistatic != result.rows.end()) {
    const double base = quasistatic->samples_per_second;
    for (CampaignModeRow& row : result.rows) row.speed_ratio = row.samples_per_second / base;
    result.reference.speed_ratio = result.reference.samples_per_second / base;
  }
  return result;
}

void PrintCampaignSpeed(std::ostream& out, const CampaignSpeedResult& result) {
  out << fmt::format("campaign          {}\n", result.campaign);
  out << fmt::format("samples           the design's first {}, on {} threads; errors against quasistatic at full resolution\n\n",
                     result.samples, result.threads);
  out << fmt::format("{:<32} {:>10} {:>8} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>6}\n", "mode", "samples/s",
                     "x quasi", "median ms", "D_traj um", "runout um", "swing um", "life D um", "status !=", "ok");
  const auto line = [&](const CampaignModeRow& row) {
    out << fmt::format("{:<32} {:>10.1f} {:>8} {:>10.3f} {:>10} {:>10} {:>10} {:>10} {:>10} {:>6}\n", row.name,
                       row.samples_per_second, row.speed_ratio > 0.0 ? fmt::format("{:.2f}", row.speed_ratio) : "-",
                       row.median_solve_time * 1e3, ErrorCell(row.max_error_d_trajectory),
                       ErrorCell(row.max_error_runout), ErrorCell(row.max_error_swing),
                       ErrorCell(row.max_error_life_d_trajectory), row.status_mismatches, row.ok);
  };
  for (const CampaignModeRow& row : result.rows) line(row);
  line(result.reference);
  for (const CampaignModeRow& row : result.rows) {
    if (!row.first_mismatch.empty()) out << fmt::format("{}: first status mismatch, {}\n", row.name, row.first_mismatch);
  }
  out << "errors: the largest |value - reference| over the samples both computed, per output\n";
}

void WriteCampaignSpeedCsv(std::ostream& out, const CampaignSpeedResult& result) {
  out << "mode,solver,samples_per_second,median_solve_ms,ok,compared,max_error_d_trajectory_um,max_error_runout_um,"
         "max_error_swing_um,max_error_static_offset_um,max_error_life_d_trajectory_um,status_mismatches,speed_ratio\n";
  const auto line = [&](const CampaignModeRow& row) {
    out << fmt::format("{},\"{}\",{:.6g},{:.6g},{},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{},{:.6g}\n", row.name,
                       row.solver, row.samples_per_second, row.median_solve_time * 1e3, row.ok, row.compared,
                       row.max_error_d_trajectory, row.max_error_runout, row.max_error_swing,
                       row.max_error_static_offset, row.max_error_life_d_trajectory, row.status_mismatches,
                       row.speed_ratio);
  };
  for (const CampaignModeRow& row : result.rows) line(row);
  line(result.reference);
}

void WriteCampaignSpeedSvg(std::ostream& out, const CampaignSpeedResult& result) {
  constexpr double kErrorFloor = 1e-3;  // [um] where errors below are drawn
  // The error axis reaches 10 um at least, so that the 1 um line lies inside the plot.
  double rate_min = std::numeric_limits<double>::infinity(), rate_max = 0.0, error_max = 10.0;
  const auto drawn = [&](double error) { return std::max(std::isnan(error) ? kErrorFloor : error, kErrorFloor); };
  for (const CampaignModeRow& row : result.rows) {
    rate_min = std::min(rate_min, row.samples_per_second);
    rate_max = std::max(rate_max, row.samples_per_second);
    error_max = std::max({error_max, drawn(row.max_error_d_trajectory), drawn(row.max_error_runout)});
  }
  if (!(rate_max > 0.0)) rate_min = 1.0, rate_max = 10.0;
  svg::Chart chart;
  chart.title = fmt::format("ringtol campaign modes: throughput against the largest per-sample error ({} samples, {} threads)",
                            result.samples, result.threads);
  chart.x = {.label = "max |value - full-resolution quasistatic| over the samples [µm] (below 1e-3 drawn at 1e-3)",
             .log10 = true,
             .min = kErrorFloor,
             .max = std::pow(10.0, std::ceil(std::log10(error_max)))};
  chart.y = {.label = "samples per second (all threads)",
             .log10 = true,
             .min = std::pow(10.0, std::floor(std::log10(rate_min))),
             .max = std::pow(10.0, std::ceil(std::log10(rate_max)) + (rate_max == rate_min ? 1.0 : 0.0))};
  chart.width = 900.0;
  chart.height = 600.0;
  chart.lines.push_back({svg::ReferenceLine::Direction::kVertical, kWithinUm, "1 µm"});
  for (std::size_t i = 0; i < result.rows.size(); ++i) {
    const CampaignModeRow& row = result.rows[i];
    const int colour = static_cast<int>(i);
    chart.series.push_back({.name = fmt::format("{}. {}: D_trajectory", i + 1, row.name),
                            .x = {drawn(row.max_error_d_trajectory)},
                            .y = {row.samples_per_second},
                            .style = svg::Series::Style::kPoints,
                            .marker = svg::Series::Marker::kCircle,
                            .colour = colour,
                            .labels = {fmt::format("{}", i + 1)}});
    chart.series.push_back({.name = fmt::format("{}. {}: runout", i + 1, row.name),
                            .x = {drawn(row.max_error_runout)},
                            .y = {row.samples_per_second},
                            .style = svg::Series::Style::kPoints,
                            .marker = svg::Series::Marker::kSquare,
                            .colour = colour});
  }
  out << svg::RenderChart(chart);
}

}  // namespace ringtol::jobs
