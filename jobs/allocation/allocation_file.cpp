#include "jobs/allocation/allocation_file.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "engine/units.h"
#include "jobs/campaign/sample_record.h"
#include "jobs/inputs/toml_fields.h"
#include "sampling/assembly_sampler.h"

namespace ringtol::jobs {
namespace {

using sampling::ToleranceMode;

constexpr double kPercentPerUnit = 100.0;

// [spec] is listed so that it is refused with a pointer to what replaces it, not as an
// unknown key.
constexpr std::array<std::string_view, 3> kAllocationTables = {"solver", "spec", "allocation"};

sampling::ErrorSource SourceOf(AllocatedComponent component) {
  switch (component) {
    case AllocatedComponent::kRing: return sampling::ErrorSource::kRingShape;
    case AllocatedComponent::kRollers: return sampling::ErrorSource::kRollerShape;
    case AllocatedComponent::kRollerPositions: return sampling::ErrorSource::kRollerPosition;
    case AllocatedComponent::kSprings: return sampling::ErrorSource::kSpring;
  }
  return sampling::ErrorSource::kRingShape;
}

// The catalogue's classes of a component's kind, for the canonical name of a class given
// by alias and for messages.
template <typename F>
auto WithClasses(const sampling::ToleranceCatalogue& catalogue, AllocatedComponent component, F f) {
  switch (component) {
    case AllocatedComponent::kRing: return f(catalogue.ring_classes);
    case AllocatedComponent::kRollers: return f(catalogue.roller_classes);
    case AllocatedComponent::kRollerPositions: return f(catalogue.position_classes);
    case AllocatedComponent::kSprings: return f(catalogue.spring_classes);
  }
  return f(catalogue.ring_classes);
}

std::string ClassNames(const sampling::ToleranceCatalogue& catalogue, AllocatedComponent component) {
  return WithClasses(catalogue, component, [](const auto& classes) {
    std::string names;
    for (const auto& c : classes) names += (names.empty() ? "\"" : ", \"") + c.name + "\"";
    return names;
  });
}

// The class's name where `name` is one of its aliases; `name` itself when no class has it.
std::string CanonicalName(const sampling::ToleranceCatalogue& catalogue, AllocatedComponent component,
                          const std::string& name) {
  return WithClasses(catalogue, component, [&](const auto& classes) {
    for (const auto& c : classes) {
      if (c.name == name) return c.name;
      for (const std::string& alias : c.aliases) {
        if (alias == name) return c.name;
      }
    }
    return name;
  });
}

// The current design's class and mode of a component: empty class when its
// [tolerances.*] table is absent or gives numbers.
std::pair<std::string, ToleranceMode> CurrentClass(const sampling::AssemblyTolerances& t,
                                                   AllocatedComponent component) {
  auto first = [](const auto& list) -> std::pair<std::string, ToleranceMode> {
    for (const auto& entry : list) {
      if (entry) return {entry->class_name, entry->capability.mode};
    }
    return {"", ToleranceMode::kProcess};
  };
  switch (component) {
    case AllocatedComponent::kRing:
      return t.ring ? std::pair{t.ring->class_name, t.ring->capability.mode} : std::pair{std::string(), ToleranceMode::kProcess};
    case AllocatedComponent::kRollers: return first(t.roller_shapes);
    case AllocatedComponent::kRollerPositions: return first(t.roller_positions);
    case AllocatedComponent::kSprings: return first(t.springs);
  }
  return {"", ToleranceMode::kProcess};
}

// The characteristic tolerance of an option's resolved tolerances, in the unit of
// AllocationOption::tolerance.
double CharacteristicTolerance(const sampling::AssemblyTolerances& t, AllocatedComponent component) {
  switch (component) {
    case AllocatedComponent::kRing: return t.ring->circularity * units::kMicrometresPerMetre;
    case AllocatedComponent::kRollers: return t.roller_shapes.front()->kea * units::kMicrometresPerMetre;
    case AllocatedComponent::kRollerPositions:
      return t.roller_positions.front()->zone_diameter * units::kMicrometresPerMetre;
    case AllocatedComponent::kSprings:
      for (const auto& spring : t.springs) {
        if (spring) return spring->stiffness * kPercentPerUnit;
      }
  }
  return 0.0;
}

std::string_view ToleranceUnit(AllocatedComponent component) {
  return component == AllocatedComponent::kSprings ? "%" : "µm";
}

// Which sampler inputs an option's tolerances draw, in words. The sampler
// (sampling/assembly_sampler.cpp) leaves an input out where its tolerance is zero: a
// roller's eccentricity for Kea = 0, its form for VDsp = 0, its size for equal ΔDmp
// bounds, a spring's stiffness or preload for a zero tolerance. The ring's and the
// positions' inputs are always drawn, their spectra and capability are inherited from one
// table, and the mode changes redraws only, never the list; so options of a component draw
// the same inputs exactly when these words agree.
std::string DrawnInputs(const sampling::AssemblyTolerances& t, AllocatedComponent component) {
  std::string words;
  auto add = [&](bool drawn, std::string_view what) {
    if (drawn) words += (words.empty() ? "" : ", ") + std::string(what);
  };
  if (component == AllocatedComponent::kRollers) {
    const sampling::RollerShapeTolerance& r = *t.roller_shapes.front();
    add(r.kea > 0.0, "eccentricity (Kea > 0)");
    add(r.vdsp > 0.0, "form (VDsp > 0)");
    add(r.mean_diameter_upper > r.mean_diameter_lower, "size (ΔDmp bounds apart)");
  } else if (component == AllocatedComponent::kSprings) {
    for (const auto& spring : t.springs) {
      if (!spring) continue;
      add(spring->stiffness > 0.0, "stiffness");
      add(spring->preload > 0.0, "preload");
      break;
    }
  } else {
    words = "all";
  }
  return words.empty() ? "none" : words;
}

struct ComponentInput {
  std::vector<Site> options;
  std::optional<Site> cost;
  std::optional<analysis::CostModel> model;
};

struct AllocationInput {
  std::optional<solvers::Rung> screen = solvers::Rung::kLinear;
  std::optional<analysis::SearchKind> search;  // empty: auto
  int max_exhaustive = 256;
  int batch = 8;
  int first_samples = 256;
  double confidence = 0.95;
  CostReference reference = CostReference::kCurrent;
  std::vector<analysis::Constraint> constraints;
  std::array<std::optional<ComponentInput>, 4> components;
};

std::vector<Field<analysis::CostModel>> CostModelFields() {
  using analysis::CostModel;
  return {
      Choice("form", Presence::kOptional, analysis::kCostFormNames, &CostModel::form),
      Number("a", Presence::kOptional, kSameUnit, AtLeast(0), &CostModel::a),
      Number("b", Presence::kOptional, kSameUnit, Above(0), &CostModel::b),
      Number("k", Presence::kOptional, kSameUnit, Above(0), &CostModel::k),
  };
}

std::vector<Field<ComponentInput>> ComponentFields() {
  static const std::string options_allowed =
      "a non-empty array of class names or { class = \"...\", mode = \"process\" | \"inspected\" } tables, loosest "
      "first";
  return {
      {"options", Presence::kRequired, options_allowed,
       [](const Site& site, ComponentInput& in) {
         const toml::array& array = ReadArray(site, options_allowed);
         if (array.empty()) site.Fail("empty", options_allowed);
         for (std::size_t i = 0; i < array.size(); ++i) in.options.push_back(site.Element(i));
       },
       {}, {}},
      {"cost", Presence::kOptional, "an array of numbers >= 0, one per option, never falling",
       [](const Site& site, ComponentInput& in) { in.cost.emplace(site); }, {}, {}},
      Section<ComponentInput>("cost_model", Presence::kOptional, [](const TableReader& t, ComponentInput& in) {
        analysis::CostModel model;
        t.Read(CostModelFields(), model);
        in.model = model;
      }),
  };
}

std::string OutputList() {
  std::string outputs;
  for (const char* name : kOutputNames) outputs += (outputs.empty() ? "\"" : ", \"") + std::string(name) + "\"";
  return outputs;
}

// A constraint's limit key, in its output's unit (OutputDescription::unit).
std::string UpperKey(const OutputDescription& output) { return std::string("upper_") + output.unit; }

// The limit keys of every unit of the outputs, each once, in kOutputs' order.
std::vector<std::string> UpperKeys() {
  std::vector<std::string> keys;
  for (const OutputDescription& output : kOutputs) {
    if (std::find(keys.begin(), keys.end(), UpperKey(output)) == keys.end()) keys.push_back(UpperKey(output));
  }
  return keys;
}

// `upper_given[k]`: whether the table gave UpperKeys()[k].
std::vector<Field<analysis::Constraint>> ConstraintFields(const std::vector<std::string>& upper_keys,
                                                          std::vector<bool>& upper_given) {
  const std::string outputs = OutputList();
  std::vector<Field<analysis::Constraint>> fields{
      Text("output", Presence::kRequired, outputs, &analysis::Constraint::output),
      {"quantile", Presence::kOptional, "> 0 and < 1",
       [](const Site& site, analysis::Constraint& c) {
         c.kind = analysis::ConstraintKind::kQuantile;
         c.level = ReadNumber(site, Range{0, true, 1, true});
       },
       {}, {}},
      {"yield", Presence::kOptional, "> 0 and < 1",
       [](const Site& site, analysis::Constraint& c) {
         c.kind = analysis::ConstraintKind::kYield;
         c.level = ReadNumber(site, Range{0, true, 1, true});
       },
       {}, {}},
  };
  for (std::size_t k = 0; k < upper_keys.size(); ++k) {
    fields.push_back({upper_keys[k], Presence::kOptional, "> 0", [k, &upper_given](const Site& site, analysis::Constraint& c) {
                        c.upper = ReadNumber(site, Above(0));
                        upper_given[k] = true;
                      }, {}, {}});
  }
  return fields;
}

// One [[allocation.constraint]], checked: a campaign output, exactly one of quantile and
// yield, and its limit under the key of the output's unit.
analysis::Constraint ReadConstraint(const TableReader& t) {
  const std::vector<std::string> upper_keys = UpperKeys();
  std::vector<bool> upper_given(upper_keys.size());
  analysis::Constraint c;
  t.Read(ConstraintFields(upper_keys, upper_given), c);
  if (OutputIndex(c.output) == kOutputCount) t.Fail("output", "not an output of a campaign", OutputList());
  t.RequireExactlyOne("quantile", "yield",
                      "exactly one of quantile (> 0 and < 1: that quantile must be <= the limit) and yield (> 0 "
                      "and < 1: at least that fraction within the limit)");
  const std::string key = UpperKey(OutputNamed(c.output));
  for (std::size_t k = 0; k < upper_keys.size(); ++k) {
    if (upper_given[k] && upper_keys[k] != key)
      t.Fail(upper_keys[k], "the limit of " + c.output + " is in the unit of its name", key + " > 0");
  }
  if (!t.Has(key)) t.FailAbout("output", t.KeyPath(key), "missing: the limit of " + c.output, key + " > 0");
  return c;
}

// An option as written: a class name, or a table { class, mode }.
struct OptionText {
  std::string class_name;
  std::optional<ToleranceMode> mode;
};

AllocationOption ReadOption(const Site& site, AllocatedComponent component, const SamplingPlan& sampling,
                            ToleranceMode inherited_mode) {
  const std::string classes = ClassNames(sampling.catalogue, component);
  const std::string class_allowed = "a " + std::string(NameOf(kAllocatedComponentNames, component)) +
                                    " class of the catalogue (`ringtol classes` lists them): " + classes;
  OptionText text;
  std::optional<Site> class_site;
  if (site.node.is_string()) {
    text.class_name = ReadText(site, class_allowed);
    class_site.emplace(site);
  } else if (const toml::table* t = site.node.as_table()) {
    const TableReader table(*t, site.key_path, site.file);
    const std::vector<Field<OptionText>> fields{
        Text("class", Presence::kRequired, "a class of the catalogue for this component (`ringtol classes` lists them)",
             &OptionText::class_name),
        Choice<OptionText, std::optional<ToleranceMode>>(
            "mode", Presence::kOptional, {{"process", ToleranceMode::kProcess}, {"inspected", ToleranceMode::kInspected}},
            &OptionText::mode),
    };
    table.Read(fields, text);
    class_site.emplace(table.At("class"));
  } else {
    site.Fail("neither a class name nor a table",
              "a class name or { class = \"...\", mode = \"process\" | \"inspected\" }");
  }
  AllocationOption option;
  option.class_name = text.class_name;
  option.mode = text.mode.value_or(inherited_mode);
  try {
    option.tolerances = ToleranceOfClass(sampling, SourceOf(component), option.class_name, option.mode);
  } catch (const std::invalid_argument& e) {
    class_site->Fail(e.what(), class_allowed + ", with a row for this diameter");
  }
  option.tolerance = CharacteristicTolerance(option.tolerances, component);
  return option;
}

std::string ShowOption(const AllocationOption& option) {
  return "\"" + option.class_name + "\" (" + std::string(option.mode == ToleranceMode::kProcess ? "process" : "inspected") +
         ")";
}

// A component's options, in order and priced.
ComponentChoice ReadComponent(const TableReader& t, const ComponentInput& in, AllocatedComponent component,
                              const SamplingPlan& sampling) {
  ComponentChoice choice;
  choice.component = component;
  const ToleranceMode inherited_mode = CurrentClass(sampling.tolerances, component).second;
  const std::string unit(ToleranceUnit(component));
  for (std::size_t i = 0; i < in.options.size(); ++i) {
    const Site& site = in.options[i];
    AllocationOption option = ReadOption(site, component, sampling, inherited_mode);
    if (i > 0) {
      const AllocationOption& before = choice.options.back();
      const std::string order_allowed =
          "options loosest first: characteristic tolerance <= " + ShowDerived(before.tolerance) + " " + unit +
          " (that of " + ShowOption(before) + "), and at equal tolerance process before inspected";
      if (option.tolerance > before.tolerance)
        site.Fail("characteristic tolerance " + ShowDerived(option.tolerance) + " " + unit + " is looser than that of " +
                      ShowOption(before),
                  order_allowed);
      if (option.tolerance == before.tolerance && option.mode == ToleranceMode::kProcess &&
          before.mode == ToleranceMode::kInspected)
        site.Fail("a process option after an inspected one of the same tolerance", order_allowed);
      for (const AllocationOption& other : choice.options) {
        if (CanonicalName(sampling.catalogue, component, other.class_name) ==
                CanonicalName(sampling.catalogue, component, option.class_name) &&
            other.mode == option.mode)
          site.Fail("the same class and mode as an earlier option", "each class and mode once");
      }
      const std::string drawn = DrawnInputs(option.tolerances, component);
      const std::string first = DrawnInputs(choice.options.front().tolerances, component);
      if (drawn != first)
        site.Fail("draws other sampler inputs (" + drawn + ") than " + ShowOption(choice.options.front()) + " (" +
                      first + ")",
                  "classes that draw the same inputs, so that every candidate reuses the same design points "
                  "(common random numbers)");
    }
    choice.options.push_back(std::move(option));
  }

  if (in.cost && in.model) t.Fail("cost_model", "given together with cost", "either cost or cost_model");
  if (in.cost) {
    const std::string allowed = "an array of " + std::to_string(choice.options.size()) +
                                " numbers >= 0, one per option, never falling as options tighten";
    const toml::array& array = ReadArray(*in.cost, allowed);
    if (array.size() != choice.options.size())
      in.cost->Fail("has " + std::to_string(array.size()) + " values for " + std::to_string(choice.options.size()) +
                        " options",
                    allowed);
    for (std::size_t i = 0; i < array.size(); ++i) {
      const Site element = in.cost->Element(i);
      const double cost = ReadNumber(element, AtLeast(0));
      if (i > 0 && cost < choice.options[i - 1].cost)
        element.Fail("falls below the cost " + ShowNumber(choice.options[i - 1].cost) + " of the looser option " +
                         ShowOption(choice.options[i - 1]),
                     ">= " + ShowNumber(choice.options[i - 1].cost) + ": a tighter option never costs less");
      choice.options[i].cost = cost;
    }
  } else {
    choice.cost_model = in.model.value_or(analysis::CostModel{});
    for (std::size_t i = 0; i < choice.options.size(); ++i) {
      AllocationOption& option = choice.options[i];
      option.cost = choice.cost_model->Cost(option.tolerance);
      if (!(option.tolerance > 0.0) || !std::isfinite(option.cost))
        in.options[i].Fail("a cost model needs a characteristic tolerance > 0; this class's is " +
                               ShowDerived(option.tolerance) + " " + unit,
                           "classes with a tolerance > 0, or a cost table (cost = [...])");
    }
  }
  return choice;
}

std::int64_t CandidateCount(const std::vector<ComponentChoice>& components) {
  std::int64_t count = 1;
  for (const ComponentChoice& c : components) {
    const auto options = static_cast<std::int64_t>(c.options.size());
    count = count > std::numeric_limits<std::int64_t>::max() / options ? std::numeric_limits<std::int64_t>::max()
                                                                        : count * options;
  }
  return count;
}

}  // namespace

AllocationPlan ReadAllocationFile(const std::filesystem::path& file, const StoredSampling* stored) {
  AllocationPlan plan;
  plan.campaign.file = file;
  plan.campaign.sampling = ReadSamplingFile(file, kAllocationTables, stored);
  const SamplingPlan& sampling = plan.campaign.sampling;
  plan.text = sampling.text;

  const std::string source = file.string();
  const toml::table document = ParseToml(plan.text, source);
  const TableReader root(document, "", source);

  AllocationInput in;
  const std::vector<Field<ComponentInput>> component_fields = ComponentFields();
  std::vector<Field<AllocationInput>> component_sections;
  for (std::size_t c = 0; c < kAllocatedComponentNames.size(); ++c) {
    component_sections.push_back(Section<AllocationInput>(
        kAllocatedComponentNames[c].name, Presence::kOptional, [&, c](const TableReader& t, AllocationInput& a) {
          ComponentInput component;
          t.Read(component_fields, component);
          a.components[c].emplace(std::move(component));
        }));
  }
  std::vector<std::pair<std::string_view, std::optional<analysis::SearchKind>>> searches{{"auto", std::nullopt}};
  for (const auto& [kind, name] : analysis::kSearchKindNames) searches.emplace_back(name, kind);
  const std::vector<Field<AllocationInput>> allocation_fields{
      Choice<AllocationInput, std::optional<solvers::Rung>>("screen", Presence::kOptional,
                                                            {{"linear", solvers::Rung::kLinear}, {"none", std::nullopt}},
                                                            &AllocationInput::screen),
      Choice<AllocationInput, std::optional<analysis::SearchKind>>("search", Presence::kOptional, searches,
                                                                    &AllocationInput::search),
      Integer("max_exhaustive", Presence::kOptional, Between(1, std::numeric_limits<int>::max()),
              &AllocationInput::max_exhaustive),
      Integer("batch", Presence::kOptional, Between(1, 4096), &AllocationInput::batch),
      Integer("first_samples", Presence::kOptional, Between(1, std::numeric_limits<int>::max()),
              &AllocationInput::first_samples),
      Number("confidence", Presence::kOptional, kSameUnit, Range{0, true, 1, true}, &AllocationInput::confidence),
      Choice("reference", Presence::kOptional, kCostReferenceNames, &AllocationInput::reference),
      Sections<AllocationInput>("constraint", Presence::kRequired, 1,
                                [](const TableReader& t, std::size_t, AllocationInput& a) {
                                  a.constraints.push_back(ReadConstraint(t));
                                }),
      Section<AllocationInput>("components", Presence::kRequired,
                               [&](const TableReader& t, AllocationInput& a) { t.Read(component_sections, a); }),
  };

  struct Root {};
  Root unused;
  std::vector<Field<Root>> fields{
      Section<Root>("solver", Presence::kOptional,
                    [&](const TableReader& t, Root&) { plan.campaign.solver = ReadSolverTable(t); }),
      {"spec", Presence::kOptional, "", [](const Site& site, Root&) {
         site.Fail("an allocation file states its limits as constraints, which may bound a quantile or a yield",
                   "no [spec]; [[allocation.constraint]] tables { output, quantile or yield, upper_mm or upper_N }");
       }, {}, {}},
      Section<Root>("allocation", Presence::kRequired,
                    [&](const TableReader& t, Root&) { t.Read(allocation_fields, in); }),
  };
  // The sampling half was read and checked above; here only the allocation's own tables.
  for (const auto& [key, node] : document) {
    if (key.str() != "solver" && key.str() != "spec" && key.str() != "allocation")
      fields.push_back({key.str(), Presence::kOptional, "", [](const Site&, Root&) {}, {}, {}});
  }
  root.Read(fields, unused);

  const TableReader allocation(*document.get_as<toml::table>("allocation"), "allocation", source);
  const TableReader components(*allocation.table().get_as<toml::table>("components"), "allocation.components", source);
  for (std::size_t c = 0; c < in.components.size(); ++c) {
    if (!in.components[c]) continue;
    const AllocatedComponent component = kAllocatedComponentNames[c].value;
    const TableReader table(*components.table().get_as<toml::table>(kAllocatedComponentNames[c].name),
                            components.KeyPath(kAllocatedComponentNames[c].name), source);
    if (component == AllocatedComponent::kSprings && engine::SpringRollerCount(sampling.scene) == 0)
      components.Fail("springs", "the scene has no spring roller", "ring, rollers, roller_positions");
    plan.components.push_back(ReadComponent(table, *in.components[c], component, sampling));
  }
  if (plan.components.empty())
    allocation.FailAbout("components", "allocation.components", "no component to allocate",
                         "at least one of " + NameList(kAllocatedComponentNames, "") + ", each with options");

  if (const toml::table* solver = document.get_as<toml::table>("solver")) {
    // Every option can be drawn: the fastest term is the fastest of any option's.
    engine::FastestHarmonic fastest = sampling::FastestDrawnHarmonic(sampling.scene, sampling.tolerances);
    for (const ComponentChoice& choice : plan.components) {
      for (const AllocationOption& option : choice.options) {
        const engine::FastestHarmonic drawn = sampling::FastestDrawnHarmonic(sampling.scene, option.tolerances);
        if (drawn.rate > fastest.rate) fastest = drawn;
      }
    }
    RequireEnoughSteps(TableReader(*solver, "solver", source), plan.campaign.solver.simulation.steps, sampling.scene,
                       fastest);
  }

  plan.constraints = in.constraints;
  plan.screen = in.screen;
  // The linear rung's bound on its own error is validated against the quasistatic rung
  // (the exact model without inertia). The auto rung answers with the linear rung's own
  // path or the quasistatic rung's, so the bound holds against it too, except on the
  // samples auto sends to the dynamic rung (the ring's inertia could open a contact:
  // solvers/auto.h), which at the speeds the catalogue's classes meet it does not.
  // Against the linear or dynamic [solver] the bound proves nothing.
  const solvers::Rung confirm = plan.campaign.solver.rung;
  if (plan.screen && confirm != solvers::Rung::kQuasistatic && confirm != solvers::Rung::kAuto) {
    allocation.Fail("screen",
                    "screens for [solver] name = \"" +
                        std::string(NameOf(solvers::kRungNames, plan.campaign.solver.rung)) +
                        "\", but its error bound is known only against the quasistatic rung",
                    "\"none\", or [solver] name = \"auto\" or \"quasistatic\"");
  }
  plan.max_exhaustive = in.max_exhaustive;
  plan.search.batch = in.batch;
  plan.confidence = in.confidence;
  plan.reference = in.reference;
  const std::int64_t candidates = CandidateCount(plan.components);
  plan.search.kind = in.search.value_or(candidates <= plan.max_exhaustive ? analysis::SearchKind::kExhaustive
                                                                         : analysis::SearchKind::kBranchAndBound);

  // A stage is a prefix of the design, and its samples must be independent draws for the
  // intervals: a prefix of a Latin hypercube is no Latin hypercube, and a Saltelli design's
  // rows re-use each other's coordinates.
  if (const sampling::DesignKind kind = sampling.design.kind;
      kind == sampling::DesignKind::kLatinHypercube || kind == sampling::DesignKind::kSaltelli) {
    const toml::node* design = document.at_path("design.kind").node();
    FailAt(design != nullptr ? Where(source, design->source()) : source,
           "design.kind = \"" + std::string(sampling::DesignName(kind)) + "\"",
           "an allocation simulates each candidate in stages that are prefixes of the design, which must be "
           "independent draws",
           "\"sobol\" (one net: every stage a net) or \"monte_carlo\"");
  }

  // An absent first_samples never exceeds a small design: the whole design is then one stage.
  if (allocation.Has("first_samples") && in.first_samples > sampling.samples)
    allocation.Fail("first_samples", "is more than design.samples = " + std::to_string(sampling.samples),
                    "an integer >= 1 and <= design.samples");
  plan.first_samples = std::min<std::int64_t>(in.first_samples, sampling.samples);

  // The current design: the candidate whose options are the [tolerances.*] tables' classes.
  std::vector<int> current;
  std::string missing;
  for (const ComponentChoice& choice : plan.components) {
    const auto [name, mode] = CurrentClass(sampling.tolerances, choice.component);
    const std::string canonical = CanonicalName(sampling.catalogue, choice.component, name);
    std::int64_t found = -1;
    for (std::size_t o = 0; o < choice.options.size() && !name.empty(); ++o) {
      if (CanonicalName(sampling.catalogue, choice.component, choice.options[o].class_name) == canonical &&
          choice.options[o].mode == mode)
        found = static_cast<std::int64_t>(o);
    }
    const std::string component(NameOf(kAllocatedComponentNames, choice.component));
    if (found < 0 && missing.empty()) {
      missing = name.empty() ? "[tolerances." + component + "] names no class"
                             : "[tolerances." + component + "] class \"" + name + "\" (" +
                                   (mode == ToleranceMode::kProcess ? "process" : "inspected") +
                                   ") is not among allocation.components." + component + ".options";
    }
    current.push_back(static_cast<int>(std::max<std::int64_t>(found, 0)));
  }
  if (missing.empty()) plan.current = plan.Space().Candidate(current);
  if (plan.reference == CostReference::kCurrent && !plan.current)
    allocation.Fail("reference",
                    std::string(allocation.Has("reference") ? "" : "the default, ") +
                        "needs the current design among the candidates, and " + missing,
                    "\"loosest\", or each allocated component's [tolerances] class and mode among its options");
  return plan;
}

analysis::AllocationSpace AllocationPlan::Space() const {
  std::vector<std::vector<double>> costs;
  for (const ComponentChoice& choice : components) {
    std::vector<double>& component = costs.emplace_back();
    for (const AllocationOption& option : choice.options) component.push_back(option.cost);
  }
  return analysis::AllocationSpace(std::move(costs));
}

sampling::AssemblyTolerances AllocationPlan::Tolerances(std::int64_t candidate) const {
  sampling::AssemblyTolerances tolerances = campaign.sampling.tolerances;
  const std::vector<int> options = Space().Options(candidate);
  for (std::size_t k = 0; k < components.size(); ++k) {
    const sampling::AssemblyTolerances& option = components[k].options[static_cast<std::size_t>(options[k])].tolerances;
    switch (components[k].component) {
      case AllocatedComponent::kRing: tolerances.ring = option.ring; break;
      case AllocatedComponent::kRollers: tolerances.roller_shapes = option.roller_shapes; break;
      case AllocatedComponent::kRollerPositions: tolerances.roller_positions = option.roller_positions; break;
      case AllocatedComponent::kSprings: tolerances.springs = option.springs; break;
    }
  }
  return tolerances;
}

}  // namespace ringtol::jobs
