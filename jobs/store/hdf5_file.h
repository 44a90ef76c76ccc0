// The HDF5 machinery the results files share (jobs/store/campaign_store.h,
// jobs/store/allocation_store.h): owning handles, errors turned into exceptions that name
// the file, attributes, checksummed datasets, the sample status enumeration, opening a file
// a killed writer left, the writers' lock and publishing a new file under its name, and
// arrays of one or two dimensions written and read whole or by rows.
// Private to jobs/store: the public headers never expose HDF5.
//
// Failure: every function throws through Fail, so an InputError (the user's file is wrong
// or damaged) while a file is opened and validated (Where::input), a std::runtime_error
// (the system failed: disk full) once it is open.
#pragma once

#include <hdf5.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "engine/error_motion.h"
#include "sampling/assembly_sampler.h"

namespace ringtol::jobs::hdf5 {

// A reader of a file being written may read a chunk while the writer rewrites it in place:
// that torn read fails its checksum once and succeeds on the next attempt. Real damage
// fails every attempt, which costs a damaged chunk these few milliseconds.
inline constexpr int kRawReadAttempts = 3;

// ---------------------------------------------------------------------------------------
// Handles and errors

template <herr_t (*Closer)(hid_t)>
class Id {
 public:
  Id() = default;
  explicit Id(hid_t id) : id_(id) {}
  ~Id() { reset(); }
  Id(Id&& other) noexcept : id_(std::exchange(other.id_, H5I_INVALID_HID)) {}
  Id& operator=(Id&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, H5I_INVALID_HID);
    }
    return *this;
  }
  Id(const Id&) = delete;
  Id& operator=(const Id&) = delete;

  hid_t get() const { return id_; }
  // Closes now and reports whether HDF5 managed to (a file's close flushes).
  bool Close() {
    const hid_t id = std::exchange(id_, H5I_INVALID_HID);
    return id < 0 || Closer(id) >= 0;
  }
  void reset() {
    if (id_ >= 0) Closer(id_);
    id_ = H5I_INVALID_HID;
  }

 private:
  hid_t id_ = H5I_INVALID_HID;
};

using FileId = Id<H5Fclose>;
using GroupId = Id<H5Gclose>;
using DatasetId = Id<H5Dclose>;
using AttributeId = Id<H5Aclose>;
using SpaceId = Id<H5Sclose>;
using TypeId = Id<H5Tclose>;
using PlistId = Id<H5Pclose>;

// HDF5 prints its error stack to stderr by default; ringtol turns failures into exceptions
// instead. Restores the previous handler so that other HDF5 users in the process keep theirs.
class QuietErrors {
 public:
  QuietErrors();
  ~QuietErrors();
  QuietErrors(const QuietErrors&) = delete;
  QuietErrors& operator=(const QuietErrors&) = delete;

 private:
  H5E_auto2_t function_ = nullptr;
  void* data_ = nullptr;
};

// The most specific message on HDF5's error stack; for system errors only the errno text,
// since the full message also carries times, descriptors and buffer addresses.
std::string Hdf5Detail();

// Who is to blame for a failure: while a file is opened and validated, the user (a wrong
// or damaged file: InputError); once it is open, the system (disk full: runtime_error).
struct Where {
  std::string file;
  bool input = false;
};

[[noreturn]] void Fail(const Where& where, const std::string& what);
hid_t Check(hid_t id, const Where& where, std::string_view action, std::string_view object);
void CheckStatus(herr_t status, const Where& where, std::string_view action, std::string_view object);

// ---------------------------------------------------------------------------------------
// Types

TypeId VariableString(const Where& where);
// Fixed length, because variable-length data lives in the global heap, which SWMR readers
// cannot follow safely while it grows. Null-terminated (`bytes` includes the terminator).
TypeId FixedString(const Where& where, std::size_t bytes);
// The one-byte enumeration of SampleStatus, by SampleStatusName.
TypeId StatusType(const Where& where);
// Whether `value` is a SampleStatus some ringtol writes.
bool IsKnownStatus(std::int8_t value);

// ---------------------------------------------------------------------------------------
// Attributes

// The HDF5 types of a number a dataset or attribute keeps, T one of std::int8_t,
// std::int32_t, std::int64_t, std::uint64_t, double.
struct NumberTypes {
  hid_t native;  // in memory
  hid_t file;    // little-endian, as the files keep it
};
template <typename T>
NumberTypes TypesOf() {
  if constexpr (std::is_same_v<T, std::int8_t>) return {H5T_NATIVE_INT8, H5T_STD_I8LE};
  else if constexpr (std::is_same_v<T, std::int32_t>) return {H5T_NATIVE_INT32, H5T_STD_I32LE};
  else if constexpr (std::is_same_v<T, std::int64_t>) return {H5T_NATIVE_INT64, H5T_STD_I64LE};
  else if constexpr (std::is_same_v<T, std::uint64_t>) return {H5T_NATIVE_UINT64, H5T_STD_U64LE};
  else {
    static_assert(std::is_same_v<T, double>, "a number the results files keep");
    return {H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE};
  }
}


void WriteAttribute(const Where& where, hid_t location, const char* name, hid_t file_type, hid_t memory_type,
                    const void* value);
// Variable-length, so that h5py reads it as str; written before SWMR starts.
void WriteStringAttribute(const Where& where, hid_t location, const char* name, const std::string& value);
// Overwrites an attribute that exists (allowed in SWMR mode, unlike creating one).
void UpdateAttribute(const Where& where, hid_t location, const char* name, hid_t memory_type, const void* value);
std::optional<AttributeId> OpenAttribute(const Where& where, hid_t location, const char* name);
H5T_class_t AttributeClass(const Where& where, const AttributeId& attribute, const char* name);
std::optional<std::string> ReadStringAttribute(const Where& where, hid_t location, const char* name);

// What an error-motion dataset states beside its values, as ISO 230-7 asks a measurement
// to (docs/results.md): `filter` ("ISO 16610-21 Gaussian" or "none"), `cutoff_upr` (0:
// none) and `revolutions` ("every revolution of the life").
void WriteErrorMotionAttributes(const Where& where, hid_t dataset, const engine::ErrorMotionFilter& filter);
// The filter a dataset states: unfiltered where it states none, as files written before
// the filter were.
engine::ErrorMotionFilter ReadErrorMotionFilter(const Where& where, hid_t dataset);

template <typename T>
std::optional<T> ReadNumberAttribute(const Where& where, hid_t location, const char* name, H5T_class_t wanted,
                                     hid_t memory_type) {
  const std::optional<AttributeId> attribute = OpenAttribute(where, location, name);
  if (!attribute) return std::nullopt;
  if (AttributeClass(where, *attribute, name) != wanted) Fail(where, fmt::format("attribute {} is not a number", name));
  T value{};
  CheckStatus(H5Aread(attribute->get(), memory_type, &value), where, "reading attribute", name);
  return value;
}
// As above, of the class and through the memory type of T (TypesOf).
template <typename T>
std::optional<T> ReadNumberAttribute(const Where& where, hid_t location, const char* name) {
  return ReadNumberAttribute<T>(where, location, name, std::is_floating_point_v<T> ? H5T_FLOAT : H5T_INTEGER,
                                TypesOf<T>().native);
}

// ---------------------------------------------------------------------------------------
// Datasets

// Without time stamps, two runs of the same job write the same bytes.
PlistId ObjectCreation(const Where& where, hid_t plist_class);
// Appended last to a dataset's filters, so that it checks the bytes as stored: a damaged
// chunk then fails to read instead of reading as other numbers.
void AddChecksum(const Where& where, const PlistId& dcpl, const std::string& path);
bool HasChecksum(const Where& where, hid_t dataset, const std::string& path);

// One-dimensional description datasets [n], in one chunk so that they carry a checksum:
// fixed-length strings (as wide as the longest), int32, int64, float64.
void WriteStrings(const Where& where, hid_t file, const std::string& path, const std::vector<std::string>& values,
                  bool checksum);
void WriteInts(const Where& where, hid_t file, const std::string& path, const std::vector<std::int32_t>& values,
               bool checksum);
// Reads a whole one-dimensional dataset of fixed-length strings, or of integers as int32.
std::vector<std::string> ReadStrings(const Where& where, hid_t file, const std::string& path);
std::vector<std::int32_t> ReadInts(const Where& where, hid_t file, const std::string& path);

// The design's coordinates as /inputs/name, quantity, component, source, roller, order
// [d], in a group /inputs that exists; read back, InputError when they disagree in length
// or name an unknown source.
void WriteInputDescriptions(const Where& where, hid_t file, const std::vector<sampling::SampledInput>& inputs,
                            bool checksum);
std::vector<sampling::SampledInput> ReadInputDescriptions(const Where& where, hid_t file);
// The first way two input lists differ ("inputs differ (...)"), `now` naming the job that
// asks ("this campaign"), or nothing.
std::optional<std::string> InputDifference(const std::vector<sampling::SampledInput>& file,
                                           const std::vector<sampling::SampledInput>& now, std::string_view now_name);

// Reads the selection, retrying kRawReadAttempts times; HDF5's reason when it does not read
// (a damaged chunk: checksum, decompression or I/O).
std::optional<std::string> TryRead(hid_t dataset, hid_t memory_type, hid_t memory_space, hid_t file_space, void* data);

// Stores each chunk at `offsets` (its first element) as its fill values, with its filters
// skipped (its filter mask says so, and readers honour it): HDF5 can then take it without
// reading the damaged one, and the next write into it runs the filters again. Flushes.
void RewriteChunksWithFill(const Where& where, hid_t dataset, const std::string& path,
                           const std::vector<std::array<hsize_t, 2>>& offsets);

// ---------------------------------------------------------------------------------------
// Files

// HDF5 1.10's latest format (SWMR), HDF5's own flock() off (FileLock guards writers).
PlistId FileAccess(const Where& where);
// Read-only, in SWMR-read mode so that a file being written, or left by a killed writer
// (superblock flags still set, end of allocation stale), opens too. InputError for a
// missing path, a directory, a file that is not HDF5 or truncated.
FileId OpenForReading(const std::filesystem::path& path);
// Read-write, as h5clear does after a killed SWMR writer: its superblock flags forgotten,
// its end-of-allocation mark moved to the end of the file so that new objects never land
// on old ones. InputError when the file cannot be opened.
FileId OpenForWriting(const std::filesystem::path& path);
// Its root attribute `format`, if it has one that reads as a string.
std::optional<std::string> FormatOf(const Where& where, hid_t file);

// Where an index of shards lists them (jobs/store/campaign_store.h, allocation_store.h).
inline constexpr const char* kShardFiles = "/shards/file";

// Where a results file keeps its samples: in itself, or in the shards it is the index of.
// The root attribute `layout` says which ("file", "shard index"), and an index's
// `rows_schema` the schema of its rows (its shards are files of that schema): an index's
// schema_version numbers the index's own layout, so a store's next schema never reads as
// an index. Files written before `layout` existed have neither attribute.
enum class Layout { kFile, kShardIndex };
struct StoredLayout {
  Layout layout = Layout::kFile;
  int rows_schema = 0;  // the schema of the samples' rows (a file's own schema_version)
};
void WriteLayout(const Where& where, hid_t file, const StoredLayout& layout);
// InputError for a `layout` no ringtol writes, or an index without `rows_schema`. A file
// without `layout` is an index exactly when `schema_version` is `legacy_index_schema`, its
// rows then of `legacy_rows_schema`.
StoredLayout ReadLayout(const Where& where, hid_t file, int schema_version, int legacy_index_schema,
                        int legacy_rows_schema);
// Whether `file` lists shards in kShardFiles: it is an index of shards (a campaign's or an
// allocation's), whatever its schema says.
bool ListsShards(hid_t file);
// The shards an index at `index` lists, resolved beside it, each one checked to exist:
// HDF5 would read a missing shard's rows as fill values without an error. InputError
// naming a missing one, or a name that is not a file beside the index.
// `may_be_missing`, when given, names the missing shards to leave out instead.
std::vector<std::filesystem::path> ListedShardFiles(const Where& where, hid_t file, const std::filesystem::path& index,
                                                    bool (*may_be_missing)(const std::filesystem::path& shard) = nullptr);
// Writes an index of shards: a new file beside `index` that `write` fills and that lists
// `shards` (file names beside it) in kShardFiles, renamed over `index` once closed, so a
// kill leaves the old index or the new one (and a stale temporary the next call removes).
// Where a join of an index's shards writes: `out` itself, or, when `out` is the index
// (in place), a temporary beside it (what a killed join left there removed) that replaces
// the index once complete.
struct JoinTarget {
  std::filesystem::path path;
  bool in_place = false;
};
JoinTarget PrepareJoin(const std::filesystem::path& index, const std::filesystem::path& out);
void ReplaceIndex(const Where& where, const std::filesystem::path& index, const std::vector<std::string>& shards,
                  const std::function<void(hid_t file)>& write);

// The path a new results file is built under before Publish gives it its name, so that a
// kill while creating never leaves a half-made file under that name. InputError
// `exists_message` when the path exists, naming the directory when that does not exist.
std::filesystem::path PrepareCreate(const std::filesystem::path& path, const std::string& exists_message);
// A new file at `temporary` (the latest format, FileAccess), refusing one that exists;
// InputError naming `path` when it cannot be created.
FileId CreateExclusive(const std::filesystem::path& temporary, const std::filesystem::path& path);
// Gives the finished file its name without ever replacing a file of that name.
void Publish(const std::filesystem::path& temporary, const std::filesystem::path& path,
             const std::string& exists_message);

// A lock that keeps two writers off one file: HDF5's own lock is released once a writer
// enters SWMR mode, and the flags that would refuse a second writer are cleared on resume
// after a kill. An open file description lock: it also holds between two stores of one
// process, never blocks readers, and dies with the process.
class FileLock {
 public:
  FileLock() = default;
  ~FileLock();
  FileLock(FileLock&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
  FileLock& operator=(FileLock&& other) noexcept {
    std::swap(fd_, other.fd_);
    return *this;
  }
  // InputError when another run holds it.
  static FileLock Acquire(const std::filesystem::path& path, const std::string& name);
  // The lock of a results file a run resumes: InputError when it does not exist (naming
  // `job`, "campaign", to run without --resume), is not a regular file, or is held.
  static FileLock ToResume(const std::filesystem::path& path, std::string_view job);
  // Whether a writer holds the lock of the file at `path` now (false for a missing file, or
  // on a file system without locks).
  static bool Held(const std::filesystem::path& path);

 private:
  int fd_ = -1;
};

// A store's new results file, whole or not at all: built under a temporary name
// (PrepareCreate) and given `path` (Publish) once `write` has written it, with `file` and
// `lock` (the store's own members) holding the open file and its writer's lock. When
// anything fails, `close` closes what the store opened and the temporary is removed.
void CreateWhole(const std::filesystem::path& path, const std::string& exists_message, FileId& file, FileLock& lock,
                 const std::function<void()>& write, const std::function<void()>& close);
// What a store's destructor does: `commit` what it buffers, then `close` (false when HDF5
// failed to), never throwing: errors go to stderr, naming the file.
void CommitAndClose(const Where& where, const std::function<void()>& commit, const std::function<bool()>& close);

// The 1-based line at which two texts first differ, for identity messages.
std::size_t FirstDifferingLine(const std::string& a, const std::string& b);

// How a field of a results file's identity differs from the run's, for resume's refusal:
// "seed differs ('7' in the file, '8' now)"; a text by its first differing line.
template <typename T>
std::optional<std::string> WordDifference(std::string_view field, const T& file, const T& now) {
  if (file == now) return std::nullopt;
  return fmt::format("{} differs ('{}' in the file, '{}' now)", field, file, now);
}
std::optional<std::string> TextDifference(std::string_view field, const std::string& file, const std::string& now);


// ---------------------------------------------------------------------------------------
// Arrays: chunked datasets of one or two dimensions (rows, and columns of a row), created
// from a spec, written and read whole or by rows. A row is the unit a store appends and
// reads (a sample, a candidate, a failure); the columns are read together.

struct Shape {
  hsize_t rows = 0;
  hsize_t columns = 0;  // 0: one-dimensional [rows]
  int rank() const { return columns == 0 ? 1 : 2; }
};

// A new dataset. Type ids are borrowed, not owned: they must outlive CreateArray.
struct ArraySpec {
  std::string path;
  hid_t file_type = H5T_IEEE_F64LE;  // a number, an enumeration or a fixed-length string
  Shape shape;
  hsize_t chunk_rows = 1;  // each at least 1 (0 counts as 1)
  hsize_t chunk_columns = 1;
  bool extendable = false;  // along rows, up to max_rows (H5S_UNLIMITED: without end)
  hsize_t max_rows = 0;
  const void* fill = nullptr;  // one value of fill_type (an enumeration's own type), or HDF5's zeros
  hid_t fill_type = H5T_NATIVE_DOUBLE;
};
// Chunked, Fletcher-32 last when `checksum`, without time stamps (ObjectCreation); its
// chunks are allocated when first written, so rows never written take no space.
DatasetId CreateArray(const Where& where, hid_t file, const ArraySpec& spec, bool checksum);

// The memory type int8 codes of an enumeration dataset move through (its own native type,
// since HDF5 converts no integer to an enumeration); an invalid id for any other dataset.
TypeId EnumMemoryType(const Where& where, hid_t dataset, const std::string& path);

// Writes `count` rows from row `first` (every column, row-major in `memory_type`; an
// enumeration's int8 codes with H5T_NATIVE_INT8), extending an extendable dataset whose
// rows end before them, and flushes it.
void WriteRows(const Where& where, hid_t dataset, const std::string& path, hid_t memory_type, hsize_t first,
               hsize_t count, const void* data);
// Writes the dataset at `path` whole, as `rows` rows: an extendable one is resized to them
// first, shorter or longer.
void WriteWhole(const Where& where, hid_t file, const std::string& path, hid_t memory_type, hsize_t rows,
                const void* data);

// Reads rows [first, first + count) (every column, row-major; an enumeration's int8 codes
// whatever `memory_type`) into `data`, retrying as TryRead; HDF5's reason when they do not
// read (a damaged chunk, or rows beyond the dataset's).
std::optional<std::string> TryReadRows(const Where& where, hid_t dataset, const std::string& path,
                                       hid_t memory_type, hsize_t first, hsize_t count, void* data);
// The dataset at `path` whole, row-major, T a number of TypesOf (std::int8_t for an
// enumeration). Fail unless it has `columns` columns (0: one-dimensional); InputError
// "dataset <path> is damaged (<HDF5's reason>)" when it does not read, even in a file that
// is open (`where.input` false): the file's bytes are wrong, not the system.
template <typename T>
std::vector<T> ReadWhole(const Where& where, hid_t file, const std::string& path, hsize_t columns = 0);
// Rows [begin, end) of the float64 dataset at `path` as ReadWhole, none opened when they are none;
// InputError "dataset <path> is damaged: <rows> <begin> to <end - 1> cannot be read
// (<reason>)", `rows` naming what a row is ("samples").
std::vector<double> ReadRows(const Where& where, hid_t file, const std::string& path, hsize_t begin, hsize_t end,
                             hsize_t columns, std::string_view rows);

}  // namespace ringtol::jobs::hdf5
