#include "jobs/cli/contact_warning.h"

#include <cmath>
#include <cstddef>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "engine/line_contact.h"
#include "engine/units.h"
#include "jobs/inputs/scene_file.h"
#include "jobs/inputs/scene_keys.h"
#include "solvers/contact_compliance.h"

namespace ringtol::jobs {
namespace {

std::string LawText(const engine::ContactLaw& law) {
  return fmt::format("F = {:.3g} delta^{:.4g}", law.stiffness, law.exponent);
}

}  // namespace

std::optional<std::string> ContactLawWarning(const engine::Scene& scene,
                                             const std::optional<std::filesystem::path>& stated_in) {
  const solvers::ContactCompliance compliance = solvers::AssessContactCompliance(scene);
  if (!compliance.assessed || compliance.response_change <= kContactLawShare) return std::nullopt;
  const auto um = [](double metres) { return metres * units::kMicrometresPerMetre; };
  const engine::ContactLaw& law = scene.contact;
  const engine::ContactLaw materials = engine::MaterialContactLaw(scene, law);
  const bool of_the_materials = materials.stiffness == law.stiffness && materials.exponent == law.exponent;
  if (stated_in) {
    const std::string instead =
        of_the_materials ? std::string()
                         : fmt::format("; the materials' law, {}, would sink it {:.3g} um", LawText(materials),
                                       um(std::pow(compliance.force / materials.stiffness, 1.0 / materials.exponent)));
    return fmt::format(
        "ringtol: note: the contact law {} (F in N, delta in m) that {} states ([contact] {} and {}) sinks roller "
        "\"{}\" {:.3g} um at {:.4g} N, which moves where errors put the ring's centre by up to {:.3g} %: the answer "
        "is that law's{} (docs/model.md §4)\n",
        LawText(law), stated_in->string(), scene_key::kStiffnessNPerME, scene_key::kExponent,
        scene.rollers[static_cast<std::size_t>(compliance.roller)].name, um(compliance.penetration), compliance.force,
        100.0 * compliance.response_change, instead);
  }
  std::string text = fmt::format(
      "ringtol: warning: the contact law {} (F in N, delta in m) sinks roller \"{}\" {:.3g} um at {:.4g} N: its "
      "compliance moves where errors put the ring's centre by up to {:.3g} % of their largest effect (more than "
      "{:.3g} %), so the answer depends on the law.\n",
      LawText(law), scene.rollers[static_cast<std::size_t>(compliance.roller)].name, um(compliance.penetration),
      compliance.force, 100.0 * compliance.response_change, 100.0 * kContactLawShare);
  if (of_the_materials) {
    text +=
        "  It is the law of the ring's and rollers' materials (Hertzian line contact, docs/model.md §4): the "
        "compliance is the assembly's own, so check their youngs_modulus_GPa, poisson_ratio and widths.\n";
    return text;
  }
  const double sinks = std::pow(compliance.force / materials.stiffness, 1.0 / materials.exponent);
  text += fmt::format(
      "  The ring's and rollers' materials give {} (Hertzian line contact), which sinks it {:.3g} um at that "
      "force: remove stiffness_N_per_m_e and exponent from [contact] to use that law, and give youngs_modulus_GPa "
      "and poisson_ratio on [ring] and [[rollers]] where they are not steel (docs/model.md §4).\n",
      LawText(materials), um(sinks));
  return text;
}

void WarnAboutContactLaw(const engine::Scene& scene, const std::filesystem::path& scene_file, std::ostream& warnings) {
  const std::optional<std::filesystem::path> stated_in =
      StatesContactLaw(scene_file) ? std::optional<std::filesystem::path>(scene_file.lexically_normal()) : std::nullopt;
  if (const std::optional<std::string> warning = ContactLawWarning(scene, stated_in)) {
    fmt::print(warnings, "{}", *warning);
    warnings.flush();
  }
}

}  // namespace ringtol::jobs
