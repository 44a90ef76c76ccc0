// AllocationPlan::Space apart from the reader: the space's constructor lives in
// analysis/allocation.cpp, which programs that only read allocation files need not link.
#include "jobs/allocation/allocation_file.h"

#include <utility>
#include <vector>

namespace ringtol::jobs {

analysis::AllocationSpace AllocationPlan::Space() const {
  std::vector<std::vector<double>> costs;
  for (const ComponentChoice& choice : components) {
    std::vector<double>& component = costs.emplace_back();
    for (const AllocationOption& option : choice.options) component.push_back(option.cost);
  }
  return analysis::AllocationSpace(std::move(costs));
}

}  // namespace ringtol::jobs
