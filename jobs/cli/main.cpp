// ringtol: the command line. Parsing only: one function declares each command's
// arguments; the work is in jobs/cli/<command>_command.h.
#include <malloc.h>
#include <mpi.h>

#include <charconv>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include <CLI/CLI.hpp>

#include "jobs/cli/allocate_command.h"
#include "jobs/cli/bench_command.h"
#include "jobs/cli/campaign_command.h"
#include "jobs/cli/classes_command.h"
#include "jobs/cli/fit_command.h"
#include "jobs/cli/report_command.h"
#include "jobs/cli/match_command.h"
#include "jobs/cli/sample_command.h"
#include "jobs/cli/simulate_command.h"
#include "jobs/cli/inputs_command.h"
#include "jobs/cli/join_command.h"
#include "jobs/cli/nearest_name.h"
#include "jobs/cli/verify_command.h"
#include "jobs/inputs/input_error.h"
#include "jobs/inputs/sampling_file.h"
#include "jobs/inputs/toml_fields.h"
#include "engine/units.h"
#include "engine/visible_text.h"
#include "solvers/simulation.h"

namespace {

// Open MPI's defaults for a process started without a launcher, where it is the only rank:
// no daemon (Open MPI's singleton otherwise forks and execs an orted to support spawning
// ranks, which ringtol never does), and no transport to other processes (the PSM2 one's
// library alone sleeps about 0.2 s when loaded). Together they cost about half the wall
// time of a 16-sample campaign (docs/dependencies.md §4). The user's own settings of these
// variables win.
void PrepareSingletonMpi() {
  for (const char* launched : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"}) {
    if (std::getenv(launched) != nullptr) return;
  }
  setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);
  setenv("OMPI_MCA_pml", "ob1", 0);
  setenv("OMPI_MCA_btl", "self", 0);
}

// `ringtol campaign`, `ringtol allocate` and `ringtol bench allocate` are the MPI commands:
// they run alone as a singleton or under mpirun.
template <typename Run>
int RunMpiCommand(Run run) {
  PrepareSingletonMpi();
  int provided = 0;
  if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
    std::cerr << "ringtol: error: MPI could not start (MPI_Init_thread failed); under mpirun as root, pass "
                 "--allow-run-as-root\n";
    return 1;
  }
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  int code = 0;
  if (provided < MPI_THREAD_FUNNELED) {
    if (rank == 0) std::cerr << "ringtol: error: this MPI library cannot run a computing thread beside MPI calls "
                                "(MPI_THREAD_FUNNELED)\n";
    code = 1;
  } else {
    try {
      code = run();
    } catch (const ringtol::jobs::InputError& e) {
      if (rank == 0) std::cerr << "ringtol: error: " << e.what() << "\n";
      code = 1;
    } catch (const std::exception& e) {
      // A failure after the start (disk full, a lost rank): what is committed stays on disk.
      std::cerr << "ringtol: error: rank " << rank << ": " << e.what() << "; --resume continues from the file\n";
      MPI_Abort(MPI_COMM_WORLD, 2);
    } catch (...) {
      std::cerr << "ringtol: error: rank " << rank << ": an unknown exception; --resume continues from the file\n";
      MPI_Abort(MPI_COMM_WORLD, 2);
    }
  }
  MPI_Finalize();
  return code;
}

// The file a command reads: a positional argument that must name an existing file.
void AddInputFile(CLI::App& app, const std::string& name, std::filesystem::path& file, const std::string& help) {
  app.add_option(name, file, help)->required()->check(CLI::ExistingFile);
}

// Integer options are read as decimal by this transform (it runs before any check) and handed
// on as the number's plain digits, within [min, max]: CLI11 reads integers as strtoll does
// with base 0, "0360" as 240 and "0x10" as 16. Leading zeros are decimal, "0360" is 360.
CLI::Validator DecimalIn(std::int64_t min, std::int64_t max) {
  const std::string allowed = "; allowed: an integer >= " + std::to_string(min) + " and <= " + std::to_string(max);
  return CLI::Validator(
      [min, max, allowed](std::string& text) {
        std::int64_t value = 0;
        const char* const last = text.data() + text.size();
        const auto [end, error] = std::from_chars(text.data(), last, value);
        if (text.empty() || end != last || (error != std::errc() && error != std::errc::result_out_of_range)) {
          return ringtol::VisibleText(text) + ": not a decimal integer" + allowed;
        }
        if (error == std::errc::result_out_of_range || value < min || value > max) {
          return ringtol::VisibleText(text) + ": out of range" + allowed;
        }
        text = std::to_string(value);
        return std::string();
      },
      "[" + std::to_string(min) + " - " + std::to_string(max) + "]");
}

// DecimalIn over the range of an int.
CLI::Validator DecimalIn(int min) { return DecimalIn(min, std::numeric_limits<int>::max()); }

// DecimalIn over an options struct's range of an integer field (engine/option_range.h).
CLI::Validator DecimalIn(const ringtol::Range& range) {
  return DecimalIn(static_cast<std::int64_t>(range.lower), static_cast<std::int64_t>(range.upper));
}

// A count of samples, as --samples, --chunk and --index take it: at most 2^40.
constexpr std::int64_t kMostSamples = std::int64_t{1} << 40;

// --samples and --seed, which override a sampling or campaign file's own. The seed takes the
// file's range (jobs/inputs/sampling_file.h), read as decimal by the file's own rule: CLI11
// alone wraps -1 and 2^64 to 2^64 - 1.
void AddSamplesAndSeed(CLI::App& app, std::optional<std::int64_t>& samples, std::optional<std::uint64_t>& seed) {
  app.add_option("--samples", samples, "Number of samples (default: the file's design.samples)")
      ->transform(DecimalIn(1, kMostSamples));
  const CLI::Validator seed_range(
      [](std::string& text) {
        const std::optional<std::uint64_t> value = ringtol::jobs::SeedOfText(text);
        if (!value) {
          return ringtol::VisibleText(text) + ": not a decimal integer in range; allowed: " +
                 ringtol::jobs::SeedAllowed();
        }
        text = std::to_string(*value);
        return std::string();
      },
      "SEED");
  app.add_option("--seed", seed, "Campaign seed, " + ringtol::jobs::SeedAllowed() + " (default: the file's)")
      ->transform(seed_range);
}

// An option whose values are the names of `table`, setting `target`, its default shown.
template <typename Enum, std::size_t N>
void AddNamedOption(CLI::App& app, const std::string& option, const ringtol::NameTable<Enum, N>& table, Enum& target,
                    const std::string& help) {
  std::vector<std::string> names;
  for (const auto& [value, name] : table) names.emplace_back(name);
  app.add_option_function<std::string>(
         option, [&table, &target](const std::string& name) { target = *ValueNamed(table, name); }, help)
      ->check(CLI::IsMember(names))
      ->default_str(std::string(NameOf(table, target)));
}

// --solver, --steps, --angles, --accuracy, --relative-tolerance and --dynamic-start, as simulate and sweep
// take them.
void AddSolverOptions(CLI::App& app, ringtol::solvers::SolverSettings& settings, const std::string& steps_help) {
  AddNamedOption(app, "--solver", ringtol::solvers::kRungNames, settings.rung,
                 "Solver, a rung of the ladder, or auto: the cheapest whose error estimate fits half the path "
                 "tolerance (docs/model.md §7)");
  app.add_option("--steps", settings.simulation.steps, steps_help)
      ->transform(DecimalIn(1, ringtol::solvers::kMaxSteps));
  AddNamedOption(app, "--angles", ringtol::solvers::kAngleModeNames, settings.simulation.angles,
                 "Angles evaluated at full cost: every one (dense), a coarse grid refined where the metrics could "
                 "change (refined), or the linear rung read from its phasors there (spectral; docs/model.md §5)");
  AddNamedOption(app, "--accuracy", ringtol::solvers::kAccuracyNames, settings.simulation.accuracy,
                 "Every output as defined (full), or the spectral angles certified by the Hermite bound and the "
                 "life's lobe curves sampled looser, each output moved within its bound (fast; docs/model.md §5)");
  app.add_option("--relative-tolerance", settings.relative_tolerance, "Dynamic solver: integrator tolerance, > 0 and < 1")
      ->capture_default_str();
  AddNamedOption(app, "--dynamic-start", ringtol::solvers::kDynamicStartNames, settings.dynamic_start,
                 "Dynamic solver: start at rest at the quasistatic equilibrium, or centred with the article's settle");
}

CLI::App* AddSimulate(CLI::App& app, ringtol::jobs::SimulateCommand& simulate) {
  CLI::App* sub = app.add_subcommand(
      "simulate", "Simulate one revolution of one scene and print D_trajectory, Dist_init, static offset, runout");
  AddInputFile(*sub, "scene", simulate.scene, "Scene file (TOML)");
  AddSolverOptions(*sub, simulate.solver, "Angles per revolution (default: chosen so no harmonic aliases)");
  sub->add_flag("--json", simulate.json, "Print one JSON object");
  sub->add_option("--trajectory", simulate.trajectory_csv, "Write the path to this CSV file");
  sub->add_option("--revolutions", simulate.revolutions,
                  "Also the life metrics over this many revolutions, roller phases turning (docs/model.md §9); "
                  "with --solver linear also over every revolution: every phase of each roller, or the cycle of "
                  "rollers the scene's [life] phase_locked_rollers gears together")
      ->transform(DecimalIn(0));
  sub->add_option("--history", simulate.history_csv,
                  "Dynamic solver: write the time history over the motion law's span to this CSV file");
  sub->add_option("--history-interval-ms", simulate.history_interval_ms,
                  "Dynamic solver: time between history samples [ms], > 0")
      ->capture_default_str();
  return sub;
}

CLI::App* AddSweep(CLI::App& app, ringtol::jobs::SweepCommand& sweep) {
  CLI::App* sub = app.add_subcommand("sweep", "Simulate every case of a sweep file (orders, amplitudes or named cases)");
  AddInputFile(*sub, "sweep", sweep.sweep, "Sweep file (TOML)");
  AddSolverOptions(*sub, sweep.solver, "Angles per revolution (default: chosen per case)");
  sub->add_flag("--json", sweep.json, "Print a JSON array, one object per case");
  sub->add_option("--csv", sweep.csv, "Write one row per case to this CSV file");
  return sub;
}

CLI::App* AddSample(CLI::App& app, ringtol::jobs::SampleCommand& sample) {
  CLI::App* sub = app.add_subcommand(
      "sample", "Draw the assemblies of a sampling file (tolerance classes and a design) without simulating them");
  AddInputFile(*sub, "file", sample.file, "Sampling file (TOML)");
  AddSamplesAndSeed(*sub, sample.samples, sample.seed);
  sub->add_option("--csv", sample.csv, "Write every sample's drawn inputs to this CSV file");
  sub->add_option("--index", sample.index, "With --scene: the sample to write (0-based)")
      ->transform(DecimalIn(0, kMostSamples - 1));
  sub->add_option("--scene", sample.scene, "Write sample --index as a standalone scene file, to replay it");
  return sub;
}

CLI::App* AddMatch(CLI::App& app, ringtol::jobs::MatchCommand& match) {
  CLI::App* sub = app.add_subcommand(
      "match", "Which rollers of a measured batch to install with a measured ring ([population.rollers] resampled)");
  AddInputFile(*sub, "file", match.file, "Campaign file: the ring's scene and the batch");
  sub->add_option("--output", match.output, "The output to lower (default: the first [spec] limit's, else d_trajectory_mm)");
  sub->add_option("--exhaustive-limit", match.exhaustive_limit,
                  "Search every assignment up to this many, the heuristic beyond (default 20000)")
      ->transform(DecimalIn(1, kMostSamples));
  sub->add_option("--budget", match.budget, "The heuristic's random assignments (default 2000)")
      ->transform(DecimalIn(1, kMostSamples));
  sub->add_option("--top", match.top, "Assignments listed (default 5)")->transform(DecimalIn(1, 1000));
  sub->add_option("--draws", match.draws,
                  "Fit each assignment to this many assemblies of the file's other tolerances, the same for each, and "
                  "rank by the mean (default 0: the scene as it stands)")
      ->transform(DecimalIn(0, kMostSamples));
  sub->add_option("--threads", match.threads, "Simulating threads (default 0: one per core)")
      ->transform(DecimalIn(ringtol::jobs::PoolOptions::kThreadsRange));
  sub->add_flag("--json", match.json, "Print one JSON object");
  return sub;
}

CLI::App* AddFit(CLI::App& app, ringtol::jobs::FitCommand& fit) {
  CLI::App* sub = app.add_subcommand(
      "fit", "Fit a Fourier series to a roundness tester's export (angle, radius or deviation CSV)");
  AddInputFile(*sub, "profile", fit.profile, "Profile CSV: angle_deg, radius_mm | deviation_mm | deviation_um");
  sub->add_option("--orders", fit.orders, "Highest order fitted")
      ->required()
      ->transform(DecimalIn(1, ringtol::jobs::kMaxHarmonicOrder));
  sub->add_flag("--keep-eccentricity", fit.keep_eccentricity,
                "Keep order 1 in the fragment (by default it is the tester's set-up eccentricity)");
  sub->add_option("--fragment", fit.fragment, "Write the [ring] keys of a scene file to this TOML file");
  sub->add_flag("--json", fit.json, "Print one JSON object");
  return sub;
}

CLI::App* AddBenchDynamics(CLI::App& bench, ringtol::jobs::BenchDynamicsCommand& dynamics) {
  CLI::App* sub = bench.add_subcommand(
      "dynamics", "Start transient and speed: where the quasistatic answer stops being within 1 um of the dynamic one");
  AddInputFile(*sub, "scene", dynamics.scene, "Scene file (TOML); its ring errors are replaced per order");
  sub->add_option("--orders", dynamics.orders, "Ring orders to study (default: the article's)")
      ->transform(DecimalIn(1, ringtol::jobs::kMaxHarmonicOrder));
  sub->add_option("--rates-deg-per-s", dynamics.rates_deg_per_s, "Steady speeds to compare (default: 1 3 10 30 90 270)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--svg", dynamics.svg, "Write the start table as a chart (D_trajectory against order) to this SVG file");
  return sub;
}

CLI::App* AddBenchLadder(CLI::App& bench, ringtol::jobs::BenchLadderCommand& ladder) {
  CLI::App* sub = bench.add_subcommand(
      "ladder", "Speed against accuracy of every rung and setting on the article's order and amplitude studies");
  AddInputFile(*sub, "scene", ladder.scene, "Scene file (TOML) whose error-free assembly the studies use");
  sub->add_option("--cases", ladder.cases, "orders, amplitudes or all")
      ->check(CLI::IsMember({"orders", "amplitudes", "all"}))
      ->capture_default_str();
  sub->add_option("--repeats", ladder.repeats, "Timing repetitions per method and case (median)")
      ->transform(DecimalIn(1, 1000))
      ->capture_default_str();
  sub->add_flag("--explicit-full-model", ladder.explicit_full_model,
                "Also run explicit RK4 on the full model at 65 ns (order-2 case only, about 3 minutes)");
  sub->add_option("--csv", ladder.csv, "Write one row per method to this CSV file");
  sub->add_option("--svg", ladder.svg, "Write the speed-against-accuracy chart to this SVG file");
  return sub;
}

CLI::App* AddBenchCampaign(CLI::App& bench, ringtol::jobs::BenchCampaignCommand& command) {
  CLI::App* sub = bench.add_subcommand(
      "campaign", "Samples per second against the largest per-sample error of each solver mode on a campaign's samples");
  AddInputFile(*sub, "file", command.file, "Campaign file (TOML)");
  sub->add_option("--samples", command.samples, "Override design.samples")->transform(DecimalIn(1, kMostSamples));
  sub->add_option("--threads", command.threads, "Computing threads (default 0: one per core)")
      ->transform(DecimalIn(ringtol::jobs::PoolOptions::kThreadsRange))
      ->capture_default_str();
  sub->add_flag("!--no-report", command.report, "Do not time `ringtol report` on the campaign mode's results");
  sub->add_option("--results", command.results, "Keep the campaign mode's results in this new HDF5 file");
  sub->add_option("--csv", command.csv, "Write one row per mode to this CSV file");
  sub->add_option("--svg", command.svg, "Write the speed-against-accuracy chart to this SVG file");
  return sub;
}

// Progress lines on stderr, as the pool's commands take them.
void AddProgressOptions(CLI::App& app, bool& quiet, double& progress_seconds) {
  app.add_flag("--quiet", quiet, "No progress on stderr");
  app.add_option("--progress-seconds", progress_seconds, "Seconds between progress lines when stderr is not a terminal")
      ->capture_default_str();
}

// The pool's options, as campaign and allocate take them.
void AddPoolOptions(CLI::App& app, ringtol::jobs::PoolOptions& pool) {
  app.add_option("--chunk", pool.chunk_samples, "Samples per chunk handed to a rank (default 0: adaptive)")
      ->transform(DecimalIn(0, kMostSamples))
      ->capture_default_str();
  app.add_option("--chunk-seconds", pool.chunk_seconds, "Adaptive chunks' target duration [s]")->capture_default_str();
  app.add_option("--commit-seconds", pool.commit_seconds,
                  "Longest time results wait before they are written to the file [s]")
      ->capture_default_str();
  app.add_option("--coordinator-computes", pool.coordinator_computes,
                  "Whether rank 0 also computes: 1 yes, 0 no, -1 below 16 ranks")
      ->transform(DecimalIn(ringtol::jobs::PoolOptions::kCoordinatorComputesRange))
      ->capture_default_str();
  app.add_option("--threads", pool.threads, "Computing threads of rank 0 (default 0: every core alone, one under mpirun)")
      ->transform(DecimalIn(ringtol::jobs::PoolOptions::kThreadsRange))
      ->capture_default_str();
  // Test hooks standing in for kill -9 (tests/jobs/mpi/campaign_cli_test.cpp); not for users.
  app.add_option("--test-kill-after", pool.testing.kill_after_committed)->transform(DecimalIn(-1, kMostSamples))->group("");
  app.add_option("--test-kill-rank", pool.testing.kill_rank)->transform(DecimalIn(-1))->group("");
}

CLI::App* AddCampaign(CLI::App& app, ringtol::jobs::CampaignCommand& campaign) {
  CLI::App* sub = app.add_subcommand(
      "campaign", "Run a Monte Carlo campaign into an HDF5 results file, alone or under mpirun, and summarise it");
  AddInputFile(*sub, "file", campaign.file, "Campaign file (TOML)");
  sub->add_option("--out", campaign.out, "Results file (HDF5); never overwritten")->required();
  AddSamplesAndSeed(*sub, campaign.samples, campaign.seed);
  sub->add_flag("--resume", campaign.resume,
                "Continue --out after an interruption, or grow it to --samples: compute only what it lacks");
  sub->add_flag("--json", campaign.json, "Print the summary as one JSON object");
  sub->add_flag("--store-inputs", campaign.store_inputs,
                "Keep every sample's design point and drawn values in a new results file (by default the first "
                "16,384; readers replay the others from the campaign)");
  AddProgressOptions(*sub, campaign.quiet, campaign.progress_seconds);
  AddPoolOptions(*sub, campaign.pool);
  // Test hook standing in for the physics (PoolOptions::Testing::sample_seconds); not for users.
  sub->add_option_function<double>("--test-sample-us",
                                   [&campaign](double microseconds) {
                                     campaign.pool.testing.sample_seconds =
                                         microseconds * ringtol::units::kSecondsPerMicrosecond;
                                   })
      ->group("");
  return sub;
}

CLI::App* AddAllocate(CLI::App& app, ringtol::jobs::AllocateCommand& allocate) {
  CLI::App* sub = app.add_subcommand(
      "allocate",
      "Find the cheapest tolerance classes that meet a spec, with their cost-against-yield front, into an HDF5 "
      "results file, alone or under mpirun");
  AddInputFile(*sub, "file", allocate.file, "Allocation file (TOML)");
  sub->add_option("--out", allocate.out, "Results file (HDF5); never overwritten")->required();
  sub->add_flag("--resume", allocate.resume, "Continue --out after an interruption: compute only what it lacks");
  sub->add_flag("--json", allocate.json, "Print the recommendation as one JSON object");
  AddProgressOptions(*sub, allocate.quiet, allocate.progress_seconds);
  AddPoolOptions(*sub, allocate.pool);
  return sub;
}

CLI::App* AddBenchAllocate(CLI::App& bench, ringtol::jobs::AllocateCommand& allocate) {
  CLI::App* sub = bench.add_subcommand(
      "allocate",
      "Run an allocation file into a temporary results file and print its cost: candidates and samples per second, "
      "the share the screening rung settled; alone or under mpirun");
  AddInputFile(*sub, "file", allocate.file, "Allocation file (TOML)");
  AddProgressOptions(*sub, allocate.quiet, allocate.progress_seconds);
  AddPoolOptions(*sub, allocate.pool);
  return sub;
}

CLI::App* AddReport(CLI::App& app, ringtol::jobs::ReportCommand& report) {
  CLI::App* sub = app.add_subcommand(
      "report", "Turn a campaign's results file into a self-contained HTML report (and a JSON summary)");
  AddInputFile(*sub, "results", report.results, "Results file (HDF5) of ringtol campaign");
  sub->add_option("--out", report.out, "HTML report to write (replaced if it exists)")->required();
  sub->add_option("--json", report.json, "Also write every number of the report to this JSON file");
  ringtol::jobs::ReportOptions& options = report.options;
  sub->add_option("--confidence", options.confidence, "Level of every interval, in (0, 1)")
      ->check(CLI::Range(0.5, 0.9999))
      ->capture_default_str();
  sub->add_option("--estimator", report.estimator, "Sobol' estimators: saltelli2010-jansen, janon or martinez")
      ->capture_default_str();
  sub->add_option("--bootstrap", options.bootstrap_resamples, "Bootstrap resamples of the Sobol' intervals (0: none)")
      ->transform(DecimalIn(0, 100000))
      ->capture_default_str();
  sub->add_option("--quantile-precision", options.quantile_precision,
                  "Wanted half-width of the 99 % quantile's interval, as a fraction of it")
      ->check(CLI::Range(1e-6, 1.0))
      ->capture_default_str();
  sub->add_option("--yield-precision", options.yield_precision,
                  "Wanted half-width of the yield's interval, as a fraction (0.005 = half a point)")
      ->check(CLI::Range(1e-6, 0.5))
      ->capture_default_str();
  sub->add_option("--screening-samples", options.screening_samples,
                  "Samples read for the screening of non-Saltelli designs")
      ->transform(DecimalIn(16, std::int64_t{1} << 30))
      ->capture_default_str();
  return sub;
}

CLI::App* AddVerify(CLI::App& app, ringtol::jobs::VerifyCommand& verify) {
  CLI::App* sub = app.add_subcommand(
      "verify", "Read every dataset of a results file: what is intact, what is damaged, what --resume computes");
  AddInputFile(*sub, "results", verify.results, "Results file (HDF5) of ringtol campaign");
  sub->add_flag("--json", verify.json, "Print one JSON object");
  return sub;
}

CLI::App* AddInputs(CLI::App& app, ringtol::jobs::InputsCommand& inputs) {
  CLI::App* sub = app.add_subcommand(
      "inputs", "Print chosen samples' design points and drawn values as CSV, kept in the file or replayed");
  AddInputFile(*sub, "results", inputs.results, "Results file (HDF5) of ringtol campaign");
  sub->add_option("--samples", inputs.samples, "Samples to print: FIRST, or FIRST:END (END excluded)")->required();
  return sub;
}

CLI::App* AddJoin(CLI::App& app, ringtol::jobs::JoinCommand& join) {
  CLI::App* sub = app.add_subcommand(
      "join", "Join the shards of a results file written under mpirun into one self-contained file");
  AddInputFile(*sub, "results", join.results, "Results file (HDF5) of ringtol campaign or allocate under mpirun: an index of shards");
  sub->add_option("--out", join.out, "Write the joined file here and keep the index and its shards (default: replace the index)");
  return sub;
}

// A command whose arguments name none of its subcommands: `app`'s deepest parsed
// (sub)command, when that has subcommands of its own, with the first argument left over.
struct MissedCommand {
  std::string word;                // the argument where the subcommand should be: as typed, or empty
  std::string path;                // the commands before it: "" or "bench "
  std::vector<std::string> known;  // that command's subcommands
};

std::optional<MissedCommand> FindMissedCommand(const CLI::App& app) {
  const CLI::App* command = &app;
  std::string path;
  for (std::vector<CLI::App*> parsed = app.get_subcommands(); !parsed.empty(); parsed = command->get_subcommands()) {
    command = parsed.front();
    path += command->get_name() + " ";
  }
  const std::vector<const CLI::App*> subcommands = command->get_subcommands([](const CLI::App*) { return true; });
  const std::vector<std::string> left = command->remaining();
  if (subcommands.empty()) return std::nullopt;
  MissedCommand missed{left.empty() ? std::string() : left.front(), path, {}};
  for (const CLI::App* sub : subcommands) missed.known.push_back(sub->get_name());
  return missed;
}

// "unknown command 'bench campagin'; did you mean 'bench campaign'?; allowed: ...", or
// "missing command: `ringtol bench COMMAND`; allowed: ...".
std::string MissedCommandMessage(const MissedCommand& missed) {
  std::string message = "missing command: `ringtol " + missed.path + "COMMAND`";
  if (missed.word.starts_with('-')) {
    message = "unknown option '" + ringtol::VisibleText(missed.word) + "' where a command belongs: `ringtol " +
              missed.path + "COMMAND`";
  } else if (!missed.word.empty()) {
    message = "unknown command '" + missed.path + ringtol::VisibleText(missed.word) + "'";
    if (const std::optional<std::string> nearest = ringtol::jobs::NearestName(missed.word, missed.known)) {
      message += "; did you mean '" + missed.path + *nearest + "'?";
    }
  }
  std::string known;
  for (const std::string& name : missed.known) known += (known.empty() ? "" : ", ") + name;
  return message + "; allowed: " + known + " (`ringtol " + missed.path + "--help` says what each does)";
}

}  // namespace

int main(int argc, char** argv) {
  // A sample allocates and frees a few MB (profiles' tables, paths, the sampler's draws).
  // By default glibc hands a freed heap top above 128 kB back to the kernel and serves large
  // blocks by mmap, so every sample paid brk/munmap calls and fresh page faults: a third of
  // a linear-rung sample's time (one Realise 943 us against 298 us). Keep freed memory for
  // the next sample instead; the peak footprint is unchanged, it is only not returned.
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's largest allowed value on 64-bit
  CLI::App app{"ringtol: statistical tolerancing of rings guided by rollers.\n"
               "Simulates how roundness errors of the ring, shape errors of the rollers and\n"
               "position errors of the rollers move the ring's centre as it turns."};
  app.set_version_flag("--version", std::string("ringtol ") + RINGTOL_VERSION);
  app.require_subcommand(1);

  ringtol::jobs::SimulateCommand simulate;
  ringtol::jobs::SweepCommand sweep;
  ringtol::jobs::SampleCommand sample;
  ringtol::jobs::MatchCommand match;
  ringtol::jobs::FitCommand fit;
  bool classes_toml = false;
  ringtol::jobs::BenchDynamicsCommand dynamics;
  ringtol::jobs::BenchLadderCommand ladder;
  ringtol::jobs::BenchCampaignCommand bench_campaign;
  ringtol::jobs::CampaignCommand campaign;
  ringtol::jobs::AllocateCommand allocate;
  ringtol::jobs::AllocateCommand bench_allocate;
  ringtol::jobs::ReportCommand report;
  ringtol::jobs::VerifyCommand verify;

  const CLI::App* simulate_app = AddSimulate(app, simulate);
  const CLI::App* sweep_app = AddSweep(app, sweep);
  const CLI::App* sample_app = AddSample(app, sample);
  const CLI::App* match_app = AddMatch(app, match);
  const CLI::App* fit_app = AddFit(app, fit);
  CLI::App* classes_app = app.add_subcommand("classes", "List the tolerance classes of the built-in catalogue");
  classes_app->add_flag("--toml", classes_toml, "Print the catalogue file itself, every row with its source");
  CLI::App* bench_app = app.add_subcommand("bench", "Studies of the solvers themselves");
  bench_app->require_subcommand(1);
  const CLI::App* dynamics_app = AddBenchDynamics(*bench_app, dynamics);
  const CLI::App* ladder_app = AddBenchLadder(*bench_app, ladder);
  const CLI::App* bench_allocate_app = AddBenchAllocate(*bench_app, bench_allocate);
  const CLI::App* bench_campaign_app = AddBenchCampaign(*bench_app, bench_campaign);
  const CLI::App* campaign_app = AddCampaign(app, campaign);
  const CLI::App* allocate_app = AddAllocate(app, allocate);
  const CLI::App* report_app = AddReport(app, report);
  const CLI::App* verify_app = AddVerify(app, verify);
  ringtol::jobs::InputsCommand inputs;
  const CLI::App* inputs_app = AddInputs(app, inputs);
  ringtol::jobs::JoinCommand join;
  const CLI::App* join_app = AddJoin(app, join);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 prints help and the version and exits 0 for them; for everything else (an
    // option out of range, a missing file, an unknown option) its own codes (105, 103, ...)
    // would be one more table for a script to know: bad input is 1, as everywhere else.
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
    // A mistyped command leaves CLI11 saying only that one is required.
    if (const std::optional<MissedCommand> missed = FindMissedCommand(app)) {
      std::cerr << "ringtol: error: " << MissedCommandMessage(*missed) << "\n";
      return 1;
    }
    // CLI11 quotes values as typed: a zero-width space in one must be seen.
    std::cerr << "ringtol: error: " << ringtol::VisibleText(e.what()) << "\nRun with --help for more information.\n";
    return 1;
  }
  if (*campaign_app) {
    campaign.arguments.assign(argv, argv + argc);
    return RunMpiCommand([&] { return ringtol::jobs::RunCampaign(campaign, std::cout, std::cerr); });
  }
  if (*allocate_app) {
    allocate.arguments.assign(argv, argv + argc);
    return RunMpiCommand([&] { return ringtol::jobs::RunAllocate(allocate, std::cout, std::cerr); });
  }
  if (*bench_allocate_app) {
    return RunMpiCommand([&] { return ringtol::jobs::RunBenchAllocate(bench_allocate, std::cout, std::cerr); });
  }
  try {
    if (*simulate_app) return ringtol::jobs::RunSimulate(simulate, std::cout, std::cerr);
    if (*sweep_app) return ringtol::jobs::RunSweep(sweep, std::cout, std::cerr);
    if (*sample_app) return ringtol::jobs::RunSample(sample, std::cout);
    if (*match_app) return ringtol::jobs::RunMatch(match, std::cout);
    if (*fit_app) return ringtol::jobs::RunFit(fit, std::cout);
    if (*classes_app) return ringtol::jobs::RunClasses(classes_toml, std::cout);
    if (*dynamics_app) return ringtol::jobs::RunBenchDynamics(dynamics, std::cout);
    if (*ladder_app) return ringtol::jobs::RunBenchLadder(ladder, std::cout, std::cerr);
    if (*bench_campaign_app) return ringtol::jobs::RunBenchCampaign(bench_campaign, std::cout, std::cerr);
    if (*report_app) return ringtol::jobs::RunReport(report, std::cout);
    if (*verify_app) return ringtol::jobs::RunVerify(verify, std::cout);
    if (*inputs_app) return ringtol::jobs::RunInputs(inputs, std::cout);
    if (*join_app) return ringtol::jobs::RunJoin(join, std::cout);
  } catch (const ringtol::jobs::InputError& e) {
    std::cerr << "ringtol: error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    // Not the user's input (disk full, a broken invariant reported by an exception): still
    // a message and a status, never std::terminate.
    std::cerr << "ringtol: error: " << e.what() << "\n";
    return 2;
  } catch (...) {
    std::cerr << "ringtol: error: an unknown exception\n";
    return 2;
  }
  return 0;
}
