#include "jobs/inputs/catalogue_file.h"

#include <stdexcept>
#include <utility>
#include <vector>

#include "jobs/inputs/catalogue_text.h"
#include "jobs/inputs/input_error.h"
#include "jobs/inputs/toml_fields.h"
#include "engine/units.h"

namespace ringtol::jobs {
namespace {

const std::string kShippedName = "catalogue.toml (built into ringtol)";

std::vector<std::string> ReadTextList(const Site& site) {
  const toml::array& array = ReadArray(site, "an array of names");
  std::vector<std::string> names;
  for (std::size_t i = 0; i < array.size(); ++i) names.push_back(ReadText(site.Element(i), "a name"));
  return names;
}

template <typename Row>
std::vector<Field<sampling::ToleranceClass<Row>>> ClassFields(std::vector<Field<Row>> row_fields) {
  using C = sampling::ToleranceClass<Row>;
  return {
      Text("name", Presence::kRequired, "a non-empty name", &C::name),
      {"aliases", Presence::kOptional, "an array of names",
       [](const Site& site, C& c) { c.aliases = ReadTextList(site); }, {}, {}},
      Text("description", Presence::kOptional, "text", &C::description),
      Sections<C>("rows", Presence::kRequired, 1, [row_fields](const TableReader& table, std::size_t, C& c) {
        Row row;
        table.Read(row_fields, row);
        c.rows.push_back(std::move(row));
      }),
  };
}

// "over" and "up to" of a row, read into its DiameterRange member.
template <typename Row>
std::vector<Field<Row>> DiameterFields(std::string_view over, std::string_view up_to,
                                       sampling::DiameterRange Row::*range) {
  return {
      {over, Presence::kRequired, ">= 0",
       [range](const Site& site, Row& row) { (row.*range).over = ReadNumber(site, AtLeast(0)) * units::kMetresPerMillimetre; },
       {}, {}},
      {up_to, Presence::kRequired, "> 0",
       [range](const Site& site, Row& row) { (row.*range).up_to = ReadNumber(site, Above(0)) * units::kMetresPerMillimetre; },
       {}, {}},
  };
}

template <typename Row>
std::vector<Field<Row>> Join(std::vector<Field<Row>> a, std::vector<Field<Row>> b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

template <typename Row>
Field<Row> Source() {
  return Text("source", Presence::kRequired, "where the numbers come from", &Row::source);
}

template <typename Row>
Field<Row> Micrometres(std::string_view key, Range range, double Row::*member) {
  return Number(key, Presence::kRequired, units::kMetresPerMicrometre, range, member);
}

template <typename Row>
void AddClasses(const TableReader& root, std::string_view key, std::vector<Field<Row>> row_fields,
                sampling::ToleranceCatalogue& catalogue) {
  if (!root.Has(key)) return;
  const std::vector<TableReader> tables = ReadTableArray(root.At(key), 1, "[[" + std::string(key) + "]] tables");
  const auto fields = ClassFields<Row>(row_fields);
  for (const TableReader& table : tables) {
    sampling::ToleranceClass<Row> c;
    table.Read(fields, c);
    try {
      catalogue.Add(std::move(c));
    } catch (const std::invalid_argument& e) {
      table.Fail("rows", e.what(), "rows that do not overlap, tolerances >= 0");
    }
  }
}

}  // namespace

void AddCatalogueClasses(const toml::table& table, const std::string& path, const std::string& source_name,
                         bool allow_version, sampling::ToleranceCatalogue& catalogue) {
  using sampling::PositionClassRow;
  using sampling::RingClassRow;
  using sampling::RollerClassRow;
  using sampling::SpringClassRow;
  const TableReader root(table, path, source_name);
  // Unknown keys are refused by reading every known one through one list.
  struct Keys {};
  std::vector<Field<Keys>> known;
  for (const std::string_view key : {"roller", "ring", "roller_position", "spring"})
    known.push_back({key, Presence::kOptional, "an array of tables", [](const Site&, Keys&) {}, {}, {}});
  if (allow_version) {
    known.push_back({"version", Presence::kRequired, "text", [&catalogue](const Site& site, Keys&) {
                       catalogue.version = ReadText(site, "text");
                     }, {}, {}});
  }
  Keys keys;
  root.Read(known, keys);

  AddClasses<RollerClassRow>(
      root, "roller",
      Join(DiameterFields("outside_diameter_over_mm", "outside_diameter_up_to_mm", &RollerClassRow::outside_diameter),
           std::vector<Field<RollerClassRow>>{
               Micrometres("kea_um", AtLeast(0), &RollerClassRow::kea),
               {"vdsp_series_9_um", Presence::kRequired, ">= 0",
                [](const Site& s, RollerClassRow& r) { r.vdsp[0] = ReadNumber(s, AtLeast(0)) * units::kMetresPerMicrometre; },
                {}, {}},
               {"vdsp_series_0_1_um", Presence::kRequired, ">= 0",
                [](const Site& s, RollerClassRow& r) { r.vdsp[1] = ReadNumber(s, AtLeast(0)) * units::kMetresPerMicrometre; },
                {}, {}},
               {"vdsp_series_2_4_um", Presence::kRequired, ">= 0",
                [](const Site& s, RollerClassRow& r) { r.vdsp[2] = ReadNumber(s, AtLeast(0)) * units::kMetresPerMicrometre; },
                {}, {}},
               Micrometres("mean_diameter_lower_um", Range{-1e6, false, 0, false}, &RollerClassRow::mean_diameter_lower),
               Micrometres("mean_diameter_upper_um", AnyFinite(), &RollerClassRow::mean_diameter_upper),
               Source<RollerClassRow>(),
           }),
      catalogue);
  AddClasses<RingClassRow>(
      root, "ring",
      Join(DiameterFields("diameter_over_mm", "diameter_up_to_mm", &RingClassRow::diameter),
           std::vector<Field<RingClassRow>>{
               Number("circularity_mm", Presence::kRequired, units::kMetresPerMillimetre, Above(0), &RingClassRow::circularity),
               Source<RingClassRow>()}),
      catalogue);
  AddClasses<PositionClassRow>(
      root, "roller_position",
      Join(DiameterFields("diameter_over_mm", "diameter_up_to_mm", &PositionClassRow::diameter),
           std::vector<Field<PositionClassRow>>{Number("zone_diameter_mm", Presence::kRequired, units::kMetresPerMillimetre,
                                                       Above(0), &PositionClassRow::zone_diameter),
                                                Source<PositionClassRow>()}),
      catalogue);
  AddClasses<SpringClassRow>(
      root, "spring",
      std::vector<Field<SpringClassRow>>{
          Number("stiffness_percent", Presence::kRequired, units::kFractionPerPercent, Between(0, 100), &SpringClassRow::stiffness),
          Number("preload_percent", Presence::kRequired, units::kFractionPerPercent, Range{0, false, 100, true},
                 &SpringClassRow::preload),
          Source<SpringClassRow>()},
      catalogue);
}

const std::string& ShippedCatalogueText() {
  static const std::string text(kCatalogueText);
  return text;
}

sampling::ToleranceCatalogue ShippedCatalogue() {
  sampling::ToleranceCatalogue catalogue;
  const toml::table document = ParseToml(ShippedCatalogueText(), kShippedName);
  AddCatalogueClasses(document, "", kShippedName, true, catalogue);
  return catalogue;
}

}  // namespace ringtol::jobs
