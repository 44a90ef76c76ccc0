#include "jobs/studies/dynamic_study.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "jobs/inputs/input_error.h"
#include "jobs/report/svg_chart.h"
#include "solvers/dynamic.h"
#include "solvers/quasistatic.h"
#include "solvers/simulation.h"
#include "engine/units.h"

namespace ringtol::jobs {
namespace {

constexpr double kFailed = std::numeric_limits<double>::quiet_NaN();  // a run that failed: no point

// D_trajectory of one run and, for the dynamic rung, of its steady revolution; NaN where
// the run failed, with the reason appended to `failures`.
struct Diameters {
  double first = kFailed;   // [m]
  double steady = kFailed;  // [m]
};

Diameters Run(const engine::Scene& scene, const solvers::Solver& solver, const std::string& what,
              std::vector<std::string>& failures) {
  const solvers::SimulationResult result = solvers::Simulate(scene, solver);
  Diameters d;
  if (result.status != solvers::Status::kOk) {
    failures.push_back(what + ": " + std::string(solvers::StatusName(result.status)) + ": " + result.message);
    return d;
  }
  d.first = result.d_trajectory;
  if (result.steady) {
    if (result.steady->status == solvers::Status::kOk) {
      d.steady = result.steady->d_trajectory;
    } else {
      failures.push_back(what + ", steady revolution: " + std::string(solvers::StatusName(result.steady->status)) +
                         ": " + result.steady->message);
    }
  }
  return d;
}

// The lowest rate at which gap exceeds `agreement`, interpolated in log-log between the
// last rate below it and the first above; 0 when the slowest already exceeds it, +inf
// when none does.
double Threshold(const std::vector<double>& rates, const std::vector<double>& gap, double agreement) {
  for (std::size_t j = 0; j < rates.size(); ++j) {
    if (!(gap[j] > agreement)) continue;
    if (j == 0 || !(gap[j - 1] > 0.0)) return j == 0 ? 0.0 : rates[j];
    const double f = std::log(agreement / gap[j - 1]) / std::log(gap[j] / gap[j - 1]);
    return rates[j - 1] * std::pow(rates[j] / rates[j - 1], f);
  }
  return std::numeric_limits<double>::infinity();
}

// A length [m] as a table cell: micrometres to two decimals, "-" for a failed run.
std::string MicrometresCell(double metres) {
  return std::isnan(metres) ? "-" : fmt::format("{:.2f}", units::InMicrometres(metres));
}

}  // namespace

DynamicStudy RunDynamicStudy(const engine::Scene& scene, const DynamicStudyOptions& options, std::ostream* progress) {
  if (options.orders.empty()) throw InputError("--orders: at least one order is needed");
  if (options.rates.empty()) throw InputError("--rates-deg-per-s: at least one rate is needed");
  const engine::MotionLaw& law = scene.motion;
  DynamicStudy study;
  study.settle = law.RotationStart();
  if (!std::isfinite(study.settle)) throw InputError("[motion]: the law never turns the ring; the study needs a steady rate");
  study.rate = law.Rate(study.settle);
  for (std::size_t j = law.SegmentAt(study.settle); j < law.segments().size(); ++j) {
    const engine::MotionSegment& segment = law.segments()[j];
    if (segment.acceleration != 0.0 || (segment.start_rate && *segment.start_rate != study.rate)) {
      throw InputError("[motion]: the study needs the article's kind of law (at rest, then one steady rate)");
    }
  }
  study.rates = options.rates;
  const solvers::QuasistaticSolver quasistatic;
  const solvers::DynamicSolver dynamic;
  solvers::DynamicOptions article_start;
  article_start.start = solvers::DynamicStart::kArticleSettle;
  const solvers::DynamicSolver dynamic_article(article_start);
  article_start.steady_revolution = 0;
  const solvers::DynamicSolver dynamic_article_first(article_start);
  const double revolutions = dynamic.options().steady_revolution + 1.0;
  for (const int order : options.orders) {
    engine::Scene sample = scene;
    sample.ring.inner = engine::PolarProfile(scene.ring.inner.radius(), 0.0, {{order, options.amplitude, options.phase}});
    const std::string name = "order " + std::to_string(order);
    if (progress != nullptr) fmt::print(*progress, "{}\n", name);
    TransientRow transient;
    transient.order = order;
    transient.quasistatic = Run(sample, quasistatic, name + ", quasistatic", study.failures).first;
    sample.motion = engine::ArticleLaw(study.settle, study.rate, revolutions);
    const Diameters at_speed = Run(sample, dynamic, name + ", dynamic", study.failures);
    transient.first = at_speed.first;
    transient.steady = at_speed.steady;
    const Diameters settled = Run(sample, dynamic_article, name + ", dynamic after the article's settle", study.failures);
    transient.first_article_settle = settled.first;
    transient.steady_article_settle = settled.steady;
    sample.motion = engine::ArticleLaw(options.long_settle, study.rate, 1.0);
    transient.first_long_settle =
        Run(sample, dynamic_article_first, name + ", dynamic after a long settle", study.failures).first;
    study.transient.push_back(transient);

    SpeedRow speed;
    speed.order = order;
    for (const double rate : options.rates) {
      sample.motion = engine::ArticleLaw(study.settle, rate, revolutions);
      const double steady =
          Run(sample, dynamic, fmt::format("{}, dynamic at {:g} deg/s", name, rate * units::kDegreesPerRadian), study.failures).steady;
      speed.gap.push_back(std::abs(steady - transient.quasistatic));
    }
    speed.threshold = Threshold(options.rates, speed.gap, options.agreement);
    study.speed.push_back(speed);
  }
  return study;
}

void PrintDynamicStudy(std::ostream& out, const DynamicStudy& study) {
  fmt::print(out, "Start transient at {:g} deg/s after a {:g} s settle: D_trajectory [um]\n", study.rate * units::kDegreesPerRadian,
             study.settle);
  fmt::print(out, "{:>5} {:>12} | {:^38} | {:^38} | {:^25}\n", "", "", "from the quasistatic equilibrium",
             "from the article's start", "article's first rev excess");
  fmt::print(out, "{:>5} {:>12} | {:>12} {:>12} {:>12} | {:>12} {:>12} {:>12} | {:>12} {:>12}\n", "order", "quasistatic",
             "first rev", "steady rev", "first-steady", "first rev", "after long", "steady rev", "unsettled",
             "speed step");
  for (const TransientRow& row : study.transient) {
    // The article's first revolution's excess over the quasi-static value splits into what
    // a long settle removes (the ring had not settled) and what remains (the step in speed,
    // together with the steady lag the steady revolution also carries).
    fmt::print(out, "{:>5} {:>12} | {:>12} {:>12} {:>12} | {:>12} {:>12} {:>12} | {:>12} {:>12}\n", row.order,
               MicrometresCell(row.quasistatic), MicrometresCell(row.first), MicrometresCell(row.steady),
               MicrometresCell(row.first - row.steady), MicrometresCell(row.first_article_settle),
               MicrometresCell(row.first_long_settle), MicrometresCell(row.steady_article_settle),
               MicrometresCell(row.first_article_settle - row.first_long_settle),
               MicrometresCell(row.first_long_settle - row.quasistatic));
  }
  fmt::print(out, "\nSteady revolution against quasistatic: |D_dynamic - D_quasistatic| [um]\n{:>5}", "order");
  for (const double rate : study.rates) fmt::print(out, " {:>10}", fmt::format("{:g}deg/s", rate * units::kDegreesPerRadian));
  fmt::print(out, " {:>14}\n", "1 um above");
  for (const SpeedRow& row : study.speed) {
    fmt::print(out, "{:>5}", row.order);
    for (const double gap : row.gap) fmt::print(out, " {:>10}", MicrometresCell(gap));
    const std::string threshold =
        std::isinf(row.threshold) ? fmt::format("> {:g}", study.rates.back() * units::kDegreesPerRadian)
        : row.threshold == 0.0    ? fmt::format("< {:g}", study.rates.front() * units::kDegreesPerRadian)
                                  : fmt::format("{:.3g}", row.threshold * units::kDegreesPerRadian);
    fmt::print(out, " {:>9} deg/s\n", threshold);
  }
  if (!study.failures.empty()) {
    fmt::print(out, "\nFailed runs ({}):\n", study.failures.size());
    for (const std::string& failure : study.failures) fmt::print(out, "  {}\n", failure);
  }
}

}  // namespace ringtol::jobs

namespace ringtol::jobs {

void WriteDynamicStudySvg(std::ostream& out, const DynamicStudy& study) {
  // The article's abstract: D_trajectory from 0.29 to 0.63 mm over its order study.
  constexpr double kArticleLowest = 0.29;   // [mm]
  constexpr double kArticleHighest = 0.63;  // [mm]
  svg::Chart chart;
  chart.title = fmt::format("D_trajectory against ring order at {:g} deg/s: quasistatic, dynamic first and steady revolutions",
                            study.rate * units::kDegreesPerRadian);
  chart.x = {.label = "ring order n"};
  chart.y = {.label = "D_trajectory [mm]"};
  chart.width = 900.0;
  chart.height = 500.0;
  std::vector<double> orders;
  for (const TransientRow& row : study.transient) orders.push_back(row.order);
  if (!orders.empty()) {
    svg::Series range;
    range.name = fmt::format("article's reported range, {:g}-{:g} mm", kArticleLowest, kArticleHighest);
    range.x = {orders.front() - 0.5, orders.back() + 0.5};
    range.y = {kFailed, kFailed};  // no points: the band alone
    range.band_lower = {kArticleLowest, kArticleLowest};
    range.band_upper = {kArticleHighest, kArticleHighest};
    range.colour = 5;
    chart.series.push_back(std::move(range));
  }
  struct Curve {
    std::string name;
    double TransientRow::*value;
    int colour;
    bool dashed;
  };
  const std::vector<Curve> curves = {
      {fmt::format("dynamic, first revolution after the article's {:g} s settle", study.settle),
       &TransientRow::first_article_settle, 1, false},
      {"dynamic, first revolution from the quasistatic equilibrium (default)", &TransientRow::first, 0, false},
      {"dynamic, steady (4th) revolution", &TransientRow::steady, 3, true},
      {"quasistatic", &TransientRow::quasistatic, 2, true},
  };
  for (const Curve& curve : curves) {
    svg::Series line;
    line.name = curve.name;
    line.colour = curve.colour;
    line.dashed = curve.dashed;
    svg::Series points;
    points.style = svg::Series::Style::kPoints;
    points.colour = curve.colour;
    for (const TransientRow& row : study.transient) {
      line.x.push_back(row.order);
      line.y.push_back(row.*curve.value * units::kMillimetresPerMetre);
    }
    points.x = line.x;
    points.y = line.y;
    chart.series.push_back(std::move(line));
    chart.series.push_back(std::move(points));
  }
  out << svg::RenderChart(chart);
}

}  // namespace ringtol::jobs
