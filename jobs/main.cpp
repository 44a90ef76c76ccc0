// ringtol: the command line. Parsing only; the work is in jobs/commands.h.
#include <iostream>

#include <CLI/CLI.hpp>

#include "jobs/commands.h"
#include "jobs/input_error.h"
#include "solvers/solver.h"

int main(int argc, char** argv) {
  CLI::App app{"ringtol: statistical tolerancing of rings guided by rollers.\n"
               "Simulates how roundness errors of the ring, shape errors of the rollers and\n"
               "position errors of the rollers move the ring's centre as it turns."};
  app.set_version_flag("--version", std::string("ringtol ") + RINGTOL_VERSION);
  app.require_subcommand(1);
  const std::vector<std::string> solver_names = ringtol::solvers::SolverNames();

  ringtol::jobs::SimulateCommand simulate;
  CLI::App* simulate_app = app.add_subcommand(
      "simulate", "Simulate one revolution of one scene and print D_trajectory, Dist_init, static offset, runout");
  simulate_app->add_option("scene", simulate.scene, "Scene file (TOML)")->required()->check(CLI::ExistingFile);
  simulate_app->add_option("--solver", simulate.solver, "Solver: linear or quasistatic")
      ->check(CLI::IsMember(solver_names))
      ->capture_default_str();
  simulate_app->add_option("--steps", simulate.steps, "Angles per revolution (default: chosen so no harmonic aliases)")
      ->check(CLI::Range(1, 100000000));
  simulate_app->add_flag("--json", simulate.json, "Print one JSON object");
  simulate_app->add_option("--trajectory", simulate.trajectory_csv, "Write the path to this CSV file");

  ringtol::jobs::SweepCommand sweep;
  CLI::App* sweep_app =
      app.add_subcommand("sweep", "Simulate every case of a sweep file (orders, amplitudes or named cases)");
  sweep_app->add_option("sweep", sweep.sweep, "Sweep file (TOML)")->required()->check(CLI::ExistingFile);
  sweep_app->add_option("--solver", sweep.solver, "Solver: linear or quasistatic")
      ->check(CLI::IsMember(solver_names))
      ->capture_default_str();
  sweep_app->add_option("--steps", sweep.steps, "Angles per revolution (default: chosen per case)")
      ->check(CLI::Range(1, 100000000));
  sweep_app->add_flag("--json", sweep.json, "Print a JSON array, one object per case");
  sweep_app->add_option("--csv", sweep.csv, "Write one row per case to this CSV file");

  CLI11_PARSE(app, argc, argv);
  try {
    if (*simulate_app) return ringtol::jobs::RunSimulate(simulate, std::cout);
    if (*sweep_app) return ringtol::jobs::RunSweep(sweep, std::cout);
  } catch (const ringtol::jobs::InputError& e) {
    std::cerr << "ringtol: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
