// The pool: the ranks of an MPI communicator compute numbered items (PoolWork: a
// campaign's samples, jobs/pool/campaign_pool.h; a tolerance allocation's rounds,
// jobs/pool/allocation_pool.h) and the coordinator (rank 0) files them in a results file
// (PoolResults) as they come. The same code runs alone (one process, no mpirun) and under
// `mpirun -n K`. Below, "samples" are the items.
//
// Protocol: every worker asks rank 0 for work and gets a chunk of sample indices (sent as
// runs of consecutive ones, a few bytes a chunk); it sends back the chunk's records
// (jobs/campaign/sample_record.h, packed), which is also its next request; an empty chunk
// tells it to stop. A worker given a shard (a results file of its own,
// jobs/store/campaign_store.h) files its records there instead, commits them at the end
// of each chunk, and sends only a tally of the chunk (its summed solve time and its
// samples by status: a few bytes whatever its size), so that results never travel through
// rank 0 and rank 0's work does not grow with the samples: two small messages per chunk.
// Rank 0 hands out pending indices block-cyclically (jobs/pool/block_schedule.h): block j
// of the results file's chunk rows goes to computing rank j mod K, and each rank's chunks
// are cut from its blocks in order, so that each stored chunk is written by one rank and
// each shard holds a few strided runs of blocks; a rank with none left takes the back
// half of the longest queue, and at the end half of another rank's queued samples once,
// where they are more than a chunk's worth (each share costs both shards a mapping in the
// index). It holds the pending blocks as runs (a few per range of pending samples and
// computing rank, whatever N), the records between two commits and one block's pending
// indices per computing rank, so that neither its start nor its stop grows with the
// samples asked for. With `coordinator_computes` threads of rank 0 compute too, each fed
// chunks like a worker (MPI is called from rank 0's main thread only:
// MPI_THREAD_FUNNELED).
//
// Chunk sizes adapt to the cost of a sample: each chunk is sized to take about
// chunk_seconds at the running mean time per sample, but never more than a
// 1 / (2 x computing ranks) share of what remains, so the last chunks shrink and no rank
// idles at the end while another finishes a long chunk. A fixed chunk_samples overrides
// this (tests: results do not depend on it).
//
// Results do not depend on the number of ranks, the chunk sizes or the order samples
// finish in: a sample is a pure function of (campaign, index) and lands at its index.
//
// Waiting: rank 0's main thread sleeps on a condition variable that its computing threads
// signal when they finish a chunk (or stop, or fail), with a deadline at the next due
// commit and at most 50 ms away; at each wake it collects what they finished (progress)
// and looks at the stop request. While worker ranks compute it also looks for their
// messages every 200 us: Open MPI's blocking receives and probes do not sleep but spin
// on a core, which would take it from a computing thread.
//
// Stopping early (PoolOptions::stop, e.g. on SIGTERM through jobs/pool/stop_signals.h):
// every computing thread polls it between samples. A worker that sees it sends what it
// has finished of its chunk, flagged as a stop, and abandons the rest; the coordinator,
// once it sees its own request or a worker's, hands out no more work (its replies are
// empty chunks), lets its own threads abandon their chunks the same way, files every
// record that arrives and commits. Abandoned samples stay pending for --resume; no
// finished sample is lost, so none is computed twice. The stop takes at most one
// sample's time on the ranks that see the request; a worker that does not see it
// (only rank 0 was signalled) first finishes its chunk (about chunk_seconds).
#pragma once

#include <mpi.h>

#include <cstdint>
#include <functional>
#include <map>
#include <vector>

#include "engine/check.h"
#include "engine/option_range.h"
#include "jobs/campaign/sample_record.h"
#include "jobs/store/results_check.h"

namespace ringtol::jobs {

// Each field's range is the Range beside it; IsValid checks them all.
struct PoolOptions {
  // > 0: samples per chunk, fixed; 0: adaptive (chunk_seconds).
  std::int64_t chunk_samples = 0;
  static constexpr Range kChunkSamplesRange = AtLeast(0);
  // > 0: samples are handed out block-cyclically in blocks of this many (the results file's
  // chunk rows), so that each stored chunk is written by one rank, each shard maps into the
  // index as a few strided runs, and `ringtol join` copies whole chunks; 0: in ascending
  // order (an allocation's rounds, whose items are no file's rows).
  std::int64_t align_samples = 0;
  static constexpr Range kAlignSamplesRange = AtLeast(0);
  double chunk_seconds = 0.5;  // [s] the adaptive chunks' target wall time
  static constexpr Range kChunkSecondsRange = Above(0.0);
  // [s] results reach the file at least this often (about 50 ms later when samples finish
  // in the middle of a chunk; below 50 ms, every finished sample wakes rank 0).
  double commit_seconds = 2.0;
  static constexpr Range kCommitSecondsRange = AtLeast(0.0);
  // Whether rank 0 computes beside coordinating: -1 chooses (yes below 16 ranks, where
  // its share of the work outweighs the added latency of its replies), 0 no, 1 yes.
  // With one rank it always computes.
  int coordinator_computes = -1;
  static constexpr Range kCoordinatorComputesRange = Between(-1, 1);
  // Computing threads of rank 0 when it computes: 0 chooses every core of the machine
  // when the campaign runs alone (one rank) and one thread under mpirun, where ranks are
  // the unit of parallelism; > 0 sets it, up to 4,096.
  int threads = 0;
  static constexpr Range kThreadsRange = Between(0, 4096);
  // Polled between samples by every computing thread of every rank, so it must be
  // thread-safe: 0 goes on, any other value stops the pool early (see above) and is
  // reported as PoolReport::stopped. Empty: never stops early.
  std::function<int()> stop;

  // Hooks for tests and measurements, set by the command line's hidden --test-* flags
  // alone; their defaults leave the pool as users run it.
  struct Testing {
    // Stand-ins for `kill -9`: rank 0 kills itself once this many samples of this run are
    // committed (-1: never); worker rank `kill_rank` (-1: none) kills itself after
    // computing its first chunk, before sending it.
    std::int64_t kill_after_committed = -1;
    static constexpr Range kKillAfterCommittedRange = AtLeast(-1);
    int kill_rank = -1;
    static constexpr Range kKillRankRange = AtLeast(-1);
    // [s] A stand-in for the physics: > 0 makes each of a campaign's samples draw its
    // inputs, spin until its thread has spent this much CPU time and report synthetic
    // outputs (status ok), so that the pool's own costs can be measured against a known
    // sample cost (docs/performance.md, "Campaigns at scale"). 0: the campaign's solver.
    double sample_seconds = 0.0;
    static constexpr Range kSampleSecondsRange = AtLeast(0.0);
  };
  Testing testing;

  // Whether every field lies in its range; the first that does not is described in
  // *invalid (engine/option_range.h; a field of `testing` as "testing.kill_rank").
  bool IsValid(InvalidOption* invalid = nullptr) const;
};

// What rank 0 reports while the pool runs.
struct PoolProgress {
  std::int64_t done = 0;       // samples of the campaign on disk or in the commit buffer
  std::int64_t total = 0;      // samples of the campaign
  std::int64_t this_run = 0;   // computed by this run
  std::int64_t failed = 0;     // failed samples computed by this run
  double elapsed = 0.0;        // [s] since the pool started
};

struct PoolReport {
  std::int64_t computed = 0;                   // samples computed by this run
  std::int64_t already_done = 0;               // samples found on disk at the start
  std::map<SampleStatus, std::int64_t> status;  // of the samples computed by this run
  double wall_time = 0.0;                       // [s]
  double solver_time = 0.0;                     // [s] sum of the samples' solve times, all ranks
  double commit_time = 0.0;                     // [s] rank 0 writing the file
  // [s] rank 0's main thread handling results: receiving, unpacking, replying, buffering
  // and writing. Per sample, the coordinator's cost, which bounds how many ranks it can
  // feed (docs/performance.md, "Campaigns at scale").
  double coordinator_time = 0.0;
  // Messages rank 0 exchanged with worker ranks (received and sent) and their bytes: with
  // shards 2 per chunk of a few dozen bytes; without, every record's bytes.
  std::int64_t coordinator_messages = 0;
  std::int64_t coordinator_bytes = 0;
  // [s] the CPU time of coordinator_time: what handling costs, without the waits for a core
  // that an oversubscribed or busy machine adds to it.
  double coordinator_cpu_time = 0.0;
  // [s] CPU time of the worker ranks' computing threads, all of it and the part inside
  // samples: the difference is what the pool costs a worker (asking, packing, writing its
  // shard).
  double worker_cpu_time = 0.0;
  double worker_sample_cpu_time = 0.0;
  // [s] of worker_cpu_time, waiting for rank 0's next chunk: Open MPI's blocking calls spin.
  double worker_wait_cpu_time = 0.0;
  // [s] from the last result's arrival at rank 0 to the pool's end (the last commit).
  double tail_time = 0.0;
  int computing_ranks = 0;                      // worker ranks plus rank 0's computing threads
  int ranks = 0;
  // Nonzero: the pool stopped early at this request (PoolOptions::stop of rank 0, or of
  // the first worker that asked), possibly with samples left pending.
  int stopped = 0;
};

// What a pool computes: numbered items (a campaign's samples; a round of a tolerance
// allocation's candidate samples), each a pure function of its number. Shared by every
// computing thread of a rank, so const.
class PoolWork {
 public:
  virtual ~PoolWork() = default;
  // Computes item `index` into a record whose index is `index`; never throws for the
  // item's own failure (it becomes the record's status). One per computing thread.
  using Evaluator = std::function<SampleRecord(std::int64_t index)>;
  virtual Evaluator MakeEvaluator() const = 0;
  // The size of every record's u and values, which travel with it between ranks.
  virtual std::size_t dimension() const = 0;
};

// Where rank 0 files the records, and which items are still to do: a results file, or an
// adapter in front of one.
class PoolResults {
 public:
  virtual ~PoolResults() = default;
  virtual std::int64_t items() const = 0;
  // The pending items in [begin, end) as ascending runs: a campaign of 2^40 samples, all
  // pending, is one run, so that starting the pool does not grow with the items.
  virtual std::vector<SampleRange> Pending(std::int64_t begin, std::int64_t end) const = 0;
  virtual void Add(SampleRecord record) = 0;
  virtual std::size_t buffered() const = 0;
  // Makes every added record durable.
  virtual void Commit() = 0;
  // A worker's shard whose records rank 0 must see as well (an allocation's search judges
  // each round by them): the worker files each record here, commits, then sends it, and
  // rank 0 gets it through Learn instead of Add. false: the worker sends a tally only.
  virtual bool sends_records() const { return false; }
  // Rank 0: a record worker rank `rank` filed in its shard and committed (sends_records).
  // These results learn none: only results whose shards send records override it.
  virtual void Learn(SampleRecord record, int rank) {
    constexpr bool learns_records_filed_elsewhere = false;
    RINGTOL_CHECK(learns_records_filed_elsewhere, rank, record.index);
  }
};

// Runs on every rank of `communicator`; `results` is rank 0's file, and on a worker rank
// its shard (its records stay on it) or null (its records travel to rank 0).
// `progress` (rank 0 only, may be empty) is called as results arrive. Returns the report
// on rank 0 (a default one elsewhere). Throws std::runtime_error for an MPI failure, and
// what `results` throws, after the start.
PoolReport RunPool(MPI_Comm communicator, const PoolWork& work, PoolResults* results, const PoolOptions& options,
                   const std::function<void(const PoolProgress&)>& progress);

// [s] CPU time of the calling thread (CLOCK_THREAD_CPUTIME_ID).
double ThreadCpuSeconds();

}  // namespace ringtol::jobs
