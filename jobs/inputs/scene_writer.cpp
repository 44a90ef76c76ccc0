#include "jobs/inputs/scene_writer.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "jobs/inputs/input_error.h"
#include "jobs/inputs/scene_keys.h"
#include "jobs/inputs/toml_fields.h"
#include "engine/units.h"

namespace ringtol::jobs {
namespace {

using engine::MotionLaw;
using engine::MotionSegment;

// `value` rounded to `digits` significant decimal digits.
double RoundToDigits(double value, int digits) {
  const std::string text = fmt::format("{:.{}e}", value, digits - 1);
  double rounded = value;
  std::from_chars(text.data(), text.data() + text.size(), rounded);
  return rounded;
}

// The number to write for the SI value `si` in a key the reader converts with `to_si`
// (file value -> SI): the shortest decimal near `estimate` (si in the key's unit) that
// converts back to si exactly, or estimate itself when none does.
template <typename ToSi>
double FileValue(double si, double estimate, const ToSi& to_si) {
  for (int digits = 1; digits <= std::numeric_limits<double>::max_digits10; ++digits) {
    const double candidate = RoundToDigits(estimate, digits);
    if (to_si(candidate) == si) return candidate;
  }
  return estimate;
}

// A number that TOML reads as a float, shortest round-trip text: "302.0", "0.14", "1e-07".
std::string Float(double value) {
  std::string text = ShowNumber(value);
  if (text.find_first_of(".ein") == std::string::npos) text += ".0";
  return text;
}

// `si` in the unit of a key whose reader multiplies by `to_si` (units::kMetresPerMillimetre, ...).
double InUnit(double si, double to_si) {
  return FileValue(si, si / to_si, [to_si](double value) { return value * to_si; });
}
std::string Mm(double metres) { return Float(InUnit(metres, units::kMetresPerMillimetre)); }
std::string Deg(double radians) { return Float(InUnit(radians, units::kRadiansPerDegree)); }

// A TOML basic string.
std::string Quoted(std::string_view text) {
  std::string quoted = "\"";
  for (const char c : text) {
    const auto code = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') quoted += {'\\', c};
    else if (code < 0x20 || code == 0x7f) quoted += fmt::format("\\u{:04X}", code);
    else quoted += c;
  }
  return quoted + "\"";
}

std::string Harmonics(const std::vector<engine::Harmonic>& harmonics) {
  if (harmonics.empty()) return "[]";
  std::string text = "[\n";
  for (const engine::Harmonic& h : harmonics) {
    text += fmt::format("  {{ order = {}, amplitude_mm = {}, phase_deg = {} }},\n", h.order, Mm(h.amplitude),
                        Deg(h.phase));
  }
  return text + "]";
}

// Appends table headers and "key = value" lines to a text.
class Writer {
 public:
  explicit Writer(std::string text) : text_(std::move(text)) {}
  void Table(std::string_view header) { fmt::format_to(std::back_inserter(text_), "\n{}\n", header); }
  void Key(std::string_view key, std::string_view value) {
    fmt::format_to(std::back_inserter(text_), "{} = {}\n", key, value);
  }
  void Profile(const engine::PolarProfile& profile) {
    Key(scene_key::kMeanDeviationMm, Mm(profile.mean_deviation()));
    Key(scene_key::kHarmonics, Harmonics(profile.harmonics()));
  }
  void Material(const engine::Material& material) {
    Key(scene_key::kYoungsModulusGPa, Float(InUnit(material.youngs_modulus, units::kPascalsPerGigapascal)));
    Key(scene_key::kPoissonRatio, Float(material.poisson_ratio));
  }
  std::string Text() && { return std::move(text_); }

 private:
  std::string text_;
};

// The article law's parameters when `law` has its form: an optional rest (zero rate from
// the start), then a constant non-zero rate.
struct ArticleForm {
  double settle = 0.0;  // [s]
  double rate = 0.0;    // [rad/s]
  double span = 0.0;    // [s] of the constant rate
};
std::optional<ArticleForm> AsArticle(const MotionLaw& law) {
  const std::vector<MotionSegment>& segments = law.segments();
  const bool rest_first = segments.size() == 2 && segments[0].acceleration == 0.0 && segments[0].start_rate == 0.0;
  if (!rest_first && segments.size() != 1) return std::nullopt;
  const MotionSegment& turn = segments.back();
  if (turn.acceleration != 0.0 || !turn.start_rate || *turn.start_rate == 0.0) return std::nullopt;
  return ArticleForm{rest_first ? segments[0].duration : 0.0, *turn.start_rate, turn.duration};
}

void WriteMotion(Writer& out, const MotionLaw& law) {
  out.Table("[motion]");
  const std::vector<MotionSegment>& segments = law.segments();
  const double settle = segments.size() == 4 ? segments[0].duration : 0.0;
  if (law == engine::TestBenchLaw(settle)) {
    out.Key(scene_key::kLaw, Quoted(NameOf(kMotionKindNames, MotionKind::kTestBench)));
    out.Key(scene_key::kSettleS, Float(settle));
    return;
  }
  if (const std::optional<ArticleForm> article = AsArticle(law)) {
    const double rate = InUnit(article->rate, units::kRadiansPerDegree);
    const double read_rate = rate * units::kRadiansPerDegree;
    const double revolutions = article->span * std::abs(article->rate) / (2.0 * std::numbers::pi);
    // The span the reader rebuilds from these numbers, by the engine's own formula.
    const auto span = [&](double turns) {
      try {
        return engine::ArticleLaw(article->settle, read_rate, turns).segments().back().duration;
      } catch (const std::invalid_argument&) {
        return std::numeric_limits<double>::quiet_NaN();
      }
    };
    if (std::isfinite(revolutions) && revolutions > 0.0) {
      out.Key(scene_key::kLaw, Quoted(NameOf(kMotionKindNames, MotionKind::kArticle)));
      out.Key(scene_key::kSettleS, Float(article->settle));
      out.Key(scene_key::kRateDegPerS, Float(rate));
      out.Key(scene_key::kRevolutions, Float(FileValue(article->span, revolutions, span)));
      return;
    }
  }
  out.Key(scene_key::kLaw, Quoted(NameOf(kMotionKindNames, MotionKind::kPiecewise)));
  std::string list = "[\n";
  for (const MotionSegment& s : segments) {
    list += fmt::format("  {{ duration_s = {}, acceleration_deg_per_s2 = {}", Float(s.duration), Deg(s.acceleration));
    if (s.start_rate) list += fmt::format(", start_rate_deg_per_s = {}", Deg(*s.start_rate));
    list += " },\n";
  }
  out.Key(scene_key::kSegments, list + "]");
}

void WriteRoller(Writer& out, const engine::Roller& roller, const engine::Ring& ring) {
  out.Table("[[rollers]]");
  out.Key(scene_key::kName, Quoted(roller.name));
  out.Key(scene_key::kAngleDeg, Deg(roller.angle));
  out.Key(scene_key::kRadiusMm, Mm(roller.outline.radius()));
  out.Key(scene_key::kCentreRadiusMm, Mm(roller.centre_radius));
  out.Key(scene_key::kRadialOffsetMm, Mm(roller.radial_offset));
  out.Key(scene_key::kTangentialOffsetMm, Mm(roller.tangential_offset));
  const bool spring = roller.mount == engine::RollerMount::kSpring;
  out.Key(scene_key::kMount, Quoted(NameOf(kRollerMountNames, roller.mount)));
  if (spring) {
    out.Key(scene_key::kSpringStiffnessNPerM, Float(roller.spring.stiffness));
    out.Key(scene_key::kSpringPreloadN, Float(roller.spring.preload));
    out.Key(scene_key::kSpringAxisDeg, Deg(roller.spring.axis_angle));
    out.Key(scene_key::kSpringTravelLimitMm, Mm(roller.spring.travel_limit));
  }
  // The format needs a width; with mass_kg given it is unused, so a scene built without a
  // file (width 0) takes the ring's thickness.
  out.Key(scene_key::kWidthMm, Mm(roller.width > 0.0 ? roller.width : ring.thickness));
  out.Key(scene_key::kMassKg, Float(roller.mass));
  out.Key(scene_key::kSpinInertiaKgM2, Float(roller.spin_inertia));
  out.Key(scene_key::kShapePhaseReference, Quoted(NameOf(kShapePhaseReferenceNames, roller.phase_reference)));
  out.Key(scene_key::kSpinPhaseDeg, Deg(roller.spin_phase));
  out.Material(roller.material);
  out.Profile(roller.outline);
}

}  // namespace

std::string WriteScene(const engine::Scene& scene) {
  Writer out(
      "# Written by ringtol: a complete scene file (format: docs/inputs.md, \"Scene files\"), every key explicit.\n"
      "# Masses and spin inertias are given as such; each roller's width_mm only enters a mass\n"
      "# computed from density, so with mass_kg given it has no effect.\n");

  const engine::Ring& ring = scene.ring;
  out.Table("[ring]");
  out.Key(scene_key::kInnerRadiusMm, Mm(ring.inner.radius()));
  out.Key(scene_key::kOuterRadiusMm, Mm(ring.outer_radius));
  out.Key(scene_key::kThicknessMm, Mm(ring.thickness));
  out.Key(scene_key::kMassKg, Float(ring.mass));
  out.Key(scene_key::kSpinInertiaKgM2, Float(ring.spin_inertia));
  out.Material(ring.material);
  out.Profile(ring.inner);

  if (scene.roller_positions.mean_deviation() != 0.0 || !scene.roller_positions.harmonics().empty()) {
    out.Table("[roller_positions]");
    out.Profile(scene.roller_positions);
  }

  for (const engine::Roller& roller : scene.rollers) WriteRoller(out, roller, ring);

  const engine::ContactLaw& contact = scene.contact;
  out.Table("[contact]");
  out.Key(scene_key::kLaw, Quoted(NameOf(kContactModelNames, contact.model)));
  out.Key(scene_key::kStiffnessNPerME, Float(contact.stiffness));
  out.Key(scene_key::kExponent, Float(contact.exponent));
  out.Key(scene_key::kMaxDampingNSPerM, Float(contact.max_damping));
  out.Key(scene_key::kFullDampingPenetrationMm, Mm(contact.full_damping_penetration));

  const engine::Friction& friction = scene.friction;
  out.Table("[friction]");
  out.Key(scene_key::kStaticCoefficient, Float(friction.static_coefficient));
  out.Key(scene_key::kDynamicCoefficient, Float(friction.dynamic_coefficient));
  out.Key(scene_key::kStictionVelocityMmPerS, Mm(friction.stiction_velocity));
  out.Key(scene_key::kTransitionVelocityMmPerS, Mm(friction.transition_velocity));

  out.Table("[sensor]");
  out.Key(scene_key::kAngleDeg, Deg(scene.sensor_angle));
  out.Key(scene_key::kResolutionUm, Float(InUnit(scene.sensor_swing.resolution, units::kMetresPerMicrometre)));
  out.Key(scene_key::kCutoffUpr, Float(scene.sensor_swing.cutoff_upr));
  out.Key(scene_key::kErrorMotionCutoffUpr, Float(scene.error_motion_filter.cutoff_upr));

  WriteMotion(out, scene.motion);

  const auto flag = [](bool value) { return value ? "true" : "false"; };
  out.Table("[dynamics]");
  out.Key(scene_key::kFriction, flag(scene.dynamics.friction));
  out.Key(scene_key::kRollingWithoutSlip, flag(scene.dynamics.rolling_without_slip));
  out.Key(scene_key::kMasslessSpringRollers, flag(scene.dynamics.massless_spring_rollers));

  out.Table("[life]");
  out.Key(scene_key::kPhaseLockedRollers, flag(scene.phase_locked_rollers));
  return std::move(out).Text();
}

void WriteSceneFile(const engine::Scene& scene, const std::filesystem::path& file) {
  const std::string text = WriteScene(scene);
  errno = 0;
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (!out) {
    const std::string reason = errno != 0 ? std::generic_category().message(errno) : "check its folder and permissions";
    throw InputError(fmt::format("{}: cannot open for writing: {}", file.string(), reason));
  }
  out << text;
  out.close();
  if (!out) throw InputError(fmt::format("{}: write error", file.string()));
}

}  // namespace ringtol::jobs
