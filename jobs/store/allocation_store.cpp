#include "jobs/store/allocation_store.h"

#include <hdf5.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <tuple>
#include <type_traits>
#include <utility>

#include "engine/check.h"
#include "jobs/inputs/input_error.h"
#include "jobs/store/hdf5_file.h"
#include "jobs/store/identity_attributes.h"
#include "jobs/store/sample_table.h"

namespace ringtol::jobs {

using namespace hdf5;  // NOLINT(google-build-using-namespace): the store's own HDF5 helpers

namespace {

namespace fs = std::filesystem;

constexpr const char* kFormat = "ringtol allocation";
constexpr const char* kCampaignFormat = "ringtol campaign";
// The default chunk along N: whole stages, but never so small that the chunk index
// outweighs the data, nor so large that a partial commit rewrites much.
constexpr std::int64_t kLeastChunkSamples = 64;
constexpr std::int64_t kMostChunkSamples = 1024;
// Rows of a per-candidate dataset ([C] or [C, M]) in one chunk: a few pages of numbers.
constexpr hsize_t kCandidateChunkRows = 4096;
// Rows of /inputs/u in one chunk: about 256 KiB, as the campaign's.
constexpr std::size_t kDesignChunkBytes = 256u << 10;
constexpr std::array<EvaluationRole, 2> kRoles = {EvaluationRole::kScreen, EvaluationRole::kConfirm};
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string RoleName(EvaluationRole role) { return std::string(NameOf(kEvaluationRoleNames, role)); }
std::size_t RoleIndex(EvaluationRole role) { return role == EvaluationRole::kScreen ? 0 : 1; }

// ---------------------------------------------------------------------------------------
// The [C, N] datasets of a role, statuses last: Commit writes them in this order.

enum class SampleField { kOutput, kErrorBound, kSteps, kSolveTime, kStatus };

struct RoleColumn {
  std::string name;  // under /samples/<role>/
  SampleField field = SampleField::kOutput;
  std::size_t output = 0;  // kOutput: index into the stored outputs
};

std::vector<RoleColumn> RoleColumns(EvaluationRole role, const std::vector<std::string>& outputs) {
  std::vector<RoleColumn> columns;
  for (std::size_t q = 0; q < outputs.size(); ++q) columns.push_back({outputs[q], SampleField::kOutput, q});
  if (role == EvaluationRole::kScreen) columns.push_back({"d_trajectory_error_mm", SampleField::kErrorBound, 0});
  columns.push_back({"steps", SampleField::kSteps, 0});
  columns.push_back({"solve_time_s", SampleField::kSolveTime, 0});
  columns.push_back({"status", SampleField::kStatus, 0});
  return columns;
}

std::string ColumnPath(EvaluationRole role, const RoleColumn& column) {
  return "/samples/" + RoleName(role) + "/" + column.name;
}

// The error-motion columns the samples keep, with the filter they were read through.
std::vector<std::string> ErrorMotionColumnPaths(const std::vector<std::string>& outputs) {
  std::vector<std::string> paths;
  for (const EvaluationRole role : kRoles) {
    for (const std::string& output : outputs) {
      if (IsErrorMotionOutput(output)) paths.push_back(ColumnPath(role, {output}));
    }
  }
  return paths;
}

void WriteErrorMotionColumnAttributes(const Where& where, hid_t file, const AllocationIdentity& identity,
                                      const std::vector<std::string>& outputs) {
  for (const std::string& path : ErrorMotionColumnPaths(outputs)) {
    const DatasetId dataset(Check(H5Dopen2(file, path.c_str(), H5P_DEFAULT), where, "opening dataset", path));
    WriteErrorMotionAttributes(where, dataset.get(), identity.error_motion_filter);
  }
}

// A role's columns as the sample table keeps them (jobs/store/sample_table.h).
std::vector<ColumnSpec> RoleSpecs(EvaluationRole role, const std::vector<RoleColumn>& columns) {
  std::vector<ColumnSpec> specs;
  for (const RoleColumn& column : columns) {
    ColumnSpec& spec = specs.emplace_back();
    spec.path = spec.stored_path = ColumnPath(role, column);
    spec.fill = kNaN;
    spec.cached = true;
    if (column.field == SampleField::kSteps) {
      spec.type = ColumnType::kInt32;
      spec.fill = 0;
    } else if (column.field == SampleField::kStatus) {
      spec.type = ColumnType::kInt8Enum;
      spec.enumeration = StatusType;
      spec.fill = static_cast<double>(SampleStatus::kPending);
    }
  }
  return specs;
}

// [C, N]: a row of samples per candidate.
RowSpace CandidateRows(std::int64_t candidates, std::int64_t samples, std::int64_t chunk_samples = 1) {
  RowSpace space;
  space.groups = candidates;
  space.samples = samples;
  space.chunk_samples = chunk_samples;
  return space;
}

// The outputs the samples keep: those the constraints name, each once, in their order.
std::vector<std::string> StoredOutputs(const std::vector<analysis::Constraint>& constraints) {
  std::vector<std::string> outputs;
  for (const analysis::Constraint& constraint : constraints) {
    if (std::find(outputs.begin(), outputs.end(), constraint.output) == outputs.end()) {
      outputs.push_back(constraint.output);
    }
  }
  return outputs;
}

std::int64_t CandidateCount(const AllocationIdentity& identity) {
  std::int64_t count = 1;
  for (const auto& options : identity.options) {
    if (options.empty()) return 0;
    if (count > std::numeric_limits<std::int64_t>::max() / static_cast<std::int64_t>(options.size())) return -1;
    count *= static_cast<std::int64_t>(options.size());
  }
  return count;
}

// Mixed radix, the last component fastest (analysis::AllocationSpace).
std::vector<std::int32_t> CandidateOptions(const AllocationIdentity& identity, std::int64_t candidate) {
  std::vector<std::int32_t> options(identity.options.size());
  for (std::size_t k = options.size(); k-- > 0;) {
    const auto radix = static_cast<std::int64_t>(identity.options[k].size());
    options[k] = static_cast<std::int32_t>(candidate % radix);
    candidate /= radix;
  }
  return options;
}

double CandidateCost(const AllocationIdentity& identity, const std::vector<std::int32_t>& options) {
  double cost = 0.0;
  for (std::size_t k = 0; k < options.size(); ++k) cost += identity.options[k][static_cast<std::size_t>(options[k])].cost;
  return cost;
}

void CheckIdentity(const AllocationIdentity& identity, const AllocationStoreOptions& options) {
  const auto fail = [](const std::string& what) { throw std::invalid_argument("AllocationStore: " + what); };
  if (identity.samples < 1) fail(fmt::format("samples = {} must be >= 1", identity.samples));
  if (identity.first_samples < 1 || identity.first_samples > identity.samples) {
    fail(fmt::format("first_samples = {} is outside [1, {}]", identity.first_samples, identity.samples));
  }
  if (identity.inputs.empty()) fail("an allocation needs at least one sampled input");
  if (identity.components.empty() || identity.components.size() != identity.options.size()) {
    fail(fmt::format("{} components with {} option lists", identity.components.size(), identity.options.size()));
  }
  const std::int64_t candidates = CandidateCount(identity);
  if (candidates < 1) fail("every component needs an option, and the candidates must be countable");
  if (identity.constraints.empty()) fail("an allocation needs at least one constraint");
  for (const analysis::Constraint& constraint : identity.constraints) {
    if (OutputIndex(constraint.output) == kOutputCount) fail("constraint on unknown output '" + constraint.output + "'");
  }
  if (identity.reference && (*identity.reference < 0 || *identity.reference >= candidates)) {
    fail(fmt::format("reference candidate {} is outside [0, {})", *identity.reference, candidates));
  }
  if (options.chunk_samples < 0) fail(fmt::format("chunk_samples = {} is negative", options.chunk_samples));
}

// ---------------------------------------------------------------------------------------
// Types of the outcome's enumerations

template <typename Enum, std::size_t N>
TypeId EnumType(const Where& where, const NameTable<Enum, N>& names, const char* what) {
  TypeId type(Check(H5Tenum_create(H5T_NATIVE_INT8), where, "creating", what));
  for (const NamedValue<Enum>& entry : names) {
    const auto value = static_cast<std::int8_t>(entry.value);
    const std::string name(entry.name);
    CheckStatus(H5Tenum_insert(type.get(), name.c_str(), &value), where, "naming a value of", what);
  }
  return type;
}

// settled_by: a role, or none (-1).
TypeId SettledByType(const Where& where) {
  TypeId type = EnumType(where, kEvaluationRoleNames, "the settled_by type");
  const std::int8_t none = -1;
  CheckStatus(H5Tenum_insert(type.get(), "none", &none), where, "naming a value of", "the settled_by type");
  return type;
}

// ---------------------------------------------------------------------------------------
// The outcome's arrays and attributes, once: CreateOutcome, WriteOutcome, ReadOutcomeFrom
// and CheckOutcome iterate over these tables, in the order the file has them created.

// How many rows and columns an array has: C candidates, K components, M constraints.
enum class Extent {
  kCandidates,            // [C]
  kJudgedCandidates,      // [C], the fill unless the candidate's yield has trials
  kCandidateComponents,   // [C, K]
  kCandidateConstraints,  // [C, M], the fill unless the candidate has judgements
  kUpToCandidates,        // [*]: a list of candidates, extendable up to C
  kUpToConstraints,       // [*]: a list of constraints, extendable up to M
};

struct Extents {
  hsize_t candidates = 0;
  hsize_t components = 0;
  hsize_t constraints = 0;

  // A row's columns of a per-candidate array (0: one-dimensional).
  hsize_t Columns(Extent extent) const {
    return extent == Extent::kCandidateComponents    ? components
           : extent == Extent::kCandidateConstraints ? constraints
                                                     : 0;
  }
  // The most entries of a list, and the end of the range each one is in.
  hsize_t Most(Extent extent) const { return extent == Extent::kUpToConstraints ? constraints : candidates; }
};

// Of a candidate's row, the elements it holds; the rest are the array's fill.
std::size_t HeldBy(const CandidateOutcome& candidate, Extent extent) {
  switch (extent) {
    case Extent::kJudgedCandidates:
      return candidate.yield.trials > 0 ? 1 : 0;
    case Extent::kCandidateComponents:
      return candidate.options.size();
    case Extent::kCandidateConstraints:
      return candidate.constraints.size();
    default:
      return 1;
  }
}

// A field as the file keeps it, T, and back: an enumeration by its code, a bool as 0 or 1,
// an optional as -1 when empty.
template <typename T, typename V>
T Encode(const V& value) {
  return static_cast<T>(value);
}
template <typename T, typename V>
T Encode(const std::optional<V>& value) {
  return value ? static_cast<T>(*value) : T{-1};
}
template <typename T, typename V>
void Decode(T stored, V& field) {
  field = static_cast<V>(stored);
}
template <typename T, typename V>
void Decode(T stored, std::optional<V>& field) {
  field = stored >= 0 ? std::optional<V>(static_cast<V>(stored)) : std::nullopt;
}

// An array, or an attribute of /outcome, of T (TypesOf; in the file an `enumeration` of
// int8 codes where given): access(candidate, j) is element j of a candidate's row,
// access(outcome) a list or an attribute, each a reference to the field.
template <typename T, typename Access>
struct OutcomeField {
  using Element = T;
  const char* path;  // an attribute's name
  Extent extent;
  T fill;  // an attribute's value before any outcome
  Access access;
  TypeId (*enumeration)(const Where& where) = nullptr;
};
template <typename T, typename Access>
constexpr OutcomeField<T, Access> Field(const char* path, Extent extent, T fill, Access access,
                                        TypeId (*enumeration)(const Where&) = nullptr) {
  return {path, extent, fill, access, enumeration};
}
template <typename T, typename Access>
constexpr OutcomeField<T, Access> Attribute(const char* name, T before, Access access) {
  return {name, Extent::kCandidates, before, access};
}

TypeId VerdictType(const Where& where) { return EnumType(where, analysis::kVerdictNames, "the verdict type"); }
TypeId SettlementType(const Where& where) {
  return EnumType(where, analysis::kSettlementNames, "the settlement type");
}

// Created and written with the identity (WriteIdentity), read back into the outcome.
constexpr std::tuple kCandidateArrays{
    Field<std::int32_t>("/candidates/options", Extent::kCandidateComponents, 0,
                        [](auto& c, std::size_t k) -> auto& { return c.options[k]; }),
    Field<double>("/candidates/cost", Extent::kCandidates, 0, [](auto& c, std::size_t) -> auto& { return c.cost; }),
    Field<double>("/candidates/relative_cost", Extent::kCandidates, 0,
                  [](auto& c, std::size_t) -> auto& { return c.relative_cost; }),
};

// Created as an allocation with nothing visited (every row its fill), rewritten whole at
// every commit.
constexpr std::tuple kOutcomeArrays{
    Field<std::int8_t>("/outcome/verdict", Extent::kCandidates, 0,
                       [](auto& c, std::size_t) -> auto& { return c.verdict; }, VerdictType),
    Field<std::int8_t>("/outcome/settlement", Extent::kCandidates, 0,
                       [](auto& c, std::size_t) -> auto& { return c.settlement; }, SettlementType),
    Field<std::int8_t>("/outcome/settled_by", Extent::kCandidates, -1,
                       [](auto& c, std::size_t) -> auto& { return c.settled_by; }, SettledByType),
    Field<std::int64_t>("/outcome/samples", Extent::kCandidates, 0,
                        [](auto& c, std::size_t) -> auto& { return c.samples; }),
    Field<std::int64_t>("/outcome/implied_by", Extent::kCandidates, -1,
                        [](auto& c, std::size_t) -> auto& { return c.implied_by; }),
    Field<double>("/outcome/estimate", Extent::kCandidateConstraints, kNaN,
                  [](auto& c, std::size_t j) -> auto& { return c.constraints[j].estimate; }),
    Field<double>("/outcome/lower", Extent::kCandidateConstraints, kNaN,
                  [](auto& c, std::size_t j) -> auto& { return c.constraints[j].interval.lower; }),
    Field<double>("/outcome/upper", Extent::kCandidateConstraints, kNaN,
                  [](auto& c, std::size_t j) -> auto& { return c.constraints[j].interval.upper; }),
    Field<std::int8_t>("/outcome/constraint_verdict", Extent::kCandidateConstraints, 0,
                       [](auto& c, std::size_t j) -> auto& { return c.constraints[j].verdict; }, VerdictType),
    Field<std::int64_t>("/outcome/samples_to_decide", Extent::kCandidateConstraints, 0,
                        [](auto& c, std::size_t j) -> auto& { return c.constraints[j].samples_to_decide; }),
    Field<double>("/outcome/yield", Extent::kJudgedCandidates, kNaN,
                  [](auto& c, std::size_t) -> auto& { return c.yield.value; }),
    Field<double>("/outcome/yield_lower", Extent::kJudgedCandidates, kNaN,
                  [](auto& c, std::size_t) -> auto& { return c.yield.interval.lower; }),
    Field<double>("/outcome/yield_upper", Extent::kJudgedCandidates, kNaN,
                  [](auto& c, std::size_t) -> auto& { return c.yield.interval.upper; }),
    Field<std::int64_t>("/outcome/yield_trials", Extent::kCandidates, 0,
                        [](auto& c, std::size_t) -> auto& { return c.yield.trials; }),
};

// Lists of /outcome, rewritten whole at every commit; their fill is never seen.
constexpr std::tuple kOutcomeLists{
    Field<std::int64_t>("/outcome/alternatives", Extent::kUpToCandidates, 0,
                        [](auto& o) -> auto& { return o.alternatives; }),
    Field<std::int64_t>("/outcome/undecided_cheaper", Extent::kUpToCandidates, 0,
                        [](auto& o) -> auto& { return o.undecided_cheaper; }),
    Field<std::int64_t>("/outcome/front", Extent::kUpToCandidates, 0, [](auto& o) -> auto& { return o.front; }),
    Field<std::int32_t>("/outcome/binding", Extent::kUpToConstraints, 0, [](auto& o) -> auto& { return o.binding; }),
};

// The attributes of /outcome.
constexpr std::tuple kOutcomeAttributes{
    Attribute<std::int64_t>("recommendation", -1, [](auto& o) -> auto& { return o.recommendation; }),
    Attribute<std::int8_t>("complete", 0, [](auto& o) -> auto& { return o.complete; }),
    Attribute<std::int64_t>("simulated", 0, [](auto& o) -> auto& { return o.simulated; }),
    Attribute<std::int64_t>("settled_by_screen", 0, [](auto& o) -> auto& { return o.settled_by_screen; }),
    Attribute<std::int64_t>("samples_screen", 0, [](auto& o) -> auto& { return o.samples_screen; }),
    Attribute<std::int64_t>("samples_confirm", 0, [](auto& o) -> auto& { return o.samples_confirm; }),
    Attribute<double>("common_random_numbers_gain", kNaN, [](auto& o) -> auto& { return o.common_random_numbers_gain; }),
};

// Calls `visit` on each row of `table`, in order.
template <typename Table, typename Visit>
void ForEachRow(const Table& table, const Visit& visit) {
  std::apply([&](const auto&... row) { (visit(row), ...); }, table);
}

// ---------------------------------------------------------------------------------------
// Identity

// The identity's root attributes, but for `candidates` (its options') and `reference`
// (-1 for none).
constexpr std::array<IdentityAttribute<AllocationIdentity>, 13> kIdentityAttributes = {{
    {"ringtol_version", &AllocationIdentity::ringtol_version},
    {"catalogue_version", &AllocationIdentity::catalogue_version},
    {"allocation_path", &AllocationIdentity::allocation_path, Comparison::kNever},
    {"allocation_file", &AllocationIdentity::allocation_file, Comparison::kText},
    {"base_scene", &AllocationIdentity::base_scene, Comparison::kText},
    {"design", &AllocationIdentity::design},
    {"solver", &AllocationIdentity::solver},
    {"screen", &AllocationIdentity::screen},
    {"search", &AllocationIdentity::search},
    {"seed", &AllocationIdentity::seed},
    {"samples", &AllocationIdentity::samples},
    {"first_samples", &AllocationIdentity::first_samples},
    {"confidence", &AllocationIdentity::confidence},
}};

struct Stored {
  AllocationIdentity identity;
  int schema_version = 0;
  std::int64_t candidates = 0;
  bool index = false;  // an index of shards (its layout)
};

template <typename T>
T Require(const Where& where, std::optional<T> value, const char* name) {
  if (!value) Fail(where, fmt::format("is not a complete ringtol allocation file: attribute {} is missing", name));
  return *std::move(value);
}

void CheckFormat(const Where& where, hid_t file) {
  const std::optional<std::string> format = FormatOf(where, file);
  if (format == std::optional<std::string>(kFormat)) return;
  if (format == std::optional<std::string>(kCampaignFormat)) {
    throw InputError(where.file + ": is a ringtol campaign results file, not an allocation's");
  }
  throw InputError(where.file + ": is not a ringtol allocation file (its root has no attribute format = \"" + kFormat +
                   "\")");
}

Stored ReadStored(const Where& where, hid_t file) {
  CheckFormat(where, file);
  Stored stored;
  const auto integer = [&](const char* name) {
    return Require(where, ReadNumberAttribute<std::int64_t>(where, file, name, H5T_INTEGER, H5T_NATIVE_INT64), name);
  };
  const std::int64_t schema = integer("schema_version");
  if (schema > kAllocationIndexSchemaVersion) {
    throw InputError(fmt::format("{}: was written by a newer ringtol (schema {}); this ringtol reads schemas {} and {}",
                                 where.file, schema, kAllocationSchemaVersion, kAllocationIndexSchemaVersion));
  }
  if (schema != kAllocationSchemaVersion && schema != kAllocationIndexSchemaVersion) {
    throw InputError(fmt::format("{}: has unknown schema version {}; this ringtol reads schemas {} and {}",
                                 where.file, schema, kAllocationSchemaVersion, kAllocationIndexSchemaVersion));
  }
  const StoredLayout layout =
      ReadLayout(where, file, static_cast<int>(schema), kAllocationIndexSchemaVersion, kAllocationSchemaVersion);
  if (layout.rows_schema != kAllocationSchemaVersion) {
    throw InputError(fmt::format("{}: keeps rows of schema {}; this ringtol reads schema {}", where.file,
                                 layout.rows_schema, kAllocationSchemaVersion));
  }
  stored.schema_version = layout.rows_schema;
  stored.index = layout.layout == Layout::kShardIndex;

  AllocationIdentity& identity = stored.identity;
  ReadIdentityAttributes(where, file, identity, kIdentityAttributes, kFormat);
  stored.candidates = integer("candidates");
  if (const std::int64_t reference = integer("reference"); reference >= 0) identity.reference = reference;
  identity.inputs = ReadInputDescriptions(where, file);

  identity.components = ReadStrings(where, file, "/components/name");
  const std::vector<std::int32_t> component = ReadInts(where, file, "/options/component");
  const std::vector<std::string> classes = ReadStrings(where, file, "/options/class");
  const std::vector<std::string> modes = ReadStrings(where, file, "/options/mode");
  const auto tolerances = ReadWhole<double>(where, file, "/options/tolerance");
  const auto costs = ReadWhole<double>(where, file, "/options/cost");
  const std::size_t o = component.size();
  if (classes.size() != o || modes.size() != o || tolerances.size() != o || costs.size() != o) {
    Fail(where, "the datasets in /options describe different numbers of options");
  }
  identity.options.resize(identity.components.size());
  for (std::size_t i = 0; i < o; ++i) {
    if (component[i] < 0 || static_cast<std::size_t>(component[i]) >= identity.components.size()) {
      Fail(where, fmt::format("/options/component[{}] = {} is no component", i, component[i]));
    }
    identity.options[static_cast<std::size_t>(component[i])].push_back({classes[i], modes[i], tolerances[i], costs[i]});
  }

  const std::vector<std::string> outputs = ReadStrings(where, file, "/constraints/output");
  const std::vector<std::string> kinds = ReadStrings(where, file, "/constraints/kind");
  const auto levels = ReadWhole<double>(where, file, "/constraints/level");
  const auto uppers = ReadWhole<double>(where, file, "/constraints/upper");
  const std::size_t m = outputs.size();
  if (kinds.size() != m || levels.size() != m || uppers.size() != m) {
    Fail(where, "the datasets in /constraints describe different numbers of constraints");
  }
  for (std::size_t j = 0; j < m; ++j) {
    const std::optional<analysis::ConstraintKind> kind = ValueNamed(analysis::kConstraintKindNames, kinds[j]);
    if (!kind) Fail(where, fmt::format("/constraints/kind[{}] = '{}' is unknown", j, kinds[j]));
    identity.constraints.push_back({outputs[j], *kind, levels[j], uppers[j]});
  }
  // Unfiltered where no error-motion column is kept: nothing is then read through it.
  if (const std::vector<std::string> paths = ErrorMotionColumnPaths(StoredOutputs(identity.constraints));
      !paths.empty()) {
    const DatasetId dataset(
        Check(H5Dopen2(file, paths.front().c_str(), H5P_DEFAULT), where, "opening dataset", paths.front()));
    identity.error_motion_filter = ReadErrorMotionFilter(where, dataset.get());
  } else {
    identity.error_motion_filter.cutoff_upr = 0.0;
  }
  try {
    CheckIdentity(identity, {});
  } catch (const std::invalid_argument& error) {
    Fail(where, fmt::format("describes no valid allocation: {}", error.what()));
  }
  if (stored.candidates != CandidateCount(identity)) {
    Fail(where, fmt::format("attribute candidates = {} where its options make {}", stored.candidates,
                            CandidateCount(identity)));
  }
  return stored;
}

// The first identity field in which `now` differs from the file, or nothing.
std::optional<std::string> IdentityDifference(const AllocationIdentity& file, const AllocationIdentity& now) {
  if (auto d = IdentityAttributeDifference(file, now, kIdentityAttributes)) return d;
  if (auto d = InputDifference(file.inputs, now.inputs, "this allocation")) return d;
  if (auto d = WordDifference("components", fmt::format("{}", fmt::join(file.components, ", ")),
                               fmt::format("{}", fmt::join(now.components, ", ")))) {
    return d;
  }
  for (std::size_t k = 0; k < file.options.size(); ++k) {
    const auto describe = [](const std::vector<AllocationIdentity::Option>& options) {
      std::vector<std::string> parts;
      for (const auto& option : options) {
        parts.push_back(fmt::format("{} {} {} {}", option.class_name, option.mode, option.tolerance, option.cost));
      }
      return fmt::format("{}", fmt::join(parts, "; "));
    };
    const std::string field = "options of " + file.components[k];
    if (auto d = WordDifference(field, describe(file.options[k]), describe(now.options[k]))) return d;
  }
  const auto constraints = [](const std::vector<analysis::Constraint>& list) {
    std::vector<std::string> parts;
    for (const auto& c : list) {
      parts.push_back(
          fmt::format("{} {} {} <= {}", NameOf(analysis::kConstraintKindNames, c.kind), c.level, c.output, c.upper));
    }
    return fmt::format("{}", fmt::join(parts, "; "));
  };
  if (auto d = WordDifference("constraints", constraints(file.constraints), constraints(now.constraints))) return d;
  return WordDifference("reference", file.reference.value_or(-1), now.reference.value_or(-1));
}

// ---------------------------------------------------------------------------------------
// Creating

std::string ExistsMessage(const std::string& file) {
  return file + ": already exists; pass --resume to continue that allocation, or remove the file to start a new one";
}

hsize_t ChunkSamples(const AllocationStoreOptions& options, const AllocationIdentity& identity) {
  const std::int64_t chunk = options.chunk_samples > 0
                                 ? options.chunk_samples
                                 : std::clamp(identity.first_samples, kLeastChunkSamples, kMostChunkSamples);
  return static_cast<hsize_t>(std::min(chunk, identity.samples));
}

// The outcome's datasets, before any outcome: /outcome/... as an empty allocation.
void CreateOutcome(const Where& where, hid_t file, hsize_t candidates, hsize_t constraints, bool checksum) {
  const Extents extents{candidates, 0, constraints};
  ForEachRow(kOutcomeArrays, [&](const auto& array) {
    using T = typename std::decay_t<decltype(array)>::Element;
    const TypeId enumeration = array.enumeration != nullptr ? array.enumeration(where) : TypeId();
    const NumberTypes types = array.enumeration != nullptr ? NumberTypes{enumeration.get(), enumeration.get()}
                                                           : TypesOf<T>();
    const hsize_t columns = extents.Columns(array.extent);
    CreateArray(where, file,
                {array.path, types.file, {candidates, columns}, std::min(candidates, kCandidateChunkRows), columns,
                 false, 0, &array.fill, types.native},
                checksum);
  });
  ForEachRow(kOutcomeLists, [&](const auto& list) {
    using T = typename std::decay_t<decltype(list)>::Element;
    const hsize_t most = extents.Most(list.extent);
    CreateArray(where, file,
                {list.path, TypesOf<T>().file, {0, 0}, std::min(most, kCandidateChunkRows), 1, true, most, nullptr},
                checksum);
  });
  const GroupId group(Check(H5Gopen2(file, "/outcome", H5P_DEFAULT), where, "opening group", "/outcome"));
  ForEachRow(kOutcomeAttributes, [&](const auto& attribute) {
    const NumberTypes types = TypesOf<typename std::decay_t<decltype(attribute)>::Element>();
    WriteAttribute(where, group.get(), attribute.path, types.file, types.native, &attribute.fill);
  });
}

// Everything but the samples and /outcome; /inputs/u written unless `design_points` is
// empty (a shard's).
void WriteIdentity(const Where& where, hid_t file, const AllocationIdentity& identity,
                   const std::vector<double>& design_points, bool checksum, Layout layout) {
  const std::int64_t candidates = CandidateCount(identity);
  const std::int32_t schema = layout == Layout::kFile ? kAllocationSchemaVersion : kAllocationIndexSchemaVersion;
  WriteStringAttribute(where, file, "format", kFormat);
  WriteAttribute(where, file, "schema_version", H5T_STD_I32LE, H5T_NATIVE_INT32, &schema);
  WriteLayout(where, file, {layout, kAllocationSchemaVersion});
  WriteIdentityAttributes(where, file, identity, kIdentityAttributes);
  WriteAttribute(where, file, "candidates", H5T_STD_I64LE, H5T_NATIVE_INT64, &candidates);
  const std::int64_t reference = identity.reference.value_or(-1);
  WriteAttribute(where, file, "reference", H5T_STD_I64LE, H5T_NATIVE_INT64, &reference);

  const PlistId gcpl = ObjectCreation(where, H5P_GROUP_CREATE);
  for (const char* name :
       {"inputs", "components", "options", "constraints", "candidates", "samples", "samples/screen", "samples/confirm",
        "outcome"}) {
    GroupId(Check(H5Gcreate2(file, name, H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), where, "creating group", name));
  }
  WriteInputDescriptions(where, file, identity.inputs, checksum);
  const auto n = static_cast<hsize_t>(identity.samples);
  const hsize_t d = identity.inputs.size();
  const hsize_t design_rows = std::clamp<hsize_t>(kDesignChunkBytes / (d * sizeof(double)), 1, n);
  CreateArray(where, file, {"/inputs/u", H5T_IEEE_F64LE, {n, d}, design_rows, d, false, 0, &kNaN, H5T_NATIVE_DOUBLE},
              checksum);
  if (!design_points.empty()) WriteWhole(where, file, "/inputs/u", H5T_NATIVE_DOUBLE, n, design_points.data());

  WriteStrings(where, file, "/components/name", identity.components, checksum);
  std::vector<std::int32_t> component;
  std::vector<std::string> classes;
  std::vector<std::string> modes;
  std::vector<double> tolerances;
  std::vector<double> costs;
  for (std::size_t k = 0; k < identity.options.size(); ++k) {
    for (const AllocationIdentity::Option& option : identity.options[k]) {
      component.push_back(static_cast<std::int32_t>(k));
      classes.push_back(option.class_name);
      modes.push_back(option.mode);
      tolerances.push_back(option.tolerance);
      costs.push_back(option.cost);
    }
  }
  const auto numbers = [&](const std::string& path, const std::vector<double>& values) {
    CreateArray(where, file, {path, H5T_IEEE_F64LE, {values.size(), 0}, std::max<hsize_t>(1, values.size())},
                checksum);
    WriteWhole(where, file, path, H5T_NATIVE_DOUBLE, values.size(), values.data());
  };
  WriteInts(where, file, "/options/component", component, checksum);
  WriteStrings(where, file, "/options/class", classes, checksum);
  WriteStrings(where, file, "/options/mode", modes, checksum);
  numbers("/options/tolerance", tolerances);
  numbers("/options/cost", costs);

  std::vector<std::string> outputs;
  std::vector<std::string> kinds;
  std::vector<double> levels;
  std::vector<double> uppers;
  for (const analysis::Constraint& constraint : identity.constraints) {
    outputs.push_back(constraint.output);
    kinds.emplace_back(NameOf(analysis::kConstraintKindNames, constraint.kind));
    levels.push_back(constraint.level);
    uppers.push_back(constraint.upper);
  }
  WriteStrings(where, file, "/constraints/output", outputs, checksum);
  WriteStrings(where, file, "/constraints/kind", kinds, checksum);
  numbers("/constraints/level", levels);
  numbers("/constraints/upper", uppers);

  const auto c = static_cast<hsize_t>(candidates);
  const hsize_t k = identity.components.size();
  std::vector<std::int32_t> options_of(c * k);
  std::vector<double> cost(c);
  for (hsize_t i = 0; i < c; ++i) {
    const std::vector<std::int32_t> options_i = CandidateOptions(identity, static_cast<std::int64_t>(i));
    std::copy(options_i.begin(), options_i.end(), options_of.begin() + static_cast<std::ptrdiff_t>(i * k));
    cost[i] = CandidateCost(identity, options_i);
  }
  const double reference_cost = cost[static_cast<std::size_t>(identity.reference.value_or(0))];
  std::vector<double> relative(c);
  for (hsize_t i = 0; i < c; ++i) relative[i] = reference_cost > 0.0 ? cost[i] / reference_cost : kNaN;
  const hsize_t rows = std::min(c, kCandidateChunkRows);
  CreateArray(where, file, {"/candidates/options", H5T_STD_I32LE, {c, k}, rows, k}, checksum);
  WriteWhole(where, file, "/candidates/options", H5T_NATIVE_INT32, c, options_of.data());
  CreateArray(where, file, {"/candidates/cost", H5T_IEEE_F64LE, {c, 0}, rows}, checksum);
  WriteWhole(where, file, "/candidates/cost", H5T_NATIVE_DOUBLE, c, cost.data());
  CreateArray(where, file, {"/candidates/relative_cost", H5T_IEEE_F64LE, {c, 0}, rows}, checksum);
  WriteWhole(where, file, "/candidates/relative_cost", H5T_NATIVE_DOUBLE, c, relative.data());
}

void WriteSchema(const Where& where, hid_t file, const AllocationIdentity& identity,
                 const std::vector<double>& design_points, const AllocationStoreOptions& options) {
  const bool checksum = options.checksums;
  WriteIdentity(where, file, identity, design_points, checksum, Layout::kFile);
  const std::int64_t candidates = CandidateCount(identity);
  const std::vector<std::string> stored = StoredOutputs(identity.constraints);
  const hsize_t chunk = ChunkSamples(options, identity);
  for (const EvaluationRole role : kRoles) {
    SampleTable::Create(where, file, CandidateRows(candidates, identity.samples, static_cast<std::int64_t>(chunk)),
                        RoleSpecs(role, RoleColumns(role, stored)), checksum);
  }
  WriteErrorMotionColumnAttributes(where, file, identity, stored);
  CreateOutcome(where, file, static_cast<hsize_t>(candidates), identity.constraints.size(), checksum);
}

// ---------------------------------------------------------------------------------------
// The samples of an open file

// One buffered sample: what its row of each column gets.
struct Buffered {
  SampleStatus status = SampleStatus::kPending;
  std::vector<double> outputs;  // per stored output
  double error_bound = kNaN;    // [mm]
  std::int32_t steps = 0;
  double solve_time = 0.0;  // [s]
};

using Buffer = std::array<RowBuffer<Buffered>, 2>;  // per role, keyed by (candidate, sample)

struct Samples {
  std::int64_t candidates = 0;
  std::int64_t samples = 0;
  std::vector<std::string> outputs;  // stored
  std::array<std::vector<RoleColumn>, 2> columns;
  std::array<SampleTable, 2> tables;

  void Open(const Where& where, hid_t file, const AllocationIdentity& identity, std::size_t cache_bytes) {
    candidates = CandidateCount(identity);
    samples = identity.samples;
    outputs = StoredOutputs(identity.constraints);
    for (const EvaluationRole role : kRoles) {
      const std::size_t r = RoleIndex(role);
      columns[r] = RoleColumns(role, outputs);
      tables[r] = SampleTable::Open(where, file, CandidateRows(candidates, samples), RoleSpecs(role, columns[r]),
                                    cache_bytes);
    }
  }

  void set_where(const Where& where) {
    for (SampleTable& table : tables) table.set_where(where);
  }

  void Close() {
    for (SampleTable& table : tables) table = SampleTable();
  }

  const SampleTable& Table(EvaluationRole role) const { return tables[RoleIndex(role)]; }

  std::size_t ColumnOf(EvaluationRole role, SampleField field, std::size_t output = 0) const {
    const std::vector<RoleColumn>& list = columns[RoleIndex(role)];
    const auto column = std::find_if(list.begin(), list.end(), [&](const RoleColumn& c) {
      return c.field == field && c.output == output;
    });
    RINGTOL_CHECK(column != list.end(), RoleIndex(role), field, output);  // a column of the role's schema
    return static_cast<std::size_t>(column - list.begin());
  }

  std::size_t OutputColumn(std::string_view what, EvaluationRole role, std::string_view output) const {
    const auto found = std::find(outputs.begin(), outputs.end(), output);
    if (found == outputs.end()) {
      throw std::invalid_argument(fmt::format("{}: output '{}' is not stored; stored: {}", what, output,
                                              fmt::join(outputs, ", ")));
    }
    return ColumnOf(role, SampleField::kOutput, static_cast<std::size_t>(found - outputs.begin()));
  }

  void CheckRange(std::string_view what, std::int64_t candidate, std::int64_t begin, std::int64_t end) const {
    if (candidate < 0 || candidate >= candidates) {
      throw std::out_of_range(fmt::format("{}: candidate {} is outside [0, {})", what, candidate, candidates));
    }
    if (begin < 0 || end < begin || end > samples) {
      throw std::out_of_range(fmt::format("{}: range [{}, {}) is outside [0, {})", what, begin, end, samples));
    }
  }

  // Samples [begin, end) of one candidate's row of a column; InputError for a damaged chunk.
  std::vector<double> Row(EvaluationRole role, std::size_t column, std::int64_t candidate, std::int64_t begin,
                          std::int64_t end) const {
    return Table(role).Read<double>(column, candidate, begin, end - begin);
  }

  // The screening rung's error bounds [mm] of samples [begin, end) of a candidate.
  std::vector<double> ErrorBounds(std::int64_t candidate, std::int64_t begin, std::int64_t end) const {
    const EvaluationRole role = EvaluationRole::kScreen;
    return Row(role, ColumnOf(role, SampleField::kErrorBound), candidate, begin, end);
  }

  std::vector<SampleStatus> Statuses(EvaluationRole role, std::int64_t candidate, std::int64_t begin,
                                     std::int64_t end) const {
    return Table(role).Statuses(candidate, begin, end - begin);
  }
};

// ---------------------------------------------------------------------------------------
// Damage: every allocated chunk of every [C, N] dataset read once.

struct RoleDamage {
  EvaluationRole role = EvaluationRole::kScreen;
  DamagedChunk chunk;
};

// `done` (per role, optional) counts the finished samples of the status chunks that read.
std::vector<RoleDamage> ScanSamples(const Samples& samples, std::array<std::int64_t, 2>* done = nullptr) {
  std::vector<RoleDamage> damaged;
  for (const EvaluationRole role : kRoles) {
    const TableScan scan = samples.Table(role).Scan();
    for (const DamagedChunk& chunk : scan.damaged) damaged.push_back({role, chunk});
    if (done != nullptr) (*done)[RoleIndex(role)] = scan.done;
  }
  return damaged;
}

// Gives every damaged chunk its fill values and marks its samples pending, chunks first and
// statuses after (SampleTable::Repair).
void RepairSamples(Samples& samples, const std::vector<RoleDamage>& damaged) {
  for (const EvaluationRole role : kRoles) {
    std::vector<DamagedChunk> chunks;
    for (const RoleDamage& damage : damaged) {
      if (damage.role == role) chunks.push_back(damage.chunk);
    }
    if (!chunks.empty()) samples.tables[RoleIndex(role)].Repair(chunks);
  }
}

// ---------------------------------------------------------------------------------------
// The outcome

void CheckOutcome(const AllocationOutcome& outcome, std::int64_t candidates, std::size_t constraints) {
  const auto fail = [](const std::string& what) { throw std::invalid_argument("AllocationStore::Commit: " + what); };
  if (static_cast<std::int64_t>(outcome.candidates.size()) != candidates) {
    fail(fmt::format("an outcome of {} candidates for {}", outcome.candidates.size(), candidates));
  }
  for (std::size_t i = 0; i < outcome.candidates.size(); ++i) {
    const std::size_t m = outcome.candidates[i].constraints.size();
    if (m != 0 && m != constraints) fail(fmt::format("candidate {} has {} constraint judgements for {}", i, m, constraints));
  }
  const Extents extents{static_cast<hsize_t>(candidates), 0, constraints};
  ForEachRow(kOutcomeLists, [&](const auto& list) {
    const hsize_t most = extents.Most(list.extent);
    const auto& entries = list.access(outcome);
    if (entries.size() > most) fail(fmt::format("{} lists {} entries, more than {}", list.path, entries.size(), most));
    for (const auto entry : entries) {
      if (entry < 0 || static_cast<hsize_t>(entry) >= most) fail(fmt::format("{} names {}", list.path, entry));
    }
  });
  if (outcome.recommendation && (*outcome.recommendation < 0 || *outcome.recommendation >= candidates)) {
    fail(fmt::format("recommendation names candidate {}", *outcome.recommendation));
  }
}

void WriteOutcome(const Where& where, hid_t file, const AllocationOutcome& outcome, std::size_t constraints) {
  const Extents extents{outcome.candidates.size(), 0, constraints};
  ForEachRow(kOutcomeArrays, [&](const auto& array) {
    using T = typename std::decay_t<decltype(array)>::Element;
    const hsize_t width = std::max<hsize_t>(1, extents.Columns(array.extent));
    std::vector<T> values;
    values.reserve(outcome.candidates.size() * width);
    for (const CandidateOutcome& candidate : outcome.candidates) {
      const std::size_t held = HeldBy(candidate, array.extent);
      for (std::size_t j = 0; j < width; ++j) {
        values.push_back(j < held ? Encode<T>(array.access(candidate, j)) : array.fill);
      }
    }
    WriteWhole(where, file, array.path, TypesOf<T>().native, outcome.candidates.size(), values.data());
  });
  ForEachRow(kOutcomeLists, [&](const auto& list) {
    using T = typename std::decay_t<decltype(list)>::Element;
    const std::vector<T> values(list.access(outcome).begin(), list.access(outcome).end());
    WriteWhole(where, file, list.path, TypesOf<T>().native, values.size(), values.data());
  });
  const GroupId group(Check(H5Gopen2(file, "/outcome", H5P_DEFAULT), where, "opening group", "/outcome"));
  ForEachRow(kOutcomeAttributes, [&](const auto& attribute) {
    using T = typename std::decay_t<decltype(attribute)>::Element;
    const T value = Encode<T>(attribute.access(outcome));
    UpdateAttribute(where, group.get(), attribute.path, TypesOf<T>().native, &value);
  });
}

AllocationOutcome ReadOutcomeFrom(const Where& where, hid_t file, const AllocationIdentity& identity) {
  const Extents extents{static_cast<hsize_t>(CandidateCount(identity)), identity.components.size(),
                        identity.constraints.size()};
  AllocationOutcome outcome;
  outcome.candidates.resize(extents.candidates);
  for (CandidateOutcome& candidate : outcome.candidates) {
    candidate.options.resize(extents.components);
    candidate.constraints.resize(extents.constraints);
  }
  ForEachRow(std::tuple_cat(kCandidateArrays, kOutcomeArrays), [&](const auto& array) {
    using T = typename std::decay_t<decltype(array)>::Element;
    const hsize_t columns = extents.Columns(array.extent);
    const std::vector<T> values = ReadWhole<T>(where, file, array.path, columns);
    const hsize_t width = std::max<hsize_t>(1, columns);
    if (values.size() != extents.candidates * width) {
      Fail(where, fmt::format("dataset {} has {} rows for {} candidates", array.path, values.size() / width,
                              extents.candidates));
    }
    for (std::size_t i = 0; i < outcome.candidates.size(); ++i) {
      for (std::size_t j = 0; j < width; ++j) Decode(values[i * width + j], array.access(outcome.candidates[i], j));
    }
  });
  // Judgements of simulated candidates only, each with the candidate's samples; a yield
  // only where it has trials.
  for (CandidateOutcome& candidate : outcome.candidates) {
    if (candidate.settlement != analysis::Settlement::kSimulated) candidate.constraints.clear();
    for (analysis::ConstraintJudgement& judgement : candidate.constraints) judgement.samples = candidate.samples;
    analysis::ProportionEstimate& yield = candidate.yield;
    if (yield.trials > 0) {
      yield.successes = std::llround(yield.value * static_cast<double>(yield.trials));
    } else {
      const std::int64_t trials = yield.trials;
      yield = analysis::ProportionEstimate();
      yield.trials = trials;
    }
    yield.confidence = identity.confidence;
  }
  ForEachRow(kOutcomeLists, [&](const auto& list) {
    using T = typename std::decay_t<decltype(list)>::Element;
    const std::vector<T> values = ReadWhole<T>(where, file, list.path);
    list.access(outcome).assign(values.begin(), values.end());
  });
  const GroupId group(Check(H5Gopen2(file, "/outcome", H5P_DEFAULT), where, "opening group", "/outcome"));
  ForEachRow(kOutcomeAttributes, [&](const auto& attribute) {
    using T = typename std::decay_t<decltype(attribute)>::Element;
    Decode(Require(where, ReadNumberAttribute<T>(where, group.get(), attribute.path), attribute.path),
           attribute.access(outcome));
  });
  return outcome;
}

// ---------------------------------------------------------------------------------------
// Shards and their index

// Reads a shard as readers do: its identity, and its sample tables opened with their chunk
// indexes (damaged chunks are for a resume to repair). InputError when it cannot be read.
Stored ReadShard(const fs::path& shard) {
  const Where opening{shard.string(), true};
  const FileId file = OpenForReading(shard);
  Stored stored = ReadStored(opening, file.get());
  if (!stored.index) Samples().Open(opening, file.get(), stored.identity, 0);
  return stored;
}

// The shards an index lists, each checked to exist, to read (InputError naming the resume
// that recovers an unreadable one's samples) and to be a file of `identity`'s allocation.
std::vector<fs::path> ListedShards(const Where& where, hid_t file, const fs::path& index,
                                   const AllocationIdentity& identity) {
  std::vector<fs::path> shards = ListedShardFiles(where, file, index);
  for (const fs::path& shard : shards) {
    Stored stored;
    try {
      stored = ReadShard(shard);
    } catch (const InputError& error) {
      throw InputError(UnreadableShardMessage(where.file, shard, error.what(), "allocate", identity.allocation_path));
    }
    if (stored.index) {
      throw InputError(fmt::format("{}: lists {}, another index, as its shard", where.file, shard.string()));
    }
    if (const std::optional<std::string> difference = IdentityDifference(stored.identity, identity)) {
      throw InputError(fmt::format("{}: its shard {} was written by another allocation: {}", where.file,
                                   shard.string(), *difference));
    }
  }
  return shards;
}

bool IsVirtual(const Where& where, hid_t dataset, const std::string& path) {
  const PlistId dcpl(Check(H5Dget_create_plist(dataset), where, "reading the creation properties of", path));
  return H5Pget_layout(dcpl.get()) == H5D_VIRTUAL;
}

}  // namespace

// ---------------------------------------------------------------------------------------

struct AllocationStore::File {
  fs::path path;
  Where where;
  FileLock lock;
  FileId file;  // closed after the datasets (members are destroyed in reverse order)
  AllocationIdentity identity;
  Samples samples;
  Buffer buffer;

  // Everything is created by now: enter SWMR mode, then open the datasets (entering SWMR
  // reopens open datasets with default access, losing the chunk cache).
  void StartWriting(const AllocationStoreOptions& options) {
    CheckStatus(H5Fstart_swmr_write(file.get()), where, "starting", "SWMR writing");
    samples.Open(where, file.get(), identity, options.chunk_cache_bytes);
  }

  // Writes the buffered samples, each role's statuses after its other columns.
  void CommitSamples() {
    for (const EvaluationRole role : kRoles) {
      const std::size_t r = RoleIndex(role);
      const RowBuffer<Buffered>& rows = buffer[r];
      if (rows.empty()) continue;
      const std::vector<RoleColumn>& columns = samples.columns[r];
      std::vector<std::vector<double>> numbers(columns.size());
      std::vector<std::int32_t> steps;
      std::vector<std::int8_t> codes;
      std::vector<const void*> values(columns.size());
      for (std::size_t c = 0; c < columns.size(); ++c) {
        const RoleColumn& column = columns[c];
        for (const auto& [key, sample] : rows.rows()) {
          switch (column.field) {
            case SampleField::kOutput:
              numbers[c].push_back(sample.outputs[column.output]);
              break;
            case SampleField::kErrorBound:
              numbers[c].push_back(sample.error_bound);
              break;
            case SampleField::kSolveTime:
              numbers[c].push_back(sample.solve_time);
              break;
            case SampleField::kSteps:
              steps.push_back(sample.steps);
              break;
            case SampleField::kStatus:
              codes.push_back(static_cast<std::int8_t>(sample.status));
              break;
          }
        }
        values[c] = column.field == SampleField::kSteps    ? static_cast<const void*>(steps.data())
                    : column.field == SampleField::kStatus ? static_cast<const void*>(codes.data())
                                                           : static_cast<const void*>(numbers[c].data());
      }
      samples.tables[r].Write(rows.Keys(), values);
    }
    for (RowBuffer<Buffered>& role : buffer) role.clear();
  }

  bool Close() {
    samples.Close();
    return file.Close();
  }
};

AllocationStore::AllocationStore(std::unique_ptr<File> file) : file_(std::move(file)) {}

// Commits what is buffered, as the campaign's store does, but not the outcome, which only
// Commit has: the samples on disk may then be newer than /outcome, which is derived from
// them (the next run's first commit brings it up to date).
AllocationStore::~AllocationStore() {
  if (!file_) return;
  CommitAndClose(file_->where, [&] { file_->CommitSamples(); }, [&] { return file_->Close(); });
  file_.reset();
}

AllocationStore::AllocationStore(AllocationStore&&) noexcept = default;

AllocationStore& AllocationStore::operator=(AllocationStore&& other) noexcept {
  if (this != &other) {
    AllocationStore previous(std::move(file_));
    file_ = std::move(other.file_);
  }
  return *this;
}

AllocationStore AllocationStore::Create(const fs::path& path, const AllocationIdentity& identity,
                                        const std::vector<double>& design_points,
                                        const AllocationStoreOptions& options) {
  if (design_points.size() != static_cast<std::size_t>(identity.samples) * identity.inputs.size()) {
    throw std::invalid_argument(fmt::format("AllocationStore: {} design point coordinates for {} samples of {} inputs",
                                            design_points.size(), identity.samples, identity.inputs.size()));
  }
  return CreateFile(path, identity, design_points, options);
}

AllocationStore AllocationStore::CreateShard(const fs::path& path, const AllocationIdentity& identity,
                                             const AllocationStoreOptions& options) {
  return CreateFile(path, identity, {}, options);
}

AllocationStore AllocationStore::CreateFile(const fs::path& path, const AllocationIdentity& identity,
                                            const std::vector<double>& design_points,
                                            const AllocationStoreOptions& options) {
  const QuietErrors quiet;
  CheckIdentity(identity, options);
  const std::string name = path.string();
  auto file = std::make_unique<File>();
  file->path = path;
  file->where = Where{name, false};
  file->identity = identity;
  CreateWhole(
      path, ExistsMessage(name), file->file, file->lock,
      [&] {
        WriteSchema(file->where, file->file.get(), identity, design_points, options);
        file->StartWriting(options);
      },
      [&] { file->Close(); });
  return AllocationStore(std::move(file));
}

AllocationStore AllocationStore::Resume(const fs::path& path, const AllocationIdentity& identity,
                                        const AllocationStoreOptions& options) {
  const QuietErrors quiet;
  CheckIdentity(identity, options);
  const std::string name = path.string();
  const Where opening{name, true};
  FileLock lock = FileLock::ToResume(path, "allocation");

  // Everything is checked read-only first: a refused file is never modified.
  std::vector<RoleDamage> damaged;
  {
    const FileId reading = OpenForReading(path);
    const Stored stored = ReadStored(opening, reading.get());
    if (stored.index) {
      throw InputError(name + ": is an index of shards; a run continues its shards (ringtol allocate --resume), "
                              "not the index itself");
    }
    if (const std::optional<std::string> difference = IdentityDifference(stored.identity, identity)) {
      throw InputError(name + ": was written by another allocation: " + *difference +
                       "; resume it with the allocation that wrote it, or choose a new results file");
    }
    Samples samples;
    samples.Open(opening, reading.get(), stored.identity, 0);
    damaged = ScanSamples(samples);
  }

  auto file = std::make_unique<File>();
  file->path = path;
  file->where = Where{name, false};
  file->lock = std::move(lock);
  file->identity = identity;
  file->file = OpenForWriting(path);
  if (!damaged.empty()) {
    Samples samples;
    samples.Open(file->where, file->file.get(), identity, 0);
    RepairSamples(samples, damaged);
  }
  file->StartWriting(options);
  return AllocationStore(std::move(file));
}

const fs::path& AllocationStore::path() const { return file_->path; }

const AllocationIdentity& AllocationStore::identity() const { return file_->identity; }

std::vector<bool> AllocationStore::Done(EvaluationRole role, std::int64_t candidate, std::int64_t begin,
                                        std::int64_t end) const {
  const std::vector<SampleStatus> statuses = ReadStatus(role, candidate, begin, end);
  std::vector<bool> done(statuses.size());
  for (std::size_t i = 0; i < statuses.size(); ++i) done[i] = statuses[i] != SampleStatus::kPending;
  return done;
}

std::vector<SampleStatus> AllocationStore::ReadStatus(EvaluationRole role, std::int64_t candidate,
                                                      std::int64_t begin, std::int64_t end) const {
  const QuietErrors quiet;
  file_->samples.CheckRange("AllocationStore::ReadStatus", candidate, begin, end);
  std::vector<SampleStatus> statuses = file_->samples.Statuses(role, candidate, begin, end);
  file_->buffer[RoleIndex(role)].Overlay(candidate, begin, end, statuses,
                                         [](const Buffered& sample) { return sample.status; });
  return statuses;
}

std::vector<double> AllocationStore::ReadOutput(EvaluationRole role, std::string_view output,
                                                std::int64_t candidate, std::int64_t begin, std::int64_t end) const {
  const QuietErrors quiet;
  const Samples& s = file_->samples;
  const std::size_t column = s.OutputColumn("AllocationStore::ReadOutput", role, output);
  s.CheckRange("AllocationStore::ReadOutput", candidate, begin, end);
  std::vector<double> values = s.Row(role, column, candidate, begin, end);
  const std::size_t q = s.columns[RoleIndex(role)][column].output;
  file_->buffer[RoleIndex(role)].Overlay(candidate, begin, end, values,
                                         [q](const Buffered& sample) { return sample.outputs[q]; });
  return values;
}

std::vector<double> AllocationStore::ReadErrorBound(std::int64_t candidate, std::int64_t begin,
                                                    std::int64_t end) const {
  const QuietErrors quiet;
  const Samples& s = file_->samples;
  s.CheckRange("AllocationStore::ReadErrorBound", candidate, begin, end);
  std::vector<double> values = s.ErrorBounds(candidate, begin, end);
  file_->buffer[RoleIndex(EvaluationRole::kScreen)].Overlay(candidate, begin, end, values,
                                         [](const Buffered& sample) { return sample.error_bound; });
  return values;
}

void AllocationStore::Add(EvaluationRole role, std::int64_t candidate, const SampleRecord& record) {
  const Samples& s = file_->samples;
  if (role != EvaluationRole::kScreen && role != EvaluationRole::kConfirm) {
    throw std::invalid_argument("AllocationStore::Add: unknown role");
  }
  s.CheckRange("AllocationStore::Add", candidate, record.index, record.index + 1);
  if (record.status == SampleStatus::kPending || !IsKnownStatus(static_cast<std::int8_t>(record.status))) {
    throw std::invalid_argument(fmt::format("AllocationStore::Add: candidate {} sample {} has no final status",
                                            candidate, record.index));
  }
  AllocationSample kept = KeptSample(role, candidate, record, s.outputs);
  Buffered sample;
  sample.status = record.status;
  sample.outputs = std::move(kept.outputs);
  sample.error_bound = kept.error_bound;
  sample.steps = record.steps;
  sample.solve_time = record.solve_time;
  file_->buffer[RoleIndex(role)].Put({candidate, record.index}, std::move(sample));
}

std::size_t AllocationStore::buffered() const { return file_->buffer[0].size() + file_->buffer[1].size(); }

AllocationSample KeptSample(EvaluationRole role, std::int64_t candidate, const SampleRecord& record,
                            const std::vector<std::string>& outputs) {
  const bool ok = record.status == SampleStatus::kOk;
  AllocationSample sample{role, candidate, record.index, record.status, {}, kNaN};
  for (const std::string& output : outputs) sample.outputs.push_back(ok ? record.outputs[OutputIndex(output)] : kNaN);
  if (ok && role == EvaluationRole::kScreen) sample.error_bound = record.d_trajectory_error;
  return sample;
}

void AllocationStore::CommitSamples() {
  const QuietErrors quiet;
  File& f = *file_;
  f.CommitSamples();
  CheckStatus(H5Fflush(f.file.get(), H5F_SCOPE_LOCAL), f.where, "flushing", "the file");
}

std::int64_t AllocationStore::Absorb(const fs::path& shard) {
  const QuietErrors quiet;
  CommitSamples();
  File& f = *file_;
  const Where opening{shard.string(), true};
  const FileId file = OpenForReading(shard);
  const Stored stored = ReadStored(opening, file.get());
  if (stored.index) throw InputError(opening.file + ": is an index of shards, not a shard");
  if (const std::optional<std::string> difference = IdentityDifference(stored.identity, f.identity)) {
    throw InputError(fmt::format("{}: is a shard of another allocation than {}: {}", opening.file, f.where.file,
                                 *difference));
  }
  Samples from;
  from.Open(opening, file.get(), stored.identity, 0);
  from.set_where(Where{opening.file, false});
  std::int64_t copied = 0;
  for (const EvaluationRole role : kRoles) {
    SampleTable& ours = f.samples.tables[RoleIndex(role)];
    const SampleTable& theirs = from.Table(role);
    copied += ours.Absorb(theirs, ours.PlanAbsorb(theirs, true)).samples;
  }
  return copied;
}

const std::vector<std::string>& AllocationStore::outputs() const { return file_->samples.outputs; }

std::vector<AllocationSample> AllocationStore::Finished() const {
  const QuietErrors quiet;
  const Samples& s = file_->samples;
  std::vector<AllocationSample> finished;
  for (const EvaluationRole role : kRoles) {
    for (std::int64_t candidate = 0; candidate < s.candidates; ++candidate) {
      const std::vector<SampleStatus> statuses = s.Statuses(role, candidate, 0, s.samples);
      if (std::all_of(statuses.begin(), statuses.end(), [](SampleStatus x) { return x == SampleStatus::kPending; })) {
        continue;
      }
      std::vector<std::vector<double>> outputs;
      for (std::size_t q = 0; q < s.outputs.size(); ++q) {
        outputs.push_back(s.Row(role, s.ColumnOf(role, SampleField::kOutput, q), candidate, 0, s.samples));
      }
      std::vector<double> bounds;
      if (role == EvaluationRole::kScreen) bounds = s.ErrorBounds(candidate, 0, s.samples);
      for (std::int64_t i = 0; i < s.samples; ++i) {
        const auto k = static_cast<std::size_t>(i);
        if (statuses[k] == SampleStatus::kPending) continue;
        AllocationSample sample{role, candidate, i, statuses[k], {}, bounds.empty() ? kNaN : bounds[k]};
        for (const std::vector<double>& output : outputs) sample.outputs.push_back(output[k]);
        finished.push_back(std::move(sample));
      }
    }
  }
  return finished;
}

void AllocationStore::Commit(const AllocationOutcome& outcome) {
  File& f = *file_;
  CheckOutcome(outcome, f.samples.candidates, f.identity.constraints.size());
  const QuietErrors quiet;
  f.CommitSamples();
  // After the statuses: an outcome on disk never describes samples that are not.
  WriteOutcome(f.where, f.file.get(), outcome, f.identity.constraints.size());
  CheckStatus(H5Fflush(f.file.get(), H5F_SCOPE_LOCAL), f.where, "flushing", "the file");
}

// ---------------------------------------------------------------------------------------

struct AllocationReader::File {
  Where where;
  FileId file;
  AllocationIdentity identity;
  Samples samples;
};

AllocationReader::AllocationReader(const fs::path& path) : file_(std::make_unique<File>()) {
  const QuietErrors quiet;
  try {
    File& f = *file_;
    f.where = Where{path.string(), true};
    f.file = OpenForReading(path);
    const Stored stored = ReadStored(f.where, f.file.get());
    f.identity = stored.identity;
    // HDF5 reads a missing shard's rows as fill, silently: every shard is checked first.
    if (stored.index) ListedShards(f.where, f.file.get(), path, f.identity);
    f.samples.Open(f.where, f.file.get(), f.identity, 0);
    f.where.input = false;
    f.samples.set_where(f.where);
  } catch (...) {
    file_.reset();  // while HDF5 is quiet
    throw;
  }
}

AllocationReader::~AllocationReader() {
  if (!file_) return;
  const QuietErrors quiet;
  file_.reset();
}

AllocationReader::AllocationReader(AllocationReader&&) noexcept = default;

const AllocationIdentity& AllocationReader::identity() const { return file_->identity; }

AllocationOutcome AllocationReader::ReadOutcome() const {
  const QuietErrors quiet;
  return ReadOutcomeFrom(Where{file_->where.file, true}, file_->file.get(), file_->identity);
}

std::vector<SampleStatus> AllocationReader::ReadStatus(EvaluationRole role, std::int64_t candidate,
                                                       std::int64_t begin, std::int64_t end) const {
  const QuietErrors quiet;
  file_->samples.CheckRange("AllocationReader::ReadStatus", candidate, begin, end);
  return file_->samples.Statuses(role, candidate, begin, end);
}

std::vector<double> AllocationReader::ReadOutput(EvaluationRole role, std::string_view output,
                                                 std::int64_t candidate, std::int64_t begin, std::int64_t end) const {
  const QuietErrors quiet;
  const Samples& s = file_->samples;
  const std::size_t column = s.OutputColumn("AllocationReader::ReadOutput", role, output);
  s.CheckRange("AllocationReader::ReadOutput", candidate, begin, end);
  return s.Row(role, column, candidate, begin, end);
}

std::vector<double> AllocationReader::ReadErrorBound(std::int64_t candidate, std::int64_t begin,
                                                     std::int64_t end) const {
  const QuietErrors quiet;
  const Samples& s = file_->samples;
  s.CheckRange("AllocationReader::ReadErrorBound", candidate, begin, end);
  return s.ErrorBounds(candidate, begin, end);
}

std::vector<std::int32_t> AllocationReader::ReadSteps(EvaluationRole role, std::int64_t candidate,
                                                      std::int64_t begin, std::int64_t end) const {
  const QuietErrors quiet;
  const Samples& s = file_->samples;
  s.CheckRange("AllocationReader::ReadSteps", candidate, begin, end);
  return s.Table(role).Read<std::int32_t>(s.ColumnOf(role, SampleField::kSteps), candidate, begin, end - begin);
}

std::vector<double> AllocationReader::ReadSolveTime(EvaluationRole role, std::int64_t candidate, std::int64_t begin,
                                                    std::int64_t end) const {
  const QuietErrors quiet;
  const Samples& s = file_->samples;
  s.CheckRange("AllocationReader::ReadSolveTime", candidate, begin, end);
  return s.Row(role, s.ColumnOf(role, SampleField::kSolveTime), candidate, begin, end);
}

std::vector<double> AllocationReader::ReadDesignPoints(std::int64_t begin, std::int64_t end) const {
  const QuietErrors quiet;
  const File& f = *file_;
  const std::int64_t n = f.identity.samples;
  if (begin < 0 || end < begin || end > n) {
    throw std::out_of_range(
        fmt::format("AllocationReader::ReadDesignPoints: range [{}, {}) is outside [0, {})", begin, end, n));
  }
  return ReadRows(f.where, f.file.get(), "/inputs/u", static_cast<hsize_t>(begin),
                          static_cast<hsize_t>(end), f.identity.inputs.size(), "samples");
}

ResultsCheck CheckAllocationResults(const fs::path& path) {
  const QuietErrors quiet;
  const Where where{path.string(), true};
  const FileId file = OpenForReading(path);
  const Stored stored = ReadStored(where, file.get());
  ResultsCheck check;
  check.candidates = stored.candidates;
  check.samples = stored.identity.samples;
  std::vector<std::string> paths;
  H5Ovisit2(
      file.get(), H5_INDEX_NAME, H5_ITER_INC,
      [](hid_t, const char* name, const H5O_info_t* info, void* data) -> herr_t {
        if (info->type == H5O_TYPE_DATASET) static_cast<std::vector<std::string>*>(data)->push_back(std::string("/") + name);
        return 0;
      },
      &paths, H5O_INFO_BASIC);
  for (const std::string& dataset_path : paths) {
    const DatasetId dataset(Check(H5Dopen2(file.get(), dataset_path.c_str(), H5P_DEFAULT), where, "opening",
                                  dataset_path));
    // An index's virtual datasets are as checked as its shards' (below).
    const bool checksummed =
        HasChecksum(where, dataset.get(), dataset_path) || IsVirtual(where, dataset.get(), dataset_path);
    check.datasets.push_back({dataset_path, dataset_path.starts_with("/samples/"), checksummed, {}, {}});
  }
  const auto dataset = [&](const std::string& dataset_path) -> DatasetCheck& {
    const auto found = std::find_if(check.datasets.begin(), check.datasets.end(),
                                    [&](const DatasetCheck& d) { return d.path == dataset_path; });
    if (found != check.datasets.end()) return *found;
    check.datasets.push_back({dataset_path, false, true, {}, {}});
    return check.datasets.back();
  };
  const auto damage = [&](const std::string& dataset_path, SampleRange rows, const std::string& problem) {
    DatasetCheck& d = dataset(dataset_path);
    if (d.damaged.empty()) d.first_problem = problem;
    d.damaged.push_back(rows);
  };
  if (stored.index) {
    // Each sample is in one shard (the coordinator never hands out one a shard holds), so
    // the shards' counts add up; /inputs/u, never written in a shard, is the index's own.
    std::vector<ShardCheck> shards;
    for (const fs::path& shard : ListedShards(where, file.get(), path, stored.identity)) {
      shards.push_back({shard.filename().string(), CheckAllocationResults(shard)});
    }
    check = SumOfShards(std::move(check), shards);
  } else {
    Samples samples;
    samples.Open(where, file.get(), stored.identity, 0);
    std::array<std::int64_t, 2> done{};
    for (const RoleDamage& role : ScanSamples(samples, &done)) {
      const DamagedChunk& chunk = role.chunk;
      const std::int64_t first = chunk.group * check.samples;
      damage(samples.Table(role.role).spec(chunk.column).path,
             {first + chunk.samples.begin, first + chunk.samples.end}, chunk.problem);
    }
    check.done_screen = done[RoleIndex(EvaluationRole::kScreen)];
    check.done_confirm = done[RoleIndex(EvaluationRole::kConfirm)];
  }
  check.done = check.done_screen + check.done_confirm;
  try {
    ReadRows(where, file.get(), "/inputs/u", 0, static_cast<hsize_t>(check.samples),
                     stored.identity.inputs.size(), "samples");
  } catch (const InputError& error) {
    damage("/inputs/u", {0, check.samples}, error.what());
  }
  try {
    ReadOutcomeFrom(where, file.get(), stored.identity);
  } catch (const InputError& error) {
    damage("/outcome", {0, check.samples}, error.what());
  }
  for (DatasetCheck& d : check.datasets) {
    std::sort(d.damaged.begin(), d.damaged.end(),
              [](const SampleRange& x, const SampleRange& y) { return x.begin < y.begin; });
  }
  return check;
}

std::int64_t WriteAllocationIndex(const fs::path& results, const AllocationIdentity& identity,
                                  const std::vector<double>& design_points, const AllocationOutcome& outcome,
                                  const std::vector<AllocationShard>& shards) {
  const QuietErrors quiet;
  const std::string name = results.string();
  CheckIdentity(identity, {});
  const std::int64_t candidates = CandidateCount(identity);
  CheckOutcome(outcome, candidates, identity.constraints.size());
  if (shards.empty()) throw std::invalid_argument("WriteAllocationIndex: no shards");
  if (design_points.size() != static_cast<std::size_t>(identity.samples) * identity.inputs.size()) {
    throw std::invalid_argument("WriteAllocationIndex: design points of another shape");
  }
  std::vector<fs::path> paths;
  for (const AllocationShard& shard : shards) paths.push_back(shard.path);
  CheckIndexTarget(results, paths, "WriteAllocationIndex");
  std::vector<std::string> names;
  std::array<std::vector<VirtualSource>, 2> sources;
  for (const AllocationShard& shard : shards) {
    names.push_back(shard.path.filename().string());
    for (const EvaluationRole role : kRoles) {
      VirtualSource source{names.back(), identity.samples, {}, {}};
      for (const AllocationShard::Rows& rows : shard.rows[RoleIndex(role)]) {
        source.group_rows.push_back({rows.candidate, rows.samples});
      }
      sources[RoleIndex(role)].push_back(std::move(source));
    }
  }
  const Where where{name, false};
  std::int64_t mappings = 0;
  ReplaceIndex(where, results, names, [&](hid_t file) {
    WriteIdentity(where, file, identity, design_points, true, Layout::kShardIndex);
    const std::vector<std::string> stored = StoredOutputs(identity.constraints);
    for (const EvaluationRole role : kRoles) {
      mappings += SampleTable::CreateVirtual(where, file, CandidateRows(candidates, identity.samples),
                                             RoleSpecs(role, RoleColumns(role, stored)), sources[RoleIndex(role)]);
    }
    WriteErrorMotionColumnAttributes(where, file, identity, stored);
    CreateOutcome(where, file, static_cast<hsize_t>(candidates), identity.constraints.size(), true);
    WriteOutcome(where, file, outcome, identity.constraints.size());
  });
  return mappings;
}

std::int64_t JoinAllocationShards(const fs::path& results, const fs::path& out) {
  const std::vector<fs::path> shards = IndexedAllocationShards(results);
  if (shards.empty()) throw InputError(results.string() + ": keeps its samples itself: there are no shards to join");
  // A damaged chunk would stop the join half-way, or a damaged /outcome be carried into the
  // joined file: the shards that --resume repairs are kept instead.
  if (const ResultsCheck check = CheckAllocationResults(results); !check.intact()) {
    throw InputError(fmt::format(
        "{}: cannot be joined: {}; the index and its shards are left as they are: `ringtol allocate {} --out {} "
        "--resume` computes those samples again, then join",
        results.string(), DamagedDatasets(check), AllocationReader(results).identity().allocation_path,
        results.string()));
  }
  const auto [target, in_place] = PrepareJoin(results, out);
  std::error_code error;
  std::int64_t joined = 0;
  {
    const AllocationReader index(results);
    const AllocationIdentity& identity = index.identity();
    AllocationStore store = AllocationStore::Create(target, identity, index.ReadDesignPoints(0, identity.samples));
    for (const fs::path& shard : shards) joined += store.Absorb(shard);
    store.Commit(index.ReadOutcome());
  }
  if (in_place) {
    fs::rename(target, results, error);
    if (error) throw InputError(results.string() + ": cannot replace the index by the joined file: " + error.message());
    for (const fs::path& shard : shards) fs::remove(shard, error);
  }
  return joined;
}

ShardPlan PlanAllocationShards(const fs::path& results, const AllocationIdentity& identity, int ranks, bool resume) {
  return PlanShards(results, ranks, resume,
                    [&](const fs::path& file) { const AllocationStore plain = AllocationStore::Resume(file, identity); });
}

AllocationStore OpenAllocationShard(const fs::path& results, int rank, const AllocationIdentity& identity) {
  const fs::path own = ShardPath(results, rank);
  return fs::exists(own) ? AllocationStore::Resume(own, identity) : AllocationStore::CreateShard(own, identity);
}

std::vector<UnreadableShard> SetAsideUnreadableAllocationShards(const fs::path& results) {
  return SetAsideUnreadableShards(results, [](const fs::path& shard) { ReadShard(shard); });
}

std::vector<fs::path> IndexedAllocationShards(const fs::path& results) {
  const QuietErrors quiet;
  const Where where{results.string(), true};
  const FileId file = OpenForReading(results);
  const Stored stored = ReadStored(where, file.get());
  if (!stored.index) return {};
  return ListedShards(where, file.get(), results, stored.identity);
}

ResultsKind ReadResultsKind(const fs::path& path) {
  const QuietErrors quiet;
  const Where where{path.string(), true};
  const FileId file = OpenForReading(path);
  const std::optional<std::string> format = FormatOf(where, file.get());
  if (format == std::optional<std::string>(kCampaignFormat)) return ResultsKind::kCampaign;
  if (format == std::optional<std::string>(kFormat)) return ResultsKind::kAllocation;
  throw InputError(where.file + ": is not a ringtol results file (its root attribute format is neither \"" +
                   kCampaignFormat + "\" nor \"" + kFormat + "\")");
}

}  // namespace ringtol::jobs
