#include "jobs/cli/fit_command.h"

#include <cmath>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "jobs/inputs/input_error.h"
#include "jobs/inputs/toml_fields.h"
#include "engine/units.h"

namespace ringtol::jobs {
namespace {

bool IsRadius(const MeasuredFit& measured) { return measured.quantity == ProfileQuantity::kRadius; }

// The fragment's orders in words, for the text output and the fragment's header.
std::string FragmentOrders(const FitCommand& command) {
  const int first = command.keep_eccentricity ? 1 : 2;
  if (first > command.orders) return "no orders";
  return first == command.orders ? fmt::format("order {}", first) : fmt::format("orders {}..{}", first, command.orders);
}

nlohmann::json FitJson(const FitCommand& command, const MeasuredFit& measured) {
  const sampling::FourierFit& fit = measured.fit;
  nlohmann::json j;
  j["profile"] = command.profile.string();
  j["points"] = fit.points;
  j["largest_gap_deg"] = units::InDegrees(fit.largest_gap);
  j["condition_number"] = fit.condition_number;
  if (IsRadius(measured)) {
    j["mean_radius_mm"] = units::InMillimetres(fit.mean);
  } else {
    j["mean_deviation_um"] = units::InMicrometres(fit.mean);
  }
  j["r_squared"] = fit.r_squared;
  j["residual_rms_um"] = units::InMicrometres(fit.residual_rms);
  j["residual_max_um"] = units::InMicrometres(fit.residual_max);
  nlohmann::json harmonics = nlohmann::json::array();
  for (std::size_t i = 0; i < fit.harmonics.size(); ++i) {
    const engine::Harmonic& h = fit.harmonics[i];
    // A NaN standard error (no residual to estimate it from) is dumped as null.
    harmonics.push_back({{"order", h.order},
                         {"amplitude_um", units::InMicrometres(h.amplitude)},
                         {"phase_deg", units::InDegrees(h.phase)},
                         {"standard_error_um", units::InMicrometres(fit.amplitude_standard_errors[i])},
                         {"set_up_eccentricity", h.order == 1}});
  }
  j["harmonics"] = std::move(harmonics);
  if (!command.fragment.empty()) j["fragment"] = command.fragment.string();
  return j;
}

void PrintFit(std::ostream& out, const FitCommand& command, const MeasuredFit& measured) {
  const sampling::FourierFit& fit = measured.fit;
  fmt::print(out, "profile           {}\n", command.profile.string());
  fmt::print(out, "points            {}\n", fit.points);
  fmt::print(out, "largest gap       {:.3f} deg\n", units::InDegrees(fit.largest_gap));
  fmt::print(out, "condition number  {:.4g}\n", fit.condition_number);
  if (IsRadius(measured)) {
    fmt::print(out, "mean radius       {:.6f} mm\n", units::InMillimetres(fit.mean));
  } else {
    fmt::print(out, "mean deviation    {:.4f} um\n", units::InMicrometres(fit.mean));
  }
  fmt::print(out, "R^2               {:.6f}\n", fit.r_squared);
  fmt::print(out, "residual          rms {:.4f} um, max {:.4f} um\n", units::InMicrometres(fit.residual_rms),
             units::InMicrometres(fit.residual_max));
  if (!command.fragment.empty()) {
    fmt::print(out, "fragment          {} ([ring] with {})\n", command.fragment.string(), FragmentOrders(command));
  }
  fmt::print(out, "\nharmonics C_n cos(n theta + phi_n)\n{:>5}  {:>12}  {:>10}  {:>17}\n", "order", "amplitude_um",
             "phase_deg", "standard_error_um");
  for (std::size_t i = 0; i < fit.harmonics.size(); ++i) {
    const engine::Harmonic& h = fit.harmonics[i];
    const double error = fit.amplitude_standard_errors[i];
    fmt::print(out, "{:>5}  {:>12.4f}  {:>10.3f}  {:>17}", h.order, units::InMicrometres(h.amplitude), units::InDegrees(h.phase),
               std::isnan(error) ? std::string("n/a") : fmt::format("{:.4f}", units::InMicrometres(error)));
    if (h.order == 1) {
      fmt::print(out, "  set-up eccentricity (centring on the tester): {}",
                 command.keep_eccentricity ? "kept by --keep-eccentricity" : "left out of --fragment");
    }
    fmt::print(out, "\n");
  }
}

std::string Fragment(const FitCommand& command, const MeasuredFit& measured) {
  const sampling::FourierFit& fit = measured.fit;
  // The form alone: a fragment pasted into a design of another nominal size keeps that
  // design's size, and the export's own size, which only the ring it was measured on has,
  // is stated for whoever wants it.
  const std::string size =
      IsRadius(measured)
          ? fmt::format("# Its mean radius is {} mm. On a scene of that ring, mean_deviation_mm = {} less its\n"
                        "# inner_radius_mm keeps its size too; or name the export: measured_profile =\n"
                        "# {{ file = \"...\", orders = {} }}.\n",
                        units::InMillimetres(fit.mean), units::InMillimetres(fit.mean), command.orders)
          : fmt::format("# Its mean deviation is {} mm from the tester's nominal: on that ring's scene,\n"
                        "# mean_deviation_mm = {} keeps its size too.\n",
                        units::InMillimetres(fit.mean), units::InMillimetres(fit.mean));
  std::string text = fmt::format(
      "# [ring] keys for a scene file (docs/usage.md, \"Measured profiles\"), written by ringtol fit from\n"
      "#   {}\n"
      "# Least-squares Fourier fit of orders 0..{} to {} points: R^2 = {:.6f}, residual rms {:.4f} um.\n"
      "# Harmonics: {} of the fit; order 1, the tester's set-up eccentricity, {}.\n"
      "# The form alone, for a ring of any nominal size: these keys replace the [ring] table's harmonics.\n"
      "{}[ring]\n",
      command.profile.string(), command.orders, fit.points, fit.r_squared, units::InMicrometres(fit.residual_rms),
      FragmentOrders(command), command.keep_eccentricity ? "is kept" : "is left out", size);
  const std::vector<engine::Harmonic> harmonics = FormHarmonics(fit, command.keep_eccentricity);
  if (harmonics.empty()) return text + "harmonics = []\n";
  text += "harmonics = [\n";
  for (const engine::Harmonic& h : harmonics) {
    text += fmt::format("  {{ order = {}, amplitude_mm = {}, phase_deg = {} }},\n", h.order, units::InMillimetres(h.amplitude),
                        units::InDegrees(h.phase));
  }
  return text + "]\n";
}

}  // namespace

int RunFit(const FitCommand& command, std::ostream& out) {
  if (command.orders < 1 || command.orders > kMaxHarmonicOrder) {
    throw InputError(fmt::format("--orders {}: out of range; allowed: an integer >= 1 and <= {}", command.orders,
                                 kMaxHarmonicOrder));
  }
  const MeasuredFit measured = FitProfileFile(command.profile, command.orders);

  // Opened only now, so a refused fit leaves an existing fragment as it was.
  std::ofstream fragment;
  if (!command.fragment.empty()) {
    const std::string name = command.fragment.string();
    std::error_code error;
    if (std::filesystem::equivalent(command.profile, command.fragment, error)) {
      throw InputError(fmt::format("--fragment {}: the profile itself; allowed: another file", name));
    }
    fragment.open(command.fragment);
    if (!fragment) {
      throw InputError(fmt::format("--fragment {}: cannot open for writing; allowed: a file in an existing, "
                                   "writable folder",
                                   name));
    }
  }

  if (command.json) {
    out << FitJson(command, measured).dump(2) << "\n";
  } else {
    PrintFit(out, command, measured);
  }
  if (fragment.is_open()) {
    fragment << Fragment(command, measured);
    fragment.close();
    if (!fragment) throw InputError(fmt::format("--fragment {}: write failed", command.fragment.string()));
  }
  return 0;
}

}  // namespace ringtol::jobs
