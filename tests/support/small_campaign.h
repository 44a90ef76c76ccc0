// A campaign file quick to calibrate and to solve, for the tests that need a real campaign:
// a low-order ring spectrum and the rollers' positions on `scene`, `samples` Monte Carlo
// samples on the quasistatic rung, and a spec on D_trajectory. `tables` (TOML, ending in a
// newline) adds tolerance tables before [solver].
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace ringtol::testing {

inline std::string SmallCampaign(std::string_view scene, std::uint64_t seed, std::int64_t samples,
                                 std::string_view tables = "") {
  return "scene = \"" + std::string(scene) + "\"\nseed = " + std::to_string(seed) +
         "\n[design]\nkind = \"monte_carlo\"\nsamples = " + std::to_string(samples) +
         "\n[tolerances.ring]\ncircularity_mm = 0.2\nmax_order = 6\n[tolerances.roller_positions]\n"
         "zone_diameter_mm = 0.05\n" +
         std::string(tables) + "[solver]\nname = \"quasistatic\"\n[spec]\nd_trajectory_mm = 0.25\n";
}

}  // namespace ringtol::testing
