#include "jobs/inputs/sweep_file.h"

#include <array>
#include <cstddef>
#include <optional>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "jobs/inputs/scene_file.h"
#include "jobs/inputs/toml_fields.h"
#include "engine/units.h"

namespace ringtol::jobs {
namespace {

// What a harmonic series of a sweep replaces in the base scene.
enum class Target { kRing, kRollerPositions, kRollerShape };

// The targets' names, shared by [study] target and the keys of [[cases]].
constexpr std::array<std::pair<std::string_view, Target>, 3> kTargets{{
    {"ring", Target::kRing},
    {"roller_positions", Target::kRollerPositions},
    {"roller_shape", Target::kRollerShape},
}};

std::string_view TargetName(Target target) {
  for (const auto& [name, value] : kTargets) {
    if (value == target) return name;
  }
  return "?";
}

constexpr std::string_view kOneOf = "exactly one of [study] or [[cases]]";

engine::Scene WithHarmonics(engine::Scene scene, Target target, const std::vector<engine::Harmonic>& harmonics) {
  const auto replace = [&harmonics](const engine::PolarProfile& profile) {
    return engine::PolarProfile(profile.radius(), profile.mean_deviation(), harmonics);
  };
  switch (target) {
    case Target::kRing:
      scene.ring.inner = replace(scene.ring.inner);
      break;
    case Target::kRollerPositions:
      scene.roller_positions = replace(scene.roller_positions);
      break;
    case Target::kRollerShape:
      for (engine::Roller& roller : scene.rollers) roller.outline = replace(roller.outline);
      break;
  }
  return scene;
}

// Why a case's scene fails the scene file's geometry checks, and which target to blame.
struct Problem {
  std::string what;
  std::string allowed;
  Target culprit = Target::kRing;
};

std::optional<Problem> FindProblem(const engine::Scene& scene) {
  const auto oversized = [](const engine::PolarProfile& profile, const std::string& whose,
                            const std::string& radius_key, Target culprit) -> std::optional<Problem> {
    const double bound = DeviationBound(profile);
    if (bound < profile.radius()) return std::nullopt;
    return Problem{fmt::format("amplitudes larger than the radius of {}: |mean deviation| + sum of amplitudes = {} mm",
                               whose, ShowDerived(units::InMillimetres(bound))),
                   fmt::format("< {} mm ({} in the scene file)", ShowDerived(units::InMillimetres(profile.radius())),
                               radius_key),
                   culprit};
  };
  if (auto problem = oversized(scene.ring.inner, "the ring", "ring.inner_radius_mm", Target::kRing)) return problem;
  for (std::size_t i = 0; i < scene.rollers.size(); ++i) {
    const engine::Roller& roller = scene.rollers[i];
    if (auto problem = oversized(roller.outline, "roller " + roller.name, fmt::format("rollers[{}].radius_mm", i),
                                 Target::kRollerShape)) {
      return problem;
    }
  }
  const engine::GeometryCheck check = engine::CheckGeometry(scene);
  if (check.issue == engine::GeometryIssue::kRollerDoesNotFit) {
    return Problem{check.message, FitRule(scene.ring.inner.radius()), Target::kRollerPositions};
  }
  if (check.issue == engine::GeometryIssue::kRollersOverlap) {
    return Problem{check.message, ClearanceRule(), Target::kRollerPositions};
  }
  return std::nullopt;
}

// ---- [study]

struct StudyInput {
  Target target = Target::kRing;
  std::vector<int> orders;
  std::vector<double> amplitudes;  // [m]
  double phase = 0.0;              // [rad]
};

std::vector<Field<StudyInput>> StudyFields() {
  return {
      Choice<StudyInput, Target>("target", Presence::kRequired, {kTargets.begin(), kTargets.end()},
                                 &StudyInput::target),
      IntegerList("orders", Presence::kRequired, Between(1.0, kMaxHarmonicOrder), &StudyInput::orders),
      NumberList("amplitudes_mm", Presence::kRequired, units::kMetresPerMillimetre, AtLeast(0.0), &StudyInput::amplitudes),
      Number("phase_deg", Presence::kOptional, units::kRadiansPerDegree, AnyFinite(), &StudyInput::phase),
  };
}

std::string StudyCaseName(const StudyInput& study, std::size_t order, std::size_t amplitude) {
  return fmt::format("{} n={} C={}mm", TargetName(study.target), study.orders[order],
                     ShowDerived(units::InMillimetres(study.amplitudes[amplitude])));
}

void AddStudyCases(const TableReader& table, const StudyInput& study, const engine::Scene& base, Sweep& sweep) {
  // Repeats would give two cases the same name.
  for (std::size_t i = 0; i < study.orders.size(); ++i) {
    for (std::size_t k = 0; k < i; ++k) {
      if (study.orders[k] == study.orders[i]) {
        table.At("orders").Element(i).Fail(fmt::format("repeats orders[{}]", k), "distinct orders");
      }
    }
  }
  for (std::size_t j = 0; j < study.amplitudes.size(); ++j) {
    for (std::size_t k = 0; k < j; ++k) {
      if (StudyCaseName(study, 0, k) == StudyCaseName(study, 0, j)) {
        table.At("amplitudes_mm")
            .Element(j)
            .Fail(fmt::format("repeats amplitudes_mm[{}] to 6 significant digits", k), "distinct amplitudes");
      }
    }
  }
  for (std::size_t i = 0; i < study.orders.size(); ++i) {
    for (std::size_t j = 0; j < study.amplitudes.size(); ++j) {
      const std::string name = StudyCaseName(study, i, j);
      engine::Scene scene =
          WithHarmonics(base, study.target, {engine::Harmonic{study.orders[i], study.amplitudes[j], study.phase}});
      if (const std::optional<Problem> problem = FindProblem(scene)) {
        table.At("amplitudes_mm")
            .Element(j)
            .Fail(fmt::format("case \"{}\": {}", name, problem->what), problem->allowed);
      }
      sweep.cases.push_back({name, std::move(scene)});
    }
  }
}

// ---- [[cases]]

struct CaseInput {
  std::string name;
  std::vector<std::pair<Target, std::vector<engine::Harmonic>>> replacements;  // in file order
};

std::vector<Field<CaseInput>> CaseFields() {
  std::vector<Field<CaseInput>> fields{
      Text("name", Presence::kRequired, "a non-empty string, unique among the cases", &CaseInput::name)};
  for (const auto& [key, target] : kTargets) {
    fields.push_back({key, Presence::kOptional, std::string(kHarmonicsAllowed),
                      [target = target](const Site& site, CaseInput& input) {
                        input.replacements.emplace_back(target, ReadHarmonics(site));
                      },
                      {}, {}});
  }
  return fields;
}

void AddCase(const TableReader& table, const CaseInput& input, const engine::Scene& base, Sweep& sweep) {
  engine::Scene scene = base;
  for (const auto& [target, harmonics] : input.replacements) scene = WithHarmonics(std::move(scene), target, harmonics);
  if (const std::optional<Problem> problem = FindProblem(scene)) {
    // Blame the listed key that most likely caused it; the base scene passed these checks.
    std::string_view key = "name";
    for (const auto& [target, harmonics] : input.replacements) {
      if (key == "name" || target == problem->culprit) key = TargetName(target);
    }
    table.Fail(key, fmt::format("case \"{}\": {}", input.name, problem->what), problem->allowed);
  }
  sweep.cases.push_back({input.name, std::move(scene)});
}

// ---- the file

struct SweepInput {
  std::string scene;
  std::optional<std::pair<TableReader, StudyInput>> study;
  std::vector<std::pair<TableReader, CaseInput>> cases;
};

std::vector<Field<SweepInput>> SweepFields() {
  return {
      Text("scene", Presence::kRequired, "the path of a scene file, relative to the sweep file's folder",
           &SweepInput::scene),
      Section<SweepInput>("study", Presence::kOptional,
                          [](const TableReader& table, SweepInput& sweep) {
                            StudyInput study;
                            table.Read(StudyFields(), study);
                            sweep.study.emplace(table, std::move(study));
                          }),
      Sections<SweepInput>("cases", Presence::kOptional, 1,
                           [](const TableReader& table, std::size_t, SweepInput& sweep) {
                             CaseInput input;
                             table.Read(CaseFields(), input);
                             for (std::size_t other = 0; other < sweep.cases.size(); ++other) {
                               if (sweep.cases[other].second.name == input.name) {
                                 table.Fail("name", fmt::format("the same name as cases[{}]", other),
                                            "a name no other case has");
                               }
                             }
                             sweep.cases.emplace_back(table, std::move(input));
                           }),
  };
}

}  // namespace

Sweep ReadSweep(const std::filesystem::path& file) {
  const std::string source_name = file.string();
  const toml::table document = ParseToml(ReadTextFile(file), source_name);
  const TableReader root(document, "", source_name);
  SweepInput input;
  root.Read(SweepFields(), input);
  if (input.study.has_value() && !input.cases.empty()) {
    root.FailAbout("cases", "study and cases", "both present", kOneOf);
  }
  if (!input.study.has_value() && input.cases.empty()) {
    FailAt(root.Location(), "study and cases", "neither present", kOneOf);
  }

  Sweep sweep;
  sweep.scene_file = file.parent_path() / input.scene;
  std::error_code error;
  if (!std::filesystem::is_regular_file(sweep.scene_file, error)) {
    root.Fail("scene", fmt::format("no such file: {}", sweep.scene_file.string()),
              "the path of a scene file, relative to the sweep file's folder");
  }
  const engine::Scene base = ReadScene(sweep.scene_file);

  if (input.study.has_value()) AddStudyCases(input.study->first, input.study->second, base, sweep);
  for (const auto& [table, case_input] : input.cases) AddCase(table, case_input, base, sweep);
  return sweep;
}

}  // namespace ringtol::jobs
