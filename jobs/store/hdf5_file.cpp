#include "jobs/store/hdf5_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <chrono>
#include <cstring>
#include <iostream>
#include <stdexcept>
#include <system_error>
#include <thread>

#include "jobs/campaign/sample_record.h"
#include "jobs/inputs/input_error.h"

namespace ringtol::jobs::hdf5 {
namespace {

namespace fs = std::filesystem;

// SWMR readers read checksummed metadata again while a writer may be rewriting it, sleeping
// 1 ns, 2 ns, 4 ns, ... between attempts: HDF5's default of 100 attempts turns a damaged
// file into a hang of centuries; 24 attempts wait about 17 ms in all before giving up.
constexpr unsigned kMetadataReadAttempts = 24;
constexpr std::chrono::milliseconds kRawReadRetryDelay{2};

// HDF5 shuts itself down at exit. After an object header that failed its checksum it
// cannot (the half-loaded object stays in its free lists) and prints "HDF5: infinite loop
// closing library" below ringtol's own message. Every file is closed explicitly before
// exit, so skipping that shutdown loses nothing. It must precede HDF5's first call, hence
// a static initialiser.
[[maybe_unused]] const herr_t kNoShutdownAtExit = H5dont_atexit();

// Sets one of HDF5's private file-access properties (those h5clear uses), if this HDF5 has it.
bool SetHiddenFlag(const Where& where, const PlistId& fapl, const char* name) {
  if (H5Pexist(fapl.get(), name) <= 0) return false;
  hbool_t value = true;
  CheckStatus(H5Pset(fapl.get(), name, &value), where, "setting file access property", name);
  return true;
}

// A description dataset [n]: one chunk, so that it can carry a checksum.
PlistId DescriptionCreation(const Where& where, hsize_t count, const std::string& path, bool checksum) {
  PlistId dcpl = ObjectCreation(where, H5P_DATASET_CREATE);
  if (!checksum) return dcpl;
  const hsize_t chunk[1] = {std::max<hsize_t>(1, count)};
  CheckStatus(H5Pset_chunk(dcpl.get(), 1, chunk), where, "chunking", path);
  AddChecksum(where, dcpl, path);
  return dcpl;
}

// One dimension, its length, and the dataset's type.
std::pair<hsize_t, TypeId> OpenDescription(const Where& where, hid_t file, const std::string& path,
                                           DatasetId& dataset) {
  dataset = DatasetId(Check(H5Dopen2(file, path.c_str(), H5P_DEFAULT), where, "opening dataset", path));
  const SpaceId space(Check(H5Dget_space(dataset.get()), where, "reading the shape of", path));
  hsize_t dims[1] = {0};
  if (H5Sget_simple_extent_ndims(space.get()) != 1) Fail(where, fmt::format("dataset {} is not one-dimensional", path));
  H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  return {dims[0], TypeId(Check(H5Dget_type(dataset.get()), where, "reading the type of", path))};
}

}  // namespace

QuietErrors::QuietErrors() {
  H5Eget_auto2(H5E_DEFAULT, &function_, &data_);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

QuietErrors::~QuietErrors() { H5Eset_auto2(H5E_DEFAULT, function_, data_); }

std::string Hdf5Detail() {
  std::string detail;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_UPWARD,
      [](unsigned n, const H5E_error2_t* error, void* data) -> herr_t {
        if (n == 0 && error->desc != nullptr) *static_cast<std::string*>(data) = error->desc;
        return 0;
      },
      &detail);
  const std::string key = "error message = '";
  if (const std::size_t at = detail.find(key); at != std::string::npos) {
    const std::size_t begin = at + key.size();
    return detail.substr(begin, detail.find('\'', begin) - begin);
  }
  return detail;
}

void Fail(const Where& where, const std::string& what) {
  std::string message = where.file + ": " + what;
  if (const std::string detail = Hdf5Detail(); !detail.empty()) message += " (HDF5: " + detail + ")";
  if (where.input) throw InputError(message);
  throw std::runtime_error(message);
}

hid_t Check(hid_t id, const Where& where, std::string_view action, std::string_view object) {
  if (id < 0) Fail(where, fmt::format("{} {} failed", action, object));
  return id;
}

void CheckStatus(herr_t status, const Where& where, std::string_view action, std::string_view object) {
  if (status < 0) Fail(where, fmt::format("{} {} failed", action, object));
}

// ---------------------------------------------------------------------------------------

TypeId VariableString(const Where& where) {
  TypeId type(Check(H5Tcopy(H5T_C_S1), where, "creating", "a string type"));
  CheckStatus(H5Tset_size(type.get(), H5T_VARIABLE), where, "sizing", "a string type");
  CheckStatus(H5Tset_cset(type.get(), H5T_CSET_UTF8), where, "setting", "a string type's character set");
  return type;
}

// Null-terminated, so that h5dump shows the text without its padding; h5py reads bytes
// either way.
TypeId FixedString(const Where& where, std::size_t bytes) {
  TypeId type(Check(H5Tcopy(H5T_C_S1), where, "creating", "a string type"));
  CheckStatus(H5Tset_size(type.get(), bytes), where, "sizing", "a string type");
  CheckStatus(H5Tset_strpad(type.get(), H5T_STR_NULLTERM), where, "setting", "a string type's padding");
  CheckStatus(H5Tset_cset(type.get(), H5T_CSET_UTF8), where, "setting", "a string type's character set");
  return type;
}

TypeId StatusType(const Where& where) {
  TypeId type(Check(H5Tenum_create(H5T_NATIVE_INT8), where, "creating", "the status type"));
  for (const SampleStatus status : AllSampleStatuses()) {
    const auto value = static_cast<std::int8_t>(status);
    const std::string name(SampleStatusName(status));
    CheckStatus(H5Tenum_insert(type.get(), name.c_str(), &value), where, "naming status", name);
  }
  return type;
}

bool IsKnownStatus(std::int8_t value) {
  const std::vector<SampleStatus>& all = AllSampleStatuses();
  return std::any_of(all.begin(), all.end(), [&](SampleStatus s) { return static_cast<std::int8_t>(s) == value; });
}

// ---------------------------------------------------------------------------------------

void WriteAttribute(const Where& where, hid_t location, const char* name, hid_t file_type, hid_t memory_type,
                    const void* value) {
  SpaceId scalar(Check(H5Screate(H5S_SCALAR), where, "creating", "a scalar dataspace"));
  AttributeId attribute(Check(H5Acreate2(location, name, file_type, scalar.get(), H5P_DEFAULT, H5P_DEFAULT), where,
                              "creating attribute", name));
  CheckStatus(H5Awrite(attribute.get(), memory_type, value), where, "writing attribute", name);
}

void WriteStringAttribute(const Where& where, hid_t location, const char* name, const std::string& value) {
  const TypeId type = VariableString(where);
  const char* text = value.c_str();
  WriteAttribute(where, location, name, type.get(), type.get(), &text);
}

void UpdateAttribute(const Where& where, hid_t location, const char* name, hid_t memory_type, const void* value) {
  const std::optional<AttributeId> attribute = OpenAttribute(where, location, name);
  if (!attribute) Fail(where, fmt::format("attribute {} vanished", name));
  CheckStatus(H5Awrite(attribute->get(), memory_type, value), where, "updating attribute", name);
}

std::optional<AttributeId> OpenAttribute(const Where& where, hid_t location, const char* name) {
  const htri_t exists = H5Aexists(location, name);
  if (exists < 0) Fail(where, fmt::format("looking up attribute {} failed", name));
  if (exists == 0) return std::nullopt;
  return AttributeId(Check(H5Aopen(location, name, H5P_DEFAULT), where, "opening attribute", name));
}

H5T_class_t AttributeClass(const Where& where, const AttributeId& attribute, const char* name) {
  const TypeId type(Check(H5Aget_type(attribute.get()), where, "reading the type of attribute", name));
  return H5Tget_class(type.get());
}

void WriteErrorMotionAttributes(const Where& where, hid_t dataset, const engine::ErrorMotionFilter& filter) {
  WriteStringAttribute(where, dataset, "filter", filter.filtered() ? "ISO 16610-21 Gaussian" : "none");
  WriteAttribute(where, dataset, "cutoff_upr", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &filter.cutoff_upr);
  WriteStringAttribute(where, dataset, "revolutions", "every revolution of the life");
}

engine::ErrorMotionFilter ReadErrorMotionFilter(const Where& where, hid_t dataset) {
  return {ReadNumberAttribute<double>(where, dataset, "cutoff_upr", H5T_FLOAT, H5T_NATIVE_DOUBLE).value_or(0.0)};
}

std::optional<std::string> ReadStringAttribute(const Where& where, hid_t location, const char* name) {
  const std::optional<AttributeId> attribute = OpenAttribute(where, location, name);
  if (!attribute) return std::nullopt;
  const TypeId type(Check(H5Aget_type(attribute->get()), where, "reading the type of attribute", name));
  if (H5Tget_class(type.get()) != H5T_STRING) Fail(where, fmt::format("attribute {} is not a string", name));
  if (H5Tis_variable_str(type.get()) > 0) {
    char* text = nullptr;
    CheckStatus(H5Aread(attribute->get(), type.get(), &text), where, "reading attribute", name);
    std::string value = text != nullptr ? text : "";
    H5free_memory(text);
    return value;
  }
  std::string value(H5Tget_size(type.get()), '\0');
  CheckStatus(H5Aread(attribute->get(), type.get(), value.data()), where, "reading attribute", name);
  value.resize(std::strlen(value.c_str()));
  return value;
}

// ---------------------------------------------------------------------------------------

PlistId ObjectCreation(const Where& where, hid_t plist_class) {
  PlistId plist(Check(H5Pcreate(plist_class), where, "creating", "a property list"));
  CheckStatus(H5Pset_obj_track_times(plist.get(), false), where, "configuring", "a property list");
  return plist;
}

void AddChecksum(const Where& where, const PlistId& dcpl, const std::string& path) {
  CheckStatus(H5Pset_fletcher32(dcpl.get()), where, "setting the Fletcher-32 checksum of", path);
}

bool HasChecksum(const Where& where, hid_t dataset, const std::string& path) {
  const PlistId dcpl(Check(H5Dget_create_plist(dataset), where, "reading the creation properties of", path));
  return H5Pget_filter_by_id2(dcpl.get(), H5Z_FILTER_FLETCHER32, nullptr, nullptr, nullptr, 0, nullptr, nullptr) >= 0;
}

void WriteStrings(const Where& where, hid_t file, const std::string& path, const std::vector<std::string>& values,
                  bool checksum) {
  std::size_t width = 1;  // the terminator
  for (const std::string& value : values) width = std::max(width, value.size() + 1);
  const TypeId type = FixedString(where, width);
  std::string buffer(width * values.size(), '\0');
  for (std::size_t i = 0; i < values.size(); ++i) values[i].copy(buffer.data() + i * width, width);
  const hsize_t dims[1] = {values.size()};
  const SpaceId space(Check(H5Screate_simple(1, dims, nullptr), where, "creating", "a dataspace"));
  const PlistId dcpl = DescriptionCreation(where, dims[0], path, checksum);
  const DatasetId dataset(
      Check(H5Dcreate2(file, path.c_str(), type.get(), space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT), where,
            "creating dataset", path));
  if (values.empty()) return;
  CheckStatus(H5Dwrite(dataset.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()), where,
              "writing dataset", path);
}

void WriteInts(const Where& where, hid_t file, const std::string& path, const std::vector<std::int32_t>& values,
               bool checksum) {
  const hsize_t dims[1] = {values.size()};
  const SpaceId space(Check(H5Screate_simple(1, dims, nullptr), where, "creating", "a dataspace"));
  const PlistId dcpl = DescriptionCreation(where, dims[0], path, checksum);
  const DatasetId dataset(
      Check(H5Dcreate2(file, path.c_str(), H5T_STD_I32LE, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT), where,
            "creating dataset", path));
  if (values.empty()) return;
  CheckStatus(H5Dwrite(dataset.get(), H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), where,
              "writing dataset", path);
}

std::vector<std::string> ReadStrings(const Where& where, hid_t file, const std::string& path) {
  DatasetId dataset;
  const auto [count, type] = OpenDescription(where, file, path, dataset);
  if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) != 0) {
    Fail(where, fmt::format("dataset {} does not hold fixed-length strings", path));
  }
  const std::size_t width = H5Tget_size(type.get());
  std::string buffer(width * count, '\0');
  if (count > 0) {
    CheckStatus(H5Dread(dataset.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()), where, "reading",
                path);
  }
  std::vector<std::string> values(count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::string_view cell(buffer.data() + i * width, width);
    values[i] = std::string(cell.substr(0, cell.find('\0')));
  }
  return values;
}

std::vector<std::int32_t> ReadInts(const Where& where, hid_t file, const std::string& path) {
  DatasetId dataset;
  const auto [count, type] = OpenDescription(where, file, path, dataset);
  if (H5Tget_class(type.get()) != H5T_INTEGER) Fail(where, fmt::format("dataset {} does not hold integers", path));
  std::vector<std::int32_t> values(count);
  if (count > 0) {
    CheckStatus(H5Dread(dataset.get(), H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), where,
                "reading", path);
  }
  return values;
}

namespace {
constexpr std::array<sampling::ErrorSource, 4> kErrorSources = {
    sampling::ErrorSource::kRingShape, sampling::ErrorSource::kRollerShape, sampling::ErrorSource::kRollerPosition,
    sampling::ErrorSource::kSpring};
}  // namespace

void WriteInputDescriptions(const Where& where, hid_t file, const std::vector<sampling::SampledInput>& inputs,
                            bool checksum) {
  const auto strings = [&](auto field) {
    std::vector<std::string> values;
    for (const sampling::SampledInput& input : inputs) values.push_back(field(input));
    return values;
  };
  using Input = sampling::SampledInput;
  WriteStrings(where, file, "/inputs/name", strings([](const Input& in) { return in.name; }),
                    checksum);
  WriteStrings(where, file, "/inputs/quantity", strings([](const Input& in) { return in.quantity; }),
                    checksum);
  WriteStrings(where, file, "/inputs/component", strings([](const Input& in) { return in.component; }),
                    checksum);
  WriteStrings(where, file, "/inputs/source",
                    strings([](const Input& in) { return std::string(sampling::ErrorSourceName(in.source)); }),
                    checksum);
  std::vector<std::int32_t> rollers;
  std::vector<std::int32_t> orders;
  for (const Input& input : inputs) {
    rollers.push_back(input.roller);
    orders.push_back(input.order);
  }
  WriteInts(where, file, "/inputs/roller", rollers, checksum);
  WriteInts(where, file, "/inputs/order", orders, checksum);

}

std::vector<sampling::SampledInput> ReadInputDescriptions(const Where& where, hid_t file) {
  std::vector<sampling::SampledInput> inputs;
  const std::vector<std::string> names = ReadStrings(where, file, "/inputs/name");
  const std::vector<std::string> quantities = ReadStrings(where, file, "/inputs/quantity");
  const std::vector<std::string> components = ReadStrings(where, file, "/inputs/component");
  const std::vector<std::string> sources = ReadStrings(where, file, "/inputs/source");
  const std::vector<std::int32_t> rollers = ReadInts(where, file, "/inputs/roller");
  const std::vector<std::int32_t> orders = ReadInts(where, file, "/inputs/order");
  const std::size_t d = names.size();
  if (d == 0 || quantities.size() != d || components.size() != d || sources.size() != d || rollers.size() != d ||
      orders.size() != d) {
    Fail(where, "the datasets in /inputs describe different numbers of inputs");
  }
  for (std::size_t i = 0; i < d; ++i) {
    sampling::SampledInput input;
    input.name = names[i];
    input.quantity = quantities[i];
    input.component = components[i];
    input.roller = rollers[i];
    input.order = orders[i];
    const auto* source = std::find_if(kErrorSources.begin(), kErrorSources.end(), [&](sampling::ErrorSource s) {
      return sources[i] == sampling::ErrorSourceName(s);
    });
    if (source == kErrorSources.end()) Fail(where, fmt::format("/inputs/source[{}] = '{}' is unknown", i, sources[i]));
    input.source = *source;
    inputs.push_back(std::move(input));
  }

  return inputs;
}

std::optional<std::string> InputDifference(const std::vector<sampling::SampledInput>& file,
                                           const std::vector<sampling::SampledInput>& now, std::string_view now_name) {
  if (file.size() != now.size()) {
    return fmt::format("inputs differ (the file has {} inputs, {} {})", file.size(), now_name, now.size());
  }
  for (std::size_t i = 0; i < file.size(); ++i) {
    const sampling::SampledInput& a = file[i];
    const sampling::SampledInput& b = now[i];
    if (a.name != b.name || a.quantity != b.quantity || a.component != b.component || a.source != b.source ||
        a.roller != b.roller || a.order != b.order) {
      return fmt::format("inputs differ (input {}: '{}' in the file, '{}' now)", i, a.name, b.name);
    }
  }
  return std::nullopt;
}

std::optional<std::string> TryRead(hid_t dataset, hid_t memory_type, hid_t memory_space, hid_t file_space,
                                   void* data) {
  for (int attempt = 1;; ++attempt) {
    if (H5Dread(dataset, memory_type, memory_space, file_space, H5P_DEFAULT, data) >= 0) return std::nullopt;
    if (attempt == kRawReadAttempts) break;
    std::this_thread::sleep_for(kRawReadRetryDelay);
  }
  const std::string detail = Hdf5Detail();
  return detail.empty() ? std::string("HDF5 cannot read it") : detail;
}

void RewriteChunksWithFill(const Where& where, hid_t dataset, const std::string& path,
                           const std::vector<std::array<hsize_t, 2>>& offsets) {
  const PlistId dcpl(Check(H5Dget_create_plist(dataset), where, "reading the layout of", path));
  const SpaceId space(Check(H5Dget_space(dataset), where, "reading the shape of", path));
  const int rank = H5Sget_simple_extent_ndims(space.get());
  hsize_t chunk[2] = {1, 1};
  if (rank < 1 || rank > 2 || H5Pget_chunk(dcpl.get(), rank, chunk) != rank) {
    Fail(where, fmt::format("dataset {} is not chunked", path));
  }
  const TypeId type(Check(H5Dget_type(dataset), where, "reading the type of", path));
  const std::size_t element = H5Tget_size(type.get());
  std::vector<unsigned char> fill(element);
  CheckStatus(H5Pget_fill_value(dcpl.get(), type.get(), fill.data()), where, "reading the fill value of", path);
  std::vector<unsigned char> bytes(chunk[0] * chunk[1] * element);
  for (std::size_t at = 0; at < bytes.size(); at += element) std::memcpy(bytes.data() + at, fill.data(), element);
  const int filters = H5Pget_nfilters(dcpl.get());
  if (filters < 0 || filters >= 32) Fail(where, fmt::format("reading the filters of {} failed", path));
  const std::uint32_t skip_all = (std::uint32_t{1} << filters) - 1;
  for (const std::array<hsize_t, 2>& offset : offsets) {
    CheckStatus(H5Dwrite_chunk(dataset, H5P_DEFAULT, skip_all, offset.data(), bytes.size(), bytes.data()), where,
                "rewriting a damaged chunk of", path);
  }
  CheckStatus(H5Dflush(dataset), where, "flushing", path);
}

// ---------------------------------------------------------------------------------------

PlistId FileAccess(const Where& where) {
  PlistId fapl(Check(H5Pcreate(H5P_FILE_ACCESS), where, "creating", "a file access property list"));
  CheckStatus(H5Pset_libver_bounds(fapl.get(), H5F_LIBVER_LATEST, H5F_LIBVER_LATEST), where, "configuring",
              "file access");
  // HDF5's flock() would stop SWMR readers while a writer holds it, and it cannot outlast
  // the switch to SWMR mode; FileLock guards writers instead.
  CheckStatus(H5Pset_file_locking(fapl.get(), false, true), where, "configuring", "file access");
  // A virtual dataset (an index of shards) opens its sources with HDF5's default access,
  // locking on, and HDF5 refuses a second open of a file with other locking settings: the
  // variable HDF5 reads for that default makes every open of this process agree. A value
  // the user set is kept.
  static const bool unlocked_by_default = setenv("HDF5_USE_FILE_LOCKING", "FALSE", 0) == 0;
  if (!unlocked_by_default) Fail(where, "cannot set HDF5_USE_FILE_LOCKING");
  CheckStatus(H5Pset_metadata_read_attempts(fapl.get(), kMetadataReadAttempts), where, "configuring", "file access");
  return fapl;
}

FileId OpenForReading(const fs::path& path) {
  const Where where{path.string(), true};
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (!fs::exists(status)) throw InputError(where.file + ": does not exist");
  if (fs::is_directory(status)) throw InputError(where.file + ": is a directory, not a results file");
  const htri_t is_hdf5 = H5Fis_hdf5(where.file.c_str());
  if (is_hdf5 < 0) Fail(where, "cannot be read");
  if (is_hdf5 == 0) throw InputError(where.file + ": is not an HDF5 file or is truncated");

  const PlistId fapl = FileAccess(where);
  // Flags left by a writer killed before it entered SWMR mode would refuse even a reader.
  SetHiddenFlag(where, fapl, "clear_status_flags");
  hid_t id = H5Fopen(where.file.c_str(), H5F_ACC_RDONLY | H5F_ACC_SWMR_READ, fapl.get());
  if (id < 0) {
    // Files from other writers (superblock before version 3) need a plain read-only open.
    id = H5Fopen(where.file.c_str(), H5F_ACC_RDONLY, fapl.get());
  }
  if (id < 0) Fail(where, "is not an HDF5 file or is truncated");
  return FileId(id);
}

FileId OpenForWriting(const fs::path& path) {
  const std::string name = path.string();
  const Where opening{name, true};
  const PlistId fapl = FileAccess(opening);
  // As h5clear does after a killed SWMR writer: forget its superblock flags, and accept an
  // end-of-allocation mark that lags behind what it wrote...
  if (!SetHiddenFlag(opening, fapl, "clear_status_flags")) {
    throw InputError(name + ": this HDF5 library cannot reopen files; run 'h5clear -s --increment' on it first");
  }
  SetHiddenFlag(opening, fapl, "skip_eof_check");
  FileId file(H5Fopen(name.c_str(), H5F_ACC_RDWR, fapl.get()));
  if (file.get() < 0) Fail(opening, "cannot be opened for writing");
  // ...and move that mark to the end of the file, so that new objects never land on old ones.
  CheckStatus(H5Fincrement_filesize(file.get(), 0), Where{name, false}, "updating", "the end-of-allocation mark");
  return file;
}

std::optional<std::string> FormatOf(const Where& where, hid_t file) {
  try {
    return ReadStringAttribute(where, file, "format");
  } catch (const std::runtime_error&) {
    return std::nullopt;
  }
}

void CreateWhole(const fs::path& path, const std::string& exists_message, FileId& file, FileLock& lock,
                 const std::function<void()>& write, const std::function<void()>& close) {
  const fs::path temporary = PrepareCreate(path, exists_message);
  try {
    file = CreateExclusive(temporary, path);
    lock = FileLock::Acquire(temporary, path.string());
    write();
    Publish(temporary, path, exists_message);
  } catch (...) {
    close();
    std::error_code error;
    fs::remove(temporary, error);
    throw;
  }
}

void CommitAndClose(const Where& where, const std::function<void()>& commit, const std::function<bool()>& close) {
  const QuietErrors quiet;
  try {
    commit();
  } catch (const std::exception& error) {
    std::cerr << "ringtol: " << error.what() << '\n';
  }
  if (!close()) std::cerr << "ringtol: " << where.file << ": closing failed (HDF5: " << Hdf5Detail() << ")\n";
}

fs::path PrepareCreate(const fs::path& path, const std::string& exists_message) {
  const std::string name = path.string();
  std::error_code error;
  if (fs::exists(fs::symlink_status(path, error))) throw InputError(exists_message);
  const fs::path directory = path.has_parent_path() ? path.parent_path() : fs::path(".");
  if (!fs::is_directory(directory, error)) {
    throw InputError(name + ": directory '" + directory.string() + "' does not exist");
  }
  fs::path temporary = path;
  temporary += fmt::format(".{}.creating", ::getpid());
  fs::remove(temporary, error);  // left by a killed run that had this process id
  return temporary;
}

FileId CreateExclusive(const fs::path& temporary, const fs::path& path) {
  const Where opening{path.string(), true};
  const PlistId fapl = FileAccess(opening);
  FileId file(H5Fcreate(temporary.c_str(), H5F_ACC_EXCL, H5P_DEFAULT, fapl.get()));
  const fs::path directory = path.has_parent_path() ? path.parent_path() : fs::path(".");
  if (file.get() < 0) Fail(opening, "cannot be created in '" + directory.string() + "'");
  return file;
}

// A hard link fails when the name exists (rename would overwrite it).
void Publish(const fs::path& temporary, const fs::path& path, const std::string& exists_message) {
  if (::link(temporary.c_str(), path.c_str()) == 0) {
    ::unlink(temporary.c_str());
    return;
  }
  const int link_error = errno;
  if (link_error == EEXIST) throw InputError(exists_message);
  // File systems without hard links: rename after a last look.
  std::error_code error;
  if (fs::exists(fs::symlink_status(path, error))) throw InputError(exists_message);
  fs::rename(temporary, path, error);
  if (error) throw InputError(path.string() + ": cannot be created: " + error.message());
}

FileLock::~FileLock() {
  if (fd_ >= 0) ::close(fd_);
}

FileLock FileLock::ToResume(const fs::path& path, std::string_view job) {
  const std::string name = path.string();
  std::error_code error;
  if (!fs::exists(path, error)) {
    throw InputError(fmt::format("{}: does not exist; run the {} without --resume to start it", name, job));
  }
  if (!fs::is_regular_file(path, error)) throw InputError(name + ": is not a regular file");
  return Acquire(path, name);
}

FileLock FileLock::Acquire(const fs::path& path, const std::string& name) {
  FileLock lock;
  lock.fd_ = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
  if (lock.fd_ < 0) throw InputError(name + ": cannot be opened for writing: " + std::strerror(errno));
  struct flock region {};
  region.l_type = F_WRLCK;
  region.l_whence = SEEK_SET;
  if (::fcntl(lock.fd_, F_OFD_SETLK, &region) < 0 && (errno == EAGAIN || errno == EACCES)) {
    throw InputError(name + ": is being written by another ringtol run; let it finish or stop it first");
  }
  // Other errors mean a file system without locks: go on unguarded, as HDF5 does there.
  return lock;
}

bool FileLock::Held(const fs::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  struct flock region {};
  region.l_type = F_WRLCK;
  region.l_whence = SEEK_SET;
  const bool held = ::fcntl(fd, F_OFD_GETLK, &region) == 0 && region.l_type != F_UNLCK;
  ::close(fd);
  return held;
}

std::size_t FirstDifferingLine(const std::string& a, const std::string& b) {
  const auto [at, unused] = std::mismatch(a.begin(), a.end(), b.begin(), b.end());
  return 1 + static_cast<std::size_t>(std::count(a.begin(), at, '\n'));
}

std::optional<std::string> TextDifference(std::string_view field, const std::string& file, const std::string& now) {
  if (file == now) return std::nullopt;
  return fmt::format("{} differs (first at line {})", field, FirstDifferingLine(file, now));
}

namespace {
constexpr const char* kFileLayout = "file";
constexpr const char* kShardIndexLayout = "shard index";
}  // namespace

void WriteLayout(const Where& where, hid_t file, const StoredLayout& layout) {
  if (layout.layout == Layout::kFile) {
    WriteStringAttribute(where, file, "layout", kFileLayout);
    return;
  }
  WriteStringAttribute(where, file, "layout", kShardIndexLayout);
  const std::int32_t rows = layout.rows_schema;
  WriteAttribute(where, file, "rows_schema", H5T_STD_I32LE, H5T_NATIVE_INT32, &rows);
}

StoredLayout ReadLayout(const Where& where, hid_t file, int schema_version, int legacy_index_schema,
                        int legacy_rows_schema) {
  const std::optional<std::string> layout = ReadStringAttribute(where, file, "layout");
  if (!layout) {
    if (schema_version == legacy_index_schema) return {Layout::kShardIndex, legacy_rows_schema};
    return {Layout::kFile, schema_version};
  }
  if (*layout == kFileLayout) return {Layout::kFile, schema_version};
  if (*layout != kShardIndexLayout) {
    Fail(where, fmt::format("attribute layout = \"{}\" is neither \"{}\" nor \"{}\"", *layout, kFileLayout,
                            kShardIndexLayout));
  }
  const std::optional<std::int64_t> rows =
      ReadNumberAttribute<std::int64_t>(where, file, "rows_schema", H5T_INTEGER, H5T_NATIVE_INT64);
  if (!rows) Fail(where, "is an index of shards without the attribute rows_schema");
  return {Layout::kShardIndex, static_cast<int>(*rows)};
}

bool ListsShards(hid_t file) {
  return H5Lexists(file, "/shards", H5P_DEFAULT) > 0 && H5Lexists(file, kShardFiles, H5P_DEFAULT) > 0;
}

std::vector<std::filesystem::path> ListedShardFiles(const Where& where, hid_t file, const std::filesystem::path& index,
                                                    bool (*may_be_missing)(const std::filesystem::path& shard)) {
  std::vector<std::filesystem::path> shards;
  for (const std::string& name : ReadStrings(where, file, kShardFiles)) {
    if (name.empty() || std::filesystem::path(name).has_parent_path()) {
      Fail(where, fmt::format("dataset {} names '{}', not a file beside the index", kShardFiles, name));
    }
    shards.push_back(index.parent_path() / name);
    std::error_code error;
    if (!std::filesystem::exists(shards.back(), error)) {
      if (may_be_missing != nullptr && may_be_missing(shards.back())) {
        shards.pop_back();
        continue;
      }
      throw InputError(fmt::format("{}: is an index of shards, and its shard {} is missing: put it back beside the "
                                   "index (the samples it holds are nowhere else)",
                                   where.file, shards.back().string()));
    }
  }
  return shards;
}

JoinTarget PrepareJoin(const std::filesystem::path& index, const std::filesystem::path& out) {
  JoinTarget target{out, std::filesystem::weakly_canonical(out) == std::filesystem::weakly_canonical(index)};
  if (target.in_place) {
    target.path += ".joining";
    std::error_code error;
    std::filesystem::remove(target.path, error);
  }
  return target;
}

void ReplaceIndex(const Where& where, const std::filesystem::path& index, const std::vector<std::string>& shards,
                  const std::function<void(hid_t file)>& write) {
  std::filesystem::path temporary = index;
  temporary += ".index-new";
  std::error_code error;
  std::filesystem::remove(temporary, error);  // what a kill while writing the last one left
  try {
    FileId file = CreateExclusive(temporary, index);
    write(file.get());
    const PlistId gcpl = ObjectCreation(where, H5P_GROUP_CREATE);
    GroupId(Check(H5Gcreate2(file.get(), "shards", H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), where, "creating group",
                  "shards"));
    WriteStrings(where, file.get(), kShardFiles, shards, true);
    if (!file.Close()) Fail(where, "closing the new index failed (HDF5: " + Hdf5Detail() + ")");
    std::filesystem::rename(temporary, index, error);
    if (error) Fail(where, "cannot give the new index its name: " + error.message());
  } catch (...) {
    std::filesystem::remove(temporary, error);
    throw;
  }
}


// ---------------------------------------------------------------------------------------
// Arrays

namespace {

DatasetId OpenArray(const Where& where, hid_t file, const std::string& path) {
  return DatasetId(Check(H5Dopen2(file, path.c_str(), H5P_DEFAULT), where, "opening dataset", path));
}

// Its rows and columns (0: one-dimensional); Fail for another rank.
Shape ShapeOf(const Where& where, hid_t dataset, const std::string& path) {
  const SpaceId space(Check(H5Dget_space(dataset), where, "reading the shape of", path));
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 1 || rank > 2) Fail(where, fmt::format("dataset {} has rank {}", path, rank));
  hsize_t dims[2] = {0, 0};
  H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  return {dims[0], dims[1]};
}

// Its rows, Fail unless it has `columns` columns.
hsize_t RowsOf(const Where& where, hid_t dataset, const std::string& path, hsize_t columns) {
  const Shape shape = ShapeOf(where, dataset, path);
  if (shape.columns != columns) {
    Fail(where, fmt::format("dataset {} has {} columns where {} are expected", path, shape.columns, columns));
  }
  return shape.rows;
}

// The file's rows [first, first + count) and the memory they move through.
std::pair<SpaceId, SpaceId> SelectRows(const Where& where, hid_t dataset, const std::string& path, hsize_t first,
                                       hsize_t count) {
  SpaceId file_space(Check(H5Dget_space(dataset), where, "reading the shape of", path));
  const Shape shape = ShapeOf(where, dataset, path);
  const hsize_t start[2] = {first, 0};
  const hsize_t counts[2] = {count, shape.columns};
  CheckStatus(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, counts, nullptr), where,
              "selecting rows of", path);
  SpaceId memory(Check(H5Screate_simple(shape.rank(), counts, nullptr), where, "creating a dataspace for", path));
  return {std::move(file_space), std::move(memory)};
}

}  // namespace

DatasetId CreateArray(const Where& where, hid_t file, const ArraySpec& spec, bool checksum) {
  const hsize_t dims[2] = {spec.shape.rows, spec.shape.columns};
  const hsize_t max_dims[2] = {spec.extendable ? spec.max_rows : spec.shape.rows, spec.shape.columns};
  const SpaceId space(
      Check(H5Screate_simple(spec.shape.rank(), dims, max_dims), where, "creating the dataspace of", spec.path));
  const PlistId dcpl = ObjectCreation(where, H5P_DATASET_CREATE);
  const hsize_t chunk[2] = {std::max<hsize_t>(1, spec.chunk_rows), std::max<hsize_t>(1, spec.chunk_columns)};
  CheckStatus(H5Pset_chunk(dcpl.get(), spec.shape.rank(), chunk), where, "chunking", spec.path);
  if (checksum) AddChecksum(where, dcpl, spec.path);
  if (spec.fill != nullptr) {
    CheckStatus(H5Pset_fill_value(dcpl.get(), spec.fill_type, spec.fill), where, "setting the fill value of",
                spec.path);
  }
  CheckStatus(H5Pset_alloc_time(dcpl.get(), H5D_ALLOC_TIME_INCR), where, "configuring", spec.path);
  return DatasetId(Check(
      H5Dcreate2(file, spec.path.c_str(), spec.file_type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT), where,
      "creating dataset", spec.path));
}

TypeId EnumMemoryType(const Where& where, hid_t dataset, const std::string& path) {
  const TypeId stored(Check(H5Dget_type(dataset), where, "reading the type of", path));
  if (H5Tget_class(stored.get()) != H5T_ENUM) return TypeId();
  return TypeId(Check(H5Tget_native_type(stored.get(), H5T_DIR_ASCEND), where, "reading the type of", path));
}

void WriteRows(const Where& where, hid_t dataset, const std::string& path, hid_t memory_type, hsize_t first,
               hsize_t count, const void* data) {
  if (const Shape shape = ShapeOf(where, dataset, path); shape.rows < first + count) {
    const hsize_t dims[2] = {first + count, shape.columns};
    CheckStatus(H5Dset_extent(dataset, dims), where, "extending", path);
  }
  const TypeId as_enum = EnumMemoryType(where, dataset, path);
  if (as_enum.get() >= 0) memory_type = as_enum.get();
  if (count > 0) {
    const auto [file_space, memory] = SelectRows(where, dataset, path, first, count);
    CheckStatus(H5Dwrite(dataset, memory_type, memory.get(), file_space.get(), H5P_DEFAULT, data), where, "writing",
                path);
  }
  CheckStatus(H5Dflush(dataset), where, "flushing", path);
}

void WriteWhole(const Where& where, hid_t file, const std::string& path, hid_t memory_type, hsize_t rows,
                const void* data) {
  const DatasetId dataset = OpenArray(where, file, path);
  if (const Shape shape = ShapeOf(where, dataset.get(), path); shape.rows != rows) {
    const hsize_t dims[2] = {rows, shape.columns};
    CheckStatus(H5Dset_extent(dataset.get(), dims), where, "resizing", path);
  }
  WriteRows(where, dataset.get(), path, memory_type, 0, rows, data);
}

std::optional<std::string> TryReadRows(const Where& where, hid_t dataset, const std::string& path,
                                       hid_t memory_type, hsize_t first, hsize_t count, void* data) {
  const TypeId as_enum = EnumMemoryType(where, dataset, path);
  if (as_enum.get() >= 0) memory_type = as_enum.get();
  const auto [file_space, memory] = SelectRows(where, dataset, path, first, count);
  return TryRead(dataset, memory_type, memory.get(), file_space.get(), data);
}

template <typename T>
std::vector<T> ReadWhole(const Where& where, hid_t file, const std::string& path, hsize_t columns) {
  const DatasetId dataset = OpenArray(where, file, path);
  const hsize_t rows = RowsOf(where, dataset.get(), path, columns);
  std::vector<T> values(rows * std::max<hsize_t>(1, columns));
  if (values.empty()) return values;
  if (const auto problem = TryReadRows(where, dataset.get(), path, TypesOf<T>().native, 0, rows, values.data())) {
    throw InputError(fmt::format("{}: dataset {} is damaged ({})", where.file, path, *problem));
  }
  return values;
}

std::vector<double> ReadRows(const Where& where, hid_t file, const std::string& path, hsize_t begin, hsize_t end,
                             hsize_t columns, std::string_view rows) {
  std::vector<double> values((end - begin) * std::max<hsize_t>(1, columns));
  if (values.empty()) return values;
  const DatasetId dataset = OpenArray(where, file, path);
  RowsOf(where, dataset.get(), path, columns);
  if (const auto problem =
          TryReadRows(where, dataset.get(), path, H5T_NATIVE_DOUBLE, begin, end - begin, values.data())) {
    throw InputError(fmt::format("{}: dataset {} is damaged: {} {} to {} cannot be read ({})", where.file, path, rows,
                                 begin, end - 1, *problem));
  }
  return values;
}

// Every number of TypesOf the stores read whole.
template std::vector<std::int8_t> ReadWhole(const Where&, hid_t, const std::string&, hsize_t);
template std::vector<std::int32_t> ReadWhole(const Where&, hid_t, const std::string&, hsize_t);
template std::vector<std::int64_t> ReadWhole(const Where&, hid_t, const std::string&, hsize_t);
template std::vector<double> ReadWhole(const Where&, hid_t, const std::string&, hsize_t);

}  // namespace ringtol::jobs::hdf5
