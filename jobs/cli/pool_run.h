// What the commands that run the pool (`ringtol campaign`, `ringtol allocate`) share:
// agreeing on an error across ranks before any work, checking the output file and the pool
// options, and the command line that resumes a stopped run.
#pragma once

#include <mpi.h>

#include <exception>
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "jobs/pool/pool.h"
#include "jobs/store/campaign_store.h"

namespace ringtol::jobs {

// The first error of any rank (lowest rank first), known to every rank; empty if none.
// Collective: every rank calls it.
std::string Agree(MPI_Comm communicator, const std::string& error);

// Runs `step`; what it throws, as text (empty when it succeeded).
template <typename F>
std::string Attempt(F&& step) {
  try {
    step();
    return {};
  } catch (const std::exception& e) {
    return e.what();
  }
}

// On every rank: throws `error` of the first rank that has one, as an InputError on every
// rank (Agree); returns when no rank has one.
void ThrowAgreed(MPI_Comm communicator, const std::string& error);
// On every rank: rank 0's cheap checks (the pool options' IsValid, naming the flag; the
// progress interval; CheckOutput), before any second of calibration; a failure is an
// InputError on every rank.
void CheckBeforeWork(MPI_Comm communicator, const PoolOptions& pool, double progress_seconds,
                     const std::filesystem::path& out, bool resume);

// InputError unless `out` can be created (new: the path is free and its folder writable)
// or continued (resume: the file exists), and while another run writes it (RefuseLiveOutput).
void CheckOutput(const std::filesystem::path& out, bool resume);
// InputError when a running ringtol writes `out` or one of its shards (BeingWritten,
// jobs/store/campaign_store.h), saying so: the advice for files a killed run left (resume
// them, or remove them) must never reach a live run's.
void RefuseLiveOutput(const std::filesystem::path& out);

// Before a resume, on rank 0: `set_aside` (SetAsideUnreadableShards, or the allocation's)
// renames the shards of the results file that cannot be read aside, and each one is said on
// `progress`; its InputError is thrown on every rank (ThrowAgreed). Collective.
void SetAsideUnreadable(MPI_Comm communicator, std::ostream& progress,
                        const std::function<std::vector<UnreadableShard>()>& set_aside);

// "m:ss" or "h:mm:ss".
std::string Clock(double seconds);
// One shell word: as is when it holds only characters no shell treats specially,
// single-quoted otherwise.
std::string ShellWord(const std::string& word);
// The command line `words` with --resume (added if absent), under `mpirun -n ranks` when
// ranks > 1, quoted for a shell.
std::string ResumeLine(std::vector<std::string> words, int ranks);

// Whether an MPI launcher started this process (Open MPI's mpirun, or a PMI launcher such
// as MPICH's or Slurm's), as opposed to a singleton run alone.
bool UnderLauncher(MPI_Comm communicator);

}  // namespace ringtol::jobs
