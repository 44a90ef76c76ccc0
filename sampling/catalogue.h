// The tolerance catalogue: named classes a designer calls out ("Normal-class rollers, a
// waterjet-cut ring, holes IT7"), each a table of tolerance values by diameter with the
// source of every number. The shipped catalogue is jobs/inputs/catalogue.toml (read by
// jobs/inputs/catalogue_file.h); campaign files may add classes. Values here are SI.
//
// A class is looked up by name (or alias) and diameter. A diameter that no row of the
// class covers is an error, never an extrapolation: ISO 492 defines no class 4 or 2 above
// D = 400 mm, and the catalogue holds only rows whose sources were read
// (docs/tolerances.md).
#pragma once

#include <array>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "engine/enum_names.h"

namespace ringtol::sampling {

// Diameters d with over < d <= up_to [m], as ISO tables word their rows.
struct DiameterRange {
  double over = 0.0;
  double up_to = std::numeric_limits<double>::infinity();
  bool Contains(double diameter) const { return diameter > over && diameter <= up_to; }
};

// ISO 492 diameter series, which change VDsp: 9; 0 and 1; 2, 3 and 4.
enum class DiameterSeries { kSeries9, kSeries0To1, kSeries2To4 };
inline constexpr NameTable<DiameterSeries, 3> kDiameterSeriesNames = {
    {{DiameterSeries::kSeries9, "9"}, {DiameterSeries::kSeries0To1, "0-1"}, {DiameterSeries::kSeries2To4, "2-4"}}};
constexpr std::string_view DiameterSeriesName(DiameterSeries series) { return NameOf(kDiameterSeriesNames, series); }

// ISO 492 outer-ring tolerances of a radial bearing, applied to a roller's running
// surface (a track roller's outer ring).
struct RollerClassRow {
  DiameterRange outside_diameter;    // D [m]
  double kea = 0.0;                  // [m] radial runout of the assembled bearing's outer ring
  std::array<double, 3> vdsp{};      // [m] two-point diameter variation, by DiameterSeries
  double mean_diameter_lower = 0.0;  // [m] lower deviation of the mean diameter, ΔDmp (<= 0)
  double mean_diameter_upper = 0.0;  // [m] upper deviation (0 in ISO 492)
  std::string source;
};

// The roller's tolerances at one diameter and series.
struct RollerTolerance {
  double kea = 0.0;                  // [m]
  double vdsp = 0.0;                 // [m]
  double mean_diameter_lower = 0.0;  // [m]
  double mean_diameter_upper = 0.0;  // [m]
  std::string source;
};

// Circularity t of a ring bore (ISO 1101: radial width of the zone) [m].
struct RingClassRow {
  DiameterRange diameter;  // bore diameter 2R [m]
  double circularity = 0.0;
  std::string source;
};

// Position tolerance of a roller's axis: diameter of the circular zone around its nominal
// place [m], by the diameter of the rollers' centre circle.
struct PositionClassRow {
  DiameterRange diameter;
  double zone_diameter = 0.0;
  std::string source;
};

// Relative tolerances of a spring roller's spring: +-stiffness and +-preload [-].
struct SpringClassRow {
  DiameterRange diameter;  // unused: one row for any size
  double stiffness = 0.0;
  double preload = 0.0;
  std::string source;
};

template <typename Row>
struct ToleranceClass {
  std::string name;
  std::vector<std::string> aliases;  // e.g. "P0" and "ABEC 1" for Normal
  std::string description;
  std::vector<Row> rows;
};

struct ToleranceCatalogue {
  std::string version;  // the catalogue file's version string, kept with campaign results
  std::vector<ToleranceClass<RollerClassRow>> roller_classes;
  std::vector<ToleranceClass<RingClassRow>> ring_classes;
  std::vector<ToleranceClass<PositionClassRow>> position_classes;
  std::vector<ToleranceClass<SpringClassRow>> spring_classes;

  // Lookups by name or alias (case-sensitive) and diameter [m]. Throw std::invalid_argument
  // naming the class and the diameter in mm: an unknown name (listing the known ones), or
  // no row for that diameter (listing the rows there are).
  RollerTolerance Roller(std::string_view name, double outside_diameter, DiameterSeries series) const;
  RingClassRow Ring(std::string_view name, double bore_diameter) const;
  PositionClassRow Position(std::string_view name, double centre_circle_diameter) const;
  SpringClassRow Spring(std::string_view name) const;

  // Adds or replaces (same name) a class. Throws std::invalid_argument for a class without
  // rows, overlapping rows, or negative tolerances.
  void Add(ToleranceClass<RollerClassRow> c);
  void Add(ToleranceClass<RingClassRow> c);
  void Add(ToleranceClass<PositionClassRow> c);
  void Add(ToleranceClass<SpringClassRow> c);
};

}  // namespace ringtol::sampling
