#include "jobs/cli/nearest_name.h"

#include <algorithm>
#include <vector>

namespace ringtol::jobs {

std::size_t EditDistance(std::string_view a, std::string_view b) {
  // distance[i][j]: between the first i characters of a and the first j of b, three rows kept.
  const std::size_t columns = b.size() + 1;
  std::vector<std::size_t> before(columns), previous(columns), current(columns);
  for (std::size_t j = 0; j < columns; ++j) previous[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    current[0] = i;
    for (std::size_t j = 1; j < columns; ++j) {
      const std::size_t substitution = previous[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      current[j] = std::min({previous[j] + 1, current[j - 1] + 1, substitution});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
        current[j] = std::min(current[j], before[j - 2] + 1);
      }
    }
    before.swap(previous);
    previous.swap(current);
  }
  return previous[b.size()];
}

std::optional<std::string> NearestName(std::string_view word, std::span<const std::string> names) {
  constexpr std::size_t kMaxEdits = 2;
  std::optional<std::string> nearest;
  std::size_t nearest_distance = kMaxEdits + 1;
  for (const std::string& name : names) {
    const std::size_t distance = EditDistance(word, name);
    if (distance < nearest_distance && 2 * distance < word.size()) {
      nearest = name;
      nearest_distance = distance;
    }
  }
  return nearest;
}

}  // namespace ringtol::jobs
