#include "jobs/store/sample_table.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <limits>
#include <map>
#include <stdexcept>
#include <utility>

#include "engine/check.h"
#include "jobs/inputs/input_error.h"

namespace ringtol::jobs::hdf5 {

namespace {

// HDF5's advice: about 100 hash slots per chunk that fits in the cache, a prime number;
// capped, since HDF5 allocates and scans every slot (small chunks would ask for millions).
constexpr std::size_t kSlotsPerCachedChunk = 100;
constexpr std::size_t kMaxSlots = 1u << 17;
// Pending() and Finished() read statuses in blocks of this many samples to bound their memory.
constexpr std::int64_t kStatusBlock = std::int64_t{1} << 20;

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

std::string VerifyHint(const std::string& file) {
  return fmt::format("; `ringtol verify {}` lists every damaged dataset", file);
}

bool MustBeFinite(FiniteRule rule, SampleStatus status) {
  switch (rule) {
    case FiniteRule::kNone:
      return false;
    case FiniteRule::kWhenFinished:
      return status != SampleStatus::kPending;
    case FiniteRule::kUnlessSamplingFailed:
      return status != SampleStatus::kPending && status != SampleStatus::kSamplingFailed;
    case FiniteRule::kWhenOk:
      return status == SampleStatus::kOk;
  }
  return false;
}

// The first (row, value) of `rows` rows of `width` values that breaks `rule`.
template <typename T>
std::optional<std::pair<std::int64_t, std::size_t>> FirstNonFinite(FiniteRule rule, const T* values,
                                                                   std::int64_t rows, std::size_t width,
                                                                   const SampleStatus* statuses) {
  for (std::int64_t i = 0; i < rows; ++i) {
    if (!MustBeFinite(rule, statuses[i])) continue;
    for (std::size_t j = 0; j < width; ++j) {
      if (!std::isfinite(values[static_cast<std::size_t>(i) * width + j])) return std::make_pair(i, j);
    }
  }
  return std::nullopt;
}

std::optional<std::pair<std::int64_t, std::size_t>> FirstNonFinite(const ColumnSpec& spec, const void* values,
                                                                   std::int64_t rows, const SampleStatus* statuses) {
  const std::size_t width = std::max<std::size_t>(1, spec.width);
  if (spec.type == ColumnType::kFloat64) {
    return FirstNonFinite(spec.finite, static_cast<const double*>(values), rows, width, statuses);
  }
  if (spec.type == ColumnType::kFloat32) {
    return FirstNonFinite(spec.finite, static_cast<const float*>(values), rows, width, statuses);
  }
  return std::nullopt;
}

// A column's values in memory: its C++ type as an HDF5 type that this table owns.
TypeId MemoryType(const Where& where, const ColumnSpec& spec, hid_t dataset) {
  switch (spec.type) {
    case ColumnType::kFloat64:
      return TypeId(H5Tcopy(H5T_NATIVE_DOUBLE));
    case ColumnType::kFloat32:
      return TypeId(H5Tcopy(H5T_NATIVE_FLOAT));
    case ColumnType::kInt32:
      return TypeId(H5Tcopy(H5T_NATIVE_INT32));
    case ColumnType::kUInt32:
      return TypeId(H5Tcopy(H5T_NATIVE_UINT32));
    case ColumnType::kText:
      return FixedString(where, spec.text_bytes);
    case ColumnType::kInt8Enum:
      break;
  }
  // HDF5 converts no integer to an enumeration: int8 codes move through the dataset's own
  // type where it has one (files before the column was an enumeration hold plain int8).
  const TypeId stored(Check(H5Dget_type(dataset), where, "reading the type of", spec.path));
  if (H5Tget_class(stored.get()) != H5T_ENUM) return TypeId(H5Tcopy(H5T_NATIVE_INT8));
  return TypeId(Check(H5Tget_native_type(stored.get(), H5T_DIR_ASCEND), where, "reading the type of", spec.path));
}

std::size_t ElementSize(const ColumnSpec& spec) {
  switch (spec.type) {
    case ColumnType::kFloat64:
      return sizeof(double);
    case ColumnType::kFloat32:
      return sizeof(float);
    case ColumnType::kInt32:
      return sizeof(std::int32_t);
    case ColumnType::kUInt32:
      return sizeof(std::uint32_t);
    case ColumnType::kInt8Enum:
      return sizeof(std::int8_t);
    case ColumnType::kText:
      return spec.text_bytes;
  }
  return 1;
}

// Fills `rows` rows with the column's fill value, as its C++ type.
void FillRows(const ColumnSpec& spec, std::size_t values, void* out) {
  switch (spec.type) {
    case ColumnType::kFloat64:
      std::fill_n(static_cast<double*>(out), values, spec.fill);
      break;
    case ColumnType::kFloat32:
      std::fill_n(static_cast<float*>(out), values, static_cast<float>(spec.fill));
      break;
    case ColumnType::kInt32:
      std::fill_n(static_cast<std::int32_t*>(out), values, static_cast<std::int32_t>(spec.fill));
      break;
    case ColumnType::kUInt32:
      std::fill_n(static_cast<std::uint32_t*>(out), values, static_cast<std::uint32_t>(spec.fill));
      break;
    case ColumnType::kInt8Enum:
      std::fill_n(static_cast<std::int8_t*>(out), values, static_cast<std::int8_t>(spec.fill));
      break;
    case ColumnType::kText:
      std::fill_n(static_cast<char*>(out), values * spec.text_bytes, '\0');
      break;
  }
}

// The column's type in the file, its fill value set in `dcpl`.
TypeId FileTypeWithFill(const Where& where, const ColumnSpec& spec, const PlistId& dcpl) {
  const std::string& path = spec.path;
  TypeId type;
  herr_t filled = 0;
  const double f64 = spec.fill;
  const auto f32 = static_cast<float>(spec.fill);
  const auto i32 = static_cast<std::int32_t>(spec.fill);
  const auto u32 = static_cast<std::uint32_t>(spec.fill);
  const auto i8 = static_cast<std::int8_t>(spec.fill);
  switch (spec.type) {
    case ColumnType::kFloat64:
      type = TypeId(H5Tcopy(H5T_IEEE_F64LE));
      filled = H5Pset_fill_value(dcpl.get(), H5T_NATIVE_DOUBLE, &f64);
      break;
    case ColumnType::kFloat32:
      type = TypeId(H5Tcopy(H5T_IEEE_F32LE));
      filled = H5Pset_fill_value(dcpl.get(), H5T_NATIVE_FLOAT, &f32);
      break;
    case ColumnType::kInt32:
      type = TypeId(H5Tcopy(H5T_STD_I32LE));
      filled = H5Pset_fill_value(dcpl.get(), H5T_NATIVE_INT32, &i32);
      break;
    case ColumnType::kUInt32:
      type = TypeId(H5Tcopy(H5T_STD_U32LE));
      filled = H5Pset_fill_value(dcpl.get(), H5T_NATIVE_UINT32, &u32);
      break;
    case ColumnType::kInt8Enum:
      RINGTOL_CHECK(spec.enumeration != nullptr, path);
      type = spec.enumeration(where);
      filled = H5Pset_fill_value(dcpl.get(), type.get(), &i8);
      break;
    case ColumnType::kText:
      type = FixedString(where, spec.text_bytes);  // the default fill, all zero bytes, is the empty string
      break;
  }
  Check(type.get(), where, "making the type of", path);
  CheckStatus(filled, where, "setting the fill value of", path);
  return type;
}

// The file dataspace of `dataset` with the rows of `runs` selected: flat [first, count)
// (times the width), grouped one group's [first, count).
struct Run {
  RowKey first;
  hsize_t count = 0;
};

std::vector<Run> RunsOf(std::span<const RowKey> rows) {
  std::vector<Run> runs;
  for (const RowKey& key : rows) {
    if (!runs.empty() && runs.back().first.group == key.group &&
        runs.back().first.sample + static_cast<std::int64_t>(runs.back().count) == key.sample) {
      ++runs.back().count;
    } else {
      runs.push_back({key, 1});
    }
  }
  return runs;
}

// Rows [0, end) of `dataset` hold every row ever written to it; rows from `end` on read as
// the fill. A chunked dataset: the end of its farthest chunk (HDF5's chunk indexes list
// chunks in ascending order, so it is the last one: two walks of the index, in time
// proportional to the chunks up to it, never to the dataset's rows). A virtual one: the end
// of its farthest mapped row.
std::int64_t WrittenRows(const Where& where, hid_t dataset, const std::string& path) {
  const PlistId dcpl(Check(H5Dget_create_plist(dataset), where, "reading the layout of", path));
  const SpaceId space(Check(H5Dget_space(dataset), where, "reading the shape of", path));
  hsize_t dims[2] = {0, 0};
  H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  switch (H5Pget_layout(dcpl.get())) {
    case H5D_CHUNKED: {
      hsize_t chunks = 0;
      CheckStatus(H5Dget_num_chunks(dataset, space.get(), &chunks), where, "counting the chunks of", path);
      if (chunks == 0) return 0;
      hsize_t offset[2] = {0, 0};
      unsigned mask = 0;
      haddr_t address = 0;
      hsize_t bytes = 0;
      CheckStatus(H5Dget_chunk_info(dataset, space.get(), chunks - 1, offset, &mask, &address, &bytes), where,
                  "reading the chunk index of", path);
      hsize_t chunk[2] = {0, 0};
      if (H5Pget_chunk(dcpl.get(), 2, chunk) < 1) Fail(where, fmt::format("reading the chunks of {} failed", path));
      return static_cast<std::int64_t>(std::min(dims[0], offset[0] + chunk[0]));
    }
    case H5D_VIRTUAL: {
      std::size_t mappings = 0;
      CheckStatus(H5Pget_virtual_count(dcpl.get(), &mappings), where, "reading the mappings of", path);
      hsize_t end = 0;
      for (std::size_t i = 0; i < mappings; ++i) {
        const SpaceId rows(Check(H5Pget_virtual_vspace(dcpl.get(), i), where, "reading a mapping of", path));
        hsize_t first[2] = {0, 0};
        hsize_t last[2] = {0, 0};
        if (H5Sget_select_npoints(rows.get()) <= 0) continue;
        CheckStatus(H5Sget_select_bounds(rows.get(), first, last), where, "reading a mapping of", path);
        end = std::max(end, last[0] + 1);
      }
      return static_cast<std::int64_t>(end);
    }
    default:
      return static_cast<std::int64_t>(dims[0]);
  }
}

// Appends samples [begin, end) to ascending runs, joining the last where they touch.
void AppendRun(std::vector<SampleRange>& runs, std::int64_t begin, std::int64_t end) {
  if (begin >= end) return;
  if (!runs.empty() && runs.back().end == begin) {
    runs.back().end = end;
  } else {
    runs.push_back({begin, end});
  }
}

}  // namespace

SampleTable::SampleTable() = default;
SampleTable::~SampleTable() = default;
SampleTable::SampleTable(SampleTable&&) noexcept = default;
SampleTable& SampleTable::operator=(SampleTable&&) noexcept = default;

bool SampleTable::stored(std::size_t column) const { return datasets_[column].get() >= 0; }

bool SampleTable::checksummed(std::size_t column) const {
  return stored(column) && HasChecksum(where_, datasets_[column].get(), specs_[column].stored_path);
}

void SampleTable::CheckType(std::size_t column, ColumnType as) const {
  RINGTOL_CHECK(specs_[column].type == as, specs_[column].path, specs_[column].type, as);
}

void SampleTable::Create(const Where& where, hid_t file, const RowSpace& space, const std::vector<ColumnSpec>& columns,
                         bool checksums) {
  // The last column is the status column.
  RINGTOL_CHECK(!columns.empty() && columns.back().type == ColumnType::kInt8Enum, columns.size(),
                columns.empty() ? std::string() : columns.back().path);
  const auto samples = static_cast<hsize_t>(space.samples);
  const auto chunk_samples = static_cast<hsize_t>(std::max<std::int64_t>(1, space.chunk_samples));
  for (const ColumnSpec& spec : columns) {
    if (spec.stored_path.empty()) continue;  // not in this schema
    const std::string& path = spec.path;
    int rank = 1;
    hsize_t dims[2] = {std::min(samples, static_cast<hsize_t>(spec.stored_below)), 0};
    hsize_t max_dims[2] = {space.extendable ? H5S_UNLIMITED : samples, 0};
    hsize_t chunk[2] = {chunk_samples, 0};
    if (space.grouped()) {
      rank = 2;
      dims[0] = max_dims[0] = static_cast<hsize_t>(space.groups);
      dims[1] = max_dims[1] = samples;
      chunk[0] = 1;
      chunk[1] = chunk_samples;
    } else if (spec.width > 0) {
      rank = 2;
      dims[1] = max_dims[1] = chunk[1] = spec.width;
    }
    const SpaceId dataspace(Check(H5Screate_simple(rank, dims, max_dims), where, "creating the dataspace of", path));
    const PlistId dcpl = ObjectCreation(where, H5P_DATASET_CREATE);
    CheckStatus(H5Pset_chunk(dcpl.get(), rank, chunk), where, "chunking", path);
    if (spec.deflate_level > 0) {
      CheckStatus(H5Pset_shuffle(dcpl.get()), where, "setting the shuffle filter of", path);
      CheckStatus(H5Pset_deflate(dcpl.get(), static_cast<unsigned>(spec.deflate_level)), where, "setting deflate on",
                  path);
    }
    if (checksums) AddChecksum(where, dcpl, path);
    const TypeId file_type = FileTypeWithFill(where, spec, dcpl);
    // Chunks are written when first filled, so rows never written take no space.
    CheckStatus(H5Pset_alloc_time(dcpl.get(), H5D_ALLOC_TIME_INCR), where, "configuring", path);
    const DatasetId dataset(Check(
        H5Dcreate2(file, path.c_str(), file_type.get(), dataspace.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT), where,
        "creating dataset", path));
  }
}

std::vector<StridedRows> RegularRuns(std::span<const SampleRange> rows) {
  std::vector<StridedRows> runs;
  for (const SampleRange& range : rows) {
    const std::int64_t length = range.end - range.begin;
    if (!runs.empty()) {
      StridedRows& run = runs.back();
      const std::int64_t gap = range.begin - run.start;
      const std::int64_t next = run.start + run.count * run.stride;
      if (run.block == length && (run.count == 1 ? gap >= run.block : range.begin == next)) {
        if (run.count == 1) run.stride = gap;
        ++run.count;
        continue;
      }
    }
    runs.push_back({range.begin, length, 1, length});
  }
  return runs;
}

namespace {

// Maps `runs` of `source`'s dataset into the same rows of the view: rows of group `group`
// in a grouped table, whole rows of a flat one (`width` values each, 0 for one). Returns
// the mappings made.
std::int64_t MapRuns(const Where& where, hid_t dcpl, hid_t view, hid_t from, const std::string& source,
                     const ColumnSpec& spec, std::optional<std::int64_t> group, std::span<const StridedRows> runs) {
  for (const StridedRows& run : runs) {
    const auto start = static_cast<hsize_t>(run.start);
    const auto stride = static_cast<hsize_t>(run.stride);
    const auto count = static_cast<hsize_t>(run.count);
    const auto block = static_cast<hsize_t>(run.block);
    const std::array<hsize_t, 2> starts = group ? std::array<hsize_t, 2>{static_cast<hsize_t>(*group), start}
                                                : std::array<hsize_t, 2>{start, 0};
    const std::array<hsize_t, 2> strides = group ? std::array<hsize_t, 2>{1, stride} : std::array<hsize_t, 2>{stride, 1};
    const std::array<hsize_t, 2> counts = group ? std::array<hsize_t, 2>{1, count} : std::array<hsize_t, 2>{count, 1};
    const std::array<hsize_t, 2> blocks =
        group ? std::array<hsize_t, 2>{1, block} : std::array<hsize_t, 2>{block, spec.width};
    for (hid_t selection : {view, from}) {
      CheckStatus(H5Sselect_hyperslab(selection, H5S_SELECT_SET, starts.data(), strides.data(), counts.data(),
                                      blocks.data()),
                  where, "selecting rows of", spec.path);
    }
    CheckStatus(H5Pset_virtual(dcpl, view, source.c_str(), spec.stored_path.c_str(), from), where,
                "mapping " + source + " into", spec.path);
  }
  return static_cast<std::int64_t>(runs.size());
}

}  // namespace

std::int64_t SampleTable::CreateVirtual(const Where& where, hid_t file, const RowSpace& space,
                                        const std::vector<ColumnSpec>& columns,
                                        std::span<const VirtualSource> sources) {
  // The last column is the status column.
  RINGTOL_CHECK(!columns.empty() && columns.back().type == ColumnType::kInt8Enum, columns.size(),
                columns.empty() ? std::string() : columns.back().path);
  std::int64_t mappings = 0;
  for (const ColumnSpec& spec : columns) {
    if (spec.stored_path.empty()) continue;
    const std::string& path = spec.path;
    const int rank = space.grouped() || spec.width > 0 ? 2 : 1;
    const hsize_t dims[2] = {
        space.grouped() ? static_cast<hsize_t>(space.groups)
                        : static_cast<hsize_t>(std::min(space.samples, spec.stored_below)),
        space.grouped() ? static_cast<hsize_t>(space.samples) : spec.width};
    const SpaceId view(Check(H5Screate_simple(rank, dims, nullptr), where, "creating the dataspace of", path));
    const PlistId dcpl = ObjectCreation(where, H5P_DATASET_CREATE);
    const TypeId type = FileTypeWithFill(where, spec, dcpl);
    // Virtual even without a mapping (nothing finished yet): every row then reads as the fill.
    CheckStatus(H5Pset_layout(dcpl.get(), H5D_VIRTUAL), where, "configuring", path);
    std::int64_t column_mappings = 0;
    for (const VirtualSource& source : sources) {
      if (space.grouped()) {
        const SpaceId from(Check(H5Screate_simple(rank, dims, nullptr), where, "creating the dataspace of", path));
        for (const VirtualSource::GroupRows& group : source.group_rows) {
          column_mappings += MapRuns(where, dcpl.get(), view.get(), from.get(), source.file, spec, group.group,
                                     RegularRuns(group.samples));
        }
        continue;
      }
      const hsize_t source_dims[2] = {static_cast<hsize_t>(std::min(source.samples, spec.stored_below)), spec.width};
      // Rows beyond either file's stored rows are not mapped.
      std::vector<SampleRange> shown;
      const auto end = static_cast<std::int64_t>(std::min(dims[0], source_dims[0]));
      for (const SampleRange& range : source.rows) {
        if (range.begin < end) shown.push_back({range.begin, std::min(range.end, end)});
      }
      const SpaceId from(Check(H5Screate_simple(rank, source_dims, nullptr), where, "creating the dataspace of", path));
      column_mappings +=
          MapRuns(where, dcpl.get(), view.get(), from.get(), source.file, spec, std::nullopt, RegularRuns(shown));
    }
    CheckStatus(H5Sselect_all(view.get()), where, "selecting", path);
    const DatasetId dataset(Check(H5Dcreate2(file, spec.stored_path.c_str(), type.get(), view.get(), H5P_DEFAULT,
                                             dcpl.get(), H5P_DEFAULT),
                                  where, "creating dataset", path));
    mappings = column_mappings;
  }
  return mappings;
}

SampleTable SampleTable::Open(const Where& where, hid_t file, RowSpace space, std::vector<ColumnSpec> columns,
                              std::size_t cache_bytes) {
  // The last column is the status column, stored.
  RINGTOL_CHECK(!columns.empty() && columns.back().type == ColumnType::kInt8Enum && !columns.back().stored_path.empty(),
                columns.size(), columns.empty() ? std::string() : columns.back().path);
  SampleTable table;
  table.where_ = where;
  table.datasets_.resize(columns.size());
  table.memory_types_.resize(columns.size());
  const auto open = [&](std::size_t c, hid_t access) {
    const ColumnSpec& spec = columns[c];
    DatasetId dataset(H5Dopen2(file, spec.stored_path.c_str(), access));
    if (dataset.get() < 0) {
      Fail(where, "is not a complete ringtol results file: cannot open dataset " + spec.stored_path);
    }
    const SpaceId dataspace(Check(H5Dget_space(dataset.get()), where, "reading the shape of", spec.stored_path));
    const int rank = space.grouped() || spec.width > 0 ? 2 : 1;
    if (H5Sget_simple_extent_ndims(dataspace.get()) != rank) {
      Fail(where, fmt::format("dataset {} has the wrong rank", spec.stored_path));
    }
    hsize_t dims[2] = {0, 0};
    H5Sget_simple_extent_dims(dataspace.get(), dims, nullptr);
    if (space.grouped()) {
      if (dims[0] != static_cast<hsize_t>(space.groups) || dims[1] != static_cast<hsize_t>(space.samples)) {
        Fail(where, fmt::format("dataset {} is [{}, {}] where the file declares {} {}s and {} samples",
                                spec.stored_path, dims[0], dims[1], space.groups, space.group_name, space.samples));
      }
    } else if (dims[0] < static_cast<hsize_t>(std::min(space.samples, spec.stored_below)) ||
               (rank == 2 && dims[1] != spec.width)) {
      Fail(where, fmt::format("dataset {} has {} rows{} where the file declares {} samples{}", spec.stored_path,
                              dims[0], rank == 2 ? fmt::format(" of {}", dims[1]) : "",
                              std::min(space.samples, spec.stored_below),
                              rank == 2 ? fmt::format(" and {} inputs", spec.width) : ""));
    }
    const TypeId type(Check(H5Dget_type(dataset.get()), where, "reading the type of", spec.stored_path));
    if (spec.type == ColumnType::kText &&
        (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) != 0)) {
      Fail(where, fmt::format("dataset {} does not hold fixed-length strings", spec.stored_path));
    }
    if (c + 1 == columns.size() && (H5Tget_class(type.get()) != H5T_ENUM || H5Tget_size(type.get()) != 1)) {
      Fail(where, fmt::format("dataset {} is not a one-byte enumeration", spec.stored_path));
    }
    table.memory_types_[c] = MemoryType(where, spec, dataset.get());
    table.datasets_[c] = std::move(dataset);
  };
  // The status column's chunks are the table's, and size the cached columns' caches.
  const std::size_t status = columns.size() - 1;
  const auto chunk_samples = [&](hid_t dataset) {
    const PlistId dcpl(Check(H5Dget_create_plist(dataset), where, "reading the layout of", columns[status].stored_path));
    if (H5Pget_layout(dcpl.get()) == H5D_VIRTUAL) return std::max<std::int64_t>(1, space.chunk_samples);
    hsize_t chunk[2] = {0, 0};
    const int rank = space.grouped() ? 2 : 1;
    if (H5Pget_chunk(dcpl.get(), rank, chunk) != rank || chunk[rank - 1] == 0) {
      Fail(where, fmt::format("dataset {} is not chunked", columns[status].stored_path));
    }
    return static_cast<std::int64_t>(chunk[rank - 1]);
  };
  // Columns without a cache of their own first, in order, the statuses always among them.
  const auto own_cache = [&](std::size_t c) { return columns[c].cached && cache_bytes > 0 && c != status; };
  for (std::size_t c = 0; c < columns.size(); ++c) {
    if (!columns[c].stored_path.empty() && !own_cache(c)) open(c, H5P_DEFAULT);
  }
  space.chunk_samples = chunk_samples(table.datasets_[status].get());
  const auto chunks = static_cast<std::size_t>(std::max<std::int64_t>(1, space.groups) *
                                               ((space.samples + space.chunk_samples - 1) / space.chunk_samples));
  for (std::size_t c = 0; c < columns.size(); ++c) {
    const ColumnSpec& spec = columns[c];
    if (spec.stored_path.empty() || !own_cache(c)) continue;
    // Keeps the chunks being filled in memory between commits, so that a commit rewrites a
    // partly filled chunk without first reading it from the file.
    const std::size_t chunk_bytes =
        static_cast<std::size_t>(space.chunk_samples) * std::max<std::size_t>(1, spec.width) * ElementSize(spec);
    const std::size_t cached = std::clamp<std::size_t>(cache_bytes / std::max<std::size_t>(1, chunk_bytes), 1, chunks);
    const std::size_t slots = NextPrime(std::min(kMaxSlots, kSlotsPerCachedChunk * cached));
    const PlistId dapl(Check(H5Pcreate(H5P_DATASET_ACCESS), where, "creating", "a dataset access property list"));
    CheckStatus(H5Pset_chunk_cache(dapl.get(), slots, cache_bytes, H5D_CHUNK_CACHE_W0_DEFAULT), where, "configuring",
                "the chunk cache");
    open(c, dapl.get());
  }
  table.space_ = space;
  table.specs_ = std::move(columns);
  table.written_end_ = space.grouped() ? space.samples : 0;
  for (std::size_t c = 0; c < table.specs_.size() && !space.grouped(); ++c) {
    if (!table.stored(c)) continue;
    table.written_end_ =
        std::max(table.written_end_, WrittenRows(where, table.datasets_[c].get(), table.specs_[c].stored_path));
  }
  table.written_end_ = std::min(table.written_end_, space.samples);
  return table;
}

std::string SampleTable::Rows(std::int64_t group, std::int64_t first, std::int64_t last) const {
  const std::string samples =
      first == last ? fmt::format("sample {}", first) : fmt::format("samples {} to {}", first, last);
  return space_.grouped() ? fmt::format("{} {}, {}", space_.group_name, group, samples) : samples;
}

void SampleTable::Write(std::span<const RowKey> rows, std::span<const void* const> values) {
  if (rows.empty()) return;
  RINGTOL_CHECK(values.size() == specs_.size(), values.size(), specs_.size());  // one value array per column
  if (!space_.grouped()) {
    // Rows are sorted: the last is the farthest, and its chunk ends the written rows.
    const std::int64_t chunk = std::max<std::int64_t>(1, space_.chunk_samples);
    written_end_ = std::max(written_end_, std::min(space_.samples, (rows.back().sample / chunk + 1) * chunk));
  }
  // Statuses last, after everything else is flushed: a status on disk vouches for its sample.
  for (std::size_t c = 0; c < specs_.size(); ++c) {
    const ColumnSpec& spec = specs_[c];
    if (!stored(c)) continue;
    // Samples beyond stored_below are dropped: in a flat table they end the sorted rows.
    std::span<const RowKey> kept = rows;
    if (!space_.grouped() && spec.stored_below < space_.samples) {
      const auto end = std::lower_bound(rows.begin(), rows.end(), RowKey{0, spec.stored_below});
      kept = rows.first(static_cast<std::size_t>(end - rows.begin()));
      if (kept.empty()) continue;
    }
    const std::vector<Run> runs = RunsOf(kept);
    const auto m = static_cast<hsize_t>(kept.size());
    const SpaceId file_space(Check(H5Dget_space(datasets_[c].get()), where_, "reading the shape of", spec.path));
    CheckStatus(H5Sselect_none(file_space.get()), where_, "selecting rows of", spec.path);
    for (const Run& run : runs) {
      hsize_t start[2] = {static_cast<hsize_t>(run.first.sample), 0};
      hsize_t count[2] = {run.count, spec.width};
      if (space_.grouped()) {
        start[0] = static_cast<hsize_t>(run.first.group);
        start[1] = static_cast<hsize_t>(run.first.sample);
        count[0] = 1;
        count[1] = run.count;
      }
      CheckStatus(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_OR, start, nullptr, count, nullptr), where_,
                  "selecting rows of", spec.path);
    }
    const hsize_t memory_dims[2] = {m, spec.width};
    const SpaceId memory_space(Check(H5Screate_simple(spec.width > 0 ? 2 : 1, memory_dims, nullptr), where_,
                                     "creating a dataspace for", spec.path));
    CheckStatus(H5Dwrite(datasets_[c].get(), memory_types_[c].get(), memory_space.get(), file_space.get(), H5P_DEFAULT,
                         values[c]),
                where_, "writing", spec.path);
    CheckStatus(H5Dflush(datasets_[c].get()), where_, "flushing", spec.path);
  }
}

std::optional<std::string> SampleTable::TryReadRows(std::size_t column, std::int64_t group, std::int64_t first,
                                                    std::int64_t count, void* out) const {
  if (count == 0) return std::nullopt;
  const ColumnSpec& spec = specs_[column];
  if (!stored(column)) {
    FillRows(spec, static_cast<std::size_t>(count) * Width(column), out);
    return std::nullopt;
  }
  // Samples beyond stored_below read as the fill.
  const std::int64_t stored_end = space_.grouped() ? first + count : std::min(first + count, StoredRows(column));
  if (stored_end < first + count) {
    const std::int64_t held = std::max<std::int64_t>(0, stored_end - first);
    const std::size_t row_bytes = Width(column) * ElementSize(spec);
    FillRows(spec, static_cast<std::size_t>(count - held) * Width(column),
             static_cast<unsigned char*>(out) + static_cast<std::size_t>(held) * row_bytes);
    if (held == 0) return std::nullopt;
    count = held;
  }
  const SpaceId file_space(Check(H5Dget_space(datasets_[column].get()), where_, "reading the shape of", spec.path));
  hsize_t start[2] = {static_cast<hsize_t>(first), 0};
  hsize_t rows[2] = {static_cast<hsize_t>(count), spec.width};
  if (space_.grouped()) {
    start[0] = static_cast<hsize_t>(group);
    start[1] = static_cast<hsize_t>(first);
    rows[0] = 1;
    rows[1] = static_cast<hsize_t>(count);
  }
  CheckStatus(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, rows, nullptr), where_,
              "selecting rows of", spec.path);
  const hsize_t memory_dims[2] = {static_cast<hsize_t>(count), spec.width};
  const SpaceId memory_space(Check(H5Screate_simple(spec.width > 0 ? 2 : 1, memory_dims, nullptr), where_,
                                   "creating a dataspace for", spec.path));
  return hdf5::TryRead(datasets_[column].get(), memory_types_[column].get(), memory_space.get(), file_space.get(), out);
}

void SampleTable::ReadInto(std::size_t column, ColumnType as, std::int64_t group, std::int64_t begin,
                           std::int64_t count, void* out, const SampleStatus* statuses) const {
  CheckType(column, as);
  const ColumnSpec& spec = specs_[column];
  if (count < 0 || begin < 0 || begin + count > space_.samples || group < 0 ||
      group >= std::max<std::int64_t>(1, space_.groups)) {
    throw std::out_of_range(fmt::format("SampleTable: {} is outside the table", Rows(group, begin, begin + count - 1)));
  }
  if (count == 0) return;
  if (const auto problem = TryReadRows(column, group, begin, count, out)) {
    throw InputError(fmt::format("{}: dataset {} is damaged: {} cannot be read ({}){}", where_.file, spec.path,
                                 Rows(group, begin, begin + count - 1), *problem, VerifyHint(where_.file)));
  }
  // Only stored samples must be finite: those beyond stored_below read as the fill.
  const std::int64_t checked = space_.grouped() ? count : std::min(count, StoredRows(column) - begin);
  if (spec.finite == FiniteRule::kNone || !stored(column) || checked <= 0) return;
  std::vector<SampleStatus> read;
  if (statuses == nullptr) {
    read = Statuses(group, begin, checked);
    statuses = read.data();
  }
  if (const auto bad = FirstNonFinite(spec, out, checked, statuses)) {
    const std::int64_t sample = begin + bad->first;
    throw InputError(fmt::format("{}: dataset {} is damaged: {} is {} but holds a non-finite number{}{}", where_.file,
                                 spec.path, Rows(group, sample, sample),
                                 SampleStatusName(statuses[bad->first]),
                                 spec.width > 0 ? fmt::format(" at input {}", bad->second) : std::string(),
                                 VerifyHint(where_.file)));
  }
}

std::vector<SampleStatus> SampleTable::Statuses(std::int64_t group, std::int64_t begin, std::int64_t count) const {
  const std::vector<std::int8_t> raw = Read<std::int8_t>(status_column(), group, begin, count);
  std::vector<SampleStatus> statuses;
  statuses.reserve(raw.size());
  for (std::size_t i = 0; i < raw.size(); ++i) {
    if (!IsKnownStatus(raw[i])) {
      const std::int64_t sample = begin + static_cast<std::int64_t>(i);
      throw InputError(fmt::format("{}: dataset {} is damaged: {} has status {}, which no ringtol writes{}",
                                   where_.file, specs_.back().path, Rows(group, sample, sample), raw[i],
                                   VerifyHint(where_.file)));
    }
    statuses.push_back(static_cast<SampleStatus>(raw[i]));
  }
  return statuses;
}

std::vector<SampleRange> SampleTable::Pending(std::int64_t group, std::int64_t begin, std::int64_t end) const {
  std::vector<SampleRange> pending;
  const auto code = static_cast<std::int8_t>(SampleStatus::kPending);
  const std::int64_t read_end = std::clamp(written_end_, begin, std::max(begin, end));
  for (std::int64_t first = begin; first < read_end; first += kStatusBlock) {
    const std::int64_t count = std::min(kStatusBlock, read_end - first);
    const std::vector<std::int8_t> block = Read<std::int8_t>(status_column(), group, first, count);
    for (std::int64_t i = 0; i < count; ++i) {
      if (block[static_cast<std::size_t>(i)] == code) AppendRun(pending, first + i, first + i + 1);
    }
  }
  AppendRun(pending, read_end, end);
  return pending;
}

std::vector<SampleRange> SampleTable::Finished() const {
  std::vector<SampleRange> finished;
  for (std::int64_t first = 0; first < written_end_; first += kStatusBlock) {
    const std::int64_t count = std::min(kStatusBlock, written_end_ - first);
    const std::vector<SampleStatus> block = Statuses(0, first, count);
    for (std::int64_t i = 0; i < count; ++i) {
      if (block[static_cast<std::size_t>(i)] != SampleStatus::kPending) AppendRun(finished, first + i, first + i + 1);
    }
  }
  return finished;
}

std::vector<RowKey> SampleTable::ChunkFirsts(std::size_t column) const {
  std::vector<RowKey> firsts;
  if (!space_.grouped()) {
    const std::int64_t end = std::min(StoredRows(column), written_end_);
    for (std::int64_t first = 0; first < end; first += space_.chunk_samples) firsts.push_back({0, first});
    return firsts;
  }
  const std::string& path = specs_[column].path;
  const SpaceId dataspace(Check(H5Dget_space(datasets_[column].get()), where_, "reading the shape of", path));
  hsize_t allocated = 0;
  CheckStatus(H5Dget_num_chunks(datasets_[column].get(), dataspace.get(), &allocated), where_,
              "counting the chunks of", path);
  for (hsize_t i = 0; i < allocated; ++i) {
    std::array<hsize_t, 2> offset{};
    unsigned mask = 0;
    haddr_t address = 0;
    hsize_t bytes = 0;
    if (H5Dget_chunk_info(datasets_[column].get(), dataspace.get(), i, offset.data(), &mask, &address, &bytes) < 0) {
      Fail(where_, fmt::format("reading the chunk index of {} failed", path));
    }
    firsts.push_back({static_cast<std::int64_t>(offset[0]), static_cast<std::int64_t>(offset[1])});
  }
  std::sort(firsts.begin(), firsts.end());
  return firsts;
}

TableScan SampleTable::Scan() const {
  TableScan scan;
  const std::int64_t chunk = space_.chunk_samples;
  const auto chunks_of = [&](std::size_t column) { return ChunkFirsts(column); };

  // The statuses of every chunk whose status chunk reads, by its first row.
  std::map<RowKey, std::vector<SampleStatus>> statuses;
  std::vector<DamagedChunk> status_damage;
  const std::size_t status = status_column();
  std::vector<std::int8_t> raw;
  for (const RowKey& first : chunks_of(status)) {
    const std::int64_t count = std::min(chunk, space_.samples - first.sample);
    raw.resize(static_cast<std::size_t>(count));
    std::optional<std::string> problem = TryReadRows(status, first.group, first.sample, count, raw.data());
    if (!problem) {
      const auto unknown = std::find_if(raw.begin(), raw.end(), [](std::int8_t value) { return !IsKnownStatus(value); });
      if (unknown != raw.end()) {
        const std::int64_t sample = first.sample + (unknown - raw.begin());
        problem = fmt::format("{} has status {}, which no ringtol writes", Rows(first.group, sample, sample), *unknown);
      }
    }
    if (problem) {
      status_damage.push_back({status, first.group, {first.sample, first.sample + count}, *problem});
      continue;
    }
    std::vector<SampleStatus>& chunk_statuses = statuses[first];
    for (std::int64_t i = 0; i < count; ++i) {
      const auto value = static_cast<SampleStatus>(raw[static_cast<std::size_t>(i)]);
      chunk_statuses.push_back(value);
      if (value != SampleStatus::kPending) {
        ++scan.done;
      } else if (!space_.grouped()) {
        AppendRun(scan.pending, first.sample + i, first.sample + i + 1);
      }
    }
  }
  // Rows never written are pending, unread.
  if (!space_.grouped()) AppendRun(scan.pending, written_end_, space_.samples);

  std::vector<unsigned char> buffer;
  for (std::size_t c = 0; c < status; ++c) {
    if (!stored(c)) continue;
    const ColumnSpec& spec = specs_[c];
    for (const RowKey& first : chunks_of(c)) {
      const std::int64_t count = std::min(chunk, StoredRows(c) - first.sample);
      buffer.resize(static_cast<std::size_t>(count) * Width(c) * ElementSize(spec));
      std::optional<std::string> problem = TryReadRows(c, first.group, first.sample, count, buffer.data());
      if (!problem && spec.finite != FiniteRule::kNone) {
        const auto found = statuses.find(first);
        if (found != statuses.end()) {
          if (const auto bad = FirstNonFinite(spec, buffer.data(), count, found->second.data())) {
            const std::int64_t sample = first.sample + bad->first;
            problem = fmt::format("{} is {} but holds a non-finite number{}", Rows(first.group, sample, sample),
                                  SampleStatusName(found->second[static_cast<std::size_t>(bad->first)]),
                                  spec.width > 0 ? fmt::format(" at input {}", bad->second) : std::string());
          }
        }
      }
      if (problem) scan.damaged.push_back({c, first.group, {first.sample, first.sample + count}, *problem});
    }
  }
  scan.damaged.insert(scan.damaged.end(), status_damage.begin(), status_damage.end());
  return scan;
}

void SampleTable::Repair(const std::vector<DamagedChunk>& damaged) {
  std::vector<DamagedChunk> recompute;  // of the columns other than the statuses
  for (std::size_t c = 0; c < specs_.size(); ++c) {
    std::vector<std::array<hsize_t, 2>> offsets;
    std::vector<std::pair<std::int64_t, SampleRange>> reported;  // by group, merged
    for (const DamagedChunk& chunk : damaged) {
      if (chunk.column != c) continue;
      offsets.push_back(space_.grouped()
                            ? std::array<hsize_t, 2>{static_cast<hsize_t>(chunk.group),
                                                     static_cast<hsize_t>(chunk.samples.begin)}
                            : std::array<hsize_t, 2>{static_cast<hsize_t>(chunk.samples.begin), 0});
      if (!reported.empty() && reported.back().first == chunk.group &&
          reported.back().second.end == chunk.samples.begin) {
        reported.back().second.end = chunk.samples.end;
      } else {
        reported.emplace_back(chunk.group, chunk.samples);
      }
      if (c != status_column()) recompute.push_back(chunk);
    }
    if (offsets.empty()) continue;
    RewriteChunksWithFill(where_, datasets_[c].get(), specs_[c].path, offsets);
    // HDF5 remembers where it last found a chunk, and its filter mask, in the open dataset:
    // reopened, it reads the rewritten chunks as they now are.
    const PlistId access(Check(H5Dget_access_plist(datasets_[c].get()), where_, "reading the access of",
                               specs_[c].path));
    const FileId file(Check(H5Iget_file_id(datasets_[c].get()), where_, "finding the file of", specs_[c].path));
    datasets_[c].reset();
    datasets_[c] = DatasetId(Check(H5Dopen2(file.get(), specs_[c].stored_path.c_str(), access.get()), where_,
                                   "opening dataset", specs_[c].stored_path));
    for (const auto& [group, range] : reported) {
      std::cerr << fmt::format("ringtol: {}: dataset {} was damaged at {}; they are computed again\n", where_.file,
                               specs_[c].path, Rows(group, range.begin, range.end - 1));
    }
  }
  if (recompute.empty()) return;
  const std::size_t status = status_column();
  const ColumnSpec& spec = specs_[status];
  const SpaceId file_space(Check(H5Dget_space(datasets_[status].get()), where_, "reading the shape of", spec.path));
  std::vector<std::int8_t> pending;
  for (const DamagedChunk& chunk : recompute) {
    const auto count = static_cast<hsize_t>(chunk.samples.end - chunk.samples.begin);
    hsize_t start[2] = {static_cast<hsize_t>(chunk.samples.begin), 0};
    hsize_t rows[2] = {count, 0};
    if (space_.grouped()) {
      start[0] = static_cast<hsize_t>(chunk.group);
      start[1] = static_cast<hsize_t>(chunk.samples.begin);
      rows[0] = 1;
      rows[1] = count;
    }
    CheckStatus(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, rows, nullptr), where_,
                "selecting rows of", spec.path);
    const SpaceId memory(Check(H5Screate_simple(1, &count, nullptr), where_, "creating a dataspace for", spec.path));
    pending.assign(count, static_cast<std::int8_t>(SampleStatus::kPending));
    CheckStatus(H5Dwrite(datasets_[status].get(), memory_types_[status].get(), memory.get(), file_space.get(),
                         H5P_DEFAULT, pending.data()),
                where_, "writing", spec.path);
  }
  CheckStatus(H5Dflush(datasets_[status].get()), where_, "flushing", spec.path);
}

void SampleTable::MarkPending(std::span<const std::int64_t> samples) const {
  if (samples.empty()) return;
  std::vector<RowKey> rows;
  rows.reserve(samples.size());
  for (const std::int64_t sample : samples) rows.push_back({0, sample});
  const std::size_t status = status_column();
  const ColumnSpec& spec = specs_[status];
  const SpaceId file_space(Check(H5Dget_space(datasets_[status].get()), where_, "reading the shape of", spec.path));
  CheckStatus(H5Sselect_none(file_space.get()), where_, "selecting rows of", spec.path);
  for (const Run& run : RunsOf(rows)) {
    const hsize_t start[1] = {static_cast<hsize_t>(run.first.sample)};
    const hsize_t count[1] = {run.count};
    CheckStatus(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_OR, start, nullptr, count, nullptr), where_,
                "selecting rows of", spec.path);
  }
  const auto m = static_cast<hsize_t>(rows.size());
  const SpaceId memory(Check(H5Screate_simple(1, &m, nullptr), where_, "creating a dataspace for", spec.path));
  const std::vector<std::int8_t> pending(rows.size(), static_cast<std::int8_t>(SampleStatus::kPending));
  CheckStatus(H5Dwrite(datasets_[status].get(), memory_types_[status].get(), memory.get(), file_space.get(),
                       H5P_DEFAULT, pending.data()),
              where_, "writing", spec.path);
  CheckStatus(H5Dflush(datasets_[status].get()), where_, "flushing", spec.path);
}

void SampleTable::Grow(std::int64_t samples) {
  RINGTOL_CHECK(!space_.grouped() && space_.extendable, space_.grouped(), space_.extendable, samples);
  for (std::size_t c = 0; c < specs_.size(); ++c) {
    if (!stored(c)) continue;
    const std::string& path = specs_[c].path;
    const SpaceId dataspace(Check(H5Dget_space(datasets_[c].get()), where_, "reading the shape of", path));
    hsize_t dims[2] = {0, 0};
    H5Sget_simple_extent_dims(dataspace.get(), dims, nullptr);
    const auto rows = static_cast<hsize_t>(std::min(samples, specs_[c].stored_below));
    if (dims[0] >= rows) continue;
    dims[0] = rows;
    CheckStatus(H5Dset_extent(datasets_[c].get(), dims), where_, "extending", path);
  }
  space_.samples = std::max(space_.samples, samples);
}

bool SampleTable::SameStorage(const SampleTable& other) const {
  if (other.specs_.size() != specs_.size() || other.space_.chunk_samples != space_.chunk_samples) return false;
  const auto filter = [](const PlistId& dcpl, int k) {
    unsigned flags = 0;
    std::size_t values = 0;  // asks for none of its parameters: HDF5 then needs no array
    return H5Pget_filter2(dcpl.get(), static_cast<unsigned>(k), &flags, &values, nullptr, 0, nullptr, nullptr);
  };
  for (std::size_t c = 0; c < specs_.size(); ++c) {
    if (stored(c) != other.stored(c)) return false;
    if (!stored(c)) continue;  // a column neither file's schema has
    const PlistId a(Check(H5Dget_create_plist(other.datasets_[c].get()), other.where_, "reading the layout of",
                          specs_[c].path));
    const PlistId b(Check(H5Dget_create_plist(datasets_[c].get()), where_, "reading the layout of", specs_[c].path));
    const int filters = H5Pget_nfilters(a.get());
    if (filters < 0 || filters != H5Pget_nfilters(b.get())) return false;
    for (int k = 0; k < filters; ++k) {
      const H5Z_filter_t id = filter(a, k);
      if (id < 0 || id != filter(b, k)) return false;
    }
    hsize_t x[2] = {0, 0};
    hsize_t y[2] = {0, 0};
    if (H5Pget_chunk(a.get(), 2, x) != H5Pget_chunk(b.get(), 2, y) || x[0] != y[0] || x[1] != y[1]) return false;
  }
  return true;
}

std::int64_t SampleTable::CopyChunks(const SampleTable& other, std::span<const RowKey> firsts) {
  if (firsts.empty()) return 0;
  if (!space_.grouped()) {
    for (const RowKey& first : firsts) {
      written_end_ = std::max(written_end_, std::min(space_.samples, first.sample + space_.chunk_samples));
    }
  }
  std::int64_t copied = 0;
  std::vector<unsigned char> buffer;
  // Every column before the statuses, flushed, so that a status copied vouches for its sample.
  for (std::size_t c = 0; c < specs_.size(); ++c) {
    const std::string& path = specs_[c].path;
    if (!stored(c)) continue;
    for (const RowKey& first : firsts) {
      if (!space_.grouped() && first.sample >= StoredRows(c)) continue;
      const hsize_t offset[2] = {static_cast<hsize_t>(space_.grouped() ? first.group : first.sample),
                                 static_cast<hsize_t>(space_.grouped() ? first.sample : 0)};
      hsize_t bytes = 0;
      CheckStatus(H5Dget_chunk_storage_size(other.datasets_[c].get(), offset, &bytes), other.where_,
                  "sizing a chunk of", path);
      buffer.resize(static_cast<std::size_t>(bytes));
      std::uint32_t mask = 0;
      CheckStatus(H5Dread_chunk(other.datasets_[c].get(), H5P_DEFAULT, offset, &mask, buffer.data()), other.where_,
                  "reading a chunk of", path);
      CheckStatus(H5Dwrite_chunk(datasets_[c].get(), H5P_DEFAULT, mask, offset, buffer.size(), buffer.data()), where_,
                  "writing a chunk of", path);
      copied += static_cast<std::int64_t>(bytes);
    }
    CheckStatus(H5Dflush(datasets_[c].get()), where_, "flushing", path);
  }
  return copied;
}

SampleTable::AbsorbPlan SampleTable::PlanAbsorb(const SampleTable& from, bool as_stored) const {
  AbsorbPlan plan;
  const bool whole_chunks = as_stored && from.space_.samples == space_.samples && SameStorage(from);
  const std::int64_t chunk = from.space_.chunk_samples;
  const std::size_t status = status_column();
  const auto pending = static_cast<std::int8_t>(SampleStatus::kPending);
  const auto ok = static_cast<std::int8_t>(SampleStatus::kOk);
  std::vector<std::int8_t> theirs(static_cast<std::size_t>(chunk));
  std::vector<RowKey> wanted;
  for (const RowKey& first : from.ChunkFirsts(from.status_column())) {
    const std::int64_t count = std::min(chunk, from.space_.samples - first.sample);
    if (from.TryReadRows(status, first.group, first.sample, count, theirs.data())) continue;
    const auto theirs_end = theirs.begin() + count;
    if (std::any_of(theirs.begin(), theirs_end, [](std::int8_t value) { return !IsKnownStatus(value); })) continue;
    const std::vector<std::int8_t> ours = Read<std::int8_t>(status, first.group, first.sample, count);
    wanted.clear();
    for (std::int64_t i = 0; i < count; ++i) {
      const auto k = static_cast<std::size_t>(i);
      if (theirs[k] == pending || ours[k] != pending) continue;
      wanted.push_back({first.group, first.sample + i});
      if (theirs[k] != ok) plan.failed.push_back(wanted.back());
    }
    if (wanted.empty()) continue;
    plan.samples += static_cast<std::int64_t>(wanted.size());
    const bool ours_empty = std::all_of(ours.begin(), ours.end(), [&](std::int8_t value) { return value == pending; });
    if (whole_chunks && ours_empty) {
      plan.whole.push_back(first);
      plan.whole_samples += static_cast<std::int64_t>(wanted.size());
    } else {
      plan.rows.insert(plan.rows.end(), wanted.begin(), wanted.end());
    }
  }
  return plan;
}

SampleTable::Absorbed SampleTable::Absorb(const SampleTable& from, const AbsorbPlan& plan) {
  Absorbed absorbed;
  const std::int64_t chunk = from.space_.chunk_samples;
  std::vector<std::vector<unsigned char>> read(specs_.size());
  std::vector<std::vector<unsigned char>> kept(specs_.size());
  std::vector<const void*> values(specs_.size());
  for (auto row = plan.rows.begin(); row != plan.rows.end();) {
    // The rows of one chunk of `from`, read whole, column by column.
    const RowKey first{row->group, row->sample - row->sample % chunk};
    const auto end = std::find_if(row, plan.rows.end(), [&](const RowKey& key) {
      return key.group != first.group || key.sample >= first.sample + chunk;
    });
    const std::span<const RowKey> keys(row, end);
    row = end;
    const std::int64_t count = std::min(chunk, from.space_.samples - first.sample);
    bool readable = true;
    for (std::size_t c = 0; c < specs_.size() && readable; ++c) {
      const std::size_t row_bytes = Width(c) * ElementSize(specs_[c]);
      read[c].resize(static_cast<std::size_t>(count) * row_bytes);
      readable = !from.TryReadRows(c, first.group, first.sample, count, read[c].data());
      kept[c].clear();
      for (const RowKey& key : keys) {
        const auto at = read[c].begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(key.sample - first.sample) * row_bytes);
        kept[c].insert(kept[c].end(), at, at + static_cast<std::ptrdiff_t>(row_bytes));
      }
      values[c] = kept[c].data();
    }
    if (!readable) continue;  // a damaged row of the shard: computed again
    Write(keys, values);
    absorbed.samples += static_cast<std::int64_t>(keys.size());
  }
  absorbed.bytes = CopyChunks(from, plan.whole);
  absorbed.samples += plan.whole_samples;
  absorbed.chunk_samples = plan.whole_samples;
  return absorbed;
}

}  // namespace ringtol::jobs::hdf5
