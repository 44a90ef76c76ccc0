#include "jobs/inputs/scene_file.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "jobs/inputs/profile_csv.h"
#include "jobs/inputs/input_error.h"
#include "jobs/inputs/scene_keys.h"
#include "jobs/inputs/toml_fields.h"
#include "engine/line_contact.h"
#include "engine/units.h"

namespace ringtol::jobs {
namespace {

using engine::RollerMount;
using engine::ShapePhaseReference;

constexpr std::size_t kMinRollers = 3;  // fewer cannot hold the ring's centre in its plane
constexpr std::string_view kMassAllowed = "exactly one of density_kg_per_m3 and mass_kg";
constexpr std::string_view kSpringOnly = "mount = \"spring\"";

// A body's material keys, on [ring] and each [[rollers]]: only the contact law of a file
// that states none reads them (docs/model.md §4). The stiffest solids (diamond, about
// 1,100 GPa) stay below the modulus' bound, so a modulus in MPa or Pa is refused; nu <=
// 0.5 is incompressible.
const Range kYoungsModulusRange{0.0, true, 1500.0, false};
const Range kPoissonRatioRange = Between(0.0, 0.5);

template <typename T>
void AddMaterialFields(std::vector<Field<T>>& fields) {
  fields.push_back(Number(scene_key::kYoungsModulusGPa, Presence::kOptional, units::kPascalsPerGigapascal,
                          kYoungsModulusRange, &T::youngs_modulus));
  fields.push_back(Number(scene_key::kPoissonRatio, Presence::kOptional, kSameUnit, kPoissonRatioRange, &T::poisson_ratio));
}

// What ringtol models: rings from a few millimetres to a few metres across, of metal,
// ceramic or plastic, on rollers down to a millimetre. A density, mass or spin inertia
// outside these ranges, given or implied by the dimensions, is a key in another unit (a
// density in g/cm^3 is a thousand times too small) or a typo (an outer radius of 1e308 mm),
// which would otherwise surface only as the dynamic solver's failure.
constexpr Range kDensityRange{100.0, false, 30000.0, false};  // [kg/m^3] foamed plastics' to osmium's
constexpr Range kMassRange{1e-7, false, 1e5, false};  // [kg] a 1 mm plastic roller to a 100 t ring with its load
constexpr Range kSpinInertiaRange{1e-15, false, 1e7, false};  // [kg m^2] those masses at 0.5 mm to 10 m

// A body's mass [kg] and spin inertia [kg m^2], each given (and range-checked as read) or
// implied: the mass by density_kg_per_m3 and `volume_keys`, the spin inertia by the mass and
// `radius_keys`. An implied one out of range is refused at the first key it comes from,
// every such key named with its value.
void RequireModelledInertia(const TableReader& table, double mass, double spin_inertia,
                            const std::vector<std::string_view>& volume_keys,
                            const std::vector<std::string_view>& radius_keys) {
  const auto require = [&table](const std::vector<std::string_view>& keys, std::string_view quantity, double value,
                                std::string_view unit, const Range& range) {
    if (range.Contains(value)) return;
    std::string subject;
    for (const std::string_view key : keys) {
      const std::string name = subject.empty() ? table.KeyPath(key) : ", " + std::string(key);
      subject += fmt::format("{} = {}", name, ShowValue(table.At(key).node));
    }
    table.FailAbout(keys.front(), subject, fmt::format("imply a {} of {} {}", quantity, ShowDerived(value), unit),
                    fmt::format("a {} {} {} (docs/inputs.md, \"Scene files\")", quantity, Describe(range), unit));
  };
  std::vector<std::string_view> mass_keys{scene_key::kMassKg};
  if (!table.Has(scene_key::kMassKg)) {
    mass_keys = {"density_kg_per_m3"};
    mass_keys.insert(mass_keys.end(), volume_keys.begin(), volume_keys.end());
    require(mass_keys, "mass", mass, "kg", kMassRange);
  }
  if (table.Has(scene_key::kSpinInertiaKgM2)) return;
  std::vector<std::string_view> inertia_keys = mass_keys;
  for (const std::string_view key : radius_keys) {
    if (std::find(inertia_keys.begin(), inertia_keys.end(), key) == inertia_keys.end()) inertia_keys.push_back(key);
  }
  require(inertia_keys, "spin inertia", spin_inertia, "kg m^2", kSpinInertiaRange);
}

// The polar form r = r0 + dr0 + sum C_n cos(n theta + phi_n) only describes an outline
// while every deviation stays below r0; beyond, r can reach zero and the body is not a
// body. radius_key names the key that set r0, for the message.
void RequireDeviationsBelowRadius(const TableReader& table, const engine::PolarProfile& profile,
                                  std::string_view radius_key) {
  const double bound = DeviationBound(profile);
  if (bound < profile.radius()) return;
  // A measured profile is the likelier culprit: a fit of too many orders across a gap.
  const bool measured = table.Has("measured_profile");
  const std::string_view key = measured ? "measured_profile" : table.Has(scene_key::kHarmonics) ? scene_key::kHarmonics : scene_key::kMeanDeviationMm;
  table.FailAbout(key,
                  fmt::format("{} (|mean_deviation_mm| + sum of amplitude_mm = {})", table.KeyPath(key),
                              ShowDerived(units::InMillimetres(bound))),
                  measured ? "amplitudes larger than the radius (`ringtol fit` shows the fit: fewer orders?)"
                           : "amplitudes larger than the radius",
                  fmt::format("< {} ({})", ShowDerived(units::InMillimetres(profile.radius())), table.KeyPath(radius_key)));
}

// ---- [ring]

// ring.measured_profile, rollers[].measured_profile: a roundness tester's export, fitted on
// reading, held to the part as its `reference` says (ProfileReference, profile_csv.h).

struct MeasuredProfileInput {
  std::filesystem::path file;  // resolved against the scene file's folder
  int orders = 0;
  bool keep_eccentricity = false;
  ProfileReference reference = ProfileReference::kNominal;
};

constexpr std::string_view kOwnMeanAdvice =
    "reference = \"own_mean\" to take its form alone on this ring, or a profile of a ring of this size";
constexpr std::string_view kProfileFileAllowed =
    "the path of an existing CSV file (docs/inputs.md, \"Profile CSV files\"), relative to the scene file's folder";
constexpr std::string_view kMeasuredProfileAllowed =
    "a table { file = \"profile.csv\", orders = integer 1..1000, keep_eccentricity = false, reference = "
    "\"nominal\" or \"own_mean\" }";

std::vector<Field<MeasuredProfileInput>> MeasuredProfileFields(const std::filesystem::path& folder) {
  return {
      Field<MeasuredProfileInput>{
          "file", Presence::kRequired, std::string(kProfileFileAllowed),
          [folder](const Site& site, MeasuredProfileInput& in) {
            in.file = ReadProfilePath(site, folder, kProfileFileAllowed);
          },
          {}, {}},
      Integer("orders", Presence::kRequired, Between(1.0, kMaxHarmonicOrder), &MeasuredProfileInput::orders),
      Flag("keep_eccentricity", Presence::kOptional, &MeasuredProfileInput::keep_eccentricity),
      Choice("reference", Presence::kOptional, kProfileReferenceNames, &MeasuredProfileInput::reference),
  };
}

// What a measured profile adds to a part's keys.
struct MeasuredOutline {
  MeasuredFit fit;
  ProfileReference reference = ProfileReference::kNominal;
  std::vector<engine::Harmonic> harmonics;
  std::string file;   // the export, for messages
};

// Errors of the CSV and of the fit come with the key's position and path in front:
// "scene.toml:5:1: ring.measured_profile: ring.csv:7: radius_mm = abc: ...". radius [m]:
// the part's nominal radius, which the export's form is held to; `part`: "ring", "roller".
MeasuredOutline ReadMeasuredProfile(const Site& site, const std::filesystem::path& folder, double radius,
                                    std::string_view part) {
  const TableReader table(ReadTable(site, kMeasuredProfileAllowed), site.key_path, site.file);
  MeasuredProfileInput in;
  table.Read(MeasuredProfileFields(folder), in);
  try {
    MeasuredFit measured = FitProfileFile(in.file, in.orders, radius, part);
    std::vector<engine::Harmonic> harmonics = FormHarmonics(measured.fit, in.keep_eccentricity);
    return {std::move(measured), in.reference, std::move(harmonics), in.file.string()};
  } catch (const InputError& error) {
    throw InputError(fmt::format("{}: {}: {}", Where(site.file, site.node.source()), site.key_path, error.what()));
  }
}

struct RingInput {
  double inner_radius = 0.0;           // [m]
  double outer_radius = 0.0;           // [m]
  double thickness = 0.0;              // [m]
  std::optional<double> density;       // [kg/m^3]
  std::optional<double> mass;          // [kg]
  std::optional<double> spin_inertia;  // [kg m^2]
  double mean_deviation = 0.0;         // [m]
  std::vector<engine::Harmonic> harmonics;
  std::optional<MeasuredOutline> measured;
  double youngs_modulus = engine::Material{}.youngs_modulus;  // [Pa]
  double poisson_ratio = engine::Material{}.poisson_ratio;    // [-]
};

// A measured outline's size and form joined to a part's own keys, once its sanity is
// checked: `mean_deviation` and `harmonics` are the part's, `radius` its nominal radius,
// `radius_key` that key (for the message refusing another part's profile).
void JoinMeasured(const TableReader& table, const MeasuredOutline& measured, double radius, std::string_view radius_key,
                  std::string_view part, double& mean_deviation, std::vector<engine::Harmonic>& harmonics) {
  // A form as large as the part is a fit gone wild (too many orders across a gap), which
  // RequireDeviationsBelowRadius blames later; the check here is for sane fits. Their
  // form's size was checked on reading (FitProfileFile).
  const bool sane = AmplitudeSum(measured.harmonics) < radius;
  if (measured.reference == ProfileReference::kNominal && sane) {
    const std::string other = OtherPartReason(measured.fit, radius, measured.file, table.KeyPath(radius_key), part);
    if (!other.empty()) table.FailAbout("measured_profile", table.KeyPath("measured_profile"), other, kOwnMeanAdvice);
  }
  if (measured.reference == ProfileReference::kNominal) mean_deviation += MeanDeviation(measured.fit, radius);
  harmonics.insert(harmonics.end(), measured.harmonics.begin(), measured.harmonics.end());
}

std::vector<Field<RingInput>> RingFields(const std::filesystem::path& folder) {
  std::vector<Field<RingInput>> fields = {
      Number(scene_key::kInnerRadiusMm, Presence::kRequired, units::kMetresPerMillimetre, Above(0.0), &RingInput::inner_radius),
      Number(scene_key::kOuterRadiusMm, Presence::kRequired, units::kMetresPerMillimetre, Above(0.0), &RingInput::outer_radius),
      Number(scene_key::kThicknessMm, Presence::kRequired, units::kMetresPerMillimetre, Above(0.0), &RingInput::thickness),
      Number("density_kg_per_m3", Presence::kOptional, kSameUnit, kDensityRange, &RingInput::density),
      Number(scene_key::kMassKg, Presence::kOptional, kSameUnit, kMassRange, &RingInput::mass),
      Number(scene_key::kSpinInertiaKgM2, Presence::kOptional, kSameUnit, kSpinInertiaRange, &RingInput::spin_inertia),
      Number(scene_key::kMeanDeviationMm, Presence::kOptional, units::kMetresPerMillimetre, AnyFinite(), &RingInput::mean_deviation),
      HarmonicList(scene_key::kHarmonics, Presence::kOptional, &RingInput::harmonics),
      Field<RingInput>{"measured_profile", Presence::kOptional, std::string(kMeasuredProfileAllowed),
                       [folder](const Site& site, RingInput& in) {
                         in.measured = ReadMeasuredProfile(site, folder, in.inner_radius, "ring");
                       },
                       {}, {}},
  };
  AddMaterialFields(fields);
  return fields;
}

// folder: the scene file's, against which ring.measured_profile.file is resolved.
void ReadRing(const TableReader& table, const std::filesystem::path& folder, engine::Scene& scene) {
  RingInput in;
  table.Read(RingFields(folder), in);
  if (in.measured) {
    JoinMeasured(table, *in.measured, in.inner_radius, scene_key::kInnerRadiusMm, "ring", in.mean_deviation, in.harmonics);
  }
  if (!(in.outer_radius > in.inner_radius)) {
    table.Fail(scene_key::kOuterRadiusMm, "not larger than the inner radius",
               fmt::format("> {} (ring.inner_radius_mm)", ShowDerived(units::InMillimetres(in.inner_radius))));
  }
  table.RequireExactlyOne("density_kg_per_m3", scene_key::kMassKg, kMassAllowed);

  engine::Ring& ring = scene.ring;
  ring.inner = engine::PolarProfile(in.inner_radius, in.mean_deviation, in.harmonics);
  ring.outer_radius = in.outer_radius;
  ring.thickness = in.thickness;
  // A plain annulus: the gear teeth on the outer flank are ignored (docs/model.md §1).
  const double ro2 = in.outer_radius * in.outer_radius;
  const double ri2 = in.inner_radius * in.inner_radius;
  ring.mass = in.mass ? *in.mass : *in.density * std::numbers::pi * (ro2 - ri2) * in.thickness;
  ring.spin_inertia = in.spin_inertia.value_or(ring.mass * (ro2 + ri2) / 2.0);
  RequireModelledInertia(table, ring.mass, ring.spin_inertia,
                         {scene_key::kOuterRadiusMm, scene_key::kInnerRadiusMm, scene_key::kThicknessMm},
                         {scene_key::kOuterRadiusMm, scene_key::kInnerRadiusMm});
  ring.material = {in.youngs_modulus, in.poisson_ratio};
  RequireDeviationsBelowRadius(table, ring.inner, scene_key::kInnerRadiusMm);
}

// ---- [roller_positions]

struct ErrorSeriesInput {
  double mean_deviation = 0.0;  // [m]
  std::vector<engine::Harmonic> harmonics;
};

std::vector<Field<ErrorSeriesInput>> RollerPositionFields() {
  return {
      Number(scene_key::kMeanDeviationMm, Presence::kOptional, units::kMetresPerMillimetre, AnyFinite(),
             &ErrorSeriesInput::mean_deviation),
      HarmonicList(scene_key::kHarmonics, Presence::kOptional, &ErrorSeriesInput::harmonics),
  };
}

void ReadRollerPositions(const TableReader& table, engine::Scene& scene) {
  ErrorSeriesInput in;
  table.Read(RollerPositionFields(), in);
  // The radius of this series is never used (engine/scene.h); 1 m keeps PolarProfile valid.
  scene.roller_positions = engine::PolarProfile(1.0, in.mean_deviation, in.harmonics);
}

// ---- [[rollers]]

struct RollerInput {
  std::string name;
  double angle = 0.0;                     // [rad]
  double radius = 0.0;                    // [m]
  std::optional<double> centre_radius;    // [m]
  double radial_offset = 0.0;             // [m]
  double tangential_offset = 0.0;         // [m]
  RollerMount mount = RollerMount::kFixed;
  double spring_stiffness = 0.0;          // [N/m]
  double spring_preload = 0.0;            // [N]
  std::optional<double> spring_axis;      // [rad]
  std::optional<double> spring_travel_limit;  // [m]
  double width = 0.0;                     // [m]
  std::optional<double> density;          // [kg/m^3]
  std::optional<double> mass;             // [kg]
  std::optional<double> spin_inertia;     // [kg m^2]
  ShapePhaseReference phase_reference = ShapePhaseReference::kRadial;
  double spin_phase = 0.0;                // [rad]
  double mean_deviation = 0.0;            // [m]
  std::vector<engine::Harmonic> harmonics;
  std::optional<MeasuredOutline> measured;
  double youngs_modulus = engine::Material{}.youngs_modulus;  // [Pa]
  double poisson_ratio = engine::Material{}.poisson_ratio;    // [-]
};

// folder: the scene file's, against which rollers[].measured_profile.file is resolved.
std::vector<Field<RollerInput>> RollerFields(const std::filesystem::path& folder) {
  const auto is_spring = [](const RollerInput& roller) { return roller.mount == RollerMount::kSpring; };
  // mount comes before the spring keys: whether they are allowed depends on it.
  std::vector<Field<RollerInput>> fields = {
      Text(scene_key::kName, Presence::kOptional, "a non-empty string, unique among the rollers", &RollerInput::name),
      Number(scene_key::kAngleDeg, Presence::kRequired, units::kRadiansPerDegree, AnyFinite(), &RollerInput::angle),
      Number(scene_key::kRadiusMm, Presence::kRequired, units::kMetresPerMillimetre, Above(0.0), &RollerInput::radius),
      Number(scene_key::kCentreRadiusMm, Presence::kOptional, units::kMetresPerMillimetre, Above(0.0), &RollerInput::centre_radius),
      Number(scene_key::kRadialOffsetMm, Presence::kOptional, units::kMetresPerMillimetre, AnyFinite(), &RollerInput::radial_offset),
      Number(scene_key::kTangentialOffsetMm, Presence::kOptional, units::kMetresPerMillimetre, AnyFinite(),
             &RollerInput::tangential_offset),
      Choice(scene_key::kMount, Presence::kRequired, kRollerMountNames, &RollerInput::mount),
      Number(scene_key::kSpringStiffnessNPerM, Presence::kRequired, kSameUnit, AtLeast(0.0), &RollerInput::spring_stiffness)
          .When(is_spring, kSpringOnly),
      Number(scene_key::kSpringPreloadN, Presence::kRequired, kSameUnit, Above(0.0), &RollerInput::spring_preload)
          .When(is_spring, kSpringOnly),
      Number(scene_key::kSpringAxisDeg, Presence::kOptional, units::kRadiansPerDegree, AnyFinite(), &RollerInput::spring_axis)
          .When(is_spring, kSpringOnly),
      Number(scene_key::kSpringTravelLimitMm, Presence::kOptional, units::kMetresPerMillimetre, Above(0.0),
             &RollerInput::spring_travel_limit)
          .When(is_spring, kSpringOnly),
      Number(scene_key::kWidthMm, Presence::kRequired, units::kMetresPerMillimetre, Above(0.0), &RollerInput::width),
      Number("density_kg_per_m3", Presence::kOptional, kSameUnit, kDensityRange, &RollerInput::density),
      Number(scene_key::kMassKg, Presence::kOptional, kSameUnit, kMassRange, &RollerInput::mass),
      Number(scene_key::kSpinInertiaKgM2, Presence::kOptional, kSameUnit, kSpinInertiaRange, &RollerInput::spin_inertia),
      Choice(scene_key::kShapePhaseReference, Presence::kOptional, kShapePhaseReferenceNames,
             &RollerInput::phase_reference),
      Number(scene_key::kSpinPhaseDeg, Presence::kOptional, units::kRadiansPerDegree, AnyFinite(), &RollerInput::spin_phase),
      Number(scene_key::kMeanDeviationMm, Presence::kOptional, units::kMetresPerMillimetre, AnyFinite(), &RollerInput::mean_deviation),
      HarmonicList(scene_key::kHarmonics, Presence::kOptional, &RollerInput::harmonics),
      Field<RollerInput>{"measured_profile", Presence::kOptional, std::string(kMeasuredProfileAllowed),
                         [folder](const Site& site, RollerInput& in) {
                           in.measured = ReadMeasuredProfile(site, folder, in.radius, "roller");
                         },
                         {}, {}},
  };
  AddMaterialFields(fields);
  return fields;
}

void ReadRoller(const TableReader& table, std::size_t index, const std::filesystem::path& folder, engine::Scene& scene) {
  RollerInput in;
  in.name = fmt::format("roller{}", index + 1);
  table.Read(RollerFields(folder), in);
  if (in.measured) {
    JoinMeasured(table, *in.measured, in.radius, scene_key::kRadiusMm, "roller", in.mean_deviation, in.harmonics);
  }
  const double ring_radius = scene.ring.inner.radius();
  if (!(in.radius < ring_radius)) {
    table.Fail(scene_key::kRadiusMm, "not smaller than the ring's inner radius",
               fmt::format("> 0 and < {} (ring.inner_radius_mm)", ShowDerived(units::InMillimetres(ring_radius))));
  }
  table.RequireExactlyOne("density_kg_per_m3", scene_key::kMassKg, kMassAllowed);
  for (std::size_t other = 0; other < scene.rollers.size(); ++other) {
    if (scene.rollers[other].name != in.name) continue;
    table.FailAbout(scene_key::kName, fmt::format("{} = \"{}\"", table.KeyPath(scene_key::kName), in.name),
                    fmt::format("the same name as rollers[{}]", other), "a name no other roller has");
  }

  engine::Roller roller;
  roller.name = in.name;
  roller.angle = in.angle;
  roller.centre_radius = in.centre_radius.value_or(ring_radius - in.radius);
  roller.radial_offset = in.radial_offset;
  roller.tangential_offset = in.tangential_offset;
  roller.outline = engine::PolarProfile(in.radius, in.mean_deviation, in.harmonics);
  roller.phase_reference = in.phase_reference;
  roller.spin_phase = in.spin_phase;
  roller.mount = in.mount;
  if (in.mount == RollerMount::kSpring) {
    roller.spring = {in.spring_stiffness, in.spring_preload, in.spring_axis.value_or(in.angle),
                     in.spring_travel_limit.value_or(in.radius)};
  }
  // A solid cylinder: the bearing's bore and its inner ring standing still are ignored,
  // which overstates the spinning mass by a few per cent (docs/model.md §1).
  const double r2 = in.radius * in.radius;
  roller.width = in.width;
  roller.mass = in.mass ? *in.mass : *in.density * std::numbers::pi * r2 * in.width;
  roller.spin_inertia = in.spin_inertia.value_or(roller.mass * r2 / 2.0);
  RequireModelledInertia(table, roller.mass, roller.spin_inertia, {scene_key::kRadiusMm, scene_key::kWidthMm}, {scene_key::kRadiusMm});
  roller.material = {in.youngs_modulus, in.poisson_ratio};
  RequireDeviationsBelowRadius(table, roller.outline, scene_key::kRadiusMm);
  scene.rollers.push_back(std::move(roller));
}

// ---- [contact], [friction], [sensor]: straight into the engine's structs, whose in-class
// defaults are the documented defaults, except the penalty law's k and e: a file that
// states neither gets the law of its materials (StatesPenaltyLaw).

std::vector<Field<engine::ContactLaw>> ContactFields() {
  using Law = engine::ContactLaw;
  return {
      Choice(scene_key::kLaw, Presence::kOptional, kContactModelNames, &Law::model),
      Number(scene_key::kStiffnessNPerME, Presence::kOptional, kSameUnit, Above(0.0), &Law::stiffness).WithoutDefault(),
      Number(scene_key::kExponent, Presence::kOptional, kSameUnit, Between(1.0, 3.0), &Law::exponent).WithoutDefault(),
      Number(scene_key::kMaxDampingNSPerM, Presence::kOptional, kSameUnit, AtLeast(0.0), &Law::max_damping),
      Number(scene_key::kFullDampingPenetrationMm, Presence::kOptional, units::kMetresPerMillimetre, Above(0.0),
             &Law::full_damping_penetration),
  };
}

// k's unit, N/m^e, depends on e: one without the other is a law half stated.
void ReadContact(const TableReader& table, engine::Scene& scene) {
  table.Read(ContactFields(), scene.contact);
  constexpr std::string_view kStiffness = scene_key::kStiffnessNPerME;
  constexpr std::string_view kExponent = scene_key::kExponent;
  if (table.Has(kStiffness) == table.Has(kExponent)) return;
  const std::string_view given = table.Has(kStiffness) ? kStiffness : kExponent;
  const std::string_view missing = table.Has(kStiffness) ? kExponent : kStiffness;
  table.Fail(given, fmt::format("given without {}: k's unit, N/m^e, depends on e", table.KeyPath(missing)),
             fmt::format("both {} and {}, or neither for the law of the ring's and rollers' materials "
                         "(docs/model.md §4)",
                         kStiffness, kExponent));
}

// Whether the file states the penalty law's k and e (ReadContact allows both or neither).
bool StatesPenaltyLaw(const toml::table& document) {
  const toml::table* contact = document["contact"].as_table();
  return contact != nullptr && contact->contains(scene_key::kStiffnessNPerME);
}

std::vector<Field<engine::Friction>> FrictionFields() {
  using engine::Friction;
  return {
      Number(scene_key::kStaticCoefficient, Presence::kOptional, kSameUnit, AtLeast(0.0), &Friction::static_coefficient),
      Number(scene_key::kDynamicCoefficient, Presence::kOptional, kSameUnit, AtLeast(0.0), &Friction::dynamic_coefficient),
      Number(scene_key::kStictionVelocityMmPerS, Presence::kOptional, units::kMetresPerMillimetre, Above(0.0),
             &Friction::stiction_velocity),
      Number(scene_key::kTransitionVelocityMmPerS, Presence::kOptional, units::kMetresPerMillimetre, Above(0.0),
             &Friction::transition_velocity),
  };
}

void ReadFriction(const TableReader& table, engine::Scene& scene) {
  table.Read(FrictionFields(), scene.friction);
  const engine::Friction& friction = scene.friction;
  if (friction.transition_velocity > friction.stiction_velocity) return;
  // mu(v) falls from mu_s at v_s to mu_d at v_d: the two must be in that order.
  const std::string allowed =
      fmt::format("> stiction_velocity_mm_per_s = {}", ShowDerived(units::InMillimetres(friction.stiction_velocity)));
  constexpr std::string_view kTransition = scene_key::kTransitionVelocityMmPerS;
  if (table.Has(kTransition)) table.Fail(kTransition, "not above the stiction velocity", allowed);
  table.FailAbout(scene_key::kStictionVelocityMmPerS,
                  fmt::format("{} = {} (default)", table.KeyPath(kTransition),
                              ShowDerived(units::InMillimetres(friction.transition_velocity))),
                  "not above the stiction velocity", allowed);
}

// ---- [motion], [dynamics]: read by the dynamic solver only.

struct MotionInput {
  MotionKind law = MotionKind::kArticle;
  std::optional<double> settle;       // [s]
  std::optional<double> rate;         // [rad/s]
  std::optional<double> revolutions;  // [-]
  std::vector<engine::MotionSegment> segments;
};

constexpr std::string_view kSegmentsAllowed =
    "an array of at least one table { duration_s > 0, acceleration_deg_per_s2 (default 0), "
    "start_rate_deg_per_s (default: continue) }";

std::vector<Field<engine::MotionSegment>> SegmentFields() {
  using engine::MotionSegment;
  return {
      Number("duration_s", Presence::kRequired, kSameUnit, Above(0.0), &MotionSegment::duration),
      Number("acceleration_deg_per_s2", Presence::kOptional, units::kRadiansPerDegree, AnyFinite(),
             &MotionSegment::acceleration),
      Number("start_rate_deg_per_s", Presence::kOptional, units::kRadiansPerDegree, AnyFinite(), &MotionSegment::start_rate),
  };
}

std::vector<Field<MotionInput>> MotionFields() {
  auto is = [](MotionKind kind) { return [kind](const MotionInput& in) { return in.law == kind; }; };
  auto is_not_piecewise = [](const MotionInput& in) { return in.law != MotionKind::kPiecewise; };
  return {
      Choice(scene_key::kLaw, Presence::kOptional, kMotionKindNames, &MotionInput::law),
      Number(scene_key::kSettleS, Presence::kOptional, kSameUnit, AtLeast(0.0), &MotionInput::settle)
          .When(is_not_piecewise, "law = \"article\" or \"test_bench\""),
      Number(scene_key::kRateDegPerS, Presence::kOptional, units::kRadiansPerDegree, AnyFinite(), &MotionInput::rate)
          .When(is(MotionKind::kArticle), "law = \"article\""),
      Number(scene_key::kRevolutions, Presence::kOptional, kSameUnit, Above(0.0), &MotionInput::revolutions)
          .When(is(MotionKind::kArticle), "law = \"article\""),
      Field<MotionInput>{scene_key::kSegments, Presence::kRequired, std::string(kSegmentsAllowed),
                         [](const Site& site, MotionInput& in) {
                           for (const TableReader& table : ReadTableArray(site, 1, kSegmentsAllowed)) {
                             engine::MotionSegment segment;
                             table.Read(SegmentFields(), segment);
                             in.segments.push_back(segment);
                           }
                         },
                         {}, {}}
          .When(is(MotionKind::kPiecewise), "law = \"piecewise\""),
  };
}

void ReadMotion(const TableReader& table, engine::Scene& scene) {
  MotionInput in;
  table.Read(MotionFields(), in);
  if (in.law == MotionKind::kArticle && in.rate && *in.rate == 0.0) {
    table.Fail(scene_key::kRateDegPerS, "zero: the ring would never turn", "any non-zero number");
  }
  // Each value was range-checked as it was read; what remains is a law whose durations,
  // angles or rates overflow a double (a rate of 1e-320 deg/s takes forever to turn).
  try {
    switch (in.law) {
      case MotionKind::kArticle:
        scene.motion =
            engine::ArticleLaw(in.settle.value_or(0.5), in.rate.value_or(270.0 * units::kRadiansPerDegree), in.revolutions.value_or(3.0));
        break;
      case MotionKind::kTestBench:
        scene.motion = engine::TestBenchLaw(in.settle.value_or(0.5));
        break;
      case MotionKind::kPiecewise:
        scene.motion = engine::MotionLaw(in.segments);
        break;
    }
  } catch (const std::invalid_argument& e) {
    table.FailAbout(scene_key::kLaw, "motion", e.what(), "durations, angles and rates that stay finite");
  }
  const engine::MotionLaw& law = scene.motion;
  const double end = law.Duration();
  if (!std::isfinite(end) || !std::isfinite(law.Angle(end)) || !std::isfinite(law.Rate(end))) {
    table.FailAbout(scene_key::kLaw, "motion", "the law's time, angle or rate overflows", "durations, angles and rates that stay finite");
  }
}

std::vector<Field<engine::DynamicModel>> DynamicsFields() {
  using engine::DynamicModel;
  return {
      Flag(scene_key::kFriction, Presence::kOptional, &DynamicModel::friction),
      Flag(scene_key::kRollingWithoutSlip, Presence::kOptional, &DynamicModel::rolling_without_slip),
      Flag(scene_key::kMasslessSpringRollers, Presence::kOptional, &DynamicModel::massless_spring_rollers),
  };
}

std::vector<Field<engine::Scene>> SensorFields() {
  using engine::Scene;
  // A resolution beyond a millimetre or a cutoff beyond 100,000 undulations is a typo:
  // the first ignores every undulation, the second filters nothing a revolution resolves.
  const Range resolution = Between(0.0, 1000.0);
  const Range cutoff = Between(0.0, 100000.0);
  return {Number(scene_key::kAngleDeg, Presence::kOptional, units::kRadiansPerDegree, AnyFinite(), &Scene::sensor_angle),
          {scene_key::kResolutionUm, Presence::kOptional, Describe(resolution),
           [resolution](const Site& site, Scene& scene) {
             scene.sensor_swing.resolution = ReadNumber(site, resolution) * units::kMetresPerMicrometre;
           },
           {},
           {}},
          {scene_key::kCutoffUpr, Presence::kOptional, Describe(cutoff),
           [cutoff](const Site& site, Scene& scene) { scene.sensor_swing.cutoff_upr = ReadNumber(site, cutoff); },
           {},
           {}},
          {scene_key::kErrorMotionCutoffUpr, Presence::kOptional, Describe(cutoff),
           [cutoff](const Site& site, Scene& scene) {
             scene.error_motion_filter.cutoff_upr = ReadNumber(site, cutoff);
           },
           {},
           {}}};
}

// ---- [life]: how the rollers' phases go over the stage's life (docs/model.md §9).

std::vector<Field<engine::Scene>> LifeFields() {
  return {Flag(scene_key::kPhaseLockedRollers, Presence::kOptional, &engine::Scene::phase_locked_rollers)};
}

std::vector<Field<engine::Scene>> SceneFields(const std::filesystem::path& folder) {
  using engine::Scene;
  // The ring comes first: the rollers' limits depend on its radius.
  return {
      Section<Scene>("ring", Presence::kRequired,
                     [folder](const TableReader& table, Scene& scene) { ReadRing(table, folder, scene); }),
      Section<Scene>("roller_positions", Presence::kOptional, ReadRollerPositions),
      Sections<Scene>("rollers", Presence::kRequired, kMinRollers,
                      [folder](const TableReader& table, std::size_t index, Scene& scene) {
                        ReadRoller(table, index, folder, scene);
                      }),
      Section<Scene>("contact", Presence::kOptional, ReadContact),
      Section<Scene>(scene_key::kFriction, Presence::kOptional, ReadFriction),
      Section<Scene>("sensor", Presence::kOptional,
                     [](const TableReader& table, Scene& scene) { table.Read(SensorFields(), scene); }),
      Section<Scene>("motion", Presence::kOptional, ReadMotion),
      Section<Scene>("dynamics", Presence::kOptional,
                     [](const TableReader& table, Scene& scene) { table.Read(DynamicsFields(), scene.dynamics); }),
      Section<Scene>("life", Presence::kOptional,
                     [](const TableReader& table, Scene& scene) { table.Read(LifeFields(), scene); }),
  };
}

engine::Scene SceneFromText(std::string_view toml_text, const std::string& source_name,
                            const std::filesystem::path& folder) {
  const toml::table document = ParseToml(toml_text, source_name);
  const TableReader root(document, "", source_name);
  engine::Scene scene;
  root.Read(SceneFields(folder), scene);
  if (!StatesPenaltyLaw(document)) scene.contact = engine::MaterialContactLaw(scene, scene.contact);
  // Non-convex outlines are left to the solvers, which report them as a status.
  const engine::GeometryCheck check = engine::CheckGeometry(scene);
  if (check.issue == engine::GeometryIssue::kRollerDoesNotFit) {
    const TableReader roller = root.Element("rollers", static_cast<std::size_t>(check.roller));
    // An explicit centre radius is the likelier culprit; by default the radius sets it.
    roller.Fail(roller.Has(scene_key::kCentreRadiusMm) ? scene_key::kCentreRadiusMm : scene_key::kRadiusMm, check.message,
                FitRule(scene.ring.inner.radius()));
  }
  if (check.issue == engine::GeometryIssue::kRollersOverlap) {
    // The later roller is blamed: it is the one added where another already stands.
    const TableReader roller = root.Element("rollers", static_cast<std::size_t>(check.roller));
    roller.Fail(scene_key::kAngleDeg, check.message, ClearanceRule());
  }
  return scene;
}

}  // namespace

engine::Scene ParseScene(std::string_view toml_text, const std::string& source_name) {
  return SceneFromText(toml_text, source_name, std::filesystem::path());
}

engine::Scene ReadScene(const std::filesystem::path& file) {
  return SceneFromText(ReadTextFile(file), file.string(), file.parent_path());
}

bool StatesContactLaw(const std::filesystem::path& file) {
  return StatesPenaltyLaw(ParseToml(ReadTextFile(file), file.string()));
}

}  // namespace ringtol::jobs
