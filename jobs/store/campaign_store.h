// The results file of a campaign: one HDF5 file (Debian's serial libhdf5, C API) written
// as results arrive, or under mpirun one shard of the same schema per computing rank and
// an index of them (WriteShardIndex, below), readable by h5py and h5dump as one file, and
// safe against a kill at any moment. docs/results.md documents the schema for
// readers; this header is the contract for writers.
//
// Schema version 6 (N = samples, d = sampler inputs, S = min(N, inputs_stored_below), Z =
// rollers):
//   /                          attributes: format = "ringtol campaign", schema_version = 6,
//                              layout = "file" (jobs/store/hdf5_file.h: an index of shards
//                              says "shard index"; files before it have none), ringtol_version, catalogue_version, seed (uint64), samples
//                              (int64, N), design, solver, campaign_path, campaign_file (the
//                              campaign file's text), base_scene (the base scene as a scene
//                              file, jobs/inputs/scene_writer.h), inputs_stored_below (int64,
//                              CampaignStoreOptions::inputs_stored_below)
//   /inputs/name, quantity, component, source   [d] strings: one per design coordinate
//   /inputs/roller, order                        [d] int32 (roller -1 for the ring)
//   /inputs/u                  float64 [S, d]  the design point of each of the first S
//                              samples, before inspection redraws: AssemblySampler::Realise
//                              (index, u) replays the sample, and the same u under other
//                              tolerances are common random numbers (tolerance allocation);
//                              CampaignReader replays the others (SampleDrawer)
//   /inputs/values             float32 [S, d]  the drawn values, in the units of /inputs/name
//   /inputs/redraws            int32 [N]
//   /inputs/draw_checksum      uint32 [N]      DrawChecksum of each finished sample's draw, so
//                              that a replay which no longer reproduces it is refused
//   /outputs/<kOutputNames>    float64 [N]     NaN when the sample failed, and the life
//                              outputs of an ok sample whose roller left the bore; attribute
//                              upper_spec_limit when the campaign sets one; runout_mm and
//                              swing_mm carry a `definition` string, swing_mm also the
//                              resolution_um and cutoff_upr it was read with
//   /outputs/steps             int32 [N]
//   /outputs/rung              int8 enum [N]   solvers::Rung number of the path the outputs are
//                              (0 linear, 1 quasistatic, 2 dynamic); -1 "none" when no rung
//                              ran (schema 3: plain int8)
//   /outputs/d_trajectory_error_mm  float64 [N]  that rung's own bound on its error in
//                              d_trajectory_mm (SampleRecord::d_trajectory_error); NaN unless ok
//   /outputs/off_bore_percent  float32 [N, Z]  each roller's share of the turn off the bore
//                              (SampleRecord::off_bore); NaN unless ok
//   /rollers/name              [Z] strings: the base scene's rollers, the columns of
//                              off_bore_percent (CampaignIdentity::rollers)
//   /outputs/status            int8 enum [N]   SampleStatusName names; fill value "pending"
//   /failures/sample           int64 [M]       the failed samples committed, in commit order
//   /failures/message          fixed 256-byte strings [M]: why each failed (truncated); a
//                              sample computed again appends again, and its last row counts
//   /timing/solve_time_s       float64 [N]     wall time of each sample: the one dataset
//                              that differs between two runs of the same campaign
//   /calibration/<k>           groups, k = 0, 1, ...: what the sampler's calibration of each form
//                              spectrum came to (CampaignIdentity::calibrations), as attributes:
//                              component, measure (sampling::FormMeasureName), tolerance_m,
//                              coverage, scale_m, unit_quantile, unit_quantile_low,
//                              unit_quantile_high (float64, metres: the bits the run drew with),
//                              draws (int32). Optional: files before it, or campaigns without form
//                              tolerances, have none, and readers that ignore it lose nothing
//                              but the time to calibrate again, so the schema stays 3.
// Schema 5 is schema 6 without /outputs/off_bore_percent and /rollers.
// Schema 4 is schema 5 with u and values for every sample, no draw checksum, and a message
// per sample (/outputs/message, fixed 256-byte strings [N], empty unless the sample failed)
// instead of /failures; ringtol still resumes such a file in its own schema.
// Every per-sample dataset is chunked along samples and extendable (maximum size
// unlimited), so a campaign can grow with --samples. Every dataset ends its filter pipeline
// with HDF5's Fletcher-32 checksum, so that a chunk damaged on disk fails to read instead
// of reading as other numbers (files of earlier builds have none and still read). Redraws,
// steps, rungs and statuses are shuffled and deflated (they shrink a hundredfold); the
// floating-point columns, the draw checksums and the failure rows are
// deflated only on request (deflate_level), because they barely compress and, in SWMR
// mode, HDF5 never frees the old copy of a compressed chunk it rewrites: each commit of a
// partly filled chunk would leave one behind.
//
// Crash safety: the file is written in HDF5's single-writer/multiple-reader mode (file
// format 1.10), whose ordered metadata flushes keep the file consistent whenever the
// writing process dies. Commit() flushes a batch's inputs, outputs and timings first and
// its statuses last, so a sample is on disk exactly when its status is not pending; a
// kill between the two leaves it pending and it is computed again on resume, to the same
// bits. The failure rows are appended before the statuses of the samples they describe.
//
// Damage: a chunk whose checksum fails (or, in files without checksums, a finished sample
// holding a non-finite design point, drawn value or ok output) is damaged. Readers throw
// InputError naming the file, the dataset and the samples; CheckResults lists every damaged
// chunk; Resume recomputes the samples of damaged chunks (see Resume), and the failed samples
// whose messages a damaged chunk of the failure rows held.
//
// Failure: InputError (jobs/inputs/input_error.h) naming the file, for every problem a user can
// cause: creating over an existing file, a directory that does not exist or cannot be
// written, resuming a file that is missing, truncated, not HDF5, not a ringtol campaign,
// of a schema it does not resume, or of another campaign (what differs is named), and a
// damaged file; reading a sample whose inputs the file does not keep, when this ringtol
// draws them differently from the one that wrote it (its draw checksum differs). HDF5 write errors after a successful open (disk full) throw std::runtime_error
// naming the file and dataset.
#pragma once

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "engine/option_range.h"
#include "jobs/campaign/campaign_identity.h"
#include "jobs/campaign/sample_record.h"
#include "jobs/store/results_check.h"
#include "jobs/store/shards.h"

namespace ringtol::jobs {

inline constexpr int kCampaignSchemaVersion = 6;
// The schema_version of an index of shards (WriteShardIndex: its rows' schema's datasets,
// the per-sample ones virtual), which numbers the index's layout; its root attributes
// layout = "shard index" and rows_schema say what it is. Indexes written before `layout`
// existed are recognised by this number alone (with no layout, their rows are schema 5);
// a file of rows schema 6 says layout = "file".
inline constexpr int kShardIndexSchemaVersion = 6;
// The newest schema_version a file of this ringtol has, whatever its layout.
inline constexpr int kNewestSchemaVersion = std::max(kCampaignSchemaVersion, kShardIndexSchemaVersion);
// The oldest schema Resume continues (in its own schema).
inline constexpr int kOldestResumableSchema = 4;
// The oldest schema that records each sample's rung (/outputs/rung).
inline constexpr int kFirstSchemaWithRungs = 3;
// The oldest schema a sharded run writes (its failure rows are what an index joins).
inline constexpr int kFirstSchemaWithShards = 5;
// Samples whose design points and drawn values a file keeps unless told otherwise
// (CampaignStoreOptions::inputs_stored_below): those the report's screening reads
// (ReportOptions::screening_samples); the rest are replayed from (campaign, index).
inline constexpr std::int64_t kStoredInputSamples = 16384;
// The oldest schema CampaignReader still reads. Schema 1 (ringtol 0.3) kept the max - min
// of the sensor signal as runout_total_mm and an ill-posed "peak to nearest valley" as
// runout_mm: its runout_mm is read from runout_total_mm, and it has no swing_mm (HasOutput
// says so; ReadOutput gives NaN). Schema 2 (ringtol 0.4) has no /outputs/rung and
// /outputs/d_trajectory_error_mm: they read as -1 and NaN. Schemas 1 to 3 have none of
// the life outputs (IsLifeOutput): HasOutput says so, ReadOutput gives NaN.
// Resume refuses files older than kOldestResumableSchema.
inline constexpr int kOldestReadableSchema = 1;


// What a shard holds, for its index: reported by the rank that writes it
// (CampaignStore::Contents, in parallel on every rank), or read from the file.
struct ShardContents {
  std::filesystem::path path;
  std::int64_t samples = 0;              // its N
  std::int64_t chunk_rows = 0;
  std::int64_t inputs_stored_below = 0;
  std::int64_t failure_rows = 0;         // rows of /failures/sample
  std::vector<SampleRange> finished;     // ascending, disjoint, not touching
  int schema = kCampaignSchemaVersion;   // its rows' schema: every shard of a run has the same
};

// Each field's range is the Range beside it; IsValid checks them all.
struct CampaignStoreOptions {
  int deflate_level = 0;  // zlib level of the floating-point columns; 0 = none
  static constexpr Range kDeflateLevelRange = Between(0, 9);
  // > 0: samples per HDF5 chunk; 0: 1,024 (8 KiB of a float64 column), at most N
  std::int64_t chunk_samples = 0;
  static constexpr Range kChunkSamplesRange = AtLeast(0);
  std::size_t chunk_cache_bytes = 32u << 20;  // per 2-D dataset: keeps the chunks being filled in memory
  // false writes datasets without Fletcher-32, as builds before checksums did: for tests of
  // such files and for measuring what the checksum costs.
  bool checksums = true;
  // The samples whose u and values the file keeps: those below this index (the largest
  // int64 keeps every one: --store-inputs). Create only: a resumed file keeps its own.
  std::int64_t inputs_stored_below = kStoredInputSamples;
  static constexpr Range kInputsStoredBelowRange = AtLeast(0);
  // The schema a new file is written in: this ringtol's, or the one of a sharded run an
  // earlier ringtol began, whose new shards and joined file keep it. Create only.
  int schema = kCampaignSchemaVersion;
  static constexpr Range kSchemaRange = Between(kFirstSchemaWithShards, kCampaignSchemaVersion);

  // Whether every field lies in its range; the first that does not is described in
  // *invalid (engine/option_range.h).
  bool IsValid(InvalidOption* invalid = nullptr) const {
    return CheckOption("deflate_level", deflate_level, kDeflateLevelRange, invalid) &&
           CheckOption("chunk_samples", chunk_samples, kChunkSamplesRange, invalid) &&
           CheckOption("inputs_stored_below", inputs_stored_below, kInputsStoredBelowRange, invalid) &&
           CheckOption("schema", schema, kSchemaRange, invalid);
  }
};

class CampaignStore {
 public:
  // A new file for `samples` (>= 1) samples, all pending. Refuses an existing path.
  static CampaignStore Create(const std::filesystem::path& path, const CampaignIdentity& identity,
                              std::int64_t samples, const CampaignStoreOptions& options = {});
  // An existing file of the same campaign, opened for writing after a clean or killed run;
  // grows it to `samples` when that is larger than the file's N, refuses a smaller one.
  // Reads the whole file first (CheckResults): every damaged chunk of a per-sample dataset
  // is rewritten with fill values and its samples marked pending, so they are computed
  // again, to the same bits. A kill during a chunk's rewrite can leave it torn, failing its
  // checksum although no finished sample in it changed: resuming must repair, not refuse.
  // Damage that leaves the file unopenable (superblock, object headers, /inputs
  // descriptions) is an InputError.
  static CampaignStore Resume(const std::filesystem::path& path, const CampaignIdentity& identity,
                              std::int64_t samples, const CampaignStoreOptions& options = {});

  ~CampaignStore();  // commits what is buffered and closes; never throws (errors go to stderr)
  CampaignStore(CampaignStore&&) noexcept;
  CampaignStore& operator=(CampaignStore&&) noexcept;

  std::int64_t samples() const;
  const std::filesystem::path& path() const;

  // The pending samples in [begin, end) as ascending runs, read from the file: what a run
  // still has to do. Statuses are read only below the farthest chunk the file has, so its
  // cost follows what was computed, not N.
  std::vector<SampleRange> Pending(std::int64_t begin, std::int64_t end) const;

  // Buffers one finished sample (any order; index < samples(), u and values of size d).
  void Add(SampleRecord record);
  std::size_t buffered() const;
  // Writes and flushes every buffered sample, statuses last (see the header comment).
  void Commit();

  // Commits, and reports what the file holds (its statuses read where it was written), for
  // its index.
  ShardContents Contents();

  // Samples per HDF5 chunk of every per-sample dataset. A shard made with this many
  // (CampaignStoreOptions::chunk_samples) has chunks that Absorb copies as they are stored.
  std::int64_t chunk_rows() const;
  // The first sample whose u and values the file does not keep (schema 4: the largest int64).
  std::int64_t inputs_stored_below() const;
  // The file's schema: this ringtol's, or a resumed file's own.
  int schema() const;

  // Copies into this file every finished sample of the shard at `shard` (a results file of
  // the same campaign, no larger) that this file has pending, and flushes; the shard stays
  // as it is (JoinShards removes shards once the joined file has its name). A chunk of
  // samples this file has none of is copied as stored (its filtered bytes, checksum
  // included: no decompression, no re-filtering), when the shard's chunks, filters and
  // sample count match this file's; other samples are read and written one by one.
  // Statuses last, so a kill at any moment loses nothing, and absorbing it again copies
  // only what is still pending here. A chunk of the shard whose statuses do not read is
  // left out (its samples stay pending and are computed again). InputError when the shard
  // is an index, of another campaign or larger.
  struct Absorbed {
    std::int64_t samples = 0;         // finished samples copied
    std::int64_t chunk_samples = 0;   // of which in chunks copied as stored
    std::int64_t bytes = 0;           // stored bytes of those chunks
  };
  Absorbed Absorb(const std::filesystem::path& shard);

 private:
  struct File;
  explicit CampaignStore(std::unique_ptr<File> file);
  std::unique_ptr<File> file_;
};

// SetAsideUnreadableShards (jobs/store/shards.h) for a campaign's results file: a shard is
// unreadable when its root, descriptions or chunk indexes do not read as a campaign's.
std::vector<UnreadableShard> SetAsideUnreadableShards(const std::filesystem::path& results);

// Shards as the results file: under mpirun every computing rank keeps its shard, and the
// results file becomes their index (schema 6, layout "shard index", rows_schema the shards'
// schema): the root's attributes, /inputs descriptions, /rollers
// and /calibration of a results file, /shards/file [K] (the shards' file names, beside the
// index) and root attribute shard_chunk_rows, and every per-sample dataset a virtual
// dataset of N rows showing each sample from the shard that finished it (the first listed
// when two did), pending elsewhere; /failures/sample and /failures/message show every
// shard's failure rows one after another. h5py and HDF5's tools read it as one file;
// CampaignReader, CheckResults and JoinShards open every shard first and refuse an index
// whose shard is missing or of another campaign (HDF5 itself would read its rows as fill).
struct ShardIndexSummary {
  std::int64_t shards = 0;
  std::int64_t samples = 0;       // finished samples the index shows
  std::int64_t mappings = 0;      // of one per-sample dataset, all shards
  std::int64_t most_mappings = 0;  // of one shard
};
// Reads a shard's contents (its statuses where it was written). InputError unless it is a results file
// of `identity`'s campaign of at most `samples` samples, whose status chunks read.
ShardContents ReadShardContents(const std::filesystem::path& shard, const CampaignIdentity& identity,
                                std::int64_t samples);
// Writes `results` as the index of `shards` (of `identity`'s campaign, of at most `samples`
// samples each, in `results`'s folder, all of one chunking and stored inputs), opening
// none of them: its cost grows with the shards and their finished runs, not with N.
// Built beside it and renamed over it, so a kill leaves the old index or the new one.
// InputError when `results` is a results file that keeps samples of its own (they would
// be lost).
ShardIndexSummary WriteShardIndex(const std::filesystem::path& results, const CampaignIdentity& identity,
                                  std::int64_t samples, const std::vector<ShardContents>& shards);
// As above, each shard's contents read from its file (ReadShardContents).
ShardIndexSummary WriteShardIndex(const std::filesystem::path& results, const CampaignIdentity& identity,
                                  std::int64_t samples, const std::vector<std::filesystem::path>& shards);
// The shards a results file's index lists, checked to exist and to be results files of its
// campaign (InputError naming the missing or wrong one); empty for a self-contained file.
std::vector<std::filesystem::path> IndexedShards(const std::filesystem::path& results);
// Writes the samples of an index and its shards into `out`, one self-contained results
// file of the same campaign (chunks copied as stored where they can be: Absorb). `out`
// may be `results` itself: the joined file then replaces the index, and the shards are
// removed once it has. Returns what was copied. Every shard is checked first
// (CheckResults): a damaged chunk is an InputError naming its dataset, rows and shard and
// the --resume that computes them again, and nothing is written or removed.
CampaignStore::Absorbed JoinShards(const std::filesystem::path& results, const std::filesystem::path& out);

// A run of a campaign in shards (PlanShards, jobs/store/shards.h): a self-contained file of
// a schema before kFirstSchemaWithShards is refused (it resumes only in one process); one
// of a later schema becomes shard 0 in its own schema, which the run's new shards take.
ShardPlan PlanCampaignShards(const std::filesystem::path& results, const CampaignIdentity& identity,
                             std::int64_t samples, int ranks, bool resume);
// Rank `rank`'s own shard of `results`: resumed when it exists, else created with `options`,
// except that rank 0 chunks it, and writes it in the schema of, the shards an earlier run
// left, when there are any (a run killed before rank 0 wrote a sample).
CampaignStore OpenCampaignShard(const std::filesystem::path& results, int rank, const CampaignIdentity& identity,
                                std::int64_t samples, CampaignStoreOptions options);
// What the shards of ranks a run does not have (ShardPlan::stale) hold, each resumed
// (repaired) first.
std::vector<ShardContents> RepairStaleShards(const std::vector<std::filesystem::path>& stale,
                                             const CampaignIdentity& identity, std::int64_t samples);

// Read-only access for summaries, reports, replays and tests. Opens a file a killed run
// left behind as well as a finished one.
// A whole per-sample column of a campaign of `samples`, read as read(begin, count) in
// blocks of 2^20 samples, so no single HDF5 read holds more than one block's buffer.
template <typename T, typename Read>
std::vector<T> ReadInBlocks(std::int64_t samples, Read read) {
  constexpr std::int64_t kBlock = std::int64_t{1} << 20;
  std::vector<T> all;
  all.reserve(static_cast<std::size_t>(samples));
  for (std::int64_t begin = 0; begin < samples; begin += kBlock) {
    const std::vector<T> block = read(begin, std::min(kBlock, samples - begin));
    all.insert(all.end(), block.begin(), block.end());
  }
  return all;
}

class CampaignReader {
 public:
  // InputError for a missing, truncated, non-HDF5, non-ringtol, newer-schema file or one
  // older than kOldestReadableSchema, and from the Read functions for a damaged chunk or a
  // finished sample holding a non-finite design point, drawn value (sampling_failed aside)
  // or ok output.
  explicit CampaignReader(const std::filesystem::path& path);
  ~CampaignReader();
  CampaignReader(CampaignReader&&) noexcept;

  const CampaignIdentity& identity() const;
  std::int64_t samples() const;
  int schema_version() const;
  // Samples from here on are pending (SampleTable::written_end): a reader of what the file
  // holds reads no further, so a campaign of 2^40 samples stopped early reads in the time
  // of what it computed.
  std::int64_t written_end() const;

  std::vector<SampleStatus> ReadStatus(std::int64_t begin, std::int64_t count) const;
  // The finished samples as ascending runs, statuses read only where the file (an index:
  // its shards) was written: a campaign of 2^40 samples stopped early reads in the time of
  // what it computed.
  std::vector<SampleRange> Finished() const;
  // Whether the file holds this output (a file of an older schema may not).
  bool HasOutput(std::string_view name) const;
  // One output over [begin, begin + count), by its name in kOutputNames; NaN for an output
  // the file does not hold.
  std::vector<double> ReadOutput(std::string_view name, std::int64_t begin, std::int64_t count) const;
  // Row-major [count, d]: the drawn values of every input (stored as float32), as read; a
  // finished sample beyond inputs_stored_below drawn again (SampleDrawer, its draw
  // checksum checked), a pending one NaN. The first replay builds the campaign from the
  // file (a calibration where the file keeps none).
  std::vector<double> ReadValues(std::int64_t begin, std::int64_t count) const;
  std::vector<std::int32_t> ReadRedraws(std::int64_t begin, std::int64_t count) const;
  // /outputs/rung: kNoRung for samples no rung ran and in files of schema < 3.
  std::vector<std::int8_t> ReadRungs(std::int64_t begin, std::int64_t count) const;
  // Whether the file records each roller's share of the turn off the bore (schema >= 6).
  bool HasOffBore() const;
  // Row-major [count, identity().rollers.size()]: each roller's share of the turn off the
  // bore [%] (SampleRecord::off_bore), NaN unless the sample is ok; empty for a file that
  // does not record it (HasOffBore).
  std::vector<float> ReadOffBore(std::int64_t begin, std::int64_t count) const;
  // Everything stored about one sample (solve_time included), its inputs drawn again as
  // ReadValues's, and its message from the failure rows.
  SampleRecord ReadSample(std::int64_t index) const;

 private:
  struct File;
  std::unique_ptr<File> file_;
};

// Reads every dataset of a results file chunk by chunk. InputError when the file cannot be
// opened as a ringtol campaign (metadata damage included: HDF5 checksums its metadata); an
// allocation's results file is named as one (its resume scans it instead).
ResultsCheck CheckResults(const std::filesystem::path& path);

// "file: dataset /inputs/u is damaged at samples 0 to 99 (<problem>)...", naming every
// damaged dataset, for the commands that refuse such a file.
std::string DamageMessage(const std::filesystem::path& path, const ResultsCheck& check);

}  // namespace ringtol::jobs
