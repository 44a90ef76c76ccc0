// SIGINT and SIGTERM as a request to stop cleanly: while a StopSignals object lives, the
// first of them only sets a flag that long-running work polls (the campaign pool stops
// handing out work, keeps every finished sample and closes its file); what to do with a
// second one is the owner's choice (see `repeat`). Nothing here knows MPI or files, so any
// command that runs for long can use it.
//
// Ctrl-C in a terminal sends SIGINT, `kill` and batch schedulers at a job's time limit
// SIGTERM. By the shell's convention a process ended by signal s exits with 128 + s
// (130 for SIGINT, 143 for SIGTERM): ExitCode() gives that number.
#pragma once

#include <string>

namespace ringtol::jobs {

class StopSignals {
 public:
  enum class Repeat {
    kEndsAtOnce,  // a second signal restores the default action and re-raises: the process ends at once
    kIgnored,     // a second signal is ignored (a launcher, not the user, decides when to kill)
  };

  // Installs the handler for SIGINT and SIGTERM (with SA_RESTART, so system calls in
  // progress go on). One object at a time per process: a second one aborts.
  explicit StopSignals(Repeat repeat);
  // Restores the dispositions found at construction. A signal received afterwards takes
  // its default action.
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  // The first signal received since construction, 0 if none. Safe from any thread.
  int received() const;

  // 128 + signal: the exit code of a process that ended on `signal`.
  static int ExitCode(int signal) { return 128 + signal; }
  // "SIGINT", "SIGTERM", or "signal N" for any other number.
  static std::string Name(int signal);
};

}  // namespace ringtol::jobs
