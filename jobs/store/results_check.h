// What both results files (a campaign's, jobs/store/campaign_store.h, and an allocation's,
// jobs/store/allocation_store.h) and the sample table under them say about their samples:
// ranges of samples, and what `ringtol verify` finds dataset by dataset. Plain values, no
// HDF5: the stores fill them, the commands format them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace ringtol::jobs {

// Samples [begin, end).
struct SampleRange {
  std::int64_t begin = 0;
  std::int64_t end = 0;
  friend bool operator==(const SampleRange&, const SampleRange&) = default;
};

// One dataset of a results file, read chunk by chunk.
struct DatasetCheck {
  std::string path;          // e.g. "/inputs/u"
  bool per_sample = false;   // a row per sample (else one of the /inputs descriptions, [d])
  bool checksummed = false;  // Fletcher-32 is in its filter pipeline
  // The samples of its chunks that fail to read (checksum, decompression, I/O) or hold a
  // non-finite number where a finished sample has none, merged; a description dataset
  // that fails reports [0, samples).
  std::vector<SampleRange> damaged;
  std::string first_problem;  // HDF5's or ringtol's reason for the first damaged chunk
};

// What `ringtol verify` reports of a campaign's or an allocation's results file: every
// dataset, what is on disk, what a --resume computes.
//
// An allocation's [C, N] datasets have a row per (candidate, sample): their damaged rows
// are numbered candidate x N + sample (CandidateOf and SamplesOf give them back), each
// range within one candidate. Its /inputs/u counts rows as samples, and a derived /outcome
// that does not read is a dataset "/outcome" damaged at [0, N) (the next commit rewrites
// it). What its resume computes is for the search to decide: pending and recompute stay
// empty, and done_by_role says what each role holds.
struct ResultsCheck {
  std::int64_t samples = 0;            // N
  std::int64_t candidates = 0;         // C of an allocation; 0 for a campaign
  std::vector<DatasetCheck> datasets;  // descriptions first, then the per-sample datasets
  std::int64_t done = 0;               // finished samples in status chunks that read
  std::vector<SampleRange> pending;    // pending samples in status chunks that read
  std::vector<SampleRange> recompute;  // what Resume computes: pending and every damaged chunk's samples
  std::int64_t done_screen = 0;        // an allocation's finished samples by role
  std::int64_t done_confirm = 0;

  bool intact() const;       // no dataset damaged
  bool checksummed() const;  // every dataset carries Fletcher-32: intact() is then a verdict
  bool allocation() const { return candidates > 0; }
  // A damaged range of an allocation's [C, N] dataset: its candidate, and its samples.
  std::int64_t CandidateOf(const SampleRange& rows) const { return rows.begin / samples; }
  SampleRange SamplesOf(const SampleRange& rows) const {
    const std::int64_t first = CandidateOf(rows) * samples;
    return {rows.begin - first, rows.end - first};
  }
};

// `ranges` sorted, with those that overlap or touch joined and empty ones left out.
std::vector<SampleRange> MergeRanges(std::vector<SampleRange> ranges);

// `rows` without the samples of `removed` (both ascending and disjoint).
std::vector<SampleRange> Without(const std::vector<SampleRange>& rows, const std::vector<SampleRange>& removed);

// One shard's check, under the name an index's messages give it (its file name).
struct ShardCheck {
  std::string name;
  ResultsCheck check;
};
// The check of an index of shards as the sum of its shards' checks, in runs throughout, so
// that it costs what the shards hold, not N. Each shard answers for the rows it does not
// hold pending (an allocation's, for every row: each of its samples is in one shard), and a
// dataset is damaged where a shard answering for the row has it damaged, the problem named
// with that shard. A campaign's sample is pending where no shard answers for it, done where
// an answering shard's status reads, and computed again unless a shard holds it whole; an
// allocation's done counts add up (what it computes is its search's to decide). `index`
// holds what the index itself keeps: the shards' datasets are merged into its own of the
// same path, except those it keeps whole itself (not per sample: an allocation's design
// points).
ResultsCheck SumOfShards(ResultsCheck index, const std::vector<ShardCheck>& shards);

// "0 to 99, 250, 300 to 399": samples as a reader counts them, both ends included.
std::string FormatRanges(const std::vector<SampleRange>& ranges);

// "dataset /inputs/u is damaged at samples 0 to 99 (<problem>); ...", naming every damaged
// dataset and its rows (an allocation's by candidate and samples).
std::string DamagedDatasets(const ResultsCheck& check);

}  // namespace ringtol::jobs
