#include "jobs/store/campaign_store.h"

#include <hdf5.h>

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

namespace ringtol::jobs {

using namespace hdf5;  // NOLINT(google-build-using-namespace): the store's own HDF5 helpers

namespace {

namespace fs = std::filesystem;

constexpr const char* kFormat = "ringtol campaign";
constexpr const char* kAllocationFormat = "ringtol allocation";
constexpr std::size_t kMessageBytes = 256;
constexpr std::size_t kMessageChars = kMessageBytes - 1;  // and the terminator
// Default chunk of /inputs/u: large enough that deflate works well, small enough that the
// chunks being filled between commits fit the chunk cache many times over.
constexpr std::size_t kDefaultChunkBytes = 256u << 10;
// HDF5's advice: about 100 hash slots per chunk that fits in the cache, a prime number;
// capped, since HDF5 allocates and scans every slot (small chunks would ask for millions).
constexpr std::size_t kSlotsPerCachedChunk = 100;
constexpr std::size_t kMaxSlots = 1u << 17;
// Pending() reads statuses in blocks of this many samples to bound its memory.
constexpr hsize_t kStatusBlock = 1u << 20;
// ---------------------------------------------------------------------------------------
// The per-sample datasets ("columns"), statuses last: Commit writes them in this order.

enum Column : std::size_t {
  kU,
  kValues,
  kRedraws,
  kSteps,
  kMessage,
  kSolveTime,
  kRung,
  kErrorBound,
  kFirstOutput,
  kStatus = kFirstOutput + kOutputCount,
  kColumnCount
};

using Columns = std::array<DatasetId, kColumnCount>;

std::string ColumnPath(std::size_t column) {
  switch (column) {
    case kU:
      return "/inputs/u";
    case kValues:
      return "/inputs/values";
    case kRedraws:
      return "/inputs/redraws";
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
    case kStatus:
      return "/outputs/status";
    default:
      return std::string("/outputs/") + kOutputNames[column - kFirstOutput];
  }
}

bool IsMatrix(std::size_t column) { return column == kU || column == kValues; }

constexpr const char* kRunoutDefinition =
    "total indicator reading: max - min of the sensor signal over one revolution";
constexpr const char* kSwingDefinition =
    "largest rise or fall of the sensor signal, each net of the largest counter-move inside it beyond "
    "resolution_um, after a Gaussian filter at cutoff_upr undulations per revolution when cutoff_upr > 0";

// Where a file of `schema` keeps column `column`; empty when it has no such dataset. Schema
// 1 named the ill-posed "peak to nearest valley" runout_mm and the max - min that runout_mm
// is now runout_total_mm; it had no swing. Schemas 1 and 2 had no rung and error bound,
// schemas 1 to 3 no life outputs.
constexpr int kFirstSchemaWithRungs = 3;
constexpr int kFirstSchemaWithLife = 4;
std::string StoredColumnPath(std::size_t column, int schema) {
  if ((column == kRung || column == kErrorBound) && schema < kFirstSchemaWithRungs) return {};
  if (column >= kFirstOutput + kFirstLifeOutput && column < kStatus && schema < kFirstSchemaWithLife) return {};
  if (schema >= 2 || column < kFirstOutput || column >= kStatus) return ColumnPath(column);
  const std::string_view output = kOutputNames[column - kFirstOutput];
  if (output == "runout_mm") return "/outputs/runout_total_mm";
  constexpr std::array<std::string_view, 5> kSchema1Outputs = {
      "d_trajectory_mm", "dist_init_mm", "static_offset_mm", "min_contact_force_N", "max_contact_force_N"};
  if (std::find(kSchema1Outputs.begin(), kSchema1Outputs.end(), output) != kSchema1Outputs.end()) {
    return ColumnPath(column);
  }
  return {};
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

// What Resume and CampaignReader find in a file before trusting it.
struct Stored {
  CampaignIdentity identity;
  std::int64_t samples = 0;
  int schema_version = 0;
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
  if (schema > kCampaignSchemaVersion) {
    throw InputError(fmt::format("{}: was written by a newer ringtol (schema {}); this ringtol reads schema {}",
                                 where.file, schema, kCampaignSchemaVersion));
  }
  if (schema < kOldestReadableSchema) {
    throw InputError(fmt::format("{}: has unknown schema version {}; this ringtol reads schemas {} to {}", where.file,
                                 schema, kOldestReadableSchema, kCampaignSchemaVersion));
  }
  stored.schema_version = static_cast<int>(schema);

  CampaignIdentity& identity = stored.identity;
  const auto text = [&](const char* name) { return Require(where, ReadStringAttribute(where, file, name), name); };
  identity.ringtol_version = text("ringtol_version");
  identity.catalogue_version = text("catalogue_version");
  identity.campaign_path = text("campaign_path");
  identity.campaign_file = text("campaign_file");
  identity.base_scene = text("base_scene");
  identity.design = text("design");
  identity.solver = text("solver");
  identity.seed =
      Require(where, ReadNumberAttribute<std::uint64_t>(where, file, "seed", H5T_INTEGER, H5T_NATIVE_UINT64), "seed");
  stored.samples = Require(
      where, ReadNumberAttribute<std::int64_t>(where, file, "samples", H5T_INTEGER, H5T_NATIVE_INT64), "samples");
  if (stored.samples < 1) Fail(where, fmt::format("attribute samples = {} is not positive", stored.samples));

  identity.inputs = ReadInputDescriptions(where, file);
  identity.calibrations = ReadCalibrations(where, file);

  for (std::size_t k = 0; k < kOutputCount; ++k) {
    const std::string path = StoredColumnPath(kFirstOutput + k, stored.schema_version);
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
  using Text = std::string CampaignIdentity::*;
  for (const auto& [field, member, multiline] :
       {std::tuple<const char*, Text, bool>{"ringtol_version", &CampaignIdentity::ringtol_version, false},
        {"catalogue_version", &CampaignIdentity::catalogue_version, false},
        {"campaign_file", &CampaignIdentity::campaign_file, true},
        {"base_scene", &CampaignIdentity::base_scene, true},
        {"design", &CampaignIdentity::design, false},
        {"solver", &CampaignIdentity::solver, false}}) {
    if (auto d = multiline ? TextDifference(field, file.*member, now.*member)
                           : WordDifference(field, file.*member, now.*member)) {
      return d;
    }
  }
  if (file.seed != now.seed) return fmt::format("seed differs ({} in the file, {} now)", file.seed, now.seed);
  if (auto d = InputDifference(file.inputs, now.inputs, "this campaign")) return d;
  return SpecDifference(file.spec, now.spec);
}

// ---------------------------------------------------------------------------------------
// Opening

// Opens every per-sample dataset and checks its shape against the attributes.
// Outputs a file of an older schema lacks stay closed (ReadRows reads them as NaN).
Columns OpenColumns(const Where& where, hid_t file, std::int64_t samples, std::size_t inputs, int schema,
                    hid_t matrix_access) {
  Columns columns;
  for (std::size_t c = 0; c < kColumnCount; ++c) {
    const std::string path = StoredColumnPath(c, schema);
    if (path.empty()) continue;
    const hid_t access = IsMatrix(c) ? matrix_access : H5P_DEFAULT;
    columns[c] = DatasetId(H5Dopen2(file, path.c_str(), access));
    if (columns[c].get() < 0) Fail(where, "is not a complete ringtol campaign file: cannot open dataset " + path);
    const SpaceId space(Check(H5Dget_space(columns[c].get()), where, "reading the shape of", path));
    const int rank = IsMatrix(c) ? 2 : 1;
    hsize_t dims[2] = {0, 0};
    if (H5Sget_simple_extent_ndims(space.get()) != rank) {
      Fail(where, fmt::format("dataset {} has the wrong rank", path));
    }
    H5Sget_simple_extent_dims(space.get(), dims, nullptr);
    if (dims[0] < static_cast<hsize_t>(samples) || (rank == 2 && dims[1] != inputs)) {
      Fail(where, fmt::format("dataset {} has {} rows{} where the file declares {} samples and {} inputs", path,
                              dims[0], rank == 2 ? fmt::format(" of {}", dims[1]) : "", samples, inputs));
    }
  }
  const TypeId status(Check(H5Dget_type(columns[kStatus].get()), where, "reading the type of", ColumnPath(kStatus)));
  if (H5Tget_class(status.get()) != H5T_ENUM || H5Tget_size(status.get()) != 1) {
    Fail(where, "dataset /outputs/status is not a one-byte enumeration");
  }
  const TypeId message(Check(H5Dget_type(columns[kMessage].get()), where, "reading the type of", ColumnPath(kMessage)));
  if (H5Tget_class(message.get()) != H5T_STRING || H5Tis_variable_str(message.get()) != 0) {
    Fail(where, "dataset /outputs/message does not hold fixed-length strings");
  }
  return columns;
}

hsize_t ChunkRows(const Where& where, const DatasetId& dataset) {
  const PlistId dcpl(Check(H5Dget_create_plist(dataset.get()), where, "reading the layout of", ColumnPath(kU)));
  hsize_t chunk[2] = {0, 0};
  if (H5Pget_chunk(dcpl.get(), 2, chunk) != 2) Fail(where, "dataset /inputs/u is not chunked");
  return chunk[0];
}

std::size_t NextPrime(std::size_t n) {
  const auto prime = [](std::size_t k) {
    if (k < 2) return false;
    for (std::size_t f = 2; f * f <= k; ++f) {
      if (k % f == 0) return false;
    }
    return true;
  };
  while (!prime(n)) ++n;
  return n;
}

// Keeps the chunks being filled in memory between commits, so that a commit compresses a
// partly filled chunk again without first reading and decompressing it from the file.
PlistId MatrixAccess(const Where& where, std::size_t cache_bytes, std::int64_t samples, hsize_t chunk_rows,
                     std::size_t inputs) {
  PlistId dapl(Check(H5Pcreate(H5P_DATASET_ACCESS), where, "creating", "a dataset access property list"));
  const auto rows = static_cast<std::size_t>(std::max<hsize_t>(1, chunk_rows));
  const std::size_t chunk_bytes = rows * inputs * sizeof(double);
  const std::size_t chunks = (static_cast<std::size_t>(samples) + rows - 1) / rows;
  const std::size_t cached = std::clamp<std::size_t>(cache_bytes / chunk_bytes, 1, chunks);
  const std::size_t slots = NextPrime(std::min(kMaxSlots, kSlotsPerCachedChunk * cached));
  CheckStatus(H5Pset_chunk_cache(dapl.get(), slots, cache_bytes, H5D_CHUNK_CACHE_W0_DEFAULT), where, "configuring",
              "the chunk cache");
  return dapl;
}

// ---------------------------------------------------------------------------------------
// Creating

void CheckArguments(const CampaignIdentity& identity, std::int64_t samples, const CampaignStoreOptions& options) {
  if (samples < 1) throw std::invalid_argument(fmt::format("CampaignStore: samples = {} must be >= 1", samples));
  if (identity.inputs.empty()) {
    throw std::invalid_argument("CampaignStore: a campaign needs at least one sampled input");
  }
  if (options.deflate_level < 0 || options.deflate_level > 9) {
    throw std::invalid_argument(
        fmt::format("CampaignStore: deflate_level = {} is outside 0..9", options.deflate_level));
  }
  if (options.chunk_samples < 0) {
    throw std::invalid_argument(fmt::format("CampaignStore: chunk_samples = {} is negative", options.chunk_samples));
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

hsize_t DefaultChunkRows(const CampaignStoreOptions& options, std::int64_t samples, std::size_t inputs) {
  if (options.chunk_samples > 0) return static_cast<hsize_t>(options.chunk_samples);
  // Also bounded by /outputs/message (256 bytes a row): with few inputs its chunks would
  // outgrow HDF5's default 1 MiB chunk cache, and every read of one message would inflate
  // a whole chunk.
  const std::size_t row_bytes = std::max(inputs * sizeof(double), kMessageBytes);
  const std::size_t rows = std::max<std::size_t>(1, kDefaultChunkBytes / row_bytes);
  return std::min<hsize_t>(rows, static_cast<hsize_t>(samples));
}

constexpr int kSmallColumnDeflateLevel = 1;

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

// The rung column's memory type for its int8 numbers: the dataset's own enumeration where
// it has one (HDF5 converts no integer to an enumeration), none (-1) in files of schema 3,
// whose plain integers read as they are.
TypeId RungMemoryType(const Where& where, hid_t dataset) {
  const TypeId stored(Check(H5Dget_type(dataset), where, "reading the type of", ColumnPath(kRung)));
  if (H5Tget_class(stored.get()) != H5T_ENUM) return TypeId();
  return TypeId(Check(H5Tget_native_type(stored.get(), H5T_DIR_DEFAULT), where, "reading the type of",
                      ColumnPath(kRung)));
}

void CreateColumn(const Where& where, hid_t file, std::size_t column, hsize_t samples, hsize_t inputs,
                  hsize_t chunk_rows, int deflate_level, bool checksum, hid_t status_type, hid_t message_type) {
  const std::string path = ColumnPath(column);
  TypeId rung_type;  // the rung column's own type, alive until the dataset is created
  const int rank = IsMatrix(column) ? 2 : 1;
  const hsize_t dims[2] = {samples, inputs};
  const hsize_t max_dims[2] = {H5S_UNLIMITED, inputs};
  const hsize_t chunk[2] = {chunk_rows, inputs};
  const SpaceId space(Check(H5Screate_simple(rank, dims, max_dims), where, "creating the dataspace of", path));
  const PlistId dcpl = ObjectCreation(where, H5P_DATASET_CREATE);
  CheckStatus(H5Pset_chunk(dcpl.get(), rank, chunk), where, "chunking", path);
  // Counts, statuses and messages shrink a hundredfold and their chunks stay small, so
  // they are always deflated. The floating-point columns barely compress (design points
  // are random bits below the exponent) and, in SWMR mode, every rewrite of a compressed
  // chunk that grows leaves its old copy behind (HDF5 does not free it); stored
  // uncompressed they are rewritten in place.
  const bool small_column =
      column == kRedraws || column == kSteps || column == kRung || column == kMessage || column == kStatus;
  if (small_column) deflate_level = std::max(deflate_level, kSmallColumnDeflateLevel);
  if (deflate_level > 0) {
    CheckStatus(H5Pset_shuffle(dcpl.get()), where, "setting the shuffle filter of", path);
    CheckStatus(H5Pset_deflate(dcpl.get(), static_cast<unsigned>(deflate_level)), where, "setting deflate on", path);
  }
  // Same size for every chunk of an uncompressed column, so those are still rewritten in place.
  if (checksum) AddChecksum(where, dcpl, path);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const float nan_float = std::numeric_limits<float>::quiet_NaN();
  const std::int32_t zero = 0;
  const auto pending = static_cast<std::int8_t>(SampleStatus::kPending);
  const std::int8_t no_rung = kNoRung;
  hid_t file_type = H5T_IEEE_F64LE;
  herr_t filled = 0;
  switch (column) {
    case kU:
      filled = H5Pset_fill_value(dcpl.get(), H5T_NATIVE_DOUBLE, &nan);
      break;
    case kValues:
      file_type = H5T_IEEE_F32LE;
      filled = H5Pset_fill_value(dcpl.get(), H5T_NATIVE_FLOAT, &nan_float);
      break;
    case kRedraws:
    case kSteps:
      file_type = H5T_STD_I32LE;
      filled = H5Pset_fill_value(dcpl.get(), H5T_NATIVE_INT32, &zero);
      break;
    case kRung:
      rung_type = RungType(where);
      file_type = rung_type.get();
      filled = H5Pset_fill_value(dcpl.get(), rung_type.get(), &no_rung);
      break;
    case kMessage:
      file_type = message_type;  // the default fill, all zero bytes, is the empty string
      break;
    case kStatus:
      file_type = status_type;
      filled = H5Pset_fill_value(dcpl.get(), status_type, &pending);
      break;
    default:  // outputs, error bounds and solve times
      filled = H5Pset_fill_value(dcpl.get(), H5T_NATIVE_DOUBLE, &nan);
      break;
  }
  CheckStatus(filled, where, "setting the fill value of", path);
  const DatasetId dataset(
      Check(H5Dcreate2(file, path.c_str(), file_type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT), where,
            "creating dataset", path));
}

void WriteSchema(const Where& where, hid_t file, const CampaignIdentity& identity, std::int64_t samples,
                 const CampaignStoreOptions& options) {
  WriteStringAttribute(where, file, "format", kFormat);
  const std::int32_t schema = kCampaignSchemaVersion;
  WriteAttribute(where, file, "schema_version", H5T_STD_I32LE, H5T_NATIVE_INT32, &schema);
  WriteStringAttribute(where, file, "ringtol_version", identity.ringtol_version);
  WriteStringAttribute(where, file, "catalogue_version", identity.catalogue_version);
  WriteAttribute(where, file, "seed", H5T_STD_U64LE, H5T_NATIVE_UINT64, &identity.seed);
  WriteAttribute(where, file, "samples", H5T_STD_I64LE, H5T_NATIVE_INT64, &samples);
  WriteStringAttribute(where, file, "design", identity.design);
  WriteStringAttribute(where, file, "solver", identity.solver);
  WriteStringAttribute(where, file, "campaign_path", identity.campaign_path);
  WriteStringAttribute(where, file, "campaign_file", identity.campaign_file);
  WriteStringAttribute(where, file, "base_scene", identity.base_scene);

  const PlistId gcpl = ObjectCreation(where, H5P_GROUP_CREATE);
  for (const char* name : {"inputs", "outputs", "timing"}) {
    GroupId(Check(H5Gcreate2(file, name, H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), where, "creating group", name));
  }

  WriteInputDescriptions(where, file, identity.inputs, options.checksums);
  WriteCalibrations(where, file, identity.calibrations, gcpl);

  const TypeId status_type = StatusType(where);
  const TypeId message_type = FixedString(where, kMessageBytes);
  const hsize_t chunk_rows = DefaultChunkRows(options, samples, identity.inputs.size());
  for (std::size_t c = 0; c < kColumnCount; ++c) {
    CreateColumn(where, file, c, static_cast<hsize_t>(samples), identity.inputs.size(), chunk_rows,
                 options.deflate_level, options.checksums, status_type.get(), message_type.get());
  }
  for (const SpecLimit& limit : identity.spec) {
    const std::string path = "/outputs/" + limit.output;
    const DatasetId dataset(Check(H5Dopen2(file, path.c_str(), H5P_DEFAULT), where, "opening dataset", path));
    WriteAttribute(where, dataset.get(), "upper_spec_limit", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &limit.upper);
  }
  // What the two sensor columns mean and how the swing was read, for readers of the file
  // that do not parse base_scene.
  const DatasetId runout(Check(H5Dopen2(file, "/outputs/runout_mm", H5P_DEFAULT), where, "opening dataset",
                               "/outputs/runout_mm"));
  WriteStringAttribute(where, runout.get(), "definition", kRunoutDefinition);
  const DatasetId swing(Check(H5Dopen2(file, "/outputs/swing_mm", H5P_DEFAULT), where, "opening dataset",
                              "/outputs/swing_mm"));
  WriteStringAttribute(where, swing.get(), "definition", kSwingDefinition);
  const double resolution_um = identity.swing.resolution * units::kMicrometresPerMetre;
  WriteAttribute(where, swing.get(), "resolution_um", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &resolution_um);
  WriteAttribute(where, swing.get(), "cutoff_upr", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &identity.swing.cutoff_upr);
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

// A sample range of consecutive indices.
struct Run {
  hsize_t first = 0;
  hsize_t count = 0;
};

void WriteRows(const Where& where, const DatasetId& dataset, std::size_t column, hid_t memory_type,
               const std::vector<Run>& runs, hsize_t rows, hsize_t width, const void* data) {
  const std::string path = ColumnPath(column);
  const SpaceId file_space(Check(H5Dget_space(dataset.get()), where, "reading the shape of", path));
  bool first = true;
  for (const Run& run : runs) {
    const hsize_t start[2] = {run.first, 0};
    const hsize_t count[2] = {run.count, width};
    CheckStatus(
        H5Sselect_hyperslab(file_space.get(), first ? H5S_SELECT_SET : H5S_SELECT_OR, start, nullptr, count, nullptr),
        where, "selecting rows of", path);
    first = false;
  }
  const hsize_t memory_dims[2] = {rows, width};
  const SpaceId memory_space(
      Check(H5Screate_simple(IsMatrix(column) ? 2 : 1, memory_dims, nullptr), where, "creating a dataspace for", path));
  const TypeId rung = column == kRung ? RungMemoryType(where, dataset.get()) : TypeId();
  CheckStatus(H5Dwrite(dataset.get(), rung.get() >= 0 ? rung.get() : memory_type, memory_space.get(),
                       file_space.get(), H5P_DEFAULT, data),
              where, "writing", path);
  CheckStatus(H5Dflush(dataset.get()), where, "flushing", path);
}

std::string VerifyHint(const std::string& file) {
  return fmt::format("; `ringtol verify {}` lists every damaged dataset", file);
}

// Rows [first, first + rows) of one column; HDF5's reason when they do not read (a damaged
// chunk: checksum, decompression or I/O), after kRawReadAttempts.
std::optional<std::string> TryReadRows(const Where& where, const DatasetId& dataset, std::size_t column,
                                       hid_t memory_type, hsize_t first, hsize_t rows, hsize_t width, void* data) {
  if (rows == 0) return std::nullopt;
  // An output an older schema lacks stays closed and reads as NaN, its rung as kNoRung
  // (StoredColumnPath).
  if (dataset.get() < 0 && (column == kErrorBound || (column >= kFirstOutput && column < kStatus)) &&
      memory_type == H5T_NATIVE_DOUBLE) {
    std::fill_n(static_cast<double*>(data), rows * width, std::numeric_limits<double>::quiet_NaN());
    return std::nullopt;
  }
  if (dataset.get() < 0 && column == kRung) {
    std::fill_n(static_cast<std::int8_t*>(data), rows * width, kNoRung);
    return std::nullopt;
  }
  const std::string path = ColumnPath(column);
  const SpaceId file_space(Check(H5Dget_space(dataset.get()), where, "reading the shape of", path));
  const hsize_t start[2] = {first, 0};
  const hsize_t count[2] = {rows, width};
  CheckStatus(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr), where,
              "selecting rows of", path);
  const SpaceId memory_space(
      Check(H5Screate_simple(IsMatrix(column) ? 2 : 1, count, nullptr), where, "creating a dataspace for", path));
  const TypeId rung = column == kRung ? RungMemoryType(where, dataset.get()) : TypeId();
  return TryRead(dataset.get(), rung.get() >= 0 ? rung.get() : memory_type, memory_space.get(), file_space.get(), data);
}

// As TryReadRows; a damaged chunk is an InputError naming the file, the dataset and the samples.
void ReadRows(const Where& where, const DatasetId& dataset, std::size_t column, hid_t memory_type, hsize_t first,
              hsize_t rows, hsize_t width, void* data) {
  if (const auto problem = TryReadRows(where, dataset, column, memory_type, first, rows, width, data)) {
    throw InputError(fmt::format("{}: dataset {} is damaged: samples {} to {} cannot be read ({}){}", where.file,
                                 ColumnPath(column), first, first + rows - 1, *problem, VerifyHint(where.file)));
  }
}

// Whether a finished sample's row of `column` must hold finite numbers: its design point
// always, its drawn values unless sampling failed, its outputs when it is ok. A non-finite
// number there is damage the writer cannot have made (jobs/campaign/campaign.cpp).
bool MustBeFinite(std::size_t column, SampleStatus status) {
  if (status == SampleStatus::kPending) return false;
  if (column == kU) return true;
  if (column == kValues) return status != SampleStatus::kSamplingFailed;
  if (column >= kFirstOutput && column < kFirstOutput + kOutputCount) return status == SampleStatus::kOk;
  return false;
}

// The first (row, input) in `rows` rows of `width` numbers that breaks MustBeFinite.
template <typename T>
std::optional<std::pair<hsize_t, hsize_t>> FirstNonFinite(std::size_t column, const T* values, hsize_t rows,
                                                          hsize_t width, const SampleStatus* statuses) {
  for (hsize_t i = 0; i < rows; ++i) {
    if (!MustBeFinite(column, statuses[i])) continue;
    for (hsize_t j = 0; j < width; ++j) {
      if (!std::isfinite(values[i * width + j])) return std::make_pair(i, j);
    }
  }
  return std::nullopt;
}

std::string NonFiniteProblem(std::size_t column, hsize_t sample, hsize_t input, SampleStatus status) {
  return fmt::format("sample {} is {} but holds a non-finite number{}", sample, SampleStatusName(status),
                     IsMatrix(column) ? fmt::format(" at input {}", input) : std::string());
}

void CheckRange(std::string_view what, std::int64_t begin, std::int64_t end, std::int64_t samples) {
  if (begin < 0 || end < begin || end > samples) {
    throw std::out_of_range(
        fmt::format("{}: range [{}, {}) is outside the campaign's [0, {})", what, begin, end, samples));
  }
}

// ---------------------------------------------------------------------------------------
// Damage: CheckResults reads every chunk; Resume rewrites the damaged ones.

constexpr std::array<const char*, 6> kDescriptions = {"/inputs/name",   "/inputs/quantity", "/inputs/component",
                                                      "/inputs/source", "/inputs/roller",   "/inputs/order"};

std::vector<SampleRange> Merged(std::vector<SampleRange> ranges) {
  std::sort(ranges.begin(), ranges.end(), [](const SampleRange& a, const SampleRange& b) { return a.begin < b.begin; });
  std::vector<SampleRange> merged;
  for (const SampleRange& range : ranges) {
    if (!merged.empty() && range.begin <= merged.back().end) {
      merged.back().end = std::max(merged.back().end, range.end);
    } else {
      merged.push_back(range);
    }
  }
  return merged;
}

hsize_t ColumnChunkRows(const Where& where, const DatasetId& dataset, std::size_t column) {
  const PlistId dcpl(Check(H5Dget_create_plist(dataset.get()), where, "reading the layout of", ColumnPath(column)));
  hsize_t chunk[2] = {0, 0};
  if (H5Pget_chunk(dcpl.get(), 2, chunk) < 1 || chunk[0] == 0) {
    Fail(where, fmt::format("dataset {} is not chunked", ColumnPath(column)));
  }
  return chunk[0];
}

// Reads one per-sample column chunk by chunk. `statuses` (read first, from the status
// column) says which rows must hold finite numbers; reading the status column fills it,
// and `known` marks the rows whose status chunk read.
DatasetCheck ScanColumn(const Where& where, const DatasetId& dataset, std::size_t column, hsize_t samples,
                        hsize_t inputs, std::vector<SampleStatus>& statuses, std::vector<char>& known) {
  const std::string path = ColumnPath(column);
  DatasetCheck check;
  check.path = path;
  check.per_sample = true;
  check.checksummed = HasChecksum(where, dataset.get(), path);
  const hsize_t rows = ColumnChunkRows(where, dataset, column);
  const hsize_t width = IsMatrix(column) ? inputs : 1;
  const TypeId stored(Check(H5Dget_type(dataset.get()), where, "reading the type of", path));
  // Numbers as numbers, to check them; everything else as the bytes it is stored as.
  hid_t memory = stored.get();
  if (column == kValues) {
    memory = H5T_NATIVE_FLOAT;
  } else if (column == kU || (column >= kFirstOutput && column < kFirstOutput + kOutputCount)) {
    memory = H5T_NATIVE_DOUBLE;
  }
  std::vector<unsigned char> buffer;
  const auto damage = [&](hsize_t first, const std::string& problem) {
    if (check.damaged.empty()) check.first_problem = problem;
    check.damaged.push_back({static_cast<std::int64_t>(first), static_cast<std::int64_t>(std::min(first + rows, samples))});
  };
  for (hsize_t first = 0; first < samples; first += rows) {
    const hsize_t count = std::min(rows, samples - first);
    buffer.resize(count * width * H5Tget_size(memory));
    if (const auto problem = TryReadRows(where, dataset, column, memory, first, count, width, buffer.data())) {
      damage(first, *problem);
      continue;
    }
    if (column == kStatus) {
      const auto* raw = reinterpret_cast<const std::int8_t*>(buffer.data());
      const auto unknown = std::find_if(raw, raw + count, [](std::int8_t value) { return !IsKnownStatus(value); });
      if (unknown != raw + count) {
        damage(first, fmt::format("sample {} has status {}, which no ringtol writes",
                                  first + static_cast<hsize_t>(unknown - raw), *unknown));
        continue;
      }
      for (hsize_t i = 0; i < count; ++i) {
        statuses[first + i] = static_cast<SampleStatus>(raw[i]);
        known[first + i] = 1;
      }
      continue;
    }
    std::optional<std::pair<hsize_t, hsize_t>> bad;
    if (memory == H5T_NATIVE_FLOAT) {
      bad = FirstNonFinite(column, reinterpret_cast<const float*>(buffer.data()), count, width, &statuses[first]);
    } else if (memory == H5T_NATIVE_DOUBLE) {
      bad = FirstNonFinite(column, reinterpret_cast<const double*>(buffer.data()), count, width, &statuses[first]);
    }
    if (bad) damage(first, NonFiniteProblem(column, first + bad->first, bad->second, statuses[first + bad->first]));
  }
  check.damaged = Merged(std::move(check.damaged));
  return check;
}

ResultsCheck Scan(const Where& where, hid_t file, const Stored& stored, const Columns& columns) {
  ResultsCheck check;
  check.samples = stored.samples;
  const auto samples = static_cast<hsize_t>(stored.samples);
  // ReadStored has read the descriptions whole: a damaged one does not get this far.
  for (const char* path : kDescriptions) {
    const DatasetId dataset(Check(H5Dopen2(file, path, H5P_DEFAULT), where, "opening dataset", path));
    DatasetCheck description;
    description.path = path;
    description.checksummed = HasChecksum(where, dataset.get(), path);
    check.datasets.push_back(std::move(description));
  }
  std::vector<SampleStatus> statuses(samples, SampleStatus::kPending);
  std::vector<char> known(samples, 0);
  const hsize_t inputs = stored.identity.inputs.size();
  DatasetCheck status = ScanColumn(where, columns[kStatus], kStatus, samples, inputs, statuses, known);
  for (std::size_t c = 0; c < kColumnCount; ++c) {
    if (c == kStatus || columns[c].get() < 0) continue;  // an output an older schema lacks
    check.datasets.push_back(ScanColumn(where, columns[c], c, samples, inputs, statuses, known));
    const std::string stored_path = StoredColumnPath(c, stored.schema_version);
    if (stored_path != ColumnPath(c)) check.datasets.back().path = stored_path + " (read as " + ColumnPath(c) + ")";
  }
  check.datasets.push_back(std::move(status));

  std::vector<SampleRange> recompute;
  for (hsize_t i = 0; i < samples; ++i) {
    if (!known[i]) continue;
    const auto index = static_cast<std::int64_t>(i);
    if (statuses[i] != SampleStatus::kPending) {
      ++check.done;
    } else if (!check.pending.empty() && check.pending.back().end == index) {
      ++check.pending.back().end;
    } else {
      check.pending.push_back({index, index + 1});
    }
  }
  recompute = check.pending;
  for (const DatasetCheck& dataset : check.datasets) {
    recompute.insert(recompute.end(), dataset.damaged.begin(), dataset.damaged.end());
  }
  check.recompute = Merged(std::move(recompute));
  return check;
}

// Gives every damaged chunk of `check` its fill values (the status chunk: pending) and marks
// its samples pending, so that the run computes them again. A rewritten chunk is stored
// with its filters skipped (RewriteChunksWithFill). Chunks first, statuses after: a kill in between leaves finished statuses over
// NaN design points, which the next resume finds damaged and rewrites again.
void RepairDamage(const Where& where, hid_t file, const ResultsCheck& check) {
  std::vector<SampleRange> recompute;
  for (std::size_t c = 0; c < kColumnCount; ++c) {
    const std::string path = ColumnPath(c);
    const auto found = std::find_if(check.datasets.begin(), check.datasets.end(),
                                    [&](const DatasetCheck& dataset) { return dataset.path == path; });
    if (found == check.datasets.end() || found->damaged.empty()) continue;
    const DatasetId dataset(Check(H5Dopen2(file, path.c_str(), H5P_DEFAULT), where, "opening", path));
    const hsize_t rows = ColumnChunkRows(where, dataset, c);
    std::vector<std::array<hsize_t, 2>> offsets;
    for (const SampleRange& range : found->damaged) {
      for (auto first = static_cast<hsize_t>(range.begin); first < static_cast<hsize_t>(range.end); first += rows) {
        offsets.push_back({first, 0});
      }
    }
    RewriteChunksWithFill(where, dataset.get(), path, offsets);
    for (const SampleRange& range : found->damaged) {
      std::cerr << fmt::format("ringtol: {}: dataset {} was damaged at samples {}; they are computed again\n",
                               where.file, path, FormatRanges({range}));
    }
    if (c != kStatus) recompute.insert(recompute.end(), found->damaged.begin(), found->damaged.end());
  }
  if (recompute.empty()) return;
  const std::string path = ColumnPath(kStatus);
  const DatasetId status(Check(H5Dopen2(file, path.c_str(), H5P_DEFAULT), where, "opening", path));
  const TypeId type(Check(H5Dget_type(status.get()), where, "reading the type of", path));
  std::vector<Run> runs;
  hsize_t rows = 0;
  for (const SampleRange& range : Merged(std::move(recompute))) {
    runs.push_back({static_cast<hsize_t>(range.begin), static_cast<hsize_t>(range.end - range.begin)});
    rows += runs.back().count;
  }
  const std::vector<std::int8_t> pending(rows, static_cast<std::int8_t>(SampleStatus::kPending));
  const TypeId native(Check(H5Tget_native_type(type.get(), H5T_DIR_ASCEND), where, "reading the type of", path));
  WriteRows(where, status, kStatus, native.get(), runs, rows, 1, pending.data());
}

}  // namespace

struct CampaignStore::File {
  fs::path path;
  Where where;
  FileLock lock;
  FileId file;  // closed after the datasets (members are destroyed in reverse order)
  Columns columns;
  TypeId status_type;
  std::int64_t samples = 0;
  std::size_t inputs = 0;
  hsize_t chunk_rows = 0;
  CampaignIdentity identity;  // what a shard must match
  std::vector<SampleRecord> buffer;

  // Everything is created (or extended) by now: enter SWMR mode, then open the datasets
  // (entering SWMR reopens open datasets with default access, losing the chunk cache).
  void StartWriting(const CampaignStoreOptions& options) {
    CheckStatus(H5Fstart_swmr_write(file.get()), where, "starting", "SWMR writing");
    const PlistId matrix_access = MatrixAccess(where, options.chunk_cache_bytes, samples, chunk_rows, inputs);
    columns = OpenColumns(where, file.get(), samples, inputs, kCampaignSchemaVersion, matrix_access.get());
    status_type = StatusType(where);
  }

  // Closes the datasets, then the file (whose close flushes and clears the superblock flags).
  bool Close() {
    for (DatasetId& column : columns) column.reset();
    status_type.reset();
    return file.Close();
  }
};

CampaignStore::CampaignStore(std::unique_ptr<File> file) : file_(std::move(file)) {}

CampaignStore::~CampaignStore() {
  if (!file_) return;
  const QuietErrors quiet;
  try {
    Commit();
  } catch (const std::exception& error) {
    std::cerr << "ringtol: " << error.what() << '\n';
  }
  if (!file_->Close()) {
    std::cerr << "ringtol: " << file_->where.file << ": closing failed (HDF5: " << Hdf5Detail() << ")\n";
  }
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
  // Built under another name and renamed when complete, so that a kill while creating
  // never leaves a half-made file under the campaign's name.
  const fs::path temporary = PrepareCreate(path, ExistsMessage(name));

  auto file = std::make_unique<File>();
  file->path = path;
  file->where = Where{name, false};
  file->samples = samples;
  file->inputs = identity.inputs.size();
  file->identity = identity;
  file->chunk_rows = DefaultChunkRows(options, samples, file->inputs);
  try {
    file->file = CreateExclusive(temporary, path);
    file->lock = FileLock::Acquire(temporary, name);
    WriteSchema(file->where, file->file.get(), identity, samples, options);
    file->StartWriting(options);
    Publish(temporary, path, ExistsMessage(name));
  } catch (...) {
    file->Close();
    std::error_code error;
    fs::remove(temporary, error);
    throw;
  }
  return CampaignStore(std::move(file));
}

CampaignStore CampaignStore::Resume(const fs::path& path, const CampaignIdentity& identity, std::int64_t samples,
                                    const CampaignStoreOptions& options) {
  const QuietErrors quiet;
  CheckArguments(identity, samples, options);
  const std::string name = path.string();
  const Where opening{name, true};
  std::error_code error;
  if (!fs::exists(path, error)) {
    throw InputError(name + ": does not exist; run the campaign without --resume to start it");
  }
  if (!fs::is_regular_file(path, error)) throw InputError(name + ": is not a regular file");
  FileLock lock = FileLock::Acquire(path, name);

  // Everything is checked read-only first: a refused file is never modified.
  Stored stored;
  hsize_t chunk_rows = 0;
  ResultsCheck damage;
  {
    const FileId reading = OpenForReading(path);
    stored = ReadStored(opening, reading.get());
    if (stored.schema_version != kCampaignSchemaVersion) {
      throw InputError(fmt::format(
          "{}: was written by an older ringtol (schema {}); it can be reported but not resumed by this one (schema "
          "{}): start a new results file",
          name, stored.schema_version, kCampaignSchemaVersion));
    }
    if (const std::optional<std::string> difference = IdentityDifference(stored.identity, identity)) {
      throw InputError(name + ": was written by another campaign: " + *difference +
                       "; resume it with the campaign that wrote it, or choose a new results file");
    }
    const Columns columns =
        OpenColumns(opening, reading.get(), stored.samples, identity.inputs.size(), stored.schema_version, H5P_DEFAULT);
    chunk_rows = ChunkRows(opening, columns[kU]);
    damage = Scan(opening, reading.get(), stored, columns);
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
  file->file = OpenForWriting(path);
  RepairDamage(file->where, file->file.get(), damage);

  if (samples > stored.samples) {
    for (std::size_t c = 0; c < kColumnCount; ++c) {
      const std::string column = ColumnPath(c);
      const DatasetId dataset(
          Check(H5Dopen2(file->file.get(), column.c_str(), H5P_DEFAULT), file->where, "opening", column));
      const SpaceId space(Check(H5Dget_space(dataset.get()), file->where, "reading the shape of", column));
      hsize_t dims[2] = {0, 0};
      H5Sget_simple_extent_dims(space.get(), dims, nullptr);
      // A grow killed half-way may have extended some datasets already.
      if (dims[0] >= static_cast<hsize_t>(samples)) continue;
      dims[0] = static_cast<hsize_t>(samples);
      CheckStatus(H5Dset_extent(dataset.get(), dims), file->where, "extending", column);
    }
    const std::optional<AttributeId> attribute = OpenAttribute(file->where, file->file.get(), "samples");
    if (!attribute) Fail(file->where, "attribute samples vanished");
    CheckStatus(H5Awrite(attribute->get(), H5T_NATIVE_INT64, &samples), file->where, "updating attribute", "samples");
  }
  file->StartWriting(options);
  return CampaignStore(std::move(file));
}

std::int64_t CampaignStore::samples() const { return file_->samples; }

const fs::path& CampaignStore::path() const { return file_->path; }

std::vector<std::int64_t> CampaignStore::Pending(std::int64_t begin, std::int64_t end) const {
  const QuietErrors quiet;
  CheckRange("CampaignStore::Pending", begin, end, file_->samples);
  std::vector<std::int64_t> pending;
  std::vector<std::int8_t> block;
  for (auto first = static_cast<hsize_t>(begin); first < static_cast<hsize_t>(end); first += kStatusBlock) {
    const hsize_t rows = std::min(kStatusBlock, static_cast<hsize_t>(end) - first);
    block.resize(rows);
    ReadRows(file_->where, file_->columns[kStatus], kStatus, file_->status_type.get(), first, rows, 1, block.data());
    for (hsize_t i = 0; i < rows; ++i) {
      if (block[i] == static_cast<std::int8_t>(SampleStatus::kPending)) {
        pending.push_back(static_cast<std::int64_t>(first + i));
      }
    }
  }
  return pending;
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
  file_->buffer.push_back(std::move(record));
}

std::size_t CampaignStore::buffered() const { return file_->buffer.size(); }

void CampaignStore::Commit() {
  File& f = *file_;
  if (f.buffer.empty()) return;
  const QuietErrors quiet;

  // In index order, the last one added winning when a sample was added twice.
  std::vector<std::size_t> order(f.buffer.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return f.buffer[a].index < f.buffer[b].index; });
  std::vector<const SampleRecord*> records;
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (i + 1 < order.size() && f.buffer[order[i + 1]].index == f.buffer[order[i]].index) continue;
    records.push_back(&f.buffer[order[i]]);
  }
  std::vector<Run> runs;
  for (const SampleRecord* record : records) {
    const auto index = static_cast<hsize_t>(record->index);
    if (!runs.empty() && runs.back().first + runs.back().count == index) {
      ++runs.back().count;
    } else {
      runs.push_back({index, 1});
    }
  }

  const std::size_t m = records.size();
  const std::size_t d = f.inputs;
  std::vector<double> u(m * d);
  std::vector<float> values(m * d);
  std::vector<std::int32_t> redraws(m);
  std::vector<std::int32_t> steps(m);
  std::vector<char> messages(m * kMessageBytes, '\0');
  std::vector<double> solve_times(m);
  std::vector<std::int8_t> rungs(m);
  std::vector<double> error_bounds(m);
  std::vector<std::vector<double>> outputs(kOutputCount, std::vector<double>(m));
  std::vector<std::int8_t> statuses(m);
  for (std::size_t i = 0; i < m; ++i) {
    const SampleRecord& record = *records[i];
    std::copy(record.u.begin(), record.u.end(), u.begin() + static_cast<std::ptrdiff_t>(i * d));
    // Rounded here rather than by HDF5, whose conversion may clip instead of round.
    for (std::size_t j = 0; j < d; ++j) values[i * d + j] = static_cast<float>(record.values[j]);
    redraws[i] = record.redraws;
    steps[i] = record.steps;
    TruncateUtf8(record.message, kMessageChars).copy(messages.data() + i * kMessageBytes, kMessageChars);
    solve_times[i] = record.solve_time;
    const bool ok = record.status == SampleStatus::kOk;
    rungs[i] = record.rung;
    error_bounds[i] = ok ? record.d_trajectory_error : std::numeric_limits<double>::quiet_NaN();
    for (std::size_t k = 0; k < kOutputCount; ++k) {
      outputs[k][i] = ok ? record.outputs[k] : std::numeric_limits<double>::quiet_NaN();
    }
    statuses[i] = static_cast<std::int8_t>(record.status);
  }

  const TypeId message_type = FixedString(f.where, kMessageBytes);
  const Where& w = f.where;
  WriteRows(w, f.columns[kU], kU, H5T_NATIVE_DOUBLE, runs, m, d, u.data());
  WriteRows(w, f.columns[kValues], kValues, H5T_NATIVE_FLOAT, runs, m, d, values.data());
  WriteRows(w, f.columns[kRedraws], kRedraws, H5T_NATIVE_INT32, runs, m, 1, redraws.data());
  WriteRows(w, f.columns[kSteps], kSteps, H5T_NATIVE_INT32, runs, m, 1, steps.data());
  WriteRows(w, f.columns[kMessage], kMessage, message_type.get(), runs, m, 1, messages.data());
  WriteRows(w, f.columns[kSolveTime], kSolveTime, H5T_NATIVE_DOUBLE, runs, m, 1, solve_times.data());
  WriteRows(w, f.columns[kRung], kRung, H5T_NATIVE_INT8, runs, m, 1, rungs.data());
  WriteRows(w, f.columns[kErrorBound], kErrorBound, H5T_NATIVE_DOUBLE, runs, m, 1, error_bounds.data());
  for (std::size_t k = 0; k < kOutputCount; ++k) {
    WriteRows(w, f.columns[kFirstOutput + k], kFirstOutput + k, H5T_NATIVE_DOUBLE, runs, m, 1, outputs[k].data());
  }
  // Last, after everything else is flushed: a status on disk vouches for its sample.
  WriteRows(w, f.columns[kStatus], kStatus, f.status_type.get(), runs, m, 1, statuses.data());
  f.buffer.clear();
}

std::int64_t CampaignStore::chunk_rows() const { return static_cast<std::int64_t>(file_->chunk_rows); }

namespace {

// Whether chunks of `from` can be stored in `to` as they are: the same filters in the same
// order (so the same filter mask means the same thing) and the same chunk shape.
bool SameStorage(const Where& where, hid_t from, hid_t to, const std::string& path) {
  const PlistId a(Check(H5Dget_create_plist(from), where, "reading the layout of", path));
  const PlistId b(Check(H5Dget_create_plist(to), where, "reading the layout of", path));
  const int filters = H5Pget_nfilters(a.get());
  if (filters < 0 || filters != H5Pget_nfilters(b.get())) return false;
  const auto filter = [](const PlistId& dcpl, int k) {
    unsigned flags = 0;
    std::size_t values = 0;  // asks for none of its parameters: HDF5 then needs no array
    return H5Pget_filter2(dcpl.get(), static_cast<unsigned>(k), &flags, &values, nullptr, 0, nullptr, nullptr);
  };
  for (int k = 0; k < filters; ++k) {
    const H5Z_filter_t id = filter(a, k);
    if (id < 0 || id != filter(b, k)) return false;
  }
  hsize_t x[2] = {0, 0};
  hsize_t y[2] = {0, 0};
  return H5Pget_chunk(a.get(), 2, x) == H5Pget_chunk(b.get(), 2, y) && x[0] == y[0] && x[1] == y[1];
}

// Copies one stored chunk, filtered bytes and filter mask as they are.
std::int64_t CopyChunk(const Where& where, hid_t from, hid_t to, const std::string& path, const hsize_t* offset,
                       std::vector<unsigned char>& buffer) {
  hsize_t bytes = 0;
  CheckStatus(H5Dget_chunk_storage_size(from, offset, &bytes), where, "sizing a chunk of", path);
  buffer.resize(static_cast<std::size_t>(bytes));
  std::uint32_t mask = 0;
  CheckStatus(H5Dread_chunk(from, H5P_DEFAULT, offset, &mask, buffer.data()), where, "reading a chunk of", path);
  CheckStatus(H5Dwrite_chunk(to, H5P_DEFAULT, mask, offset, buffer.size(), buffer.data()), where, "writing a chunk of",
              path);
  return static_cast<std::int64_t>(bytes);
}

}  // namespace

CampaignStore::Absorbed CampaignStore::Absorb(const fs::path& shard_path) {
  const QuietErrors quiet;
  Commit();
  File& f = *file_;
  const Where opening{shard_path.string(), true};
  Absorbed absorbed;
  std::vector<std::int64_t> one_by_one;
  {
    const FileId shard = OpenForReading(shard_path);
    const Stored stored = ReadStored(opening, shard.get());
    if (stored.schema_version != kCampaignSchemaVersion) {
      throw InputError(fmt::format("{}: is a shard of schema {}, not {}", opening.file, stored.schema_version,
                                   kCampaignSchemaVersion));
    }
    if (const std::optional<std::string> difference = IdentityDifference(stored.identity, f.identity)) {
      throw InputError(opening.file + ": is a shard of another campaign than " + f.where.file + ": " + *difference +
                       "; remove it, or resume with the campaign that wrote it");
    }
    if (stored.samples > f.samples) {
      throw InputError(fmt::format("{}: is a shard of {} samples, more than the {} of {}", opening.file,
                                   stored.samples, f.samples, f.where.file));
    }
    const Columns from = OpenColumns(opening, shard.get(), stored.samples, f.inputs, stored.schema_version, H5P_DEFAULT);
    const hsize_t rows = ChunkRows(opening, from[kU]);
    bool as_stored = rows == f.chunk_rows && stored.samples == f.samples;
    for (std::size_t c = 0; c < kColumnCount && as_stored; ++c) {
      as_stored = SameStorage(opening, from[c].get(), f.columns[c].get(), ColumnPath(c));
    }
    const Where reading{opening.file, false};
    const auto samples = static_cast<hsize_t>(stored.samples);
    const auto pending = static_cast<std::int8_t>(SampleStatus::kPending);
    std::vector<hsize_t> whole;  // first samples of the chunks copied as stored
    std::vector<std::int8_t> theirs(rows);
    std::vector<std::int8_t> ours(rows);
    for (hsize_t first = 0; first < samples; first += rows) {
      const hsize_t count = std::min(rows, samples - first);
      // A status chunk that does not read vouches for nothing: its samples stay pending.
      if (TryReadRows(reading, from[kStatus], kStatus, f.status_type.get(), first, count, 1, theirs.data())) continue;
      ReadRows(f.where, f.columns[kStatus], kStatus, f.status_type.get(), first, count, 1, ours.data());
      std::int64_t wanted = 0;
      bool ours_empty = true;
      for (hsize_t i = 0; i < count; ++i) {
        ours_empty = ours_empty && ours[i] == pending;
        if (theirs[i] != pending && ours[i] == pending && IsKnownStatus(theirs[i])) ++wanted;
      }
      if (wanted == 0) continue;
      absorbed.samples += wanted;
      if (as_stored && ours_empty) {
        whole.push_back(first);
        absorbed.chunk_samples += wanted;
        continue;
      }
      for (hsize_t i = 0; i < count; ++i) {
        if (theirs[i] != pending && ours[i] == pending && IsKnownStatus(theirs[i])) {
          one_by_one.push_back(static_cast<std::int64_t>(first + i));
        }
      }
    }
    // Every column before the statuses, flushed, so that a status copied vouches for its sample.
    std::vector<unsigned char> buffer;
    const auto copy = [&](std::size_t column) {
      const std::string path = ColumnPath(column);
      for (const hsize_t first : whole) {
        const hsize_t offset[2] = {first, 0};
        absorbed.bytes += CopyChunk(reading, from[column].get(), f.columns[column].get(), path, offset, buffer);
      }
      CheckStatus(H5Dflush(f.columns[column].get()), f.where, "flushing", path);
    };
    if (!whole.empty()) {
      for (std::size_t column = 0; column < kColumnCount; ++column) {
        if (column != kStatus) copy(column);
      }
      copy(kStatus);
    }
  }
  if (!one_by_one.empty()) {
    const CampaignReader shard(shard_path);
    for (const std::int64_t index : one_by_one) Add(shard.ReadSample(index));
    Commit();
  }
  std::error_code error;
  fs::remove(shard_path, error);
  if (error) Fail(f.where, fmt::format("cannot remove shard {}: {}", shard_path.string(), error.message()));
  return absorbed;
}

fs::path ShardPath(const fs::path& results, int rank) {
  fs::path shard = results;
  shard += fmt::format(".shard-{}", rank);
  return shard;
}

std::vector<fs::path> FindShards(const fs::path& results) {
  const fs::path directory = results.has_parent_path() ? results.parent_path() : fs::path(".");
  const std::string prefix = results.filename().string() + ".shard-";
  std::vector<std::pair<int, fs::path>> found;
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(directory, error)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    const std::string rank = name.substr(prefix.size());
    constexpr std::size_t kMaxDigits = 9;  // fits an int
    if (rank.empty() || rank.size() > kMaxDigits || !std::all_of(rank.begin(), rank.end(), [](char c) { return c >= '0' && c <= '9'; })) continue;
    found.emplace_back(std::stoi(rank), entry.path());
  }
  std::sort(found.begin(), found.end());
  std::vector<fs::path> shards;
  for (auto& [rank, path] : found) shards.push_back(std::move(path));
  return shards;
}

// ---------------------------------------------------------------------------------------

struct CampaignReader::File {
  Where where;
  FileId file;
  Columns columns;
  TypeId status_type;
  Stored stored;

  void Open(const fs::path& path);

  void CheckRows(std::string_view what, std::int64_t begin, std::int64_t count) const {
    if (count < 0) throw std::out_of_range(fmt::format("{}: count {} is negative", what, count));
    CheckRange(what, begin, begin + count, stored.samples);
  }

  // Rows [begin, begin + count) of one column, `width` values each, checked and read quietly.
  template <typename T>
  std::vector<T> Rows(std::string_view what, std::size_t column, hid_t memory_type, std::int64_t begin,
                      std::int64_t count, std::size_t width) const {
    const QuietErrors quiet;
    CheckRows(what, begin, count);
    std::vector<T> values(static_cast<std::size_t>(count) * width);
    ReadRows(where, columns[column], column, memory_type, static_cast<hsize_t>(begin), static_cast<hsize_t>(count),
             width, values.data());
    if constexpr (std::is_floating_point_v<T>) {
      const bool held = columns[column].get() >= 0;  // an output an older schema lacks reads as NaN
      if (held && (column == kU || column == kValues || (column >= kFirstOutput && column < kFirstOutput + kOutputCount))) {
        CheckFinite(column, begin, count, width, values.data(), Statuses(begin, count).data());
      }
    }
    return values;
  }

  // InputError when a finished sample holds a non-finite number where it cannot
  // (MustBeFinite); `statuses` are those of the `count` samples from `begin`.
  template <typename T>
  void CheckFinite(std::size_t column, std::int64_t begin, std::int64_t count, std::size_t width, const T* values,
                   const SampleStatus* statuses) const {
    if (const auto bad = FirstNonFinite(column, values, static_cast<hsize_t>(count), width, statuses)) {
      const auto sample = static_cast<hsize_t>(begin) + bad->first;
      throw InputError(fmt::format("{}: dataset {} is damaged: {}{}", where.file, ColumnPath(column),
                                   NonFiniteProblem(column, sample, bad->second, statuses[bad->first]),
                                   VerifyHint(where.file)));
    }
  }

  std::vector<SampleStatus> Statuses(std::int64_t begin, std::int64_t count) const {
    std::vector<std::int8_t> raw(static_cast<std::size_t>(count));
    ReadRows(where, columns[kStatus], kStatus, status_type.get(), static_cast<hsize_t>(begin),
             static_cast<hsize_t>(count), 1, raw.data());
    std::vector<SampleStatus> statuses;
    statuses.reserve(raw.size());
    for (std::size_t i = 0; i < raw.size(); ++i) {
      if (!IsKnownStatus(raw[i])) {
        throw InputError(fmt::format("{}: dataset /outputs/status is damaged: sample {} has status {}, which no "
                                     "ringtol writes{}",
                                     where.file, begin + static_cast<std::int64_t>(i), raw[i], VerifyHint(where.file)));
      }
      statuses.push_back(static_cast<SampleStatus>(raw[i]));
    }
    return statuses;
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
  columns =
      OpenColumns(where, file.get(), stored.samples, stored.identity.inputs.size(), stored.schema_version, H5P_DEFAULT);
  const TypeId type(Check(H5Dget_type(columns[kStatus].get()), where, "reading the type of", ColumnPath(kStatus)));
  status_type =
      TypeId(Check(H5Tget_native_type(type.get(), H5T_DIR_ASCEND), where, "reading the type of", ColumnPath(kStatus)));
  where.input = false;  // open and valid: later failures are the system's
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

std::vector<SampleStatus> CampaignReader::ReadStatus(std::int64_t begin, std::int64_t count) const {
  const QuietErrors quiet;
  file_->CheckRows("CampaignReader::ReadStatus", begin, count);
  return file_->Statuses(begin, count);
}

bool CampaignReader::HasOutput(std::string_view name) const {
  const auto* found = std::find(kOutputNames.begin(), kOutputNames.end(), name);
  if (found == kOutputNames.end()) return false;
  return file_->columns[kFirstOutput + static_cast<std::size_t>(found - kOutputNames.begin())].get() >= 0;
}

std::vector<double> CampaignReader::ReadOutput(std::string_view name, std::int64_t begin, std::int64_t count) const {
  const auto* found = std::find(kOutputNames.begin(), kOutputNames.end(), name);
  if (found == kOutputNames.end()) {
    throw std::invalid_argument(fmt::format("CampaignReader::ReadOutput: unknown output '{}'; outputs: {}", name,
                                            fmt::join(kOutputNames, ", ")));
  }
  const std::size_t column = kFirstOutput + static_cast<std::size_t>(found - kOutputNames.begin());
  return file_->Rows<double>("CampaignReader::ReadOutput", column, H5T_NATIVE_DOUBLE, begin, count, 1);
}

std::vector<double> CampaignReader::ReadValues(std::int64_t begin, std::int64_t count) const {
  const std::vector<float> stored = file_->Rows<float>("CampaignReader::ReadValues", kValues, H5T_NATIVE_FLOAT, begin,
                                                       count, file_->stored.identity.inputs.size());
  return {stored.begin(), stored.end()};
}

std::vector<std::int32_t> CampaignReader::ReadRedraws(std::int64_t begin, std::int64_t count) const {
  return file_->Rows<std::int32_t>("CampaignReader::ReadRedraws", kRedraws, H5T_NATIVE_INT32, begin, count, 1);
}

std::vector<std::int8_t> CampaignReader::ReadRungs(std::int64_t begin, std::int64_t count) const {
  return file_->Rows<std::int8_t>("CampaignReader::ReadRungs", kRung, H5T_NATIVE_INT8, begin, count, 1);
}

SampleRecord CampaignReader::ReadSample(std::int64_t index) const {
  const QuietErrors quiet;
  file_->CheckRows("CampaignReader::ReadSample", index, 1);
  const File& f = *file_;
  const std::size_t d = f.stored.identity.inputs.size();
  const auto row = static_cast<hsize_t>(index);
  SampleRecord record;
  record.index = index;
  record.status = f.Statuses(index, 1).front();
  record.u.resize(d);
  ReadRows(f.where, f.columns[kU], kU, H5T_NATIVE_DOUBLE, row, 1, d, record.u.data());
  std::vector<float> values(d);
  ReadRows(f.where, f.columns[kValues], kValues, H5T_NATIVE_FLOAT, row, 1, d, values.data());
  record.values.assign(values.begin(), values.end());
  ReadRows(f.where, f.columns[kRedraws], kRedraws, H5T_NATIVE_INT32, row, 1, 1, &record.redraws);
  ReadRows(f.where, f.columns[kSteps], kSteps, H5T_NATIVE_INT32, row, 1, 1, &record.steps);
  const TypeId message_type = FixedString(f.where, kMessageBytes);
  std::array<char, kMessageBytes + 1> message{};
  ReadRows(f.where, f.columns[kMessage], kMessage, message_type.get(), row, 1, 1, message.data());
  record.message = message.data();
  ReadRows(f.where, f.columns[kSolveTime], kSolveTime, H5T_NATIVE_DOUBLE, row, 1, 1, &record.solve_time);
  ReadRows(f.where, f.columns[kRung], kRung, H5T_NATIVE_INT8, row, 1, 1, &record.rung);
  ReadRows(f.where, f.columns[kErrorBound], kErrorBound, H5T_NATIVE_DOUBLE, row, 1, 1, &record.d_trajectory_error);
  for (std::size_t k = 0; k < kOutputCount; ++k) {
    ReadRows(f.where, f.columns[kFirstOutput + k], kFirstOutput + k, H5T_NATIVE_DOUBLE, row, 1, 1, &record.outputs[k]);
    if (f.columns[kFirstOutput + k].get() >= 0) f.CheckFinite(kFirstOutput + k, index, 1, 1, &record.outputs[k], &record.status);
  }
  f.CheckFinite(kU, index, 1, d, record.u.data(), &record.status);
  f.CheckFinite(kValues, index, 1, d, values.data(), &record.status);
  return record;
}

// ---------------------------------------------------------------------------------------

bool ResultsCheck::intact() const {
  return std::all_of(datasets.begin(), datasets.end(), [](const DatasetCheck& d) { return d.damaged.empty(); });
}

bool ResultsCheck::checksummed() const {
  return std::all_of(datasets.begin(), datasets.end(), [](const DatasetCheck& d) { return d.checksummed; });
}

ResultsCheck CheckResults(const fs::path& path) {
  const QuietErrors quiet;
  const Where where{path.string(), true};
  const FileId file = OpenForReading(path);
  const Stored stored = ReadStored(where, file.get());
  const Columns columns =
      OpenColumns(where, file.get(), stored.samples, stored.identity.inputs.size(), stored.schema_version, H5P_DEFAULT);
  return Scan(where, file.get(), stored, columns);
}

std::string FormatRanges(const std::vector<SampleRange>& ranges) {
  std::vector<std::string> parts;
  for (const SampleRange& range : ranges) {
    parts.push_back(range.end - range.begin == 1 ? fmt::format("{}", range.begin)
                                                 : fmt::format("{} to {}", range.begin, range.end - 1));
  }
  return fmt::format("{}", fmt::join(parts, ", "));
}

std::string DamageMessage(const fs::path& path, const ResultsCheck& check) {
  std::vector<std::string> damaged;
  for (const DatasetCheck& dataset : check.datasets) {
    if (dataset.damaged.empty()) continue;
    damaged.push_back(fmt::format("dataset {} is damaged at samples {} ({})", dataset.path,
                                  FormatRanges(dataset.damaged), dataset.first_problem));
  }
  return fmt::format(
      "{}: {}; `ringtol campaign CAMPAIGN --out {} --resume` computes those samples again, `ringtol verify {}` "
      "lists what is intact",
      path.string(), fmt::join(damaged, "; "), path.string(), path.string());
}

}  // namespace ringtol::jobs
