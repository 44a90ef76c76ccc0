// The one protocol both results files (jobs/store/campaign_store.h, allocation_store.h)
// keep their samples with: checksummed per-sample columns over a row space, written in
// runs of consecutive samples with the status column last, read back with retries, scanned
// chunk by chunk for damage and repaired to pending. The stores keep only their schema (the
// columns' specs) and their identity. Private to jobs/store, like hdf5_file.h.
//
// Crash safety: Write flushes every column of a batch before its statuses, so a sample is
// on disk exactly when its status is not pending (a kill between the two leaves it pending
// and it is computed again, to the same bits). Repair gives damaged chunks their fill values
// first and marks their samples pending after.
//
// Failure: through hdf5::Fail (InputError while a file is opened and validated, or for a
// damaged chunk; std::runtime_error for the system's failures once it is open);
// std::logic_error for a caller's mistake (a column read as the wrong C++ type, a status
// column that is not last).
#pragma once

#include <hdf5.h>

#include <algorithm>
#include <compare>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "jobs/campaign/sample_record.h"
#include "jobs/store/results_check.h"
#include "jobs/store/hdf5_file.h"

namespace ringtol::jobs::hdf5 {

// Where a table's rows live. A flat table has one row per sample: each column is [N], or
// [N, width]. A grouped one has a row per (group, sample): each column is [groups, N] (an
// allocation's candidates), chunked one group's chunk_samples at a time and sparse (a chunk
// takes space on disk once written, so a scan reads only the chunks that exist).
struct RowSpace {
  std::int64_t groups = 0;         // 0: flat; >= 1: grouped
  std::int64_t samples = 0;        // N >= 1
  std::int64_t chunk_samples = 1;  // samples per chunk along N, >= 1 (Open reads it from the file)
  bool extendable = false;         // flat tables: N can grow (SampleTable::Grow)
  const char* group_name = "candidate";  // how messages name a group

  bool grouped() const { return groups > 0; }
};

// A row of a table: sample `sample` of group `group` (0 in a flat table).
struct RowKey {
  std::int64_t group = 0;
  std::int64_t sample = 0;
  friend auto operator<=>(const RowKey&, const RowKey&) = default;
};

// The C++ type a column is written and read as: double, float, std::int32_t,
// std::uint32_t, std::int8_t (the codes of an enumeration, or plain int8 in files written
// before it was one), and char (fixed-length text, text_bytes a row).
enum class ColumnType { kFloat64, kFloat32, kInt32, kUInt32, kInt8Enum, kText };

// Which finished samples must hold finite numbers in a floating-point column: a non-finite
// number there is damage the writer cannot have made (it writes NaN only where a sample has
// no number), and the only sign of it in files written without checksums.
enum class FiniteRule { kNone, kWhenFinished, kUnlessSamplingFailed, kWhenOk };

struct ColumnSpec {
  std::string path;         // e.g. "/outputs/runout_mm": what messages name
  std::string stored_path;  // where this file keeps it: empty when its schema lacks the column
  ColumnType type = ColumnType::kFloat64;
  std::size_t width = 0;    // 0: one value a row; k >= 1: k values a row, [N, k] (flat tables)
  double fill = 0.0;        // an unwritten row's value: NaN, 0, an enumeration's code; text: ""
  TypeId (*enumeration)(const Where&) = nullptr;  // kInt8Enum: makes the file type (Create only)
  std::size_t text_bytes = 0;                     // kText: the fixed length, terminator included
  int deflate_level = 0;    // 0..9: > 0 shuffles and deflates (never for columns rewritten
                            // in SWMR mode that would grow: HDF5 leaves the old copy behind)
  bool cached = false;      // kept in a chunk cache of Open's cache_bytes (wide columns)
  FiniteRule finite = FiniteRule::kNone;
  // Samples from here on are not stored: the dataset has min(N, stored_below) rows, writes
  // of later samples are dropped and reads of them give the fill (flat tables).
  std::int64_t stored_below = std::numeric_limits<std::int64_t>::max();
};

// A column's damaged chunk: its samples (of one group) fail to read, hold a status no
// ringtol writes, or hold a non-finite number where FiniteRule forbids one.
struct DamagedChunk {
  std::size_t column = 0;
  std::int64_t group = 0;
  SampleRange samples;
  std::string problem;  // HDF5's or ringtol's reason
};

struct TableScan {
  std::vector<DamagedChunk> damaged;  // by column, then by chunk
  std::int64_t done = 0;              // finished samples in status chunks that read
  // Flat tables: pending samples in status chunks that read (a grouped table leaves it
  // empty: its pending rows are every candidate not simulated).
  std::vector<SampleRange> pending;
};

// Rows [start + k * stride, start + k * stride + block) for k in [0, count): one regular
// hyperslab, as a virtual dataset maps it in one piece.
struct StridedRows {
  std::int64_t start = 0;
  std::int64_t stride = 1;  // >= block when count > 1
  std::int64_t count = 1;
  std::int64_t block = 1;
  friend bool operator==(const StridedRows&, const StridedRows&) = default;
};
// The fewest StridedRows a greedy pass finds for `rows` (ascending, disjoint, not
// touching): runs of equal length at equal spacing merge. Block-cyclic shards give one.
std::vector<StridedRows> RegularRuns(std::span<const SampleRange> rows);

// A file a virtual table (SampleTable::CreateVirtual) shows rows of: the same columns at
// the same rows, as a shard of a results file has.
struct VirtualSource {
  std::string file;               // as the virtual file names it (relative: to its folder)
  std::int64_t samples = 0;       // the source's N: its columns have min(N, stored_below) rows
  std::vector<SampleRange> rows;  // the rows it shows: ascending, disjoint, within [0, samples)
  // A grouped table's rows instead: each group's samples it shows (ascending, disjoint);
  // the source has the table's [groups, N] shape.
  struct GroupRows {
    std::int64_t group = 0;
    std::vector<SampleRange> samples;
  };
  std::vector<GroupRows> group_rows;
};

class SampleTable {
 public:
  // Creates every column with a stored_path (their groups must exist), all rows holding
  // their fill values.
  // The last column is the status column (kInt8Enum, fill pending).
  static void Create(const Where& where, hid_t file, const RowSpace& space, const std::vector<ColumnSpec>& columns,
                     bool checksums);
  // Creates every column with a stored_path as a virtual dataset of `space`'s rows (fixed
  // size): each source's rows (a grouped table: group_rows) read from the same rows of its
  // own column, every other row as the fill. Each source's rows (of a group) are mapped as
  // RegularRuns. Returns the mappings of one column (the status column's).
  static std::int64_t CreateVirtual(const Where& where, hid_t file, const RowSpace& space,
                                    const std::vector<ColumnSpec>& columns, std::span<const VirtualSource> sources);
  // Opens the columns of a file of `space` (at least N rows of a flat table, exactly
  // [groups, N] of a grouped one, `width` values a row); columns whose stored_path is
  // empty stay closed and read as their fill. InputError naming the dataset otherwise.
  // Virtual columns (CreateVirtual) have no chunks: the table keeps space.chunk_samples as
  // the block its scans read (Scan and CopyChunks are for stored tables).
  static SampleTable Open(const Where& where, hid_t file, RowSpace space, std::vector<ColumnSpec> columns,
                          std::size_t cache_bytes = 0);

  SampleTable();
  ~SampleTable();
  SampleTable(SampleTable&&) noexcept;
  SampleTable& operator=(SampleTable&&) noexcept;

  const RowSpace& space() const { return space_; }
  std::size_t column_count() const { return specs_.size(); }
  const ColumnSpec& spec(std::size_t column) const { return specs_[column]; }
  bool stored(std::size_t column) const;
  bool checksummed(std::size_t column) const;  // Fletcher-32 ends its filters
  std::size_t status_column() const { return specs_.size() - 1; }
  // Once a file is open and validated, later failures are the system's (Where::input).
  void set_where(Where where) { where_ = std::move(where); }
  const Where& where() const { return where_; }

  // Writes `rows` (sorted, unique) of every column this file stores, `values[c]` holding
  // rows.size() values of column c's C++ type (times its width; those of samples beyond
  // stored_below are not written), every column flushed before the statuses.
  void Write(std::span<const RowKey> rows, std::span<const void* const> values);

  // Samples [begin, begin + count) of a group's row of a column (text: text_bytes a row). `statuses`, when given,
  // are those samples' statuses (saving a read for FiniteRule's check). InputError naming
  // the dataset and the samples for a damaged chunk or a broken FiniteRule.
  template <typename T>
  std::vector<T> Read(std::size_t column, std::int64_t group, std::int64_t begin, std::int64_t count,
                      const SampleStatus* statuses = nullptr) const {
    std::vector<T> values(static_cast<std::size_t>(count) * ValuesPerRow(column));
    ReadInto(column, ElementType<T>(), group, begin, count, values.data(), statuses);
    return values;
  }
  // As Read, into `out`; HDF5's reason when a chunk does not read (after kRawReadAttempts).
  template <typename T>
  std::optional<std::string> TryRead(std::size_t column, std::int64_t group, std::int64_t begin, std::int64_t count,
                                     T* out) const {
    CheckType(column, ElementType<T>());
    return TryReadRows(column, group, begin, count, out);
  }
  // Statuses of samples [begin, begin + count); InputError for one no ringtol writes.
  std::vector<SampleStatus> Statuses(std::int64_t group, std::int64_t begin, std::int64_t count) const;
  // The pending samples of [begin, end) of a group as ascending runs, their statuses read
  // in blocks below written_end() only.
  std::vector<SampleRange> Pending(std::int64_t group, std::int64_t begin, std::int64_t end) const;
  // The finished samples of a flat table as ascending runs, read below written_end() only.
  std::vector<SampleRange> Finished() const;

  // Rows from here on hold their fill values (pending) in every column, so that what reads
  // statuses or chunks (Scan, Pending, Finished) reads no further: its cost follows what
  // was written, not N, and a campaign of 2^40 samples opens, scans and resumes at once.
  // A flat stored table has no chunk there: the end of the farthest chunk of any column,
  // found in the chunk indexes when opened (in time proportional to the chunks up to it)
  // and moved on by Write and CopyChunks. A virtual table maps no source row there. A
  // grouped table: N (its scans read the chunks that exist).
  std::int64_t written_end() const { return written_end_; }

  // Reads every chunk (a flat table: every one below written_end(); a grouped table: every
  // one that exists), statuses first.
  TableScan Scan() const;
  // Gives every damaged chunk its fill values, then marks the samples of the damaged chunks
  // of other columns pending, and reopens the columns it rewrote. Reports each chunk on
  // stderr. Needs a file open for writing outside SWMR mode.
  void Repair(const std::vector<DamagedChunk>& damaged);
  // Marks samples of a flat table pending (ascending), so that a resume computes them again.
  void MarkPending(std::span<const std::int64_t> samples) const;
  // Extends every column of a flat extendable table to `samples` rows (a grow killed
  // half-way has extended some already). Outside SWMR mode.
  void Grow(std::int64_t samples);

  // Whether `other`'s chunks can be stored here as they are: the same columns, chunks and
  // filters in the same order (so a filter mask means the same thing).
  bool SameStorage(const SampleTable& other) const;

  // Joining shards: what a table of the same columns (`from`: the same groups; a flat one
  // may have fewer samples) holds that this one does not, found chunk by chunk of `from`'s
  // statuses (a chunk whose statuses do not read, or hold one no ringtol writes, offers
  // nothing: its samples stay pending here and are computed again).
  struct AbsorbPlan {
    // First rows of the chunks copied as stored (their filtered bytes and filter mask, no
    // decompression): chunks this table has no finished row of, when `as_stored` and
    // SameStorage allow it and the two tables have the same samples.
    std::vector<RowKey> whole;
    std::vector<RowKey> rows;    // the other rows to copy, read and written one by one
    std::vector<RowKey> failed;  // of both, the rows whose status is a failure
    std::int64_t samples = 0;        // finished rows to copy
    std::int64_t whole_samples = 0;  // of which in `whole`
  };
  AbsorbPlan PlanAbsorb(const SampleTable& from, bool as_stored) const;
  struct Absorbed {
    std::int64_t samples = 0;        // finished rows copied
    std::int64_t chunk_samples = 0;  // of which in chunks copied as stored
    std::int64_t bytes = 0;          // stored bytes of those chunks
  };
  // Copies what `plan` names, every column flushed before the statuses, so that a kill
  // loses nothing and absorbing again copies only what is still pending. Rows of a chunk of
  // `from` any of whose columns does not read stay pending here.
  Absorbed Absorb(const SampleTable& from, const AbsorbPlan& plan);

 private:
  template <typename T>
  static ColumnType ElementType();
  std::size_t Width(std::size_t column) const { return specs_[column].width == 0 ? 1 : specs_[column].width; }
  // Elements of the column's C++ type a row takes: its width, in text its bytes.
  // Rows of column `column` in the file: min(N, stored_below).
  std::int64_t StoredRows(std::size_t column) const {
    return std::min(space_.samples, specs_[column].stored_below);
  }
  std::size_t ValuesPerRow(std::size_t column) const {
    return Width(column) * (specs_[column].type == ColumnType::kText ? specs_[column].text_bytes : 1);
  }
  void CheckType(std::size_t column, ColumnType as) const;
  // The first row of every chunk of a column: every one below written_end() of a flat
  // table (one never written reads as its fill), those that exist of a grouped one.
  std::vector<RowKey> ChunkFirsts(std::size_t column) const;
  // Copies the chunks starting at `firsts` of every column of `other` as stored, flushing
  // each column, the statuses last. Returns the bytes copied.
  std::int64_t CopyChunks(const SampleTable& other, std::span<const RowKey> firsts);
  void ReadInto(std::size_t column, ColumnType as, std::int64_t group, std::int64_t begin, std::int64_t count,
                void* out, const SampleStatus* statuses) const;
  std::optional<std::string> TryReadRows(std::size_t column, std::int64_t group, std::int64_t first,
                                         std::int64_t count, void* out) const;
  std::string Rows(std::int64_t group, std::int64_t first, std::int64_t last) const;

  Where where_;
  RowSpace space_;
  std::vector<ColumnSpec> specs_;
  std::vector<DatasetId> datasets_;
  std::vector<TypeId> memory_types_;  // per column: what Write and Read move its values as
  std::int64_t written_end_ = 0;
};

template <>
inline ColumnType SampleTable::ElementType<double>() { return ColumnType::kFloat64; }
template <>
inline ColumnType SampleTable::ElementType<float>() { return ColumnType::kFloat32; }
template <>
inline ColumnType SampleTable::ElementType<std::int32_t>() { return ColumnType::kInt32; }
template <>
inline ColumnType SampleTable::ElementType<std::uint32_t>() { return ColumnType::kUInt32; }
template <>
inline ColumnType SampleTable::ElementType<std::int8_t>() { return ColumnType::kInt8Enum; }
template <>
inline ColumnType SampleTable::ElementType<char>() { return ColumnType::kText; }

// Buffered rows of one table, each a `Row` the store turns into its columns' values: the
// last of two rows of one key wins, and a store's reads can lay them over the file's. Rows
// are appended as they come and put in key order when next read, so that a store buffering
// thousands of samples between commits pays for one sort, not a tree.
template <typename Row>
class RowBuffer {
 public:
  void Put(RowKey key, Row row) {
    sorted_ = sorted_ && (rows_.empty() || rows_.back().first < key);
    rows_.emplace_back(key, std::move(row));
  }
  // The number of distinct keys.
  std::size_t size() const { return rows().size(); }
  bool empty() const { return rows_.empty(); }
  void clear() {
    rows_.clear();
    sorted_ = true;
  }
  // In key order, one row per key.
  const std::vector<std::pair<RowKey, Row>>& rows() const {
    if (!sorted_) {
      std::stable_sort(rows_.begin(), rows_.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      // Of equal keys the last added wins: keep the last of each run.
      std::size_t kept = 0;
      for (std::size_t i = 0; i < rows_.size(); ++i) {
        if (i + 1 < rows_.size() && rows_[i + 1].first == rows_[i].first) continue;
        if (kept != i) rows_[kept] = std::move(rows_[i]);
        ++kept;
      }
      rows_.erase(rows_.begin() + static_cast<std::ptrdiff_t>(kept), rows_.end());
      sorted_ = true;
    }
    return rows_;
  }
  std::vector<RowKey> Keys() const {
    std::vector<RowKey> keys;
    keys.reserve(rows().size());
    for (const auto& [key, row] : rows()) keys.push_back(key);
    return keys;
  }
  // Lays the buffered rows of [begin, end) of a group over `values` (read from the file).
  template <typename T, typename Get>
  void Overlay(std::int64_t group, std::int64_t begin, std::int64_t end, std::vector<T>& values, Get get) const {
    const auto& sorted = rows();
    auto it = std::lower_bound(sorted.begin(), sorted.end(), RowKey{group, begin},
                               [](const auto& row, const RowKey& key) { return row.first < key; });
    for (; it != sorted.end() && it->first < RowKey{group, end}; ++it) {
      values[static_cast<std::size_t>(it->first.sample - begin)] = get(it->second);
    }
  }

 private:
  // Sorted lazily by the const readers above.
  mutable std::vector<std::pair<RowKey, Row>> rows_;
  mutable bool sorted_ = true;
};

}  // namespace ringtol::jobs::hdf5
