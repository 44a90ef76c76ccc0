#include "sampling/catalogue.h"
#include "engine/units.h"
#include "engine/visible_text.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ringtol::sampling {
namespace {

// A class name in a message: a user's catalogue or file may hide a zero-width space in it.
std::string Quoted(std::string_view name) { return "'" + VisibleText(name) + "'"; }

std::string Describe(const DiameterRange& r) {
  if (r.over <= 0.0 && std::isinf(r.up_to)) return "any";
  return units::ShowMillimetres(r.over) + "-" + units::ShowMillimetres(r.up_to);
}

template <typename Row>
const ToleranceClass<Row>& Find(const std::vector<ToleranceClass<Row>>& classes, std::string_view name,
                                std::string_view kind) {
  for (const auto& c : classes) {
    if (c.name == name || std::find(c.aliases.begin(), c.aliases.end(), name) != c.aliases.end()) return c;
  }
  std::string known;
  for (const auto& c : classes) known += (known.empty() ? "" : ", ") + VisibleText(c.name);
  throw std::invalid_argument("unknown " + std::string(kind) + " class " + Quoted(name) + "; known: " + known);
}

template <typename Row, typename DiameterOf>
const Row& FindRow(const ToleranceClass<Row>& c, double diameter, std::string_view kind, DiameterOf range_of) {
  for (const Row& row : c.rows) {
    if (range_of(row).Contains(diameter)) return row;
  }
  std::string rows;
  for (const Row& row : c.rows) rows += (rows.empty() ? "" : ", ") + Describe(range_of(row));
  throw std::invalid_argument(std::string(kind) + " class " + Quoted(c.name) + " has no value for diameter " +
                              units::ShowMillimetres(diameter) + " mm (its rows cover " + rows +
                              " mm); the catalogue does not extrapolate: choose another class or give "
                              "the "
                              "tolerance as a number");
}

template <typename Row, typename DiameterOf, typename Values>
void AddClass(std::vector<ToleranceClass<Row>>& classes, ToleranceClass<Row> c, DiameterOf range_of, Values values) {
  if (c.name.empty()) throw std::invalid_argument("a tolerance class needs a name");
  if (c.rows.empty()) throw std::invalid_argument("tolerance class " + Quoted(c.name) + " has no rows");
  for (std::size_t i = 0; i < c.rows.size(); ++i) {
    const DiameterRange& a = range_of(c.rows[i]);
    if (!(a.over >= 0.0 && a.up_to > a.over))
      throw std::invalid_argument("tolerance class " + Quoted(c.name) + ": diameter row " + Describe(a) +
                                  " mm is empty or negative");
    for (const double v : values(c.rows[i])) {
      if (!(v >= 0.0) || !std::isfinite(v))
        throw std::invalid_argument("tolerance class " + Quoted(c.name) + ", row " + Describe(a) +
                                    " mm: tolerances must be finite and >= 0");
    }
    for (std::size_t j = 0; j < i; ++j) {
      const DiameterRange& b = range_of(c.rows[j]);
      if (a.over < b.up_to && b.over < a.up_to)
        throw std::invalid_argument("tolerance class " + Quoted(c.name) + ": rows " + Describe(b) + " and " + Describe(a) +
                                    " mm overlap");
    }
  }
  std::erase_if(classes, [&](const ToleranceClass<Row>& old) { return old.name == c.name; });
  classes.push_back(std::move(c));
}

}  // namespace

RollerTolerance ToleranceCatalogue::Roller(std::string_view name, double outside_diameter,
                                           DiameterSeries series) const {
  const auto& c = Find(roller_classes, name, "roller (ISO 492)");
  const RollerClassRow& row =
      FindRow(c, outside_diameter, "roller (ISO 492)", [](const RollerClassRow& r) { return r.outside_diameter; });
  return {row.kea, row.vdsp[static_cast<std::size_t>(series)], row.mean_diameter_lower, row.mean_diameter_upper,
          row.source};
}

RingClassRow ToleranceCatalogue::Ring(std::string_view name, double bore_diameter) const {
  return FindRow(Find(ring_classes, name, "ring circularity"), bore_diameter, "ring circularity",
                 [](const RingClassRow& r) { return r.diameter; });
}

PositionClassRow ToleranceCatalogue::Position(std::string_view name, double centre_circle_diameter) const {
  return FindRow(Find(position_classes, name, "roller position"), centre_circle_diameter, "roller position",
                 [](const PositionClassRow& r) { return r.diameter; });
}

SpringClassRow ToleranceCatalogue::Spring(std::string_view name) const {
  return Find(spring_classes, name, "spring").rows.front();
}

void ToleranceCatalogue::Add(ToleranceClass<RollerClassRow> c) {
  AddClass(
      roller_classes, std::move(c), [](const RollerClassRow& r) { return r.outside_diameter; },
      [](const RollerClassRow& r) {
        return std::vector<double>{r.kea,
                                   r.vdsp[0],
                                   r.vdsp[1],
                                   r.vdsp[2],
                                   -r.mean_diameter_lower,
                                   r.mean_diameter_upper - r.mean_diameter_lower};
      });
}
void ToleranceCatalogue::Add(ToleranceClass<RingClassRow> c) {
  AddClass(
      ring_classes, std::move(c), [](const RingClassRow& r) { return r.diameter; },
      [](const RingClassRow& r) { return std::vector<double>{r.circularity}; });
}
void ToleranceCatalogue::Add(ToleranceClass<PositionClassRow> c) {
  AddClass(
      position_classes, std::move(c), [](const PositionClassRow& r) { return r.diameter; },
      [](const PositionClassRow& r) { return std::vector<double>{r.zone_diameter}; });
}
void ToleranceCatalogue::Add(ToleranceClass<SpringClassRow> c) {
  AddClass(
      spring_classes, std::move(c), [](const SpringClassRow& r) { return r.diameter; },
      [](const SpringClassRow& r) {
        return std::vector<double>{r.stiffness, r.preload};
      });
}

}  // namespace ringtol::sampling
