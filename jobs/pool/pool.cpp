#include "jobs/pool/pool.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <ctime>
#include <cstring>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <type_traits>
#include <limits>
#include <utility>
#include <vector>

#include "engine/check.h"
#include "jobs/pool/block_schedule.h"

namespace ringtol::jobs {
namespace {

constexpr int kTagResults = 1;  // worker -> rank 0: packed records, also the next request
constexpr int kTagWork = 2;     // rank 0 -> worker: int64 (first, count) runs of indices; empty means stop
// worker -> rank 0: the stop request's int32 value, then the packed records finished
// before the worker saw it; also its last request
constexpr int kTagStopping = 3;
// The first byte of a results message: what follows.
constexpr char kRecords = 0;    // packed records, for rank 0 to file
constexpr char kSummaries = 1;  // summaries of records the worker filed in its shard
constexpr char kFiled = 2;      // packed records the worker filed in its shard, for rank 0 to learn
// While worker ranks compute, rank 0's main thread looks for their messages this often.
// Open MPI has no blocking wait that sleeps: MPI_Probe, MPI_Recv and MPI_Waitany spin on
// a core until the message comes (measured: 0.43 s of CPU in a 1 s MPI_Probe on a loaded
// machine, all of one in a quiet one), so a short sleep between MPI_Iprobes costs a
// computing thread less; and it is far below any chunk's duration, which the worker
// waiting for its reply idles.
constexpr auto kMessagePoll = std::chrono::microseconds(200);
// Otherwise rank 0's main thread sleeps until one of its computing threads finishes a
// chunk, a commit is due, or this long has passed: it then collects what the threads
// finished (progress) and looks at the stop request. A signal's handler can only set a
// flag, so this bounds how late rank 0 sees it when no thread of its own computes (they
// look between samples, finish their chunk and wake it).
constexpr auto kWakeAtLeastEvery = std::chrono::milliseconds(50);

using Clock = std::chrono::steady_clock;

double Seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

void Check(int code, const char* call) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  throw std::runtime_error(std::string("pool: ") + call + " failed: " + std::string(text, static_cast<std::size_t>(length)));
}

// Records travel as bytes: fixed fields, then the design point, the values and the message.
class Packer {
 public:
  template <typename T>
  void Put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const char*>(&value);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  void Put(const std::vector<double>& values) {
    if (values.empty()) return;
    const auto* p = reinterpret_cast<const char*>(values.data());
    bytes_.insert(bytes_.end(), p, p + values.size() * sizeof(double));
  }
  void Put(const std::string& text) {
    Put(static_cast<std::uint32_t>(text.size()));
    bytes_.insert(bytes_.end(), text.begin(), text.end());
  }
  void Append(const std::vector<char>& bytes) { bytes_.insert(bytes_.end(), bytes.begin(), bytes.end()); }
  void Clear() { bytes_.clear(); }
  const std::vector<char>& bytes() const { return bytes_; }

 private:
  std::vector<char> bytes_;
};

class Unpacker {
 public:
  explicit Unpacker(const std::vector<char>& bytes) : bytes_(bytes) {}
  bool done() const { return at_ == bytes_.size(); }
  template <typename T>
  T Get() {
    T value;
    std::memcpy(&value, Take(sizeof(T)), sizeof(T));
    return value;
  }
  std::vector<double> GetDoubles(std::size_t count) {
    // An allocation's records carry no design points: memcpy may not be given the null
    // data() of an empty vector, even for no bytes.
    if (count == 0) return {};
    std::vector<double> values(count);
    std::memcpy(values.data(), Take(count * sizeof(double)), count * sizeof(double));
    return values;
  }
  std::string GetString() {
    const auto length = Get<std::uint32_t>();
    return std::string(Take(length), length);
  }

 private:
  const char* Take(std::size_t count) {
    if (bytes_.size() - at_ < count) throw std::runtime_error("pool: a results message is truncated");
    const char* p = bytes_.data() + at_;
    at_ += count;
    return p;
  }
  const std::vector<char>& bytes_;
  std::size_t at_ = 0;
};

void Pack(const SampleRecord& r, Packer& out) {
  out.Put(r.index);
  out.Put(r.status);
  out.Put(r.redraws);
  out.Put(r.steps);
  out.Put(r.outputs);
  out.Put(r.d_trajectory_error);
  out.Put(r.rung);
  out.Put(r.solve_time);
  out.Put(r.u);
  out.Put(r.values);
  out.Put(r.message);
}

// What rank 0 counts of the records a worker filed in its shard: one tally a chunk, so
// that rank 0's work does not grow with the samples of a chunk.
struct Tally {
  double solve_time = 0.0;  // [s] summed
  // Samples by status, indexed by the status's byte.
  std::array<std::int64_t, std::numeric_limits<std::uint8_t>::max() + 1> by_status{};

  void Count(const SampleRecord& r) {
    solve_time += r.solve_time;
    ++by_status[static_cast<std::uint8_t>(r.status)];
  }
  // The solve time, then (status, samples) of each status counted.
  void Pack(Packer& out) const {
    out.Put(solve_time);
    for (std::size_t b = 0; b < by_status.size(); ++b) {
      if (by_status[b] == 0) continue;
      out.Put(static_cast<SampleStatus>(static_cast<std::int8_t>(static_cast<std::uint8_t>(b))));
      out.Put(by_status[b]);
    }
  }
};

SampleRecord Unpack(Unpacker& in, std::size_t dimension) {
  SampleRecord r;
  r.index = in.Get<std::int64_t>();
  r.status = in.Get<SampleStatus>();
  r.redraws = in.Get<std::int32_t>();
  r.steps = in.Get<std::int32_t>();
  r.outputs = in.Get<std::array<double, kOutputCount>>();
  r.d_trajectory_error = in.Get<double>();
  r.rung = in.Get<std::int8_t>();
  r.solve_time = in.Get<double>();
  r.u = in.GetDoubles(dimension);
  r.values = in.GetDoubles(dimension);
  r.message = in.GetString();
  return r;
}

// Ascending indices as (first, count) runs: a chunk of consecutive samples is one run, so a
// reply stays a few bytes whatever the chunk's size, below Open MPI's eager limit (a larger
// send waits, spinning, until the worker is scheduled to take it).
std::vector<std::int64_t> Runs(const std::vector<std::int64_t>& indices) {
  std::vector<std::int64_t> runs;
  for (const std::int64_t index : indices) {
    if (!runs.empty() && runs[runs.size() - 2] + runs.back() == index) {
      ++runs.back();
    } else {
      runs.insert(runs.end(), {index, 1});
    }
  }
  return runs;
}

// 0 while the pool goes on; the stop request's value once there is one.
int StopRequest(const PoolOptions& options) { return options.stop ? options.stop() : 0; }

// What a worker rank's thread spent: all of its CPU time, and that inside samples.
struct WorkerCpu {
  double total = 0.0;
  double samples = 0.0;
  double waiting = 0.0;  // from sending a chunk's results to receiving the next chunk
};

WorkerCpu RunWorker(MPI_Comm communicator, int rank, const PoolWork& work, PoolResults* shard,
                    const PoolOptions& options) {
  const double cpu_start = ThreadCpuSeconds();
  WorkerCpu cpu;
  const PoolWork::Evaluator evaluate = work.MakeEvaluator();
  Packer results;  // empty: the first request
  int tag = kTagResults;
  std::vector<std::int64_t> runs;
  std::vector<std::int64_t> chunk;
  for (bool first = true;; first = false) {
    const double wait_start = ThreadCpuSeconds();
    Check(MPI_Send(results.bytes().data(), static_cast<int>(results.bytes().size()), MPI_BYTE, 0, tag, communicator),
          "MPI_Send");
    MPI_Status status;
    Check(MPI_Probe(0, kTagWork, communicator, &status), "MPI_Probe");
    int count = 0;
    Check(MPI_Get_count(&status, MPI_INT64_T, &count), "MPI_Get_count");
    runs.resize(static_cast<std::size_t>(count));
    Check(MPI_Recv(runs.data(), count, MPI_INT64_T, 0, kTagWork, communicator, MPI_STATUS_IGNORE), "MPI_Recv");
    chunk.clear();
    for (std::size_t k = 0; k + 1 < runs.size(); k += 2) {
      for (std::int64_t i = 0; i < runs[k + 1]; ++i) chunk.push_back(runs[k] + i);
    }
    cpu.waiting += ThreadCpuSeconds() - wait_start;
    if (chunk.empty()) {
      cpu.total = ThreadCpuSeconds() - cpu_start;
      return cpu;
    }
    results.Clear();
    const bool sends = shard != nullptr && shard->sends_records();
    results.Put(shard == nullptr ? kRecords : sends ? kFiled : kSummaries);
    Tally tally;
    for (const std::int64_t index : chunk) {
      if (const int stop = StopRequest(options); stop != 0) {
        // Rebuilt with the request in front of the records finished so far; the rest of
        // the chunk stays pending.
        const std::vector<char> finished = results.bytes();
        results.Clear();
        results.Put(static_cast<std::int32_t>(stop));
        results.Append(finished);
        tag = kTagStopping;
        break;
      }
      const double sample_start = ThreadCpuSeconds();
      SampleRecord record = evaluate(index);
      cpu.samples += ThreadCpuSeconds() - sample_start;
      if (shard == nullptr) {
        Pack(record, results);
      } else if (sends) {
        Pack(record, results);
        shard->Add(std::move(record));
      } else {
        tally.Count(record);
        shard->Add(std::move(record));
      }
    }
    if (shard != nullptr && !sends) tally.Pack(results);
    if (first && rank == options.testing.kill_rank) std::raise(SIGKILL);
    // On disk before rank 0 counts them: a kill after this loses none of them.
    if (shard != nullptr) shard->Commit();
  }
}

// Pending indices of the results in ascending order, from their runs.
class PendingCursor {
 public:
  explicit PendingCursor(const PoolResults& store) : runs_(store.Pending(0, store.items())) {}
  std::optional<std::int64_t> Next() {
    while (run_ < runs_.size() && at_ >= runs_[run_].end) {
      if (++run_ < runs_.size()) at_ = runs_[run_].begin;
    }
    if (run_ == runs_.size()) return std::nullopt;
    at_ = std::max(at_, runs_[run_].begin);
    return at_++;
  }

 private:
  std::vector<SampleRange> runs_;
  std::size_t run_ = 0;
  std::int64_t at_ = 0;
};

// Pending samples handed out block by block (PoolOptions::align_samples), block-cyclically
// (jobs/pool/block_schedule.h): each computing rank's chunks are cut, in order, from the
// blocks it took, so that a block is computed by one rank unless the run's last samples
// are shared out; then a rank with nothing left takes the back half of the rank with most,
// once, and only when that rank has more queued than one chunk's worth of work (about
// chunk_seconds): each such share is one more mapping in the index for each of the two
// ranks, and an index's cost grows faster than its mappings (1.7 s instead of 0.23 s for
// 1,000 shards of five mappings instead of one: build/ringtol_shard_index_benchmark),
// while a share not taken leaves a rank idle for less than chunk_seconds at the end.
class BlockHandout {
 public:
  // `pending`: the store's pending samples, as runs.
  BlockHandout(const PoolResults& store, const std::vector<SampleRange>& pending, std::int64_t block,
               int computing_ranks)
      : store_(store),
        block_(block),
        queues_(static_cast<std::size_t>(computing_ranks)),
        shared_(static_cast<std::size_t>(computing_ranks), false) {
    // The blocks that hold a pending sample, as ranges.
    std::vector<BlockRange> blocks;
    for (const SampleRange& run : pending) {
      const BlockRange range{run.begin / block, (run.end - 1) / block + 1};
      if (!blocks.empty() && range.begin <= blocks.back().end) {
        blocks.back().end = std::max(blocks.back().end, range.end);
      } else {
        blocks.push_back(range);
      }
    }
    schedule_.emplace(blocks, computing_ranks);
  }

  // Up to `size` pending samples for computing rank `who`, ascending; `worth`: the samples
  // of about chunk_seconds, below which another rank's queue is left to it.
  std::vector<std::int64_t> Next(int who, std::int64_t size, std::int64_t worth) {
    std::deque<std::int64_t>& own = queues_[static_cast<std::size_t>(who)];
    std::vector<std::int64_t> chunk;
    while (static_cast<std::int64_t>(chunk.size()) < size) {
      if (own.empty() && !Refill(who, worth)) break;
      const auto n = std::min(static_cast<std::size_t>(size) - chunk.size(), own.size());
      chunk.insert(chunk.end(), own.begin(), own.begin() + static_cast<std::ptrdiff_t>(n));
      own.erase(own.begin(), own.begin() + static_cast<std::ptrdiff_t>(n));
    }
    return chunk;
  }

 private:
  // Gives `who` more samples: its next block, or at the end half of another rank's.
  bool Refill(int who, std::int64_t worth) {
    std::deque<std::int64_t>& own = queues_[static_cast<std::size_t>(who)];
    for (const std::int64_t block : schedule_->Take(who, 1)) {
      for (const SampleRange& run : store_.Pending(block * block_, std::min(store_.items(), (block + 1) * block_))) {
        for (std::int64_t index = run.begin; index < run.end; ++index) own.push_back(index);
      }
    }
    if (!own.empty()) return true;
    if (shared_[static_cast<std::size_t>(who)]) return false;
    const auto victim = std::max_element(queues_.begin(), queues_.end(),
                                         [](const auto& a, const auto& b) { return a.size() < b.size(); });
    if (static_cast<std::int64_t>(victim->size()) <= worth) return false;
    shared_[static_cast<std::size_t>(who)] = true;
    const std::size_t take = (victim->size() + 1) / 2;
    own.insert(own.end(), victim->end() - static_cast<std::ptrdiff_t>(take), victim->end());
    victim->erase(victim->end() - static_cast<std::ptrdiff_t>(take), victim->end());
    return true;
  }

  const PoolResults& store_;
  std::int64_t block_;
  std::optional<BlockSchedule> schedule_;
  std::vector<std::deque<std::int64_t>> queues_;  // per computing rank: taken, not handed out
  std::vector<bool> shared_;                       // per computing rank: has taken another's samples
};

// What rank 0's computing threads ring when its main thread has work to do; the main
// thread sleeps on it.
class Doorbell {
 public:
  void Ring() {
    {
      std::lock_guard lock(mutex_);
      ++rings_;
    }
    wake_.notify_one();
  }
  // Rings so far: the argument of a later WaitAfter.
  std::uint64_t rings() {
    std::lock_guard lock(mutex_);
    return rings_;
  }
  // Returns at the first ring after `seen` rings, or at `deadline`.
  void WaitAfter(std::uint64_t seen, Clock::time_point deadline) {
    std::unique_lock lock(mutex_);
    wake_.wait_until(lock, deadline, [&] { return rings_ != seen; });
  }

 private:
  std::mutex mutex_;
  std::condition_variable wake_;
  std::uint64_t rings_ = 0;
};

// Rank 0's own computing thread, fed a chunk at a time like a remote worker. It rings
// `doorbell` when it wants work, has stopped or failed, and, when `eager`, at every
// finished sample.
class LocalWorker {
 public:
  LocalWorker(const PoolWork& work, const PoolOptions& options, Doorbell& doorbell, bool eager)
      : doorbell_(doorbell), eager_(eager), thread_([this, &work, &options] { Run(work, options); }) {}
  ~LocalWorker() {
    Stop();
    thread_.join();
  }

  // True when it has finished its chunk and wants another.
  bool WantsWork() {
    std::lock_guard lock(mutex_);
    return !has_work_ && !busy_ && !stop_;
  }
  void Give(std::vector<std::int64_t> chunk) {
    {
      std::lock_guard lock(mutex_);
      work_ = std::move(chunk);
      has_work_ = true;
    }
    wake_.notify_one();
  }
  void Stop() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_one();
  }
  // Stops, leaving the rest of its chunk (after the sample in progress) undone.
  void Abandon() {
    abandon_ = true;
    Stop();
  }
  // Finished records since the last call; rethrows what killed the thread, if anything.
  std::vector<SampleRecord> Collect() {
    std::lock_guard lock(mutex_);
    if (error_) std::rethrow_exception(error_);
    return std::exchange(finished_, {});
  }
  bool Finished() {
    std::lock_guard lock(mutex_);
    return stop_ && !has_work_ && !busy_;
  }

 private:
  void Run(const PoolWork& work, const PoolOptions& options) {
    try {
      const PoolWork::Evaluator evaluate = work.MakeEvaluator();
      for (;;) {
        std::vector<std::int64_t> chunk;
        {
          std::unique_lock lock(mutex_);
          wake_.wait(lock, [this] { return has_work_ || stop_; });
          if (!has_work_) return;
          chunk = std::move(work_);
          has_work_ = false;
          busy_ = true;
        }
        for (const std::int64_t index : chunk) {
          if (abandon_ || StopRequest(options) != 0) break;
          SampleRecord record = evaluate(index);
          {
            std::lock_guard lock(mutex_);
            finished_.push_back(std::move(record));
          }
          if (eager_) doorbell_.Ring();
        }
        {
          std::lock_guard lock(mutex_);
          busy_ = false;
        }
        doorbell_.Ring();
      }
    } catch (...) {
      {
        std::lock_guard lock(mutex_);
        error_ = std::current_exception();
        busy_ = has_work_ = false;
        stop_ = true;
      }
      doorbell_.Ring();
    }
  }

  Doorbell& doorbell_;
  const bool eager_;

  std::mutex mutex_;
  std::condition_variable wake_;
  std::vector<std::int64_t> work_;
  bool has_work_ = false;
  bool busy_ = false;
  bool stop_ = false;
  std::atomic<bool> abandon_{false};
  std::vector<SampleRecord> finished_;
  std::exception_ptr error_;
  std::thread thread_;  // last: starts once the members above exist
};

PoolReport RunCoordinator(MPI_Comm communicator, int ranks, const PoolWork& work, PoolResults& store,
                          const PoolOptions& options, const std::function<void(const PoolProgress&)>& progress) {
  const Clock::time_point start = Clock::now();
  PoolReport report;
  report.ranks = ranks;
  const bool computes = ranks == 1 || options.coordinator_computes == 1 ||
                        (options.coordinator_computes < 0 && ranks < 16);
  const int threads = !computes              ? 0
                      : options.threads > 0 ? options.threads
                      : ranks == 1          ? std::max(1, static_cast<int>(std::thread::hardware_concurrency()))
                                            : 1;
  report.computing_ranks = (ranks - 1) + threads;

  // The statuses are read where the results were written, and everything beyond is one
  // run: the start does not grow with the items.
  const std::vector<SampleRange> pending_runs = store.Pending(0, store.items());
  std::int64_t pending = 0;
  for (const SampleRange& run : pending_runs) pending += run.end - run.begin;
  report.already_done = store.items() - pending;
  std::int64_t unassigned = pending;
  // Computing rank numbers for the block schedule: rank 0's threads first, then the workers.
  const auto computing_rank = [&](int mpi_rank) { return threads + mpi_rank - 1; };
  std::optional<PendingCursor> cursor;
  std::optional<BlockHandout> blocks;
  if (options.align_samples > 0) {
    blocks.emplace(store, pending_runs, options.align_samples, report.computing_ranks);
  } else {
    cursor.emplace(store);
  }

  // [s] per sample, over this run; the floor keeps the division finite should a clock
  // ever read samples as taking no time.
  constexpr double kShortestSample = 1e-9;
  double mean_time = 0.0;
  auto next_chunk = [&](int who) {
    if (report.stopped != 0) return std::vector<std::int64_t>();
    std::int64_t size = options.chunk_samples;
    const double fitting = options.chunk_seconds / std::max(mean_time, kShortestSample);
    // Before a sample is timed, any queue is worth sharing.
    const std::int64_t worth = options.chunk_samples > 0 ? options.chunk_samples
                               : report.computed == 0    ? 0
                                                         : std::llround(fitting);
    if (size <= 0) {
      const std::int64_t share = std::max<std::int64_t>(1, unassigned / (2 * report.computing_ranks));
      size = report.computed == 0
                 ? 1
                 : std::clamp<std::int64_t>(std::llround(std::min(fitting, static_cast<double>(share))), 1, share);
    }
    std::vector<std::int64_t> chunk;
    if (blocks) {
      chunk = blocks->Next(who, size, worth);
    } else {
      while (static_cast<std::int64_t>(chunk.size()) < size) {
        const std::optional<std::int64_t> index = cursor->Next();
        if (!index) break;
        chunk.push_back(*index);
      }
    }
    unassigned -= static_cast<std::int64_t>(chunk.size());
    return chunk;
  };

  std::int64_t committed = 0;
  Clock::time_point last_commit = Clock::now();
  auto commit = [&] {
    const Clock::time_point begin = Clock::now();
    const auto count = static_cast<std::int64_t>(store.buffered());
    store.Commit();
    committed += count;
    last_commit = Clock::now();
    report.commit_time += Seconds(last_commit - begin);
    if (options.testing.kill_after_committed >= 0 && committed >= options.testing.kill_after_committed) std::raise(SIGKILL);
  };
  std::int64_t failed = 0;
  // `filed`: in a worker's shard already, so only counted here.
  Clock::time_point last_arrival = start;
  auto count = [&](SampleStatus status, std::int64_t samples, double solve_time) {
    last_arrival = Clock::now();
    report.computed += samples;
    report.solver_time += solve_time;
    mean_time = report.solver_time / static_cast<double>(std::max<std::int64_t>(1, report.computed));
    report.status[status] += samples;
    if (status != SampleStatus::kOk) failed += samples;
  };
  auto absorb = [&](SampleRecord record) {
    count(record.status, 1, record.solve_time);
    store.Add(std::move(record));
  };
  // A worker's tally of a chunk it filed in its shard (Tally::Pack): its solve time goes
  // with its first status.
  auto absorb_tally = [&](Unpacker& in) {
    double solve_time = in.Get<double>();
    while (!in.done()) {
      const auto status = in.Get<SampleStatus>();
      count(status, in.Get<std::int64_t>(), std::exchange(solve_time, 0.0));
    }
  };
  auto tell = [&] {
    if (progress) progress({report.already_done + report.computed, store.items(), report.computed, failed,
                            Seconds(Clock::now() - start)});
  };

  // With commits due more often than rank 0 would otherwise wake, every finished sample
  // wakes it.
  const bool eager = options.commit_seconds < std::chrono::duration<double>(kWakeAtLeastEvery).count();
  Doorbell doorbell;
  std::vector<std::unique_ptr<LocalWorker>> locals;
  for (int t = 0; t < threads; ++t) locals.push_back(std::make_unique<LocalWorker>(work, options, doorbell, eager));
  // From the first stop request on, no more work is handed out (next_chunk is empty).
  auto stop = [&](int request) {
    if (request == 0 || report.stopped != 0) return;
    report.stopped = request;
    for (const std::unique_ptr<LocalWorker>& local : locals) local->Abandon();
  };
  int active_workers = ranks - 1;
  const std::size_t dimension = work.dimension();
  std::vector<char> message;
  tell();
  for (;;) {
    const std::uint64_t rung = doorbell.rings();
    const Clock::time_point round = Clock::now();
    const double round_cpu = ThreadCpuSeconds();
    bool arrived = false;
    stop(StopRequest(options));
    while (active_workers > 0) {
      int flag = 0;
      MPI_Status status;
      Check(MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, communicator, &flag, &status), "MPI_Iprobe");
      if (!flag) break;
      int bytes = 0;
      Check(MPI_Get_count(&status, MPI_BYTE, &bytes), "MPI_Get_count");
      message.resize(static_cast<std::size_t>(bytes));
      Check(MPI_Recv(message.data(), bytes, MPI_BYTE, status.MPI_SOURCE, status.MPI_TAG, communicator,
                     MPI_STATUS_IGNORE),
            "MPI_Recv");
      Unpacker in(message);
      if (status.MPI_TAG == kTagStopping) stop(in.Get<std::int32_t>());
      // Reply first: the worker computes while rank 0 files what it sent.
      const std::vector<std::int64_t> runs = Runs(next_chunk(computing_rank(status.MPI_SOURCE)));
      Check(MPI_Send(runs.data(), static_cast<int>(runs.size()), MPI_INT64_T, status.MPI_SOURCE, kTagWork,
                     communicator),
            "MPI_Send");
      if (runs.empty()) --active_workers;
      report.coordinator_messages += 2;
      report.coordinator_bytes += bytes + static_cast<std::int64_t>(runs.size() * sizeof(std::int64_t));
      if (!in.done()) {
        const char kind = in.Get<char>();
        if (kind == kSummaries) {
          absorb_tally(in);
        } else if (kind == kFiled) {
          while (!in.done()) {
            SampleRecord record = Unpack(in, dimension);
            count(record.status, 1, record.solve_time);
            store.Learn(std::move(record), status.MPI_SOURCE);
          }
        } else {
          while (!in.done()) absorb(Unpack(in, dimension));
        }
      }
      arrived = true;
    }
    bool locals_finished = true;
    for (std::size_t t = 0; t < locals.size(); ++t) {
      const std::unique_ptr<LocalWorker>& local = locals[t];
      for (SampleRecord& record : local->Collect()) {
        absorb(std::move(record));
        arrived = true;
      }
      if (local->WantsWork()) {
        std::vector<std::int64_t> chunk = next_chunk(static_cast<int>(t));
        if (chunk.empty()) {
          local->Stop();
        } else {
          local->Give(std::move(chunk));
        }
      }
      locals_finished = locals_finished && local->Finished();
    }
    if (active_workers == 0 && locals_finished) {
      for (const std::unique_ptr<LocalWorker>& local : locals) {
        for (SampleRecord& record : local->Collect()) absorb(std::move(record));
      }
      break;
    }
    if (store.buffered() > 0 && Seconds(Clock::now() - last_commit) >= options.commit_seconds) {
      commit();
      arrived = true;
    }
    if (arrived) {
      report.coordinator_time += Seconds(Clock::now() - round);
      report.coordinator_cpu_time += ThreadCpuSeconds() - round_cpu;
      tell();
    } else {
      Clock::time_point wake = Clock::now() + (active_workers > 0 ? Clock::duration(kMessagePoll)
                                                                   : Clock::duration(kWakeAtLeastEvery));
      if (store.buffered() > 0 && options.commit_seconds < Seconds(wake - last_commit)) {
        wake = last_commit + std::chrono::duration_cast<Clock::duration>(
                                 std::chrono::duration<double>(options.commit_seconds));
      }
      doorbell.WaitAfter(rung, wake);
    }
  }
  locals.clear();
  const Clock::time_point last = Clock::now();
  const double last_cpu = ThreadCpuSeconds();
  commit();
  report.coordinator_time += Seconds(Clock::now() - last);
  report.coordinator_cpu_time += ThreadCpuSeconds() - last_cpu;
  report.wall_time = Seconds(Clock::now() - start);
  report.tail_time = Seconds(Clock::now() - last_arrival);
  tell();
  return report;
}

}  // namespace

double ThreadCpuSeconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

bool PoolOptions::IsValid(InvalidOption* invalid) const {
  return CheckOption("chunk_samples", chunk_samples, kChunkSamplesRange, invalid) &&
         CheckOption("align_samples", align_samples, kAlignSamplesRange, invalid) &&
         CheckOption("chunk_seconds", chunk_seconds, kChunkSecondsRange, invalid) &&
         CheckOption("commit_seconds", commit_seconds, kCommitSecondsRange, invalid) &&
         CheckOption("coordinator_computes", coordinator_computes, kCoordinatorComputesRange, invalid) &&
         CheckOption("threads", threads, kThreadsRange, invalid) &&
         CheckOption("testing.kill_after_committed", testing.kill_after_committed, Testing::kKillAfterCommittedRange,
                     invalid) &&
         CheckOption("testing.kill_rank", testing.kill_rank, Testing::kKillRankRange, invalid) &&
         CheckOption("testing.sample_seconds", testing.sample_seconds, Testing::kSampleSecondsRange, invalid);
}

PoolReport RunPool(MPI_Comm communicator, const PoolWork& work, PoolResults* results, const PoolOptions& options,
                   const std::function<void(const PoolProgress&)>& progress) {
  InvalidOption invalid;
  RINGTOL_CHECK(options.IsValid(&invalid), invalid.field, invalid.value);
  int rank = 0;
  int ranks = 1;
  Check(MPI_Comm_rank(communicator, &rank), "MPI_Comm_rank");
  Check(MPI_Comm_size(communicator, &ranks), "MPI_Comm_size");
  // Every rank reaches the reduction below, which adds up the workers' CPU times.
  WorkerCpu cpu;
  PoolReport report;
  if (rank != 0) {
    cpu = RunWorker(communicator, rank, work, results, options);
  } else {
    RINGTOL_CHECK(results != nullptr, rank);  // rank 0 needs the results file
    report = RunCoordinator(communicator, ranks, work, *results, options, progress);
  }
  const std::array<double, 3> mine = {cpu.total, cpu.samples, cpu.waiting};
  std::array<double, 3> all = {0.0, 0.0, 0.0};
  Check(MPI_Reduce(mine.data(), all.data(), 3, MPI_DOUBLE, MPI_SUM, 0, communicator), "MPI_Reduce");
  report.worker_cpu_time = all[0];
  report.worker_sample_cpu_time = all[1];
  report.worker_wait_cpu_time = all[2];
  return report;
}

}  // namespace ringtol::jobs
