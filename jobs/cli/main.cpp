// ringtol: the command line. Parsing only; the work is in jobs/cli/commands.h.
#include <mpi.h>

#include <cstdlib>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "jobs/cli/campaign_command.h"
#include "jobs/cli/commands.h"
#include "jobs/cli/fit_command.h"
#include "jobs/inputs/input_error.h"
#include "jobs/cli/report_command.h"
#include "solvers/solver.h"

namespace {

// `ringtol campaign` is the one MPI command: it runs alone as a singleton or under mpirun.
int RunCampaignCommand(const ringtol::jobs::CampaignCommand& command) {
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
      code = ringtol::jobs::RunCampaign(command, std::cout, std::cerr);
    } catch (const ringtol::jobs::InputError& e) {
      if (rank == 0) std::cerr << "ringtol: error: " << e.what() << "\n";
      code = 1;
    } catch (const std::exception& e) {
      // A failure after the start (disk full, a lost rank): what is committed stays on disk.
      std::cerr << "ringtol: error: rank " << rank << ": " << e.what() << "; --resume continues from the file\n";
      MPI_Abort(MPI_COMM_WORLD, 2);
    }
  }
  MPI_Finalize();
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ringtol: statistical tolerancing of rings guided by rollers.\n"
               "Simulates how roundness errors of the ring, shape errors of the rollers and\n"
               "position errors of the rollers move the ring's centre as it turns."};
  app.set_version_flag("--version", std::string("ringtol ") + RINGTOL_VERSION);
  app.require_subcommand(1);
  const std::vector<std::string> solver_names = ringtol::solvers::SolverNames();
  std::string solver_help = "Solver:";
  for (const std::string& name : solver_names) solver_help += " " + name;

  ringtol::jobs::SimulateCommand simulate;
  CLI::App* simulate_app = app.add_subcommand(
      "simulate", "Simulate one revolution of one scene and print D_trajectory, Dist_init, static offset, runout");
  simulate_app->add_option("scene", simulate.scene, "Scene file (TOML)")->required()->check(CLI::ExistingFile);
  simulate_app->add_option("--solver", simulate.solver, solver_help)
      ->check(CLI::IsMember(solver_names))
      ->capture_default_str();
  simulate_app->add_option("--steps", simulate.steps, "Angles per revolution (default: chosen so no harmonic aliases)")
      ->check(CLI::Range(1, 100000000));
  simulate_app->add_flag("--json", simulate.json, "Print one JSON object");
  simulate_app->add_option("--trajectory", simulate.trajectory_csv, "Write the path to this CSV file");
  simulate_app->add_option("--relative-tolerance", simulate.relative_tolerance,
                           "Dynamic solver: integrator tolerance, > 0 and < 1")
      ->capture_default_str();
  simulate_app->add_option("--history", simulate.history_csv,
                           "Dynamic solver: write the time history over the motion law's span to this CSV file");
  simulate_app->add_option("--history-interval-ms", simulate.history_interval_ms,
                           "Dynamic solver: time between history samples [ms], > 0")
      ->capture_default_str();

  ringtol::jobs::SweepCommand sweep;
  CLI::App* sweep_app =
      app.add_subcommand("sweep", "Simulate every case of a sweep file (orders, amplitudes or named cases)");
  sweep_app->add_option("sweep", sweep.sweep, "Sweep file (TOML)")->required()->check(CLI::ExistingFile);
  sweep_app->add_option("--solver", sweep.solver, solver_help)
      ->check(CLI::IsMember(solver_names))
      ->capture_default_str();
  sweep_app->add_option("--steps", sweep.steps, "Angles per revolution (default: chosen per case)")
      ->check(CLI::Range(1, 100000000));
  sweep_app->add_flag("--json", sweep.json, "Print a JSON array, one object per case");
  sweep_app->add_option("--csv", sweep.csv, "Write one row per case to this CSV file");
  sweep_app->add_option("--relative-tolerance", sweep.relative_tolerance,
                        "Dynamic solver: integrator tolerance, > 0 and < 1")
      ->capture_default_str();

  ringtol::jobs::SampleCommand sample;
  CLI::App* sample_app = app.add_subcommand(
      "sample", "Draw the assemblies of a sampling file (tolerance classes and a design) without simulating them");
  sample_app->add_option("file", sample.file, "Sampling file (TOML)")->required()->check(CLI::ExistingFile);
  sample_app->add_option("--samples", sample.samples, "Number of samples (default: the file's design.samples)")
      ->check(CLI::Range(std::int64_t{1}, std::int64_t{1} << 40));
  sample_app->add_option("--seed", sample.seed, "Campaign seed (default: the file's)");
  sample_app->add_option("--csv", sample.csv, "Write every sample's drawn inputs to this CSV file");
  sample_app->add_option("--index", sample.index, "With --scene: the sample to write (0-based)");
  sample_app->add_option("--scene", sample.scene, "Write sample --index as a standalone scene file, to replay it");

  ringtol::jobs::FitCommand fit;
  CLI::App* fit_app = app.add_subcommand(
      "fit", "Fit a Fourier series to a roundness tester's export (angle, radius or deviation CSV)");
  fit_app->add_option("profile", fit.profile, "Profile CSV: angle_deg, radius_mm | deviation_mm | deviation_um")
      ->required()
      ->check(CLI::ExistingFile);
  fit_app->add_option("--orders", fit.orders, "Highest order fitted (1..1000)")->required();
  fit_app->add_flag("--keep-eccentricity", fit.keep_eccentricity,
                    "Keep order 1 in the fragment (by default it is the tester's set-up eccentricity)");
  fit_app->add_option("--fragment", fit.fragment, "Write the [ring] keys of a scene file to this TOML file");
  fit_app->add_flag("--json", fit.json, "Print one JSON object");

  bool classes_toml = false;
  CLI::App* classes_app = app.add_subcommand("classes", "List the tolerance classes of the built-in catalogue");
  classes_app->add_flag("--toml", classes_toml, "Print the catalogue file itself, every row with its source");

  CLI::App* bench_app = app.add_subcommand("bench", "Studies of the solvers themselves");
  bench_app->require_subcommand(1);
  ringtol::jobs::BenchDynamicsCommand dynamics;
  CLI::App* dynamics_app = bench_app->add_subcommand(
      "dynamics", "Start transient and speed: where the quasistatic answer stops being within 1 um of the dynamic one");
  dynamics_app->add_option("scene", dynamics.scene, "Scene file (TOML); its ring errors are replaced per order")
      ->required()
      ->check(CLI::ExistingFile);
  dynamics_app->add_option("--orders", dynamics.orders, "Ring orders to study (default: the article's)")
      ->check(CLI::Range(1, 1000));
  dynamics_app->add_option("--rates-deg-per-s", dynamics.rates_deg_per_s,
                           "Steady speeds to compare (default: 1 3 10 30 90 270)")
      ->check(CLI::PositiveNumber);

  ringtol::jobs::BenchLadderCommand ladder;
  CLI::App* ladder_app = bench_app->add_subcommand(
      "ladder", "Speed against accuracy of every rung and setting on the article's order and amplitude studies");
  ladder_app->add_option("scene", ladder.scene, "Scene file (TOML) whose error-free assembly the studies use")
      ->required()
      ->check(CLI::ExistingFile);
  ladder_app->add_option("--cases", ladder.cases, "orders, amplitudes or all")
      ->check(CLI::IsMember({"orders", "amplitudes", "all"}))
      ->capture_default_str();
  ladder_app->add_option("--repeats", ladder.repeats, "Timing repetitions per method and case (median)")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  ladder_app->add_flag("--explicit-full-model", ladder.explicit_full_model,
                       "Also run explicit RK4 on the full model at 65 ns (order-2 case only, about 3 minutes)");
  ladder_app->add_option("--csv", ladder.csv, "Write one row per method to this CSV file");
  ladder_app->add_option("--svg", ladder.svg, "Write the speed-against-accuracy chart to this SVG file");

  ringtol::jobs::CampaignCommand campaign;
  CLI::App* campaign_app = app.add_subcommand(
      "campaign", "Run a Monte Carlo campaign into an HDF5 results file, alone or under mpirun, and summarise it");
  campaign_app->add_option("file", campaign.file, "Campaign file (TOML)")->required()->check(CLI::ExistingFile);
  campaign_app->add_option("--out", campaign.out, "Results file (HDF5); never overwritten")->required();
  campaign_app->add_option("--samples", campaign.samples, "Number of samples (default: the file's design.samples)")
      ->check(CLI::Range(std::int64_t{1}, std::int64_t{1} << 40));
  campaign_app->add_option("--seed", campaign.seed, "Campaign seed (default: the file's)");
  campaign_app->add_flag("--resume", campaign.resume,
                         "Continue --out after an interruption, or grow it to --samples: compute only what it lacks");
  campaign_app->add_flag("--json", campaign.json, "Print the summary as one JSON object");
  campaign_app->add_flag("--quiet", campaign.quiet, "No progress on stderr");
  campaign_app->add_option("--progress-seconds", campaign.progress_seconds,
                           "Seconds between progress lines when stderr is not a terminal")
      ->capture_default_str();
  campaign_app->add_option("--chunk", campaign.pool.chunk_samples,
                           "Samples per chunk handed to a rank (default 0: adaptive)")
      ->capture_default_str();
  campaign_app->add_option("--chunk-seconds", campaign.pool.chunk_seconds, "Adaptive chunks' target duration [s]")
      ->capture_default_str();
  campaign_app->add_option("--commit-seconds", campaign.pool.commit_seconds,
                           "Longest time results wait before they are written to the file [s]")
      ->capture_default_str();
  campaign_app->add_option("--coordinator-computes", campaign.pool.coordinator_computes,
                           "Whether rank 0 also computes: 1 yes, 0 no, -1 below 16 ranks")
      ->check(CLI::Range(-1, 1))
      ->capture_default_str();
  campaign_app->add_option("--threads", campaign.pool.threads,
                           "Computing threads of rank 0 (default 0: every core alone, one under mpirun)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  // Test hooks standing in for kill -9 (tests/jobs/campaign_cli_test.cpp); not for users.
  campaign_app->add_option("--test-kill-after", campaign.pool.kill_after_committed)->group("");
  campaign_app->add_option("--test-kill-rank", campaign.pool.kill_rank)->group("");

  ringtol::jobs::ReportCommand report;
  CLI::App* report_app = app.add_subcommand(
      "report", "Turn a campaign's results file into a self-contained HTML report (and a JSON summary)");
  report_app->add_option("results", report.results, "Results file (HDF5) of ringtol campaign")
      ->required()
      ->check(CLI::ExistingFile);
  report_app->add_option("--out", report.out, "HTML report to write (replaced if it exists)")->required();
  report_app->add_option("--json", report.json, "Also write every number of the report to this JSON file");
  report_app->add_option("--confidence", report.options.confidence, "Level of every interval, in (0, 1)")
      ->check(CLI::Range(0.5, 0.9999))
      ->capture_default_str();
  report_app->add_option("--estimator", report.estimator,
                         "Sobol' estimators: saltelli2010-jansen, janon or martinez")
      ->capture_default_str();
  report_app->add_option("--bootstrap", report.options.bootstrap_resamples,
                         "Bootstrap resamples of the Sobol' intervals (0: none)")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
  report_app->add_option("--quantile-precision", report.options.quantile_precision,
                         "Wanted half-width of the 99 % quantile's interval, as a fraction of it")
      ->check(CLI::Range(1e-6, 1.0))
      ->capture_default_str();
  report_app->add_option("--yield-precision", report.options.yield_precision,
                         "Wanted half-width of the yield's interval, as a fraction (0.005 = half a point)")
      ->check(CLI::Range(1e-6, 0.5))
      ->capture_default_str();
  report_app->add_option("--screening-samples", report.options.screening_samples,
                         "Samples read for the screening of non-Saltelli designs")
      ->check(CLI::Range(std::int64_t{16}, std::int64_t{1} << 30))
      ->capture_default_str();

  CLI11_PARSE(app, argc, argv);
  if (*campaign_app) return RunCampaignCommand(campaign);
  try {
    if (*simulate_app) return ringtol::jobs::RunSimulate(simulate, std::cout);
    if (*sweep_app) return ringtol::jobs::RunSweep(sweep, std::cout);
    if (*sample_app) return ringtol::jobs::RunSample(sample, std::cout);
    if (*fit_app) return ringtol::jobs::RunFit(fit, std::cout);
    if (*classes_app) return ringtol::jobs::RunClasses(classes_toml, std::cout);
    if (*dynamics_app) return ringtol::jobs::RunBenchDynamics(dynamics, std::cout);
    if (*ladder_app) return ringtol::jobs::RunBenchLadder(ladder, std::cout, std::cerr);
    if (*report_app) return ringtol::jobs::RunReport(report, std::cout);
  } catch (const ringtol::jobs::InputError& e) {
    std::cerr << "ringtol: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
