#include "jobs/store/campaign_store.h"

#include <hdf5.h>
#include <zlib.h>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <limits>
#include <optional>
#include <stdexcept>
#include <system_error>
#include <tuple>
#include <type_traits>
#include <utility>

#include "engine/units.h"
#include "jobs/inputs/input_error.h"
#include "jobs/store/hdf5_file.h"
#include "jobs/store/identity_attributes.h"
#include "jobs/store/sample_table.h"
#include "jobs/campaign/campaign.h"

namespace ringtol::jobs {

using namespace hdf5;  // NOLINT(google-build-using-namespace): the store's own HDF5 helpers

namespace {

namespace fs = std::filesystem;

constexpr const char* kFormat = "ringtol campaign";
constexpr const char* kAllocationFormat = "ringtol allocation";
// The root attribute `life`: whether the samples computed the life outputs.
constexpr std::string_view kLifeComputed = "computed";
constexpr std::string_view kLifeNotComputed = "not computed";
constexpr std::size_t kMessageBytes = 256;
constexpr std::size_t kMessageChars = kMessageBytes - 1;  // and the terminator
// Default chunk of /inputs/u: large enough that deflate works well, small enough that the
// chunks being filled between commits fit the chunk cache many times over.
constexpr hsize_t kChunkRows = 1024;  // 8 KiB of a float64 column
// ---------------------------------------------------------------------------------------
// The per-sample datasets ("columns"), statuses last: Commit writes them in this order.

enum Column : std::size_t {
  kU,
  kValues,
  kRedraws,
  kDrawChecksum,
  kSteps,
  kMessage,
  kSolveTime,
  kRung,
  kErrorBound,
  kOffBore,
  kFirstOutput,
  kStatus = kFirstOutput + kOutputCount,
  kColumnCount
};

std::string ColumnPath(std::size_t column) {
  switch (column) {
    case kU:
      return "/inputs/u";
    case kValues:
      return "/inputs/values";
    case kRedraws:
      return "/inputs/redraws";
    case kDrawChecksum:
      return "/inputs/draw_checksum";
    case kSteps:
      return "/outputs/steps";
    case kMessage:
      return "/outputs/message";
    case kSolveTime:
      return "/timing/solve_time_s";
    case kRung:
      return "/outputs/rung";
    case kErrorBound:
      return "/outputs/d_trajectory_error_mm";
    case kOffBore:
      return "/outputs/off_bore_percent";
    case kStatus:
      return "/outputs/status";
    default:
      return std::string("/outputs/") + kOutputNames[column - kFirstOutput];
  }
}

// The error_motion_* columns.
std::vector<std::size_t> ErrorMotionColumns() {
  std::vector<std::size_t> columns;
  for (std::size_t k = 0; k < kOutputCount; ++k) {
    if (IsErrorMotionOutput(kOutputNames[k])) columns.push_back(kFirstOutput + k);
  }
  return columns;
}

constexpr const char* kRunoutDefinition =
    "total indicator reading: max - min of the sensor signal over one revolution";
constexpr const char* kSwingDefinition =
    "largest rise or fall of the sensor signal, each net of the largest counter-move inside it beyond "
    "resolution_um, after a Gaussian filter at cutoff_upr undulations per revolution when cutoff_upr > 0";

// Where a file of `schema` keeps column `column`; empty when it has no such dataset. Schema
// 1 named the ill-posed "peak to nearest valley" runout_mm and the max - min that runout_mm
// is now runout_total_mm; it had no swing. Schemas 1 and 2 had no rung and error bound,
// schemas 1 to 3 no life outputs, nor has a file of a campaign that left the life out
// (`life`: CampaignIdentity::life). Schema 5 keeps failure messages in /failures instead of
// a message per sample, and a draw checksum per sample. Schema 6 adds each roller's share
// of the turn off the bore, and the rollers' names.
constexpr int kFirstSchemaWithLife = 4;
constexpr int kFirstSchemaWithSlimRows = 5;
constexpr int kFirstSchemaWithOpenings = 6;
constexpr const char* kRollerNames = "/rollers/name";
// The rows of an index written before the layout attribute: that ringtol's schema.
constexpr int kLegacyIndexRowsSchema = 5;
std::string StoredColumnPath(std::size_t column, int schema, bool life) {
  if (column == kOffBore && schema < kFirstSchemaWithOpenings) return {};
  if (column == kMessage && schema >= kFirstSchemaWithSlimRows) return {};
  if (column == kDrawChecksum && schema < kFirstSchemaWithSlimRows) return {};
  if ((column == kRung || column == kErrorBound) && schema < kFirstSchemaWithRungs) return {};
  if (column < kFirstOutput || column >= kFirstOutput + kOutputCount) return ColumnPath(column);
  const OutputDescription& output = kOutputs[column - kFirstOutput];
  if (schema < output.first_schema || (output.span == OutputSpan::kLife && !life)) return {};
  if (schema == 1 && std::string_view(output.name) == "runout_mm") return "/outputs/runout_total_mm";
  return ColumnPath(column);
}

template <typename T>
T Require(const Where& where, std::optional<T> value, const char* name) {
  if (!value) Fail(where, fmt::format("is not a complete ringtol campaign file: attribute {} is missing", name));
  return *std::move(value);
}

// ---------------------------------------------------------------------------------------
// Calibrations: /calibration/<k>, one group of attributes per calibrated form spectrum, in
// metres (the sampler's own unit), so that they read back to the bits the run drew with.

constexpr const char* kCalibrationGroup = "/calibration";
constexpr std::array<sampling::FormMeasure, 2> kFormMeasures = {sampling::FormMeasure::kRoundness,
                                                                sampling::FormMeasure::kTwoPointVariation};

// The numbers of one stored calibration, listed once for the writer and the reader.
using CalibrationField = double& (*)(sampling::ComponentScale&);
constexpr std::array<std::pair<const char*, CalibrationField>, 6> kCalibrationNumbers = {{
    {"tolerance_m", [](sampling::ComponentScale& s) -> double& { return s.tolerance; }},
    {"coverage", [](sampling::ComponentScale& s) -> double& { return s.coverage; }},
    {"scale_m", [](sampling::ComponentScale& s) -> double& { return s.calibration.scale; }},
    {"unit_quantile", [](sampling::ComponentScale& s) -> double& { return s.calibration.unit_quantile; }},
    {"unit_quantile_low", [](sampling::ComponentScale& s) -> double& { return s.calibration.unit_quantile_low; }},
    {"unit_quantile_high", [](sampling::ComponentScale& s) -> double& { return s.calibration.unit_quantile_high; }},
}};

void WriteCalibrations(const Where& where, hid_t file, const std::vector<sampling::ComponentScale>& scales,
                       const PlistId& gcpl) {
  if (scales.empty()) return;
  GroupId(Check(H5Gcreate2(file, kCalibrationGroup, H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), where, "creating group",
                kCalibrationGroup));
  for (std::size_t k = 0; k < scales.size(); ++k) {
    const std::string path = fmt::format("{}/{}", kCalibrationGroup, k);
    const GroupId group(
        Check(H5Gcreate2(file, path.c_str(), H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), where, "creating group", path));
    sampling::ComponentScale scale = scales[k];
    WriteStringAttribute(where, group.get(), "component", scale.component);
    WriteStringAttribute(where, group.get(), "measure", sampling::FormMeasureName(scale.measure));
    for (const auto& [name, field] : kCalibrationNumbers) {
      WriteAttribute(where, group.get(), name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &field(scale));
    }
    const std::int32_t draws = scale.calibration.draws;
    WriteAttribute(where, group.get(), "draws", H5T_STD_I32LE, H5T_NATIVE_INT32, &draws);
  }
}

// The stored calibrations; none when the file has none (written before they were stored)
// or when any of them does not read or is no calibration: a campaign rebuilt from the file
// then calibrates, as it always did.
std::vector<sampling::ComponentScale> ReadCalibrations(const Where& where, hid_t file) {
  if (H5Lexists(file, kCalibrationGroup, H5P_DEFAULT) <= 0) return {};
  std::vector<sampling::ComponentScale> scales;
  try {
    for (std::size_t k = 0;; ++k) {
      const std::string path = fmt::format("{}/{}", kCalibrationGroup, k);
      if (H5Lexists(file, path.c_str(), H5P_DEFAULT) <= 0) break;
      const GroupId group(Check(H5Gopen2(file, path.c_str(), H5P_DEFAULT), where, "opening group", path));
      sampling::ComponentScale& scale = scales.emplace_back();
      scale.component = Require(where, ReadStringAttribute(where, group.get(), "component"), "component");
      const std::string measure = Require(where, ReadStringAttribute(where, group.get(), "measure"), "measure");
      const auto* known = std::find_if(kFormMeasures.begin(), kFormMeasures.end(), [&](sampling::FormMeasure m) {
        return measure == sampling::FormMeasureName(m);
      });
      if (known == kFormMeasures.end()) return {};
      scale.measure = *known;
      for (const auto& [name, field] : kCalibrationNumbers) {
        field(scale) = Require(
            where, ReadNumberAttribute<double>(where, group.get(), name, H5T_FLOAT, H5T_NATIVE_DOUBLE), name);
      }
      scale.calibration.draws = Require(
          where, ReadNumberAttribute<std::int32_t>(where, group.get(), "draws", H5T_INTEGER, H5T_NATIVE_INT32),
          "draws");
      if (!(std::isfinite(scale.calibration.scale) && scale.calibration.scale > 0.0 && scale.calibration.draws > 0))
        return {};
    }
  } catch (const std::exception&) {
    return {};
  }
  return scales;
}

// ---------------------------------------------------------------------------------------
// Identity

// The identity's root attributes. The first three come first so that a resume names them,
// not the campaign file's line that changed them.
constexpr WordMember<CampaignIdentity> kLife = {
    [](const CampaignIdentity& c) { return std::string(c.life ? kLifeComputed : kLifeNotComputed); },
    [](const CampaignIdentity& c) { return std::string(c.life ? "true" : "false"); },
    [](CampaignIdentity& c, std::string_view word) {
      c.life = word == kLifeComputed;
      return c.life || word == kLifeNotComputed;
    },
    [] { return fmt::format("\"{}\", \"{}\"", kLifeComputed, kLifeNotComputed); }};
constexpr WordMember<CampaignIdentity> kAccuracy = {
    [](const CampaignIdentity& c) { return std::string(NameOf(solvers::kAccuracyNames, c.accuracy)); },
    [](const CampaignIdentity& c) { return std::string(NameOf(solvers::kAccuracyNames, c.accuracy)); },
    [](CampaignIdentity& c, std::string_view word) {
      const std::optional<solvers::Accuracy> named = ValueNamed(solvers::kAccuracyNames, word);
      if (named) c.accuracy = *named;
      return named.has_value();
    },
    [] { return NameList(solvers::kAccuracyNames); }};

// `life`, `accuracy` and `population` are younger than the rest: files before them computed
// the life wherever their schema has it, at full accuracy, from tolerance classes.
constexpr std::array<IdentityAttribute<CampaignIdentity>, 11> kIdentityAttributes = {{
    {"life", kLife, Comparison::kWord, Presence::kSince, "outputs.life"},
    {"accuracy", kAccuracy, Comparison::kWord, Presence::kSince, "solver.accuracy"},
    // A part's export can change while the campaign file's text does not.
    {"population", &CampaignIdentity::population, Comparison::kText, Presence::kSince},
    {"ringtol_version", &CampaignIdentity::ringtol_version},
    {"catalogue_version", &CampaignIdentity::catalogue_version},
    {"campaign_path", &CampaignIdentity::campaign_path, Comparison::kNever},
    {"campaign_file", &CampaignIdentity::campaign_file, Comparison::kText},
    {"base_scene", &CampaignIdentity::base_scene, Comparison::kText},
    {"design", &CampaignIdentity::design},
    {"solver", &CampaignIdentity::solver},
    {"seed", &CampaignIdentity::seed},
}};

// What Resume and CampaignReader find in a file before trusting it.
struct Stored {
  CampaignIdentity identity;
  std::int64_t samples = 0;
  int schema_version = 0;
  // Samples from here on keep no u and values (schema 5; every sample before it).
  std::int64_t inputs_stored_below = std::numeric_limits<std::int64_t>::max();
  // An index of shards (its layout): schema_version is then its rows' schema, and the
  // shards' chunk rows the blocks its readers read statuses in.
  bool index = false;
  std::int64_t chunk_rows = 1;
};

Stored ReadStored(const Where& where, hid_t file) {
  const std::optional<std::string> format = FormatOf(where, file);
  if (format == std::optional<std::string>(kAllocationFormat)) {
    // The campaign's readers get here: name what the file is instead.
    throw InputError(where.file + ": is a ringtol allocation results file, not a campaign's");
  }
  if (format != std::optional<std::string>(kFormat)) {
    throw InputError(where.file + ": is not a ringtol campaign file (its root has no attribute format = \"" + kFormat +
                     "\")");
  }
  Stored stored;
  const auto schema =
      Require(where, ReadNumberAttribute<std::int64_t>(where, file, "schema_version", H5T_INTEGER, H5T_NATIVE_INT64),
              "schema_version");
  if (schema > kNewestSchemaVersion) {
    throw InputError(fmt::format("{}: was written by a newer ringtol (schema {}); this ringtol reads schema {}",
                                 where.file, schema, kNewestSchemaVersion));
  }
  if (schema < kOldestReadableSchema) {
    throw InputError(fmt::format("{}: has unknown schema version {}; this ringtol reads schemas {} to {}", where.file,
                                 schema, kOldestReadableSchema, kNewestSchemaVersion));
  }
  const StoredLayout layout =
      ReadLayout(where, file, static_cast<int>(schema), kShardIndexSchemaVersion, kLegacyIndexRowsSchema);
  if (layout.rows_schema > kCampaignSchemaVersion || layout.rows_schema < kOldestReadableSchema) {
    throw InputError(fmt::format("{}: keeps rows of schema {}; this ringtol reads schemas {} to {}", where.file,
                                 layout.rows_schema, kOldestReadableSchema, kCampaignSchemaVersion));
  }
  stored.index = layout.layout == Layout::kShardIndex;
  stored.schema_version = layout.rows_schema;
  if (stored.index) {
    stored.chunk_rows = Require(
        where, ReadNumberAttribute<std::int64_t>(where, file, "shard_chunk_rows", H5T_INTEGER, H5T_NATIVE_INT64),
        "shard_chunk_rows");
    if (stored.chunk_rows < 1) Fail(where, fmt::format("attribute shard_chunk_rows = {} is not positive", stored.chunk_rows));
  }

  CampaignIdentity& identity = stored.identity;
  ReadIdentityAttributes(where, file, identity, kIdentityAttributes, kFormat);
  stored.samples = Require(
      where, ReadNumberAttribute<std::int64_t>(where, file, "samples", H5T_INTEGER, H5T_NATIVE_INT64), "samples");
  if (stored.samples < 1) Fail(where, fmt::format("attribute samples = {} is not positive", stored.samples));
  if (stored.schema_version >= kFirstSchemaWithSlimRows) {
    stored.inputs_stored_below =
        Require(where,
                ReadNumberAttribute<std::int64_t>(where, file, "inputs_stored_below", H5T_INTEGER, H5T_NATIVE_INT64),
                "inputs_stored_below");
    if (stored.inputs_stored_below < 0) {
      Fail(where, fmt::format("attribute inputs_stored_below = {} is negative", stored.inputs_stored_below));
    }
  }

  identity.inputs = ReadInputDescriptions(where, file);
  if (stored.schema_version >= kFirstSchemaWithOpenings) {
    identity.rollers = ReadStrings(where, file, kRollerNames);
    if (identity.rollers.empty()) Fail(where, fmt::format("{} is empty: a scene has rollers", kRollerNames));
  }
  identity.calibrations = ReadCalibrations(where, file);

  for (std::size_t k = 0; k < kOutputCount; ++k) {
    const std::string path = StoredColumnPath(kFirstOutput + k, stored.schema_version, identity.life);
    if (path.empty()) continue;
    const DatasetId dataset(Check(H5Dopen2(file, path.c_str(), H5P_DEFAULT), where, "opening dataset", path));
    if (const auto upper =
            ReadNumberAttribute<double>(where, dataset.get(), "upper_spec_limit", H5T_FLOAT, H5T_NATIVE_DOUBLE)) {
      identity.spec.push_back({kOutputNames[k], *upper});
    }
  }
  if (stored.schema_version >= 2) {
    const DatasetId swing(Check(H5Dopen2(file, "/outputs/swing_mm", H5P_DEFAULT), where, "opening dataset",
                                "/outputs/swing_mm"));
    const auto number = [&](const char* name) {
      return Require(where, ReadNumberAttribute<double>(where, swing.get(), name, H5T_FLOAT, H5T_NATIVE_DOUBLE), name);
    };
    identity.swing.resolution = number("resolution_um") * units::kMetresPerMicrometre;
    identity.swing.cutoff_upr = number("cutoff_upr");
  }
  if (stored.schema_version >= kFirstSchemaWithLife && identity.life) {
    const std::string path = ColumnPath(ErrorMotionColumns().front());
    const DatasetId total(Check(H5Dopen2(file, path.c_str(), H5P_DEFAULT), where, "opening dataset", path));
    identity.error_motion_filter = ReadErrorMotionFilter(where, total.get());
  }
  return stored;
}

std::optional<double> SpecOf(const std::vector<SpecLimit>& spec, std::string_view output) {
  for (const SpecLimit& limit : spec) {
    if (limit.output == output) return limit.upper;
  }
  return std::nullopt;
}

std::optional<std::string> SpecDifference(const std::vector<SpecLimit>& file, const std::vector<SpecLimit>& now) {
  const auto show = [](std::optional<double> upper) {
    return upper ? fmt::format("{}", *upper) : std::string("not set");
  };
  for (const char* output : kOutputNames) {
    const std::optional<double> a = SpecOf(file, output);
    const std::optional<double> b = SpecOf(now, output);
    if (a != b) {
      return fmt::format("spec differs (upper_spec_limit of {}: {} in the file, {} now)", output, show(a), show(b));
    }
  }
  return std::nullopt;
}

// The first identity field in which `now` differs from the file, or nothing.
std::optional<std::string> IdentityDifference(const CampaignIdentity& file, const CampaignIdentity& now) {
  if (auto d = IdentityAttributeDifference(file, now, kIdentityAttributes)) return d;
  if (auto d = InputDifference(file.inputs, now.inputs, "this campaign")) return d;
  return SpecDifference(file.spec, now.spec);
}

// ---------------------------------------------------------------------------------------
// The per-sample columns of a file of `schema` (jobs/store/sample_table.h): the specs a
// file is created with (the current schema) and opened with (any readable one).

// The rung column's enumeration (schema 4 on): solvers::Rung's numbers under its names,
// and "none" for kNoRung, so that h5py and h5dump name each sample's rung as the status
// column names its status.
TypeId RungType(const Where& where) {
  TypeId type(Check(H5Tenum_create(H5T_NATIVE_INT8), where, "creating", "the rung type"));
  const auto insert = [&](const char* name, std::int8_t value) {
    CheckStatus(H5Tenum_insert(type.get(), name, &value), where, "naming rung", name);
  };
  insert("none", kNoRung);
  for (const auto& [rung, name] : solvers::kRungNames) {
    if (rung != solvers::Rung::kAuto) insert(std::string(name).c_str(), static_cast<std::int8_t>(rung));
  }
  return type;
}

constexpr int kSmallColumnDeflateLevel = 1;

// The columns of a file of `schema` written for `identity` (its life, inputs and rollers).
// `inputs_stored_below`: the first sample whose u and values are not stored.
std::vector<ColumnSpec> Columns(int schema, const CampaignIdentity& identity, int deflate_level,
                                std::int64_t inputs_stored_below) {
  std::vector<ColumnSpec> columns(kColumnCount);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t c = 0; c < kColumnCount; ++c) {
    ColumnSpec& spec = columns[c];
    spec.path = ColumnPath(c);
    spec.stored_path = StoredColumnPath(c, schema, identity.life);
    spec.fill = nan;
    // The floating-point columns barely compress (design points are random bits below the
    // exponent) and, in SWMR mode, every rewrite of a compressed chunk that grows leaves its
    // old copy behind (HDF5 does not free it); stored uncompressed they are rewritten in
    // place. Counts, statuses and messages shrink a hundredfold and their chunks stay
    // small, so they are always deflated; checksums are random bits, never.
    spec.deflate_level = deflate_level;
    switch (c) {
      case kU:
        spec.finite = FiniteRule::kWhenFinished;
        break;
      case kValues:
        spec.type = ColumnType::kFloat32;
        spec.finite = FiniteRule::kUnlessSamplingFailed;
        break;
      case kDrawChecksum:
        spec.type = ColumnType::kUInt32;
        spec.fill = 0;
        break;
      case kRedraws:
      case kSteps:
        spec.type = ColumnType::kInt32;
        spec.fill = 0;
        break;
      case kMessage:
        spec.type = ColumnType::kText;
        spec.text_bytes = kMessageBytes;
        break;
      case kRung:
        spec.type = ColumnType::kInt8Enum;
        spec.enumeration = RungType;
        spec.fill = kNoRung;
        break;
      case kStatus:
        spec.type = ColumnType::kInt8Enum;
        spec.enumeration = StatusType;
        spec.fill = static_cast<double>(SampleStatus::kPending);
        break;
      case kSolveTime:
      case kErrorBound:
        break;
      case kOffBore:  // a row of every roller, in percent: float32 resolves far below one angle's share
        spec.type = ColumnType::kFloat32;
        spec.width = identity.rollers.size();
        spec.finite = FiniteRule::kWhenOk;
        break;
      default:  // outputs; an ok sample whose roller left the bore has no life values (NaN)
        spec.finite = IsLifeOutput(c - kFirstOutput) ? FiniteRule::kNone : FiniteRule::kWhenOk;
        break;
    }
    if (c == kU || c == kValues) {  // a row of every input, for the first samples only
      spec.width = identity.inputs.size();
      spec.cached = true;
      spec.stored_below = inputs_stored_below;
    }
    const bool small = spec.type == ColumnType::kInt32 || spec.type == ColumnType::kInt8Enum ||
                       spec.type == ColumnType::kText;
    if (small) spec.deflate_level = std::max(deflate_level, kSmallColumnDeflateLevel);
    if (spec.type == ColumnType::kUInt32) spec.deflate_level = 0;
  }
  return columns;
}

RowSpace Rows(std::int64_t samples, std::int64_t chunk_samples = 1) {
  RowSpace space;
  space.samples = samples;
  space.chunk_samples = chunk_samples;
  space.extendable = true;
  return space;
}

// Opens the columns of a file of `stored`'s schema and size.
SampleTable OpenColumns(const Where& where, hid_t file, const Stored& stored, std::size_t cache_bytes = 0) {
  return SampleTable::Open(
      where, file, Rows(stored.samples, stored.chunk_rows),
      Columns(stored.schema_version, stored.identity, 0, stored.inputs_stored_below),
      cache_bytes);
}

// ---------------------------------------------------------------------------------------
// Failures (schema 5): why each failed sample failed, one row per failed sample committed,
// appended; a sample computed again appends again and its last row counts.

constexpr const char* kFailureSamples = "/failures/sample";
constexpr const char* kFailureMessages = "/failures/message";
// Uncompressed, so that an append rewrites a partly filled chunk in place (SWMR never
// frees the old copy of a compressed one), and small, as failures are rare.
constexpr hsize_t kFailureChunkRows = 64;
constexpr std::int64_t kNoFailureSample = -1;

void CreateFailures(const Where& where, hid_t file, bool checksums) {
  const PlistId gcpl = ObjectCreation(where, H5P_GROUP_CREATE);
  GroupId(Check(H5Gcreate2(file, "failures", H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), where, "creating group",
                "failures"));
  const TypeId message = FixedString(where, kMessageBytes);
  // A row never written, or rewritten after damage, names no sample.
  CreateArray(where, file,
              {kFailureSamples, H5T_STD_I64LE, {0, 0}, kFailureChunkRows, 1, true, H5S_UNLIMITED, &kNoFailureSample,
               H5T_NATIVE_INT64},
              checksums);
  CreateArray(where, file, {kFailureMessages, message.get(), {0, 0}, kFailureChunkRows, 1, true, H5S_UNLIMITED},
              checksums);
}

// Rows of /failures/sample or /failures/message, open as `dataset`.
hsize_t FailureRowCount(const Where& where, hid_t dataset) {
  const SpaceId space(Check(H5Dget_space(dataset), where, "reading the shape of", "a dataset of /failures"));
  hsize_t rows = 0;
  H5Sget_simple_extent_dims(space.get(), &rows, nullptr);
  return rows;
}

// Appends (sample, message) rows at the end of /failures/sample, the messages first: a
// sample's row vouches for its message. A kill between the two leaves messages beyond the
// samples' rows, which the next append writes over.
void AppendFailures(const Where& where, const DatasetId& samples, const DatasetId& messages,
                    const std::vector<std::int64_t>& indices, const std::vector<char>& texts) {
  if (indices.empty()) return;
  const TypeId message_type = FixedString(where, kMessageBytes);
  const hsize_t rows = FailureRowCount(where, samples.get());
  WriteRows(where, messages.get(), kFailureMessages, message_type.get(), rows, indices.size(), texts.data());
  WriteRows(where, samples.get(), kFailureSamples, H5T_NATIVE_INT64, rows, indices.size(), indices.data());
}

// Every failure row of a file, read chunk by chunk: its samples, the row each sample's last
// one is at, and the chunks of either dataset that do not read (a kill while an append
// rewrote one in place tears it; their rows name no sample).
struct FailureRows {
  std::vector<std::int64_t> samples;  // per row; kNoFailureSample where unwritten or damaged
  std::vector<std::pair<std::int64_t, std::size_t>> latest;  // (sample, row), by sample
  std::vector<std::array<hsize_t, 2>> damaged_samples;   // chunk offsets of /failures/sample
  std::vector<std::array<hsize_t, 2>> damaged_messages;  // chunk offsets of /failures/message
  std::string problem;  // the first damaged chunk's

  bool damaged() const { return !damaged_samples.empty() || !damaged_messages.empty(); }
  std::optional<std::size_t> Find(std::int64_t sample) const {
    const auto found = std::lower_bound(latest.begin(), latest.end(), std::make_pair(sample, std::size_t{0}));
    if (found == latest.end() || found->first != sample) return std::nullopt;
    return found->second;
  }
};

FailureRows ReadFailureRows(const Where& where, hid_t file) {
  FailureRows rows;
  const TypeId message_type = FixedString(where, kMessageBytes);
  std::vector<char> texts(kFailureChunkRows * kMessageBytes);
  for (const char* path : {kFailureSamples, kFailureMessages}) {
    const bool samples = path == kFailureSamples;
    const DatasetId dataset(Check(H5Dopen2(file, path, H5P_DEFAULT), where, "opening dataset", path));
    const hsize_t extent = FailureRowCount(where, dataset.get());
    // Messages beyond the samples' rows belong to no row (a kill between the two appends).
    if (samples) rows.samples.assign(extent, kNoFailureSample);
    const hsize_t used = samples ? extent : std::min<hsize_t>(extent, rows.samples.size());
    for (hsize_t first = 0; first < used; first += kFailureChunkRows) {
      const hsize_t count = std::min(kFailureChunkRows, used - first);
      const auto problem = samples ? TryReadRows(where, dataset.get(), path, H5T_NATIVE_INT64, first, count,
                                                 rows.samples.data() + first)
                                   : TryReadRows(where, dataset.get(), path, message_type.get(), first, count,
                                                 texts.data());
      if (!problem) continue;
      if (!rows.damaged()) rows.problem = fmt::format("{}: {}", path, *problem);
      (samples ? rows.damaged_samples : rows.damaged_messages).push_back({first, 0});
      std::fill_n(rows.samples.begin() + static_cast<std::ptrdiff_t>(first), count, kNoFailureSample);
    }
  }
  for (std::size_t row = 0; row < rows.samples.size(); ++row) {
    if (rows.samples[row] != kNoFailureSample) rows.latest.emplace_back(rows.samples[row], row);
  }
  // By sample, the last row of each sample kept.
  std::stable_sort(rows.latest.begin(), rows.latest.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::pair<std::int64_t, std::size_t>> latest;
  for (std::size_t i = 0; i < rows.latest.size(); ++i) {
    if (i + 1 < rows.latest.size() && rows.latest[i + 1].first == rows.latest[i].first) continue;
    latest.push_back(rows.latest[i]);
  }
  rows.latest = std::move(latest);
  return rows;
}

// The finished, failed samples whose message the failure rows no longer hold.
std::vector<std::int64_t> LostMessages(const SampleTable& table, const FailureRows& rows) {
  std::vector<std::int64_t> lost;
  const std::int64_t chunk = table.space().chunk_samples;
  const std::int64_t samples = table.space().samples;
  std::vector<std::int8_t> statuses(static_cast<std::size_t>(chunk));
  // Chunk by chunk: a status chunk that does not read is damage of its own, computed again.
  // Beyond the written rows every sample is pending.
  for (std::int64_t begin = 0; begin < std::min(samples, table.written_end()); begin += chunk) {
    const std::int64_t count = std::min(chunk, samples - begin);
    if (table.TryRead(table.status_column(), 0, begin, count, statuses.data())) continue;
    for (std::int64_t i = 0; i < count; ++i) {
      const auto status = static_cast<SampleStatus>(statuses[static_cast<std::size_t>(i)]);
      if (status != SampleStatus::kOk && status != SampleStatus::kPending && !rows.Find(begin + i)) {
        lost.push_back(begin + i);
      }
    }
  }
  return lost;
}

std::string ReadFailureMessage(const Where& where, hid_t file, std::size_t row) {
  const DatasetId dataset(Check(H5Dopen2(file, kFailureMessages, H5P_DEFAULT), where, "opening dataset",
                                kFailureMessages));
  const TypeId type = FixedString(where, kMessageBytes);
  std::array<char, kMessageBytes + 1> text{};
  if (const auto problem = TryReadRows(where, dataset.get(), kFailureMessages, type.get(), row, 1, text.data())) {
    throw InputError(fmt::format("{}: dataset {} is damaged at row {} ({})", where.file, kFailureMessages, row,
                                 *problem));
  }
  return text.data();
}

// ---------------------------------------------------------------------------------------
// Creating

void CheckArguments(const CampaignIdentity& identity, std::int64_t samples, const CampaignStoreOptions& options) {
  if (samples < 1) throw std::invalid_argument(fmt::format("CampaignStore: samples = {} must be >= 1", samples));
  if (identity.inputs.empty()) {
    throw std::invalid_argument("CampaignStore: a campaign needs at least one sampled input");
  }
  if (options.schema >= kFirstSchemaWithOpenings && identity.rollers.empty()) {
    throw std::invalid_argument("CampaignStore: a campaign's scene has rollers: name them");
  }
  if (InvalidOption invalid; !options.IsValid(&invalid)) {
    throw std::invalid_argument(fmt::format("CampaignStore: {} = {} is out of its range", invalid.field, invalid.value));
  }
  for (std::size_t i = 0; i < identity.spec.size(); ++i) {
    const std::string& output = identity.spec[i].output;
    if (std::find(kOutputNames.begin(), kOutputNames.end(), output) == kOutputNames.end()) {
      throw std::invalid_argument("CampaignStore: spec limit on unknown output '" + output + "'");
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (identity.spec[j].output == output) {
        throw std::invalid_argument("CampaignStore: two spec limits on output '" + output + "'");
      }
    }
  }
}

hsize_t DefaultChunkRows(const CampaignStoreOptions& options, std::int64_t samples) {
  if (options.chunk_samples > 0) return static_cast<hsize_t>(options.chunk_samples);
  // Sized for the one-value columns, which every sample fills and readers scan whole: a
  // read through an index of shards pays about 70 us for each chunk it crosses, so a
  // column of 10^7 samples over 1,000 shards reads in 0.94 s with 1,024 rows a chunk and
  // 3.37 s with 208 (docs/performance.md, "Campaigns at scale"). The wide rows (u, values:
  // 1.3 MB a chunk of 157 inputs) are kept for the first samples only, and their chunks
  // are held in the chunk cache while they fill (CampaignStoreOptions::chunk_cache_bytes).
  return std::min<hsize_t>(kChunkRows, static_cast<hsize_t>(samples));
}

// The root's attributes, the groups, the input descriptions and the calibrations: what a
// results file and an index of shards share, its rows in options.schema.
void WriteIdentity(const Where& where, hid_t file, const CampaignIdentity& identity, std::int64_t samples,
                   const CampaignStoreOptions& options, Layout layout) {
  const std::int32_t schema = layout == Layout::kFile ? options.schema : kShardIndexSchemaVersion;
  WriteStringAttribute(where, file, "format", kFormat);
  WriteAttribute(where, file, "schema_version", H5T_STD_I32LE, H5T_NATIVE_INT32, &schema);
  WriteLayout(where, file, {layout, options.schema});
  WriteIdentityAttributes(where, file, identity, kIdentityAttributes);
  WriteAttribute(where, file, "samples", H5T_STD_I64LE, H5T_NATIVE_INT64, &samples);

  const PlistId gcpl = ObjectCreation(where, H5P_GROUP_CREATE);
  for (const char* name : {"inputs", "outputs", "timing"}) {
    GroupId(Check(H5Gcreate2(file, name, H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), where, "creating group", name));
  }

  WriteInputDescriptions(where, file, identity.inputs, options.checksums);
  if (options.schema >= kFirstSchemaWithOpenings) {
    GroupId(Check(H5Gcreate2(file, "rollers", H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), where, "creating group", "rollers"));
    WriteStrings(where, file, kRollerNames, identity.rollers, options.checksums);
  }
  WriteCalibrations(where, file, identity.calibrations, gcpl);

  const std::int64_t stored_below = options.inputs_stored_below;
  WriteAttribute(where, file, "inputs_stored_below", H5T_STD_I64LE, H5T_NATIVE_INT64, &stored_below);
}

// The outputs' attributes: spec limits, and what the two sensor columns mean and how the
// swing was read, for readers of the file that do not parse base_scene.
void WriteColumnAttributes(const Where& where, hid_t file, const CampaignIdentity& identity) {
  for (const SpecLimit& limit : identity.spec) {
    const std::string path = "/outputs/" + limit.output;
    const DatasetId dataset(Check(H5Dopen2(file, path.c_str(), H5P_DEFAULT), where, "opening dataset", path));
    WriteAttribute(where, dataset.get(), "upper_spec_limit", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &limit.upper);
  }
  const DatasetId runout(Check(H5Dopen2(file, "/outputs/runout_mm", H5P_DEFAULT), where, "opening dataset",
                               "/outputs/runout_mm"));
  WriteStringAttribute(where, runout.get(), "definition", kRunoutDefinition);
  const DatasetId swing(Check(H5Dopen2(file, "/outputs/swing_mm", H5P_DEFAULT), where, "opening dataset",
                              "/outputs/swing_mm"));
  WriteStringAttribute(where, swing.get(), "definition", kSwingDefinition);
  const double resolution_um = identity.swing.resolution * units::kMicrometresPerMetre;
  WriteAttribute(where, swing.get(), "resolution_um", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &resolution_um);
  WriteAttribute(where, swing.get(), "cutoff_upr", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &identity.swing.cutoff_upr);
  if (!identity.life) return;
  for (const std::size_t column : ErrorMotionColumns()) {
    const std::string path = ColumnPath(column);
    const DatasetId dataset(Check(H5Dopen2(file, path.c_str(), H5P_DEFAULT), where, "opening dataset", path));
    WriteErrorMotionAttributes(where, dataset.get(), identity.error_motion_filter);
  }
}

void WriteSchema(const Where& where, hid_t file, const CampaignIdentity& identity, std::int64_t samples,
                 const CampaignStoreOptions& options) {
  WriteIdentity(where, file, identity, samples, options, Layout::kFile);
  const auto chunk_rows = static_cast<std::int64_t>(DefaultChunkRows(options, samples));
  SampleTable::Create(
      where, file, Rows(samples, chunk_rows),
      Columns(options.schema, identity, options.deflate_level, options.inputs_stored_below),
      options.checksums);
  CreateFailures(where, file, options.checksums);
  WriteColumnAttributes(where, file, identity);
}

std::string ExistsMessage(const std::string& file) {
  return file + ": already exists; pass --resume to continue that campaign, or remove the file to start a new one";
}

std::string_view TruncateUtf8(std::string_view text, std::size_t max_bytes) {
  if (text.size() <= max_bytes) return text;
  std::size_t end = max_bytes;
  // Never cut a multi-byte character in two: back up to its first byte.
  while (end > 0 && (static_cast<unsigned char>(text[end]) & 0xC0) == 0x80) --end;
  return text.substr(0, end);
}

void CheckRange(std::string_view what, std::int64_t begin, std::int64_t end, std::int64_t samples) {
  if (begin < 0 || end < begin || end > samples) {
    throw std::out_of_range(
        fmt::format("{}: range [{}, {}) is outside the campaign's [0, {})", what, begin, end, samples));
  }
}

// Gives the damaged chunks of the failure rows their fill values (rows that name no
// sample) and marks pending the failed samples whose messages they held, so that a resume
// computes them, and their messages, again.
void RepairFailures(const Where& where, hid_t file, const SampleTable& table) {
  const FailureRows rows = ReadFailureRows(where, file);
  const std::vector<std::int64_t> lost = LostMessages(table, rows);
  if (!rows.damaged() && lost.empty()) return;
  for (const auto& [path, offsets] : {std::pair{kFailureSamples, rows.damaged_samples},
                                      std::pair{kFailureMessages, rows.damaged_messages}}) {
    if (offsets.empty()) continue;
    const DatasetId dataset(Check(H5Dopen2(file, path, H5P_DEFAULT), where, "opening", path));
    RewriteChunksWithFill(where, dataset.get(), path, offsets);
  }
  std::cerr << fmt::format("ringtol: {}: the failure rows were damaged; {} failed samples lose their message and are "
                           "computed again\n",
                           where.file, lost.size());
  table.MarkPending(lost);
}

// ---------------------------------------------------------------------------------------
// Damage: CheckResults reads every chunk; Resume rewrites the damaged ones.

constexpr std::array<const char*, 6> kDescriptions = {"/inputs/name",   "/inputs/quantity", "/inputs/component",
                                                      "/inputs/source", "/inputs/roller",   "/inputs/order"};

// What `ringtol verify` reports, from the table's scan: every dataset (descriptions first,
// the statuses last), their damaged samples merged, and what a resume computes.
ResultsCheck Check(const Where& where, hid_t file, const SampleTable& table, const TableScan& scan) {
  ResultsCheck check;
  check.samples = table.space().samples;
  // ReadStored has read the descriptions whole: a damaged one does not get this far.
  std::vector<const char*> descriptions(kDescriptions.begin(), kDescriptions.end());
  if (H5Lexists(file, "/rollers", H5P_DEFAULT) > 0) descriptions.push_back(kRollerNames);
  for (const char* path : descriptions) {
    const DatasetId dataset(hdf5::Check(H5Dopen2(file, path, H5P_DEFAULT), where, "opening dataset", path));
    DatasetCheck description;
    description.path = path;
    description.checksummed = HasChecksum(where, dataset.get(), path);
    check.datasets.push_back(std::move(description));
  }
  // The failure rows (schema 5), chunk by chunk: the failed samples whose messages a damaged
  // chunk held are what a resume computes again for it.
  std::vector<SampleRange> lost;
  if (table.stored(kDrawChecksum)) {
    const FailureRows rows = ReadFailureRows(where, file);
    for (const std::int64_t sample : LostMessages(table, rows)) lost.push_back({sample, sample + 1});
    lost = MergeRanges(std::move(lost));
    for (const char* path : {kFailureSamples, kFailureMessages}) {
      const DatasetId dataset(hdf5::Check(H5Dopen2(file, path, H5P_DEFAULT), where, "opening dataset", path));
      DatasetCheck failures;
      failures.path = path;
      failures.checksummed = HasChecksum(where, dataset.get(), path);
      // Lost messages are the failure rows' damage, whichever dataset lost them.
      const bool hit = path == kFailureSamples ? !rows.damaged_samples.empty() || !rows.damaged() : !rows.damaged_messages.empty();
      if (hit && !lost.empty()) {
        failures.damaged = lost;
        failures.first_problem = rows.damaged() ? rows.problem : "failed samples without a message row";
      }
      check.datasets.push_back(std::move(failures));
    }
  }
  for (std::size_t c = 0; c < table.column_count(); ++c) {
    if (!table.stored(c)) continue;  // an output an older schema lacks
    const ColumnSpec& spec = table.spec(c);
    DatasetCheck dataset;
    dataset.path = spec.stored_path == spec.path ? spec.path : spec.stored_path + " (read as " + spec.path + ")";
    dataset.per_sample = true;
    dataset.checksummed = table.checksummed(c);
    for (const DamagedChunk& chunk : scan.damaged) {
      if (chunk.column != c) continue;
      if (dataset.damaged.empty()) dataset.first_problem = chunk.problem;
      dataset.damaged.push_back(chunk.samples);
    }
    dataset.damaged = MergeRanges(std::move(dataset.damaged));
    check.datasets.push_back(std::move(dataset));
  }
  check.done = scan.done;
  check.pending = scan.pending;
  std::vector<SampleRange> recompute = check.pending;
  for (const DamagedChunk& chunk : scan.damaged) recompute.push_back(chunk.samples);
  recompute.insert(recompute.end(), lost.begin(), lost.end());
  check.recompute = MergeRanges(std::move(recompute));
  return check;
}

// What ReadStored found in a shard (`opening`): InputError unless it is a results file of
// the index's campaign, of no more samples, keeping the same inputs.
void CheckShardStored(const Where& index, const Where& opening, const Stored& stored, const Stored& expected) {
  if (stored.index) throw InputError(opening.file + ": is an index of shards, not a shard");
  if (stored.schema_version != expected.schema_version) {
    throw InputError(fmt::format("{}: is a shard of schema {}, not {}", opening.file, stored.schema_version,
                                 expected.schema_version));
  }
  if (const std::optional<std::string> difference = IdentityDifference(stored.identity, expected.identity)) {
    throw InputError(opening.file + ": is a shard of another campaign than " + index.file + ": " + *difference +
                     "; remove it, or resume with the campaign that wrote it");
  }
  if (stored.samples > expected.samples) {
    throw InputError(fmt::format("{}: is a shard of {} samples, more than the {} of {}", opening.file, stored.samples,
                                 expected.samples, index.file));
  }
  if (stored.inputs_stored_below != expected.inputs_stored_below) {
    throw InputError(fmt::format("{}: keeps the inputs of samples below {}, where {} keeps those below {}",
                                 opening.file, stored.inputs_stored_below, index.file, expected.inputs_stored_below));
  }
}

}  // namespace

struct CampaignStore::File {
  fs::path path;
  Where where;
  FileLock lock;
  FileId file;  // closed after the columns (members are destroyed in reverse order)
  SampleTable table;
  std::int64_t samples = 0;
  std::size_t inputs = 0;
  std::int64_t chunk_rows = 0;
  int schema = kCampaignSchemaVersion;  // a resumed file keeps its own
  std::int64_t inputs_stored_below = std::numeric_limits<std::int64_t>::max();
  DatasetId failure_samples;   // schema 5
  DatasetId failure_messages;  // schema 5
  CampaignIdentity identity;  // what a shard must match
  RowBuffer<SampleRecord> buffer;

  // Everything is created (or extended) by now: enter SWMR mode, then open the columns
  // (entering SWMR reopens open datasets with default access, losing the chunk cache).
  void StartWriting(const CampaignStoreOptions& options) {
    CheckStatus(H5Fstart_swmr_write(file.get()), where, "starting", "SWMR writing");
    table = SampleTable::Open(where, file.get(), Rows(samples), Columns(schema, identity, 0, inputs_stored_below),
                              options.chunk_cache_bytes);
    if (schema >= kFirstSchemaWithSlimRows) {
      failure_samples = DatasetId(
          Check(H5Dopen2(file.get(), kFailureSamples, H5P_DEFAULT), where, "opening dataset", kFailureSamples));
      failure_messages = DatasetId(
          Check(H5Dopen2(file.get(), kFailureMessages, H5P_DEFAULT), where, "opening dataset", kFailureMessages));
    }
  }

  // Closes the columns, then the file (whose close flushes and clears the superblock flags).
  bool Close() {
    table = SampleTable();
    failure_samples.reset();
    failure_messages.reset();
    return file.Close();
  }
};

CampaignStore::CampaignStore(std::unique_ptr<File> file) : file_(std::move(file)) {}

CampaignStore::~CampaignStore() {
  if (!file_) return;
  CommitAndClose(file_->where, [&] { Commit(); }, [&] { return file_->Close(); });
  file_.reset();
}

CampaignStore::CampaignStore(CampaignStore&&) noexcept = default;

CampaignStore& CampaignStore::operator=(CampaignStore&& other) noexcept {
  if (this != &other) {
    CampaignStore previous(std::move(file_));
    file_ = std::move(other.file_);
  }
  return *this;
}

CampaignStore CampaignStore::Create(const fs::path& path, const CampaignIdentity& identity, std::int64_t samples,
                                    const CampaignStoreOptions& options) {
  const QuietErrors quiet;
  CheckArguments(identity, samples, options);
  const std::string name = path.string();
  auto file = std::make_unique<File>();
  file->path = path;
  file->where = Where{name, false};
  file->samples = samples;
  file->inputs = identity.inputs.size();
  file->identity = identity;
  file->chunk_rows = static_cast<std::int64_t>(DefaultChunkRows(options, samples));
  file->inputs_stored_below = options.inputs_stored_below;
  file->schema = options.schema;
  CreateWhole(
      path, ExistsMessage(name), file->file, file->lock,
      [&] {
        WriteSchema(file->where, file->file.get(), identity, samples, options);
        file->StartWriting(options);
      },
      [&] { file->Close(); });
  return CampaignStore(std::move(file));
}

CampaignStore CampaignStore::Resume(const fs::path& path, const CampaignIdentity& identity, std::int64_t samples,
                                    const CampaignStoreOptions& options) {
  const QuietErrors quiet;
  CheckArguments(identity, samples, options);
  const std::string name = path.string();
  const Where opening{name, true};
  FileLock lock = FileLock::ToResume(path, "campaign");

  // Everything is checked read-only first: a refused file is never modified.
  Stored stored;
  std::int64_t chunk_rows = 0;
  TableScan damage;
  {
    const FileId reading = OpenForReading(path);
    stored = ReadStored(opening, reading.get());
    if (stored.index) {
      throw InputError(name + ": is an index of shards: `ringtol campaign --resume` continues it through its shards");
    }
    if (stored.schema_version < kOldestResumableSchema) {
      throw InputError(fmt::format(
          "{}: was written by an older ringtol (schema {}); it can be reported but not resumed by this one (schemas "
          "{} to {}): start a new results file",
          name, stored.schema_version, kOldestResumableSchema, kCampaignSchemaVersion));
    }
    if (const std::optional<std::string> difference = IdentityDifference(stored.identity, identity)) {
      throw InputError(name + ": was written by another campaign: " + *difference +
                       "; resume it with the campaign that wrote it, or choose a new results file");
    }
    const SampleTable table = OpenColumns(opening, reading.get(), stored);
    chunk_rows = table.space().chunk_samples;
    damage = table.Scan();
  }
  if (samples < stored.samples) {
    throw InputError(fmt::format("{}: holds {} samples and cannot shrink to {}; --samples can only grow a campaign",
                                 name, stored.samples, samples));
  }
  if (samples > stored.samples && !DesignCanGrow(identity)) {
    throw InputError(fmt::format("{}: is a Latin hypercube of {} samples and cannot grow to {}: its strata are its "
                                 "whole size; run a new campaign with --samples {} into another --out",
                                 name, stored.samples, samples, samples));
  }

  auto file = std::make_unique<File>();
  file->path = path;
  file->where = Where{name, false};
  file->lock = std::move(lock);
  file->samples = samples;
  file->inputs = identity.inputs.size();
  file->identity = identity;
  file->chunk_rows = chunk_rows;
  file->schema = stored.schema_version;
  file->inputs_stored_below = stored.inputs_stored_below;
  file->file = OpenForWriting(path);
  {
    SampleTable table = OpenColumns(file->where, file->file.get(), stored);
    table.Repair(damage.damaged);
    if (stored.schema_version >= kFirstSchemaWithSlimRows) RepairFailures(file->where, file->file.get(), table);
    if (samples > stored.samples) {
      table.Grow(samples);
      const std::optional<AttributeId> attribute = OpenAttribute(file->where, file->file.get(), "samples");
      if (!attribute) Fail(file->where, "attribute samples vanished");
      CheckStatus(H5Awrite(attribute->get(), H5T_NATIVE_INT64, &samples), file->where, "updating attribute",
                  "samples");
    }
  }
  file->StartWriting(options);
  return CampaignStore(std::move(file));
}

std::int64_t CampaignStore::samples() const { return file_->samples; }

const fs::path& CampaignStore::path() const { return file_->path; }

std::vector<SampleRange> CampaignStore::Pending(std::int64_t begin, std::int64_t end) const {
  const QuietErrors quiet;
  CheckRange("CampaignStore::Pending", begin, end, file_->samples);
  return file_->table.Pending(0, begin, end);
}

void CampaignStore::Add(SampleRecord record) {
  if (record.index < 0 || record.index >= file_->samples) {
    throw std::invalid_argument(
        fmt::format("CampaignStore::Add: sample {} is outside [0, {})", record.index, file_->samples));
  }
  if (record.u.size() != file_->inputs || record.values.size() != file_->inputs) {
    throw std::invalid_argument(fmt::format("CampaignStore::Add: sample {} has {} u and {} values for {} inputs",
                                            record.index, record.u.size(), record.values.size(), file_->inputs));
  }
  if (record.status == SampleStatus::kPending || !IsKnownStatus(static_cast<std::int8_t>(record.status))) {
    throw std::invalid_argument(fmt::format("CampaignStore::Add: sample {} has no final status", record.index));
  }
  const std::size_t rollers = file_->identity.rollers.size();
  if (record.status == SampleStatus::kOk && record.off_bore.size() != rollers) {
    throw std::invalid_argument(fmt::format("CampaignStore::Add: ok sample {} has {} off-bore shares for {} rollers",
                                            record.index, record.off_bore.size(), rollers));
  }
  if (record.index >= file_->inputs_stored_below) {
    // Not kept: the buffer holds the sample's checksum of its draw instead of the draw, so
    // that thousands of buffered samples take kilobytes, not megabytes.
    if (!record.draw_checksum) record.draw_checksum = DrawChecksum(record);
    record.u = std::vector<double>();
    record.values = std::vector<double>();
  }
  const RowKey key{0, record.index};
  file_->buffer.Put(key, std::move(record));
}

std::size_t CampaignStore::buffered() const { return file_->buffer.size(); }

void CampaignStore::Commit() {
  File& f = *file_;
  if (f.buffer.empty()) return;
  const QuietErrors quiet;

  const std::size_t m = f.buffer.size();
  const std::size_t d = f.inputs;
  // The design points and drawn values of the samples the file keeps them for, which come
  // first in sample order (SampleTable::Write reads no more).
  const auto& rows = f.buffer.rows();
  const auto kept = static_cast<std::size_t>(
      std::lower_bound(rows.begin(), rows.end(), RowKey{0, f.inputs_stored_below},
                       [](const auto& row, const RowKey& key) { return row.first < key; }) -
      rows.begin());
  std::vector<double> u(kept * d);
  std::vector<float> values(kept * d);
  std::vector<std::int32_t> redraws(m);
  std::vector<std::uint32_t> checksums(m);
  std::vector<std::int32_t> steps(m);
  // Schema 5 keeps the messages of failed samples only, in /failures; schema 4 one a sample.
  const bool slim = f.schema >= kFirstSchemaWithSlimRows;
  std::vector<char> messages(slim ? 0 : m * kMessageBytes, '\0');
  std::vector<std::int64_t> failed;
  std::vector<char> failure_messages;
  std::vector<double> solve_times(m);
  std::vector<std::int8_t> rungs(m);
  std::vector<double> error_bounds(m);
  const std::size_t z = f.identity.rollers.size();
  std::vector<float> off_bore(m * z, std::numeric_limits<float>::quiet_NaN());
  std::vector<std::vector<double>> outputs(kOutputCount, std::vector<double>(m));
  std::vector<std::int8_t> statuses(m);
  std::size_t i = 0;
  for (const auto& [key, record] : f.buffer.rows()) {
    if (i < kept) {
      std::copy(record.u.begin(), record.u.end(), u.begin() + static_cast<std::ptrdiff_t>(i * d));
      // Rounded here rather than by HDF5, whose conversion may clip instead of round.
      for (std::size_t j = 0; j < d; ++j) values[i * d + j] = static_cast<float>(record.values[j]);
    }
    redraws[i] = record.redraws;
    checksums[i] = record.draw_checksum ? *record.draw_checksum : DrawChecksum(record);
    steps[i] = record.steps;
    if (!slim) {
      TruncateUtf8(record.message, kMessageChars).copy(messages.data() + i * kMessageBytes, kMessageChars);
    } else if (record.status != SampleStatus::kOk) {
      failed.push_back(record.index);
      failure_messages.resize(failure_messages.size() + kMessageBytes, '\0');
      TruncateUtf8(record.message, kMessageChars)
          .copy(failure_messages.data() + failure_messages.size() - kMessageBytes, kMessageChars);
    }
    solve_times[i] = record.solve_time;
    const bool ok = record.status == SampleStatus::kOk;
    rungs[i] = record.rung;
    error_bounds[i] = ok ? record.d_trajectory_error : std::numeric_limits<double>::quiet_NaN();
    if (ok) {
      std::transform(record.off_bore.begin(), record.off_bore.end(), off_bore.begin() + static_cast<std::ptrdiff_t>(i * z),
                     [](double percent) { return static_cast<float>(percent); });
    }
    for (std::size_t k = 0; k < kOutputCount; ++k) {
      outputs[k][i] = ok ? record.outputs[k] : std::numeric_limits<double>::quiet_NaN();
    }
    statuses[i] = static_cast<std::int8_t>(record.status);
    ++i;
  }
  std::array<const void*, kColumnCount> columns{};
  columns[kU] = u.data();
  columns[kValues] = values.data();
  columns[kRedraws] = redraws.data();
  columns[kDrawChecksum] = checksums.data();
  columns[kSteps] = steps.data();
  columns[kMessage] = messages.data();
  columns[kSolveTime] = solve_times.data();
  columns[kRung] = rungs.data();
  columns[kErrorBound] = error_bounds.data();
  columns[kOffBore] = off_bore.data();
  for (std::size_t k = 0; k < kOutputCount; ++k) columns[kFirstOutput + k] = outputs[k].data();
  columns[kStatus] = statuses.data();
  // Before the statuses (Write's last column): a status on disk vouches for its message.
  if (slim) AppendFailures(f.where, f.failure_samples, f.failure_messages, failed, failure_messages);
  f.table.Write(f.buffer.Keys(), columns);
  f.buffer.clear();
}

std::int64_t CampaignStore::chunk_rows() const { return file_->chunk_rows; }

std::int64_t CampaignStore::inputs_stored_below() const { return file_->inputs_stored_below; }

int CampaignStore::schema() const { return file_->schema; }

CampaignStore::Absorbed CampaignStore::Absorb(const fs::path& shard_path) {
  const QuietErrors quiet;
  Commit();
  File& f = *file_;
  const Where opening{shard_path.string(), true};
  const FileId shard = OpenForReading(shard_path);
  const Stored stored = ReadStored(opening, shard.get());
  Stored expected;
  expected.identity = f.identity;
  expected.samples = f.samples;
  expected.schema_version = f.schema;
  expected.inputs_stored_below = f.inputs_stored_below;
  CheckShardStored(f.where, opening, stored, expected);
  SampleTable from = OpenColumns(opening, shard.get(), stored);
  from.set_where(Where{opening.file, false});
  // A shard whose failure rows are damaged is copied row by row: its failed samples that
  // lost their message stay pending here and are computed again.
  std::optional<FailureRows> failures;
  if (f.schema >= kFirstSchemaWithSlimRows) failures = ReadFailureRows(opening, shard.get());
  SampleTable::AbsorbPlan plan = f.table.PlanAbsorb(from, !failures || !failures->damaged());
  if (failures) {
    // The messages of the failed samples copied, appended before their statuses.
    std::vector<std::int64_t> failed;
    std::vector<char> messages;
    std::vector<RowKey> lost;
    for (const RowKey& key : plan.failed) {
      std::optional<std::string> text;
      if (const std::optional<std::size_t> row = failures->Find(key.sample)) {
        try {
          text = ReadFailureMessage(opening, shard.get(), *row);
        } catch (const InputError&) {
          text.reset();
        }
      }
      if (!text) {
        lost.push_back(key);
        continue;
      }
      failed.push_back(key.sample);
      messages.resize(messages.size() + kMessageBytes, '\0');
      text->copy(messages.data() + messages.size() - kMessageBytes, kMessageChars);
    }
    std::erase_if(plan.rows, [&](const RowKey& key) { return std::binary_search(lost.begin(), lost.end(), key); });
    AppendFailures(f.where, f.failure_samples, f.failure_messages, failed, messages);
  }
  const SampleTable::Absorbed copied = f.table.Absorb(from, plan);
  return {copied.samples, copied.chunk_samples, copied.bytes};
}

std::vector<UnreadableShard> SetAsideUnreadableShards(const fs::path& results) {
  return SetAsideUnreadableShards(results, [](const fs::path& shard) {
    const Where opening{shard.string(), true};
    const FileId file = OpenForReading(shard);
    const Stored stored = ReadStored(opening, file.get());
    // Its columns open and their chunk indexes read (SampleTable::written_end); damaged
    // chunks are Resume's to repair.
    if (!stored.index) OpenColumns(opening, file.get(), stored);
  });
}

// ---------------------------------------------------------------------------------------
// Shard indexes

namespace {


// /failures/sample and /failures/message as every shard's rows, one shard after another.
void CreateFailureViews(const Where& where, hid_t file, const std::vector<std::string>& shards,
                        const std::vector<hsize_t>& rows) {
  const PlistId gcpl = ObjectCreation(where, H5P_GROUP_CREATE);
  GroupId(Check(H5Gcreate2(file, "failures", H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), where, "creating group",
                "failures"));
  hsize_t total = 0;
  for (const hsize_t n : rows) total += n;
  const TypeId message = FixedString(where, kMessageBytes);
  for (const auto& [path, type] : {std::pair<const char*, hid_t>{kFailureSamples, H5T_STD_I64LE},
                                   std::pair<const char*, hid_t>{kFailureMessages, message.get()}}) {
    const SpaceId view(Check(H5Screate_simple(1, &total, nullptr), where, "creating the dataspace of", path));
    const PlistId dcpl = ObjectCreation(where, H5P_DATASET_CREATE);
    CheckStatus(H5Pset_layout(dcpl.get(), H5D_VIRTUAL), where, "configuring", path);
    if (type == H5T_STD_I64LE) {
      CheckStatus(H5Pset_fill_value(dcpl.get(), H5T_NATIVE_INT64, &kNoFailureSample), where,
                  "setting the fill value of", path);
    }
    hsize_t first = 0;
    for (std::size_t s = 0; s < shards.size(); ++s) {
      if (rows[s] == 0) continue;
      const SpaceId from(Check(H5Screate_simple(1, &rows[s], nullptr), where, "creating the dataspace of", path));
      CheckStatus(H5Sselect_hyperslab(view.get(), H5S_SELECT_SET, &first, nullptr, &rows[s], nullptr), where,
                  "selecting rows of", path);
      CheckStatus(H5Pset_virtual(dcpl.get(), view.get(), shards[s].c_str(), path, from.get()), where,
                  "mapping " + shards[s] + " into", path);
      first += rows[s];
    }
    CheckStatus(H5Sselect_all(view.get()), where, "selecting", path);
    DatasetId(Check(H5Dcreate2(file, path, type, view.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT), where,
                    "creating dataset", path));
  }
}

// A shard an index lists (it exists: ListedShardFiles): InputError as CheckShardStored, or
// naming the shard and the resume that recovers its samples when it cannot be read.
void CheckShard(const Where& index, const fs::path& shard, const Stored& expected) {
  const Where opening{shard.string(), true};
  const auto readable = [&](const auto& read) {
    try {
      return read();
    } catch (const InputError& error) {
      throw InputError(
          UnreadableShardMessage(index.file, shard, error.what(), "campaign", expected.identity.campaign_path));
    }
  };
  const FileId file = readable([&] { return OpenForReading(shard); });
  const Stored stored = readable([&] { return ReadStored(opening, file.get()); });
  CheckShardStored(index, opening, stored, expected);
  readable([&] { return OpenColumns(opening, file.get(), stored); });
}

// The shards of an index, each checked.
std::vector<fs::path> ListedShards(const Where& where, hid_t file, const fs::path& index, const Stored& stored) {
  std::vector<fs::path> shards = ListedShardFiles(where, file, index);
  for (const fs::path& shard : shards) CheckShard(where, shard, stored);
  return shards;
}

// CRC-32 of everything an index shows of its shards: equal digests, equal indexes.
std::uint32_t IndexDigest(std::int64_t samples, std::int64_t chunk_rows, std::int64_t stored_below,
                          const std::vector<VirtualSource>& sources, const std::vector<hsize_t>& failure_rows) {
  std::vector<std::int64_t> numbers = {samples, chunk_rows, stored_below};
  std::string names;
  for (std::size_t s = 0; s < sources.size(); ++s) {
    names += sources[s].file + '\n';
    numbers.insert(numbers.end(), {sources[s].samples, static_cast<std::int64_t>(failure_rows[s]),
                                   static_cast<std::int64_t>(sources[s].rows.size())});
    for (const SampleRange& range : sources[s].rows) numbers.insert(numbers.end(), {range.begin, range.end});
  }
  uLong crc = crc32(0L, Z_NULL, 0);
  crc = crc32(crc, reinterpret_cast<const Bytef*>(names.data()), static_cast<uInt>(names.size()));
  crc = crc32(crc, reinterpret_cast<const Bytef*>(numbers.data()), static_cast<uInt>(numbers.size() * sizeof(std::int64_t)));
  return static_cast<std::uint32_t>(crc);
}

}  // namespace

ShardContents ReadShardContents(const fs::path& shard, const CampaignIdentity& identity, std::int64_t samples) {
  const QuietErrors quiet;
  Stored expected;
  expected.identity = identity;
  expected.samples = samples;
  const Where opening{shard.string(), true};
  const FileId file = OpenForReading(shard);
  const Stored stored = ReadStored(opening, file.get());
  expected.schema_version = std::max(stored.schema_version, kFirstSchemaWithShards);
  expected.inputs_stored_below = stored.inputs_stored_below;
  CheckShardStored(opening, opening, stored, expected);
  const SampleTable table = OpenColumns(opening, file.get(), stored);
  const DatasetId failures(Check(H5Dopen2(file.get(), kFailureSamples, H5P_DEFAULT), opening, "opening dataset",
                                 kFailureSamples));
  return {shard,
          stored.samples,
          table.space().chunk_samples,
          stored.inputs_stored_below,
          static_cast<std::int64_t>(FailureRowCount(opening, failures.get())),
          table.Finished(),
          stored.schema_version};
}

ShardIndexSummary WriteShardIndex(const fs::path& results, const CampaignIdentity& identity, std::int64_t samples,
                                  const std::vector<fs::path>& shards) {
  std::vector<ShardContents> contents;
  for (const fs::path& shard : shards) contents.push_back(ReadShardContents(shard, identity, samples));
  return WriteShardIndex(results, identity, samples, contents);
}

ShardIndexSummary WriteShardIndex(const fs::path& results, const CampaignIdentity& identity, std::int64_t samples,
                                  const std::vector<ShardContents>& shards) {
  const QuietErrors quiet;
  const std::string name = results.string();
  if (shards.empty()) throw std::invalid_argument("WriteShardIndex: no shards");
  std::vector<fs::path> paths;
  for (const ShardContents& shard : shards) paths.push_back(shard.path);
  CheckIndexTarget(results, paths, "WriteShardIndex");
  std::error_code error;
  std::optional<std::uint32_t> written_digest;
  if (fs::exists(results, error)) {
    written_digest = ReadNumberAttribute<std::uint32_t>(Where{name, true}, OpenForReading(results).get(),
                                                        "shard_digest", H5T_INTEGER, H5T_NATIVE_UINT32);
  }
  const std::int64_t chunk_rows = shards.front().chunk_rows;
  const std::int64_t stored_below = shards.front().inputs_stored_below;
  const int schema = shards.front().schema;
  ShardIndexSummary summary;
  summary.shards = static_cast<std::int64_t>(shards.size());
  std::vector<VirtualSource> sources;
  std::vector<std::string> names;
  std::vector<hsize_t> failure_rows;
  std::vector<SampleRange> owned;  // by the shards before: the first listed wins
  for (const ShardContents& shard : shards) {
    if (shard.samples > samples || shard.chunk_rows != chunk_rows || shard.inputs_stored_below != stored_below ||
        shard.schema != schema) {
      throw std::invalid_argument("WriteShardIndex: shard " + shard.path.string() + " is not a shard of " + name);
    }
    VirtualSource source{shard.path.filename().string(), shard.samples, Without(shard.finished, owned), {}};
    for (const SampleRange& range : source.rows) summary.samples += range.end - range.begin;
    summary.most_mappings = std::max(summary.most_mappings, static_cast<std::int64_t>(RegularRuns(source.rows).size()));
    owned.insert(owned.end(), source.rows.begin(), source.rows.end());
    owned = MergeRanges(std::move(owned));
    names.push_back(source.file);
    failure_rows.push_back(static_cast<hsize_t>(shard.failure_rows));
    sources.push_back(std::move(source));
  }
  // An index that already shows these shards as they are stays as it is, so that a resume
  // with nothing to compute changes no byte (HDF5 does not lay out a new file the same way
  // every time).
  const std::uint32_t digest = IndexDigest(samples, chunk_rows, stored_below, sources, failure_rows);
  if (written_digest == digest) return summary;

  const Where where{name, false};
  ReplaceIndex(where, results, names, [&](hid_t file) {
    CampaignStoreOptions options;
    options.inputs_stored_below = stored_below;
    options.schema = schema;
    WriteIdentity(where, file, identity, samples, options, Layout::kShardIndex);
    WriteAttribute(where, file, "shard_chunk_rows", H5T_STD_I64LE, H5T_NATIVE_INT64, &chunk_rows);
    WriteAttribute(where, file, "shard_digest", H5T_STD_U32LE, H5T_NATIVE_UINT32, &digest);
    summary.mappings = SampleTable::CreateVirtual(
        where, file, Rows(samples, chunk_rows), Columns(schema, identity, 0, stored_below),
        sources);
    CreateFailureViews(where, file, names, failure_rows);
    WriteColumnAttributes(where, file, identity);
  });
  return summary;
}

ShardContents CampaignStore::Contents() {
  Commit();
  const QuietErrors quiet;
  File& f = *file_;
  const auto failures =
      f.failure_samples.get() >= 0 ? static_cast<std::int64_t>(FailureRowCount(f.where, f.failure_samples.get())) : 0;
  return {f.path, f.samples, f.chunk_rows, f.inputs_stored_below, failures, f.table.Finished(), f.schema};
}

std::vector<fs::path> IndexedShards(const fs::path& results) {
  const QuietErrors quiet;
  const Where where{results.string(), true};
  const FileId file = OpenForReading(results);
  const Stored stored = ReadStored(where, file.get());
  if (!stored.index) return {};
  return ListedShards(where, file.get(), results, stored);
}

ShardPlan PlanCampaignShards(const fs::path& results, const CampaignIdentity& identity, std::int64_t samples,
                             int ranks, bool resume) {
  return PlanShards(results, ranks, resume, [&](const fs::path& file) {
    if (const int schema = CampaignReader(file).schema_version(); schema < kFirstSchemaWithShards) {
      throw InputError(fmt::format("{}: was written by an older ringtol (schema {}), which keeps it in one file: "
                                   "resume it without mpirun",
                                   file.string(), schema));
    }
    const CampaignStore plain = CampaignStore::Resume(file, identity, samples);
  });
}

CampaignStore OpenCampaignShard(const fs::path& results, int rank, const CampaignIdentity& identity,
                                std::int64_t samples, CampaignStoreOptions options) {
  const fs::path own = ShardPath(results, rank);
  if (fs::exists(own)) return CampaignStore::Resume(own, identity, samples);
  if (rank == 0) {
    if (const std::vector<fs::path> shards = FindShards(results); !shards.empty()) {
      const ShardContents other = ReadShardContents(shards.front(), identity, samples);
      options.chunk_samples = other.chunk_rows;
      options.inputs_stored_below = other.inputs_stored_below;
      options.schema = other.schema;
    }
  }
  return CampaignStore::Create(own, identity, samples, options);
}

std::vector<ShardContents> RepairStaleShards(const std::vector<fs::path>& stale, const CampaignIdentity& identity,
                                             std::int64_t samples) {
  std::vector<ShardContents> contents;
  for (const fs::path& shard : stale) {
    { const CampaignStore repaired = CampaignStore::Resume(shard, identity, samples); }
    contents.push_back(ReadShardContents(shard, identity, samples));
  }
  return contents;
}

CampaignStore::Absorbed JoinShards(const fs::path& results, const fs::path& out) {
  std::vector<fs::path> shards;
  Stored stored;
  {
    const QuietErrors quiet;
    const Where where{results.string(), true};
    const FileId file = OpenForReading(results);
    stored = ReadStored(where, file.get());
    if (!stored.index) throw InputError(results.string() + ": keeps its samples itself: there are no shards to join");
    shards = ListedShards(where, file.get(), results, stored);
    // Whole chunks are copied as stored: a damaged one would be carried into the joined
    // file, and the shards that could repair it removed.
    if (const ResultsCheck check = CheckResults(results); !check.intact()) {
      throw InputError(fmt::format(
          "{}: cannot be joined: {}; the index and its shards are left as they are: `ringtol campaign {} --out {} "
          "--resume` computes those samples again, then join",
          results.string(), DamagedDatasets(check), stored.identity.campaign_path, results.string()));
    }
  }
  const auto [target, in_place] = PrepareJoin(results, out);
  std::error_code error;
  CampaignStoreOptions options;
  options.chunk_samples = stored.chunk_rows;
  options.inputs_stored_below = stored.inputs_stored_below;
  options.schema = stored.schema_version;
  CampaignStore::Absorbed joined;
  {
    CampaignStore store = CampaignStore::Create(target, stored.identity, stored.samples, options);
    for (const fs::path& shard : shards) {
      const CampaignStore::Absorbed one = store.Absorb(shard);
      joined.samples += one.samples;
      joined.chunk_samples += one.chunk_samples;
      joined.bytes += one.bytes;
    }
  }
  if (in_place) {
    fs::rename(target, results, error);
    if (error) throw std::runtime_error(results.string() + ": cannot replace the index: " + error.message());
    for (const fs::path& shard : shards) fs::remove(shard, error);
  }
  return joined;
}

// ---------------------------------------------------------------------------------------

struct CampaignReader::File {
  Where where;
  FileId file;
  SampleTable table;
  Stored stored;
  // Built on first need: the failure rows (schema 5) and the campaign that replays the
  // draws a file does not keep.
  mutable std::optional<FailureRows> failures;
  mutable std::unique_ptr<Campaign> campaign;
  mutable std::unique_ptr<SampleDrawer> drawer;

  void Open(const fs::path& path);

  std::string Message(std::int64_t index, SampleStatus status) const {
    if (stored.schema_version < kFirstSchemaWithSlimRows) {
      std::vector<char> message = table.Read<char>(kMessage, 0, index, 1);
      message.push_back('\0');
      return message.data();
    }
    if (status == SampleStatus::kOk || status == SampleStatus::kPending) return {};
    if (!failures) failures = ReadFailureRows(where, file.get());
    const std::optional<std::size_t> row = failures->Find(index);
    if (!row && failures->damaged()) {
      throw InputError(fmt::format("{}: the message of sample {} was in a damaged chunk ({}){}", where.file, index,
                                   failures->problem,
                                   fmt::format("; `ringtol verify {}` lists every damaged dataset", where.file)));
    }
    return row ? ReadFailureMessage(where, file.get(), *row) : std::string();
  }

  // Sample `index`'s draw replayed (it is beyond inputs_stored_below), checked against the
  // checksum the file keeps of it.
  SampleRecord Replay(std::int64_t index) const {
    if (!drawer) {
      campaign = std::make_unique<Campaign>(stored.identity, stored.samples);
      drawer = std::make_unique<SampleDrawer>(*campaign);
    }
    SampleRecord drawn = drawer->Draw(index);
    for (double& value : drawn.values) value = static_cast<float>(value);  // as a stored value reads
    const std::uint32_t kept = table.Read<std::uint32_t>(kDrawChecksum, 0, index, 1).front();
    if (const std::uint32_t now = DrawChecksum(drawn); now != kept) {
      throw InputError(fmt::format(
          "{}: keeps no inputs for sample {}, and this ringtol draws them differently from the ringtol {} that wrote "
          "it (draw checksum {:08x} now, {:08x} in the file): read it with that version",
          where.file, index, stored.identity.ringtol_version, now, kept));
    }
    return drawn;
  }

  bool Replayed(std::int64_t index, SampleStatus status) const {
    return index >= stored.inputs_stored_below && status != SampleStatus::kPending;
  }

  void CheckRows(std::string_view what, std::int64_t begin, std::int64_t count) const {
    if (count < 0) throw std::out_of_range(fmt::format("{}: count {} is negative", what, count));
    CheckRange(what, begin, begin + count, stored.samples);
  }

  // Rows [begin, begin + count) of one column, checked and read quietly.
  template <typename T>
  std::vector<T> Rows(std::string_view what, std::size_t column, std::int64_t begin, std::int64_t count) const {
    const QuietErrors quiet;
    CheckRows(what, begin, count);
    return table.Read<T>(column, 0, begin, count);
  }
};

CampaignReader::CampaignReader(const fs::path& path) : file_(std::make_unique<File>()) {
  const QuietErrors quiet;
  try {
    file_->Open(path);
  } catch (...) {
    file_.reset();  // while HDF5 is quiet
    throw;
  }
}

void CampaignReader::File::Open(const fs::path& path) {
  where = Where{path.string(), true};
  file = OpenForReading(path);
  stored = ReadStored(where, file.get());
  // HDF5 reads the rows of a shard that is missing as fill, silently: refuse instead.
  if (stored.index) ListedShards(where, file.get(), path, stored);
  table = OpenColumns(where, file.get(), stored);
  where.input = false;  // open and valid: later failures are the system's
  table.set_where(where);
}

CampaignReader::~CampaignReader() {
  if (!file_) return;
  const QuietErrors quiet;
  file_.reset();
}

CampaignReader::CampaignReader(CampaignReader&&) noexcept = default;

const CampaignIdentity& CampaignReader::identity() const { return file_->stored.identity; }

std::int64_t CampaignReader::samples() const { return file_->stored.samples; }

int CampaignReader::schema_version() const { return file_->stored.schema_version; }

std::int64_t CampaignReader::written_end() const { return file_->table.written_end(); }

std::vector<SampleStatus> CampaignReader::ReadStatus(std::int64_t begin, std::int64_t count) const {
  const QuietErrors quiet;
  file_->CheckRows("CampaignReader::ReadStatus", begin, count);
  return file_->table.Statuses(0, begin, count);
}

std::vector<SampleRange> CampaignReader::Finished() const {
  const QuietErrors quiet;
  return file_->table.Finished();
}

bool CampaignReader::HasOutput(std::string_view name) const {
  const auto* found = std::find(kOutputNames.begin(), kOutputNames.end(), name);
  if (found == kOutputNames.end()) return false;
  return file_->table.stored(kFirstOutput + static_cast<std::size_t>(found - kOutputNames.begin()));
}

std::vector<double> CampaignReader::ReadOutput(std::string_view name, std::int64_t begin, std::int64_t count) const {
  const auto* found = std::find(kOutputNames.begin(), kOutputNames.end(), name);
  if (found == kOutputNames.end()) {
    throw std::invalid_argument(fmt::format("CampaignReader::ReadOutput: unknown output '{}'; outputs: {}", name,
                                            fmt::join(kOutputNames, ", ")));
  }
  const std::size_t column = kFirstOutput + static_cast<std::size_t>(found - kOutputNames.begin());
  return file_->Rows<double>("CampaignReader::ReadOutput", column, begin, count);
}

std::vector<double> CampaignReader::ReadValues(std::int64_t begin, std::int64_t count) const {
  const File& f = *file_;
  const std::vector<float> stored = f.Rows<float>("CampaignReader::ReadValues", kValues, begin, count);
  std::vector<double> values(stored.begin(), stored.end());
  const std::int64_t replayed_from = std::max(begin, f.stored.inputs_stored_below);
  if (replayed_from >= begin + count) return values;
  const QuietErrors quiet;
  const std::size_t d = f.stored.identity.inputs.size();
  const std::vector<SampleStatus> statuses = f.table.Statuses(0, replayed_from, begin + count - replayed_from);
  for (std::int64_t index = replayed_from; index < begin + count; ++index) {
    if (!f.Replayed(index, statuses[static_cast<std::size_t>(index - replayed_from)])) continue;
    const SampleRecord drawn = f.Replay(index);
    std::copy(drawn.values.begin(), drawn.values.end(),
              values.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(index - begin) * d));
  }
  return values;
}

std::vector<std::int32_t> CampaignReader::ReadRedraws(std::int64_t begin, std::int64_t count) const {
  return file_->Rows<std::int32_t>("CampaignReader::ReadRedraws", kRedraws, begin, count);
}

std::vector<std::int8_t> CampaignReader::ReadRungs(std::int64_t begin, std::int64_t count) const {
  return file_->Rows<std::int8_t>("CampaignReader::ReadRungs", kRung, begin, count);
}

bool CampaignReader::HasOffBore() const { return file_->table.stored(kOffBore); }

std::vector<float> CampaignReader::ReadOffBore(std::int64_t begin, std::int64_t count) const {
  if (!HasOffBore()) return {};
  return file_->Rows<float>("CampaignReader::ReadOffBore", kOffBore, begin, count);
}

SampleRecord CampaignReader::ReadSample(std::int64_t index) const {
  const QuietErrors quiet;
  file_->CheckRows("CampaignReader::ReadSample", index, 1);
  const File& f = *file_;
  const SampleTable& table = f.table;
  SampleRecord record;
  record.index = index;
  record.status = table.Statuses(0, index, 1).front();
  const SampleStatus* status = &record.status;
  if (f.Replayed(index, record.status)) {
    const SampleRecord drawn = f.Replay(index);
    record.u = drawn.u;
    record.values = drawn.values;
  } else {
    record.u = table.Read<double>(kU, 0, index, 1, status);
    const std::vector<float> values = table.Read<float>(kValues, 0, index, 1, status);
    record.values.assign(values.begin(), values.end());
  }
  record.redraws = table.Read<std::int32_t>(kRedraws, 0, index, 1).front();
  record.steps = table.Read<std::int32_t>(kSteps, 0, index, 1).front();
  record.message = f.Message(index, record.status);
  record.solve_time = table.Read<double>(kSolveTime, 0, index, 1).front();
  record.rung = table.Read<std::int8_t>(kRung, 0, index, 1).front();
  record.d_trajectory_error = table.Read<double>(kErrorBound, 0, index, 1).front();
  if (table.stored(kOffBore) && record.status == SampleStatus::kOk) {
    const std::vector<float> off_bore = table.Read<float>(kOffBore, 0, index, 1, status);
    record.off_bore.assign(off_bore.begin(), off_bore.end());
  }
  for (std::size_t k = 0; k < kOutputCount; ++k) {
    record.outputs[k] = table.Read<double>(kFirstOutput + k, 0, index, 1, status).front();
  }
  return record;
}

// ---------------------------------------------------------------------------------------

namespace {

// An index's check: the sum of its shards' (SumOfShards).
ResultsCheck CheckIndex(const Where& where, hid_t file, const fs::path& path, const Stored& stored) {
  ResultsCheck index;
  index.samples = stored.samples;
  std::vector<ShardCheck> shards;
  for (const fs::path& shard : ListedShards(where, file, path, stored)) {
    shards.push_back({shard.filename().string(), CheckResults(shard)});
  }
  return SumOfShards(std::move(index), shards);
}

}  // namespace

ResultsCheck CheckResults(const fs::path& path) {
  const QuietErrors quiet;
  const Where where{path.string(), true};
  const FileId file = OpenForReading(path);
  const Stored stored = ReadStored(where, file.get());
  if (stored.index) return CheckIndex(where, file.get(), path, stored);
  const SampleTable table = OpenColumns(where, file.get(), stored);
  return Check(where, file.get(), table, table.Scan());
}

std::string DamageMessage(const fs::path& path, const ResultsCheck& check) {
  return fmt::format(
      "{}: {}; `ringtol campaign CAMPAIGN --out {} --resume` computes those samples again, `ringtol verify {}` "
      "lists what is intact",
      path.string(), DamagedDatasets(check), path.string(), path.string());
}

}  // namespace ringtol::jobs
