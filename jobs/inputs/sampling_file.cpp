#include "jobs/inputs/sampling_file.h"

#include <zlib.h>

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>
#include <type_traits>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "jobs/inputs/catalogue_file.h"
#include "jobs/inputs/input_error.h"
#include "jobs/inputs/profile_csv.h"
#include "jobs/inputs/scene_file.h"
#include "jobs/inputs/toml_fields.h"
#include "engine/units.h"

namespace ringtol::jobs {
namespace {

using sampling::ToleranceMode;

// Default spectrum cutoffs [undulations per revolution]: the ring's is the classic 50 UPR
// roundness filter; a roller's order n passes the contact about n R / r_b times a ring
// revolution, each pass costing solver steps, so its cutoff is low (docs/tolerances.md §7.2).
constexpr int kRingMaxOrder = 50;
constexpr int kRollerMaxOrder = 8;

// Keys every tolerance table has.
struct Common {
  std::optional<std::string> class_name;
  ToleranceMode mode = ToleranceMode::kProcess;
  double cp = 1.0;
  int max_order = 0;  // set by ToleranceSection to the component's default
  double exponent = 1.0;
  std::vector<double> relative_scales;

  sampling::Capability capability() const { return {mode, cp}; }
};

// `class` and `mode`, as every tolerance table and a population's comparison read them.
template <typename T>
Field<T> ClassField() {
  return Field<T>{"class", Presence::kOptional, "a class name of the catalogue (`ringtol classes` lists them)",
                  [](const Site& site, T& t) { t.class_name = ReadText(site, "a class name"); }, {}, {}};
}
template <typename T>
Field<T> ModeField() {
  return Choice<T, ToleranceMode>("mode", Presence::kOptional, sampling::kToleranceModeNames, &T::mode);
}

template <typename T>
std::vector<Field<T>> CommonFields(bool spectrum) {
  std::vector<Field<T>> fields{
      ClassField<T>(),
      ModeField<T>(),
      Number<T, double>("capability_cp", Presence::kOptional, kSameUnit, Range{0, true, 1000, false}, &T::cp),
  };
  if (spectrum) {
    fields.push_back(Integer<T>("max_order", Presence::kOptional, Between(2, kMaxHarmonicOrder), &T::max_order));
    fields.push_back(Number<T, double>("exponent", Presence::kOptional, kSameUnit, AtLeast(0), &T::exponent));
    fields.push_back(Field<T>{"relative_scales", Presence::kOptional, "an array of numbers >= 0, one per order 2..max_order",
                              [](const Site& site, T& t) {
                                const toml::array& array = ReadArray(site, "an array of numbers >= 0");
                                t.relative_scales.clear();
                                for (std::size_t i = 0; i < array.size(); ++i)
                                  t.relative_scales.push_back(ReadNumber(site.Element(i), AtLeast(0)));
                              },
                              {}, {}});
  }
  return fields;
}

template <typename T>
std::vector<Field<T>> With(std::vector<Field<T>> fields, std::vector<Field<T>> more) {
  fields.insert(fields.end(), more.begin(), more.end());
  return fields;
}

// Exactly one of `class` and the direct keys; returns whether a class was given.
bool ClassOrNumbers(const TableReader& table, const Common& common, std::vector<std::string_view> direct) {
  bool any = false, all = true;
  for (const std::string_view key : direct) {
    if (table.Has(key)) {
      any = true;
    } else {
      all = false;
    }
  }
  std::string names;
  for (const std::string_view key : direct) names += (names.empty() ? "" : ", ") + std::string(key);
  if (common.class_name && any)
    table.Fail("class", "given together with " + names, "either class or " + names);
  if (!common.class_name && !(any && all))
    table.FailAbout(direct.front(), table.KeyPath("class") + " or " + names, "missing",
                    "either class or all of " + names);
  return common.class_name.has_value();
}

sampling::SpectrumShape Spectrum(const TableReader& table, const Common& c) {
  sampling::SpectrumShape shape{2, c.max_order, c.exponent, c.relative_scales};
  if (!shape.relative_scales.empty() && static_cast<int>(shape.relative_scales.size()) != shape.order_count())
    table.Fail("relative_scales", "has " + std::to_string(shape.relative_scales.size()) + " values",
               "one per order 2.." + std::to_string(shape.max_order) + ": " + std::to_string(shape.order_count()));
  if (table.Has("relative_scales") && table.Has("exponent"))
    table.Fail("exponent", "given together with relative_scales", "one of exponent or relative_scales");
  return shape;
}

// A class lookup's std::invalid_argument as an InputError at `class`.
template <typename F>
auto Lookup(const TableReader& table, F lookup) {
  try {
    return lookup();
  } catch (const std::invalid_argument& e) {
    table.Fail("class", e.what(), "a class with a row for this diameter");
  }
}

constexpr std::string_view kRollerNamesAllowed = "an array of the scene's roller names, each once";

// `rollers = [...]`: scene roller names, checked against the scene by RollerIndices.
template <typename Input>
Field<Input> RollerNamesField(std::optional<std::vector<std::string>> Input::*names) {
  return {"rollers", Presence::kOptional, std::string(kRollerNamesAllowed),
          [names](const Site& site, Input& in) {
            const toml::array& list = ReadArray(site, kRollerNamesAllowed);
            if (list.empty()) site.Fail("names no roller", kRollerNamesAllowed);
            std::vector<std::string> read;
            for (std::size_t k = 0; k < list.size(); ++k) read.push_back(ReadText(site.Element(k), kRollerNamesAllowed));
            in.*names = std::move(read);
          },
          {}, {}};
}

// The scene rollers `names` names, ascending; every roller when `names` is absent.
std::vector<std::size_t> RollerIndices(const TableReader& t, const std::optional<std::vector<std::string>>& names,
                                       const engine::Scene& scene) {
  std::vector<std::string> known;
  for (const engine::Roller& roller : scene.rollers) known.push_back(roller.name);
  std::vector<std::size_t> indices;
  for (std::size_t i = 0; i < known.size(); ++i) {
    if (!names || std::find(names->begin(), names->end(), known[i]) != names->end()) indices.push_back(i);
  }
  if (!names) return indices;
  for (std::size_t k = 0; k < names->size(); ++k) {
    const std::string& name = (*names)[k];
    const bool found = std::find(known.begin(), known.end(), name) != known.end();
    const bool again = std::find(names->begin(), names->begin() + static_cast<std::ptrdiff_t>(k), name) !=
                       names->begin() + static_cast<std::ptrdiff_t>(k);
    if (!found || again) {
      t.Fail("rollers", fmt::format("{} \"{}\"", found ? "names twice" : "names no roller", name),
             fmt::format("{}: {}", kRollerNamesAllowed, fmt::join(known, ", ")));
    }
  }
  return indices;
}

struct RingToleranceInput : Common {
  double circularity = 0.0;
};
struct RollerToleranceInput : Common {
  std::string series = "9";
  double kea = 0.0, vdsp = 0.0, lower = 0.0, upper = 0.0;
  // The rollers the table draws, by name: every roller when absent. A measured roller left
  // out keeps the scene's outline, so that a campaign judges it alone (a disposition).
  std::optional<std::vector<std::string>> names;
};

struct PositionToleranceInput : Common {
  double zone = 0.0;
};
struct SpringToleranceInput : Common {
  double stiffness = 0.0, preload = 0.0;
};

struct FileInput {
  std::string scene;
  std::int64_t seed = 1;
  std::string design_kind = "monte_carlo";
  int samples = 1000;
  int replicates = 1;
  bool randomise = true;
  std::string base = "sobol";
  std::string groups = "source";
};

sampling::DiameterSeries Series(const TableReader& table, const std::string& text) {
  if (text == "9") return sampling::DiameterSeries::kSeries9;
  if (text == "0" || text == "1") return sampling::DiameterSeries::kSeries0To1;
  if (text == "2" || text == "3" || text == "4") return sampling::DiameterSeries::kSeries2To4;
  table.Fail("diameter_series", "unknown series", "\"9\", \"0\", \"1\", \"2\", \"3\", \"4\"");
}

// The reader of sub-table `key` (present and checked to be a table by Read), or of
// `parent` itself when absent, so that checks after Read can name keys in either.
TableReader SubTable(const TableReader& parent, std::string_view key) {
  const toml::table* table = parent.table().get_as<toml::table>(key);
  return table ? TableReader(*table, parent.KeyPath(key), parent.file()) : parent;
}


// The four [tolerances.*] tables as read, before the catalogue resolves them.
struct ToleranceInputs {
  std::optional<RingToleranceInput> ring;
  std::optional<RollerToleranceInput> rollers;
  std::optional<PositionToleranceInput> positions;
  std::optional<SpringToleranceInput> springs;
};

std::vector<Field<FileInput>> DesignFields() {
  return {
      Text("kind", Presence::kOptional, NameList(sampling::kDesignNames), &FileInput::design_kind),
      Integer("samples", Presence::kOptional, Between(1, 2147483647), &FileInput::samples),
      Integer("replicates", Presence::kOptional, Between(1, 1000000), &FileInput::replicates),
      Flag("randomise", Presence::kOptional, &FileInput::randomise),
      Text("base", Presence::kOptional, "\"sobol\" or \"monte_carlo\"", &FileInput::base),
      Text("groups", Presence::kOptional, NameList(sampling::kInputGroupingNames), &FileInput::groups),
  };
}

// One [tolerances.*] table: the fields every component has (class, spectrum when it has
// one, capability) and its own, read into its slot.
// max_order: the spectrum's default cutoff, 0 for a component without a spectrum.
template <typename Input>
Field<ToleranceInputs> ToleranceSection(std::string_view key, int max_order, std::vector<Field<Input>> own,
                                        std::optional<Input> ToleranceInputs::*slot) {
  return Section<ToleranceInputs>(key, Presence::kOptional,
                                  [max_order, own = std::move(own), slot](const TableReader& t, ToleranceInputs& in) {
                                    Input read;
                                    read.max_order = max_order;
                                    t.Read(With(CommonFields<Input>(max_order > 0), own), read);
                                    in.*slot = read;
                                  });
}

std::vector<Field<ToleranceInputs>> ToleranceFields() {
  const double um = units::kMetresPerMicrometre;
  return {
      ToleranceSection<RingToleranceInput>("ring", kRingMaxOrder,
                                  {Number("circularity_mm", Presence::kOptional, units::kMetresPerMillimetre, Above(0),
                                          &RingToleranceInput::circularity)
                                       .WithoutDefault()},
                                  &ToleranceInputs::ring),
      ToleranceSection<RollerToleranceInput>(
          "rollers", kRollerMaxOrder,
          {Text("diameter_series", Presence::kOptional, "\"9\", \"0\", \"1\", \"2\", \"3\", \"4\"", &RollerToleranceInput::series),
           RollerNamesField(&RollerToleranceInput::names),
           Number("kea_um", Presence::kOptional, um, AtLeast(0), &RollerToleranceInput::kea).WithoutDefault(),
           Number("vdsp_um", Presence::kOptional, um, AtLeast(0), &RollerToleranceInput::vdsp).WithoutDefault(),
           Number("mean_diameter_lower_um", Presence::kOptional, um, AnyFinite(), &RollerToleranceInput::lower).WithoutDefault(),
           Number("mean_diameter_upper_um", Presence::kOptional, um, AnyFinite(), &RollerToleranceInput::upper).WithoutDefault()},
          &ToleranceInputs::rollers),
      ToleranceSection<PositionToleranceInput>("roller_positions", 0,
                                      {Number("zone_diameter_mm", Presence::kOptional, units::kMetresPerMillimetre,
                                              Above(0), &PositionToleranceInput::zone)
                                           .WithoutDefault()},
                                      &ToleranceInputs::positions),
      ToleranceSection<SpringToleranceInput>(
          "springs", 0,
          {Number("stiffness_percent", Presence::kOptional, units::kFractionPerPercent, Between(0, 100),
                  &SpringToleranceInput::stiffness)
               .WithoutDefault(),
           Number("preload_percent", Presence::kOptional, units::kFractionPerPercent, Range{0, false, 100, true},
                  &SpringToleranceInput::preload)
               .WithoutDefault()},
          &ToleranceInputs::springs),
  };
}

// zlib's CRC-32 of a file's bytes: what tells a changed export from the one a campaign ran with.
std::uint32_t FileCrc32(const std::filesystem::path& file) {
  const std::string bytes = ReadTextFile(file);
  return static_cast<std::uint32_t>(
      crc32(crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(bytes.size())));
}

// [population.ring], [population.rollers]: parts drawn from measured exports
// (sampling::PartPopulation), each fitted as a scene's measured_profile is.
struct PopulationInput {
  std::vector<std::filesystem::path> profiles;  // resolved against the sampling file's folder
  std::optional<std::filesystem::path> folder;
  int orders = 0;
  bool keep_eccentricity = false;
  ProfileReference reference = ProfileReference::kNominal;
  sampling::PopulationDraw draw = sampling::PopulationDraw::kResample;
  std::optional<std::string> class_name;  // compared with in the report only
  ToleranceMode mode = ToleranceMode::kProcess;
  // [population.rollers]: the rollers the batch fills, by name; every roller when absent.
  std::optional<std::vector<std::string>> names;
};

constexpr std::string_view kPopulationProfilesAllowed =
    "an array of paths of existing CSV files (docs/inputs.md, \"Profile CSV files\"), relative to this file's folder";
constexpr std::string_view kPopulationFolderAllowed =
    "the path of a folder of CSV files (docs/inputs.md, \"Profile CSV files\"), relative to this file's folder";

// `ring`: [population.ring]'s, else [population.rollers]', which may name its rollers.
std::vector<Field<PopulationInput>> PopulationFields(const std::filesystem::path& folder, bool ring) {
  std::vector<Field<PopulationInput>> fields{
      Field<PopulationInput>{"profiles", Presence::kOptional, std::string(kPopulationProfilesAllowed),
                                 [folder](const Site& site, PopulationInput& in) {
                                   const toml::array& list = ReadArray(site, kPopulationProfilesAllowed);
                                   if (list.empty()) site.Fail("no profiles", kPopulationProfilesAllowed);
                                   for (std::size_t k = 0; k < list.size(); ++k) {
                                     in.profiles.push_back(
                                         ReadProfilePath(site.Element(k), folder, kPopulationProfilesAllowed));
                                   }
                                 },
                                 {}, {}},
      Field<PopulationInput>{"folder", Presence::kOptional, std::string(kPopulationFolderAllowed),
                                 [folder](const Site& site, PopulationInput& in) {
                                   const std::filesystem::path path = folder / ReadText(site, kPopulationFolderAllowed);
                                   std::error_code error;
                                   if (!std::filesystem::is_directory(path, error)) {
                                     site.Fail("no such folder: " + path.string(), kPopulationFolderAllowed);
                                   }
                                   in.folder = path;
                                 },
                                 {}, {}},
      Integer("orders", Presence::kRequired, Between(1.0, kMaxHarmonicOrder), &PopulationInput::orders),
      Flag("keep_eccentricity", Presence::kOptional, &PopulationInput::keep_eccentricity),
      Choice("reference", Presence::kOptional, kProfileReferenceNames, &PopulationInput::reference),
      Choice("draw", Presence::kOptional, sampling::kPopulationDrawNames, &PopulationInput::draw),
      ClassField<PopulationInput>(),
      ModeField<PopulationInput>(),
  };
  if (!ring) fields.push_back(RollerNamesField(&PopulationInput::names));
  return fields;
}

// The population's parts (`ring`: the ring's, else the rollers'), fitted in the order listed
// (a folder's *.csv files by name), and what identifies it: a line of the fit's settings,
// then a line per part with its file's CRC-32, appended to plan.population.
// `classed`: whether [tolerances.ring] draws the ring too, which the file may not; the
// rollers' class may draw only rollers the batch does not fill.
void ResolvePopulation(const TableReader& table, PopulationInput in, bool ring, bool classed, SamplingPlan& plan) {
  if (ring && classed) {
    table.Fail("draw", "draws the ring, and [tolerances.ring] draws it too",
               "one of [population.ring] and [tolerances.ring]");
  }
  const std::vector<engine::Roller>& rollers = plan.scene.rollers;
  const std::vector<std::size_t> filled = ring ? std::vector<std::size_t>() : RollerIndices(table, in.names, plan.scene);
  for (const std::size_t i : filled) {
    if (i < plan.tolerances.roller_shapes.size() && plan.tolerances.roller_shapes[i]) {
      table.FailAbout(in.names ? "rollers" : "draw", "population.rollers",
                      fmt::format("fills roller \"{}\", and [tolerances.rollers] draws it too", rollers[i].name),
                      "disjoint rollers: rollers = [...] in [tolerances.rollers] and [population.rollers]");
    }
  }
  table.RequireExactlyOne("profiles", "folder", std::string(kPopulationProfilesAllowed) + ", or folder = " +
                                                    std::string(kPopulationFolderAllowed));
  if (in.folder) {
    for (const auto& entry : std::filesystem::directory_iterator(*in.folder)) {
      if (entry.is_regular_file() && entry.path().extension() == ".csv") in.profiles.push_back(entry.path());
    }
    std::sort(in.profiles.begin(), in.profiles.end());
    if (in.profiles.empty()) table.Fail("folder", "holds no .csv file", kPopulationFolderAllowed);
  }
  const std::size_t least = in.draw == sampling::PopulationDraw::kModel ? 2 : 1;
  if (in.profiles.size() < least) {
    table.Fail("draw", fmt::format("needs at least {} parts, and the population has {}", least, in.profiles.size()),
               "\"resample\" for a single part, or more profiles");
  }
  if (!ring) {
    const engine::Roller& first = rollers[filled.front()];
    for (const std::size_t i : filled) {
      if (rollers[i].outline.radius() == first.outline.radius()) continue;
      table.FailAbout("draw", "population.rollers",
                      fmt::format("the rollers {} and {} differ in radius_mm ({} and {} mm)", first.name,
                                  rollers[i].name, units::InMillimetres(first.outline.radius()),
                                  units::InMillimetres(rollers[i].outline.radius())),
                      "rollers of one size: a batch is of one size");
    }
    if (in.draw == sampling::PopulationDraw::kResample && in.profiles.size() < filled.size()) {
      table.Fail("draw", fmt::format("takes each part once, and the batch has {} parts for {} rollers",
                                     in.profiles.size(), filled.size()),
                 "\"model\", or at least as many profiles as rollers it fills");
    }
  }
  const double radius = ring ? plan.scene.ring.inner.radius() : rollers[filled.front()].outline.radius();
  const std::string_view part_name = ring ? "ring" : "roller";
  const std::string radius_key = ring ? "ring.inner_radius_mm" : "rollers[].radius_mm";
  sampling::PartPopulation population;
  population.draw = in.draw;
  std::string identity = fmt::format("population.{}: draw = {}, orders = {}, keep_eccentricity = {}, reference = {}\n",
                                     ring ? "ring" : "rollers", NameOf(sampling::kPopulationDrawNames, in.draw),
                                     in.orders, in.keep_eccentricity, NameOf(kProfileReferenceNames, in.reference));
  // Only where named, so that a campaign that fills every roller keeps the identity it had.
  if (in.names) identity.insert(identity.size() - 1, fmt::format(", rollers = {}", fmt::join(*in.names, ", ")));
  for (const std::filesystem::path& file : in.profiles) {
    const std::string key = in.folder ? "folder" : "profiles";
    MeasuredFit measured;
    try {
      measured = FitProfileFile(file, in.orders, radius, part_name);
    } catch (const InputError& error) {
      table.FailAbout(key, table.KeyPath(key), error.what(), "profiles that read and fit (docs/inputs.md)");
    }
    sampling::MeasuredPart part{file.filename().string(), 0.0, FormHarmonics(measured.fit, in.keep_eccentricity)};
    if (in.reference == ProfileReference::kNominal) {
      if (const std::string other = OtherPartReason(measured, radius, file.string(), radius_key, part_name);
          !other.empty()) {
        table.FailAbout(key, table.KeyPath(key), other,
                        fmt::format("reference = \"own_mean\" to take the parts' form alone, or profiles of {}s of this size",
                                    part_name));
      }
      part.mean_deviation = MeanDeviation(measured, radius);
    }
    identity += fmt::format("{} crc32 {:08x}\n", file.filename().string(), FileCrc32(file));
    population.parts.push_back(std::move(part));
  }
  if (in.class_name) {
    // Refused here, as a [tolerances.*] class is, rather than when a report first compares.
    Lookup(table, [&] {
      return ToleranceOfClass(plan, ring ? sampling::ErrorSource::kRingShape : sampling::ErrorSource::kRollerShape,
                              *in.class_name, in.mode);
    });
  }
  (ring ? plan.ring_population : plan.roller_population) =
      PopulationSettings{in.orders, in.keep_eccentricity, in.reference == ProfileReference::kNominal, in.class_name,
                         in.mode};
  (ring ? plan.tolerances.ring_population : plan.tolerances.roller_population) = std::move(population);
  if (!ring && in.names) plan.tolerances.batch_rollers = filled;
  plan.population += identity;
}

// [design], checked against the names the sampling library knows.
void ResolveDesign(const TableReader& root, const FileInput& in, SamplingPlan& plan) {
  const TableReader design = SubTable(root, "design");
  using sampling::DesignKind;
  auto kind_of = [&](const std::string& name, std::string_view key, bool base) {
    const std::optional<DesignKind> kind = ValueNamed(sampling::kDesignNames, name);
    if (kind && (!base || kind == DesignKind::kSobol || kind == DesignKind::kMonteCarlo)) return *kind;
    design.Fail(key, "unknown design", base ? "\"sobol\", \"monte_carlo\"" : NameList(sampling::kDesignNames));
  };
  plan.design.kind = kind_of(in.design_kind, "kind", false);
  plan.design.seed = plan.seed;
  plan.design.latin_samples = in.samples;
  plan.design.replicates = in.replicates;
  plan.design.randomise = in.randomise;
  plan.design.saltelli_base = kind_of(in.base, "base", true);
  const std::optional<sampling::InputGrouping> grouping = ValueNamed(sampling::kInputGroupingNames, in.groups);
  if (!grouping) design.Fail("groups", "unknown grouping", NameList(sampling::kInputGroupingNames));
  plan.grouping = *grouping;
  if (plan.design.kind != DesignKind::kSobol && design.Has("replicates") && in.replicates != 1)
    design.Fail("replicates", "applies to kind = \"sobol\" only", "1 for kind = \"" + in.design_kind + "\"");
}

// A class looked up at every part's diameter (ReadSamplingFile's rule): the numbers the
// class sets, the other fields left to the caller. Throw the catalogue's
// std::invalid_argument for an unknown class or a diameter no row covers.
sampling::RingFormTolerance RingOfClass(const SamplingPlan& plan, const std::string& name) {
  sampling::RingFormTolerance r;
  r.class_name = name;
  r.circularity = plan.catalogue.Ring(name, 2 * plan.scene.ring.inner.radius()).circularity;
  return r;
}

std::vector<sampling::RollerShapeTolerance> RollersOfClass(const SamplingPlan& plan, const std::string& name,
                                                           sampling::DiameterSeries series) {
  std::vector<sampling::RollerShapeTolerance> rollers;
  for (const engine::Roller& roller : plan.scene.rollers) {
    const sampling::RollerTolerance row = plan.catalogue.Roller(name, 2 * roller.outline.radius(), series);
    rollers.push_back({name, row.kea, row.vdsp, row.mean_diameter_lower, row.mean_diameter_upper, {}, {}});
  }
  return rollers;
}

std::vector<sampling::PositionTolerance> PositionsOfClass(const SamplingPlan& plan, const std::string& name) {
  std::vector<sampling::PositionTolerance> positions;
  for (const engine::Roller& roller : plan.scene.rollers)
    positions.push_back({name, plan.catalogue.Position(name, 2 * roller.centre_radius).zone_diameter, {}});
  return positions;
}

// One spring tolerance per spring roller; fixed rollers keep an empty slot.
std::vector<std::optional<sampling::SpringTolerance>> SpringsOf(const engine::Scene& scene,
                                                               const sampling::SpringTolerance& spring) {
  std::vector<std::optional<sampling::SpringTolerance>> springs;
  for (const engine::Roller& roller : scene.rollers) {
    springs.push_back(roller.mount == engine::RollerMount::kSpring ? std::optional(spring) : std::nullopt);
  }
  return springs;
}

std::vector<std::optional<sampling::SpringTolerance>> SpringsOfClass(const SamplingPlan& plan,
                                                                     const std::string& name) {
  const sampling::SpringClassRow row = plan.catalogue.Spring(name);
  return SpringsOf(plan.scene, {name, row.stiffness, row.preload, {}});
}

// [tolerances.ring] resolved against the catalogue at the ring's diameter.
void ResolveRing(const TableReader& t, const RingToleranceInput& in, SamplingPlan& plan) {
  sampling::RingFormTolerance r;
  if (ClassOrNumbers(t, in, {"circularity_mm"})) {
    r = Lookup(t, [&] { return RingOfClass(plan, *in.class_name); });
  } else {
    r.circularity = in.circularity;
  }
  r.spectrum = Spectrum(t, in);
  r.capability = in.capability();
  plan.tolerances.ring = r;
}

// [tolerances.rollers]: one tolerance per roller, each at its own diameter.
void ResolveRollers(const TableReader& t, const RollerToleranceInput& in, SamplingPlan& plan) {
  const std::size_t count = plan.scene.rollers.size();
  plan.roller_series = Series(t, in.series);
  const bool by_class = ClassOrNumbers(t, in, {"kea_um", "vdsp_um", "mean_diameter_lower_um", "mean_diameter_upper_um"});
  if (!by_class && in.lower > in.upper)
    t.Fail("mean_diameter_lower_um", "is above mean_diameter_upper_um", "<= mean_diameter_upper_um");
  std::vector<sampling::RollerShapeTolerance> rollers =
      by_class ? Lookup(t, [&] { return RollersOfClass(plan, *in.class_name, plan.roller_series); })
               : std::vector<sampling::RollerShapeTolerance>(count, {"", in.kea, in.vdsp, in.lower, in.upper, {}, {}});
  const std::vector<std::size_t> drawn = RollerIndices(t, in.names, plan.scene);
  for (std::size_t i = 0; i < rollers.size(); ++i) {
    sampling::RollerShapeTolerance& r = rollers[i];
    r.form = Spectrum(t, in);
    r.capability = in.capability();
    const bool listed = std::binary_search(drawn.begin(), drawn.end(), i);
    plan.tolerances.roller_shapes.push_back(listed ? std::optional(r) : std::nullopt);
  }
}

// [tolerances.roller_positions]: one zone per roller, on its centre circle.
void ResolvePositions(const TableReader& t, const PositionToleranceInput& in, SamplingPlan& plan) {
  const std::size_t count = plan.scene.rollers.size();
  std::vector<sampling::PositionTolerance> positions =
      ClassOrNumbers(t, in, {"zone_diameter_mm"})
          ? Lookup(t, [&] { return PositionsOfClass(plan, *in.class_name); })
          : std::vector<sampling::PositionTolerance>(count, {"", in.zone, {}});
  for (sampling::PositionTolerance& r : positions) {
    r.capability = in.capability();
    plan.tolerances.roller_positions.push_back(r);
  }
}

// [tolerances.springs]: spring rollers only; fixed ones keep an empty slot.
void ResolveSprings(const TableReader& t, const SpringToleranceInput& in, SamplingPlan& plan) {
  const bool by_class = ClassOrNumbers(t, in, {"stiffness_percent", "preload_percent"});
  if (engine::SpringRollerCount(plan.scene) == 0)
    t.FailAbout("class", "tolerances.springs", "the scene has no spring roller", "no [tolerances.springs]");
  std::vector<std::optional<sampling::SpringTolerance>> springs =
      by_class ? Lookup(t, [&] { return SpringsOfClass(plan, *in.class_name); })
               : SpringsOf(plan.scene, {"", in.stiffness, in.preload, {}});
  for (std::optional<sampling::SpringTolerance>& r : springs) {
    if (r) r->capability = in.capability();
    plan.tolerances.springs.push_back(r);
  }
}

}  // namespace

SamplingPlan ReadSamplingFile(const std::filesystem::path& file, std::span<const std::string_view> other_tables,
                              const StoredSampling* stored) {
  const std::string source = file.string();
  SamplingPlan plan;
  plan.text = stored != nullptr ? stored->text : ReadTextFile(file);
  const toml::table document = ParseToml(plan.text, source);
  const TableReader root(document, "", source);
  plan.catalogue = ShippedCatalogue();

  FileInput in;
  ToleranceInputs tolerances;
  std::optional<PopulationInput> ring_population, roller_population;
  const std::vector<Field<FileInput>> design_fields = DesignFields();
  const std::vector<Field<ToleranceInputs>> tolerance_fields = ToleranceFields();
  std::vector<Field<FileInput>> fields{
      Text("scene", Presence::kRequired, "a scene file, relative to this file", &FileInput::scene),
      {"seed", Presence::kOptional, SeedAllowed(),
       [](const Site& site, FileInput& f) {
         const auto* value = site.node.as_integer();
         if (value == nullptr || value->get() < 0) site.Fail("not an integer >= 0", SeedAllowed());
         f.seed = value->get();
       },
       {}, {}},
      Section<FileInput>("design", Presence::kOptional,
                         [&](const TableReader& t, FileInput& f) { t.Read(design_fields, f); }),
      Section<FileInput>("tolerances", Presence::kOptional,
                         [&](const TableReader& t, FileInput&) { t.Read(tolerance_fields, tolerances); }),
      Section<FileInput>("population", Presence::kOptional,
                         [&](const TableReader& t, FileInput&) {
                           const auto population = [&](std::string_view key, std::optional<PopulationInput>& slot) {
                             return Section<FileInput>(key, Presence::kOptional,
                                                       [&slot, folder = file.parent_path(),
                                                        ring = key == "ring"](const TableReader& table, FileInput&) {
                                                         PopulationInput read;
                                                         table.Read(PopulationFields(folder, ring), read);
                                                         slot = std::move(read);
                                                       });
                           };
                           t.Read(std::vector<Field<FileInput>>{population("ring", ring_population),
                                                                population("rollers", roller_population)},
                                  in);
                         }),
      Section<FileInput>("catalogue", Presence::kOptional,
                         [&](const TableReader& t, FileInput&) {
                           AddCatalogueClasses(t.table(), "catalogue", source, false, plan.catalogue);
                         }),
  };
  for (const std::string_view key : other_tables) {
    fields.push_back(Section<FileInput>(key, Presence::kOptional, [](const TableReader&, FileInput&) {}));
  }
  root.Read(fields, in);

  // The base scene.
  plan.scene_file = file.parent_path() / in.scene;
  try {
    plan.scene = stored != nullptr ? ParseScene(stored->base_scene, source + " (stored base scene)")
                                   : ReadScene(plan.scene_file);
  } catch (const InputError& e) {
    root.Fail("scene", std::string("the scene does not read: ") + e.what(), "a valid scene file");
  }
  plan.seed = static_cast<std::uint64_t>(in.seed);
  plan.samples = in.samples;

  ResolveDesign(root, in, plan);

  // The tolerances, resolved against the catalogue at each part's diameter.
  const TableReader table = SubTable(root, "tolerances");
  if (tolerances.ring) ResolveRing(SubTable(table, "ring"), *tolerances.ring, plan);
  if (tolerances.rollers) ResolveRollers(SubTable(table, "rollers"), *tolerances.rollers, plan);
  if (tolerances.positions) ResolvePositions(SubTable(table, "roller_positions"), *tolerances.positions, plan);
  if (tolerances.springs) ResolveSprings(SubTable(table, "springs"), *tolerances.springs, plan);
  const TableReader populations = SubTable(root, "population");
  if (ring_population) {
    ResolvePopulation(SubTable(populations, "ring"), std::move(*ring_population), true, tolerances.ring.has_value(), plan);
  }
  if (roller_population) {
    ResolvePopulation(SubTable(populations, "rollers"), std::move(*roller_population), false,
                      tolerances.rollers.has_value(), plan);
  }
  return plan;
}

sampling::AssemblyTolerances ToleranceOfClass(const SamplingPlan& plan, sampling::ErrorSource component,
                                              const std::string& class_name, sampling::ToleranceMode mode) {
  const sampling::AssemblyTolerances& current = plan.tolerances;
  // The first set entry of a per-roller list: every roller's reads from the same table.
  auto first = [](const auto& list) {
    for (const auto& entry : list) {
      if (entry) return entry;
    }
    return std::decay_t<decltype(list.front())>{};
  };
  sampling::AssemblyTolerances result;
  switch (component) {
    case sampling::ErrorSource::kRingShape: {
      sampling::RingFormTolerance r = RingOfClass(plan, class_name);
      if (current.ring) {
        r.spectrum = current.ring->spectrum;
        r.capability = current.ring->capability;
      }
      r.capability.mode = mode;
      result.ring = r;
      break;
    }
    case sampling::ErrorSource::kRollerShape: {
      const std::optional<sampling::RollerShapeTolerance> inherited = first(current.roller_shapes);
      std::size_t i = 0;
      for (sampling::RollerShapeTolerance& r : RollersOfClass(plan, class_name, plan.roller_series)) {
        if (inherited) {
          r.form = inherited->form;
          r.capability = inherited->capability;
        }
        r.capability.mode = mode;
        // A roller the file's table leaves out ([tolerances.rollers] rollers) stays as measured.
        const bool drawn = current.roller_shapes.empty() || current.roller_shapes[i].has_value();
        result.roller_shapes.push_back(drawn ? std::optional(r) : std::nullopt);
        ++i;
      }
      break;
    }
    case sampling::ErrorSource::kRollerPosition: {
      const std::optional<sampling::PositionTolerance> inherited = first(current.roller_positions);
      for (sampling::PositionTolerance& r : PositionsOfClass(plan, class_name)) {
        if (inherited) r.capability = inherited->capability;
        r.capability.mode = mode;
        result.roller_positions.push_back(r);
      }
      break;
    }
    case sampling::ErrorSource::kSpring: {
      const std::optional<sampling::SpringTolerance> inherited = first(current.springs);
      result.springs = SpringsOfClass(plan, class_name);
      for (std::optional<sampling::SpringTolerance>& r : result.springs) {
        if (!r) continue;
        if (inherited) r->capability = inherited->capability;
        r->capability.mode = mode;
      }
      break;
    }
  }
  return result;
}

std::string SeedAllowed() { return "an integer >= 0 and <= " + std::to_string(kMaxSeed); }

std::optional<std::uint64_t> SeedOfText(std::string_view text) {
  // std::from_chars takes a minus sign, which no seed has.
  if (text.empty() || text.front() == '-') return std::nullopt;
  std::int64_t seed = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), seed);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return static_cast<std::uint64_t>(seed);
}

void OverridePlan(SamplingPlan& plan, std::optional<std::int64_t> samples, std::optional<std::uint64_t> seed) {
  if (samples) plan.samples = *samples;
  if (plan.design.kind == sampling::DesignKind::kLatinHypercube) plan.design.latin_samples = plan.samples;
  if (seed) plan.seed = plan.design.seed = *seed;
}

Sampling MakeSampling(const SamplingPlan& plan, const std::string& source_name,
                      std::shared_ptr<sampling::CalibrationCache> calibrations,
                      std::vector<sampling::ComponentScale> known_scales) {
  auto check_count = [&](const sampling::Design& design) {
    const std::string problem = design.CheckSampleCount(plan.samples);
    if (!problem.empty())
      throw InputError(source_name + ": design.samples = " + std::to_string(plan.samples) + ": " + problem);
  };
  // Outside Saltelli the count's rules do not depend on the inputs: refuse a bad count
  // before the calibration's second of work.
  if (plan.design.kind != sampling::DesignKind::kSaltelli) {
    try {
      check_count(sampling::Design(1, plan.design));
    } catch (const std::invalid_argument& e) {
      throw InputError(source_name + ": [design]: " + e.what());
    }
  }
  std::optional<sampling::AssemblySampler> sampler;
  try {
    sampling::AssemblySamplerOptions options;
    options.seed = plan.seed;
    options.calibrations = std::move(calibrations);
    options.known_scales = std::move(known_scales);
    sampler.emplace(plan.scene, plan.tolerances, options);
  } catch (const std::invalid_argument& e) {
    throw InputError(source_name + ": [tolerances]: " + e.what());
  }
  sampling::DesignOptions options = plan.design;
  if (options.kind == sampling::DesignKind::kSaltelli) options.groups = sampler->Groups(plan.grouping).coordinates;
  if (sampler->dimension() == 0)
    throw InputError(source_name + ": [tolerances]: nothing is toleranced; allowed: at least one of [tolerances.ring], "
                     "[tolerances.rollers], [tolerances.roller_positions], [tolerances.springs], [population.ring], "
                     "[population.rollers]");
  std::optional<sampling::Design> design;
  try {
    design.emplace(sampler->dimension(), options);
  } catch (const std::invalid_argument& e) {
    throw InputError(source_name + ": [design]: " + e.what());
  }
  check_count(*design);
  return {std::move(*sampler), std::move(*design)};
}

}  // namespace ringtol::jobs
