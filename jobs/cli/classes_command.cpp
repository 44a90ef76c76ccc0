#include "jobs/cli/classes_command.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "engine/units.h"
#include "jobs/inputs/catalogue_file.h"

namespace ringtol::jobs {
namespace {

// The diameters a class's rows cover, adjacent rows joined, as ISO tables word them:
// "over 2.5 up to 800 mm", "any diameter" for one row without bounds.
template <typename Row, typename DiameterOf>
std::string Covered(const sampling::ToleranceClass<Row>& c, DiameterOf range_of) {
  std::vector<sampling::DiameterRange> ranges;
  for (const Row& row : c.rows) ranges.push_back(range_of(row));
  std::sort(ranges.begin(), ranges.end(), [](const auto& a, const auto& b) { return a.over < b.over; });
  std::vector<sampling::DiameterRange> joined;
  for (const sampling::DiameterRange& range : ranges) {
    if (!joined.empty() && joined.back().up_to == range.over) {
      joined.back().up_to = range.up_to;
    } else {
      joined.push_back(range);
    }
  }
  std::string text;
  for (const sampling::DiameterRange& range : joined) {
    if (!text.empty()) text += ", ";
    if (range.over > 0.0) text += "over " + units::ShowMillimetres(range.over) + " ";
    text += std::isinf(range.up_to) ? std::string("up to any") : "up to " + units::ShowMillimetres(range.up_to);
  }
  if (text == "up to any") return "any diameter";
  return text + " mm";
}

}  // namespace

int RunClasses(bool toml, std::ostream& out) {
  if (toml) {
    out << ShippedCatalogueText();
    return 0;
  }
  const sampling::ToleranceCatalogue c = ShippedCatalogue();
  auto names = [](const auto& k) {
    std::string text = k.name;
    for (const auto& a : k.aliases) text += ", " + a;
    return text;
  };
  const auto print = [&](const auto& k, const std::string& covered) {
    fmt::print(out, "  {:<20} {}: {}\n", names(k), k.description, covered);
  };
  fmt::print(out, "catalogue version {}\n", c.version);
  fmt::print(out, "\nrollers (ISO 492 outer ring), by outside diameter:\n");
  for (const auto& k : c.roller_classes) print(k, Covered(k, [](const auto& row) { return row.outside_diameter; }));
  fmt::print(out, "\nring bore circularity, by bore diameter:\n");
  for (const auto& k : c.ring_classes) print(k, Covered(k, [](const auto& row) { return row.diameter; }));
  fmt::print(out, "\nroller positions (zone diameter), by centre-circle diameter:\n");
  for (const auto& k : c.position_classes) print(k, Covered(k, [](const auto& row) { return row.diameter; }));
  fmt::print(out, "\nsprings:\n");
  for (const auto& k : c.spring_classes) fmt::print(out, "  {:<20} {}\n", names(k), k.description);
  fmt::print(out, "\n`ringtol classes --toml` prints every row with its source.\n");
  return 0;
}

}  // namespace ringtol::jobs
