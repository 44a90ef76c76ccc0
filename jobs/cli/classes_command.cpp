#include "jobs/cli/classes_command.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "jobs/inputs/catalogue_file.h"

namespace ringtol::jobs {
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
  fmt::print(out, "catalogue version {}\n", c.version);
  fmt::print(out, "\nrollers (ISO 492 outer ring), by outside diameter:\n");
  for (const auto& k : c.roller_classes) fmt::print(out, "  {:<20} {} ({} rows)\n", names(k), k.description, k.rows.size());
  fmt::print(out, "\nring bore circularity:\n");
  for (const auto& k : c.ring_classes) fmt::print(out, "  {:<20} {} ({} rows)\n", names(k), k.description, k.rows.size());
  fmt::print(out, "\nroller positions (zone diameter), by centre-circle diameter:\n");
  for (const auto& k : c.position_classes)
    fmt::print(out, "  {:<20} {} ({} rows)\n", names(k), k.description, k.rows.size());
  fmt::print(out, "\nsprings:\n");
  for (const auto& k : c.spring_classes) fmt::print(out, "  {:<20} {}\n", names(k), k.description);
  fmt::print(out, "\n`ringtol classes --toml` prints every row with its source.\n");
  return 0;
}

}  // namespace ringtol::jobs
