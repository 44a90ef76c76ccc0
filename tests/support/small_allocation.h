// A tolerance allocation that is quick to calibrate and to solve (low harmonic orders, few
// samples) for tests of the allocation: six candidates (ring 3 x rollers 2) on the
// article's assembly, with a screening rung and stages. Its ring's class decides the one
// constraint, D_trajectory's `quantile` <= 0.1 mm: the waterjet ring fails it, the others
// meet it.
#pragma once

#include <filesystem>
#include <string>

namespace ringtol::testing {

struct SmallAllocationOptions {
  std::string design = "monte_carlo";
  int samples = 64;
  int first_samples = 16;
  std::string search = "exhaustive";
  std::string ring_mode = "process";
};

inline std::string SmallAllocation(const SmallAllocationOptions& o = {}) {
  const std::string scene = (std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/paper/scene.toml").string();
  return "scene = \"" + scene + "\"\nseed = 5\n[design]\nkind = \"" + o.design + "\"\nsamples = " +
         std::to_string(o.samples) + "\n[tolerances.ring]\nclass = \"precise\"\nmax_order = 6\nmode = \"" +
         o.ring_mode + R"("
[tolerances.rollers]
class = "Normal"
max_order = 2
mode = "inspected"
[tolerances.roller_positions]
class = "IT7"
[tolerances.springs]
class = "pm10"
[solver]
name = "quasistatic"
path_tolerance_um = 2.0
[allocation]
first_samples = )" + std::to_string(o.first_samples) +
         "\nbatch = 2\nsearch = \"" + o.search + R"("
[[allocation.constraint]]
output = "d_trajectory_mm"
quantile = 0.9
upper_mm = 0.1
[allocation.components.ring]
options = ["waterjet", "precise", "IT7/2"]
cost = [1.0, 2.0, 4.0]
[allocation.components.rollers]
options = ["Normal", "5"]
cost = [1.0, 3.0]
)";
}

}  // namespace ringtol::testing
