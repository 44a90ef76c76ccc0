// Runs of the executable in the background, so that a test can signal them while they work.
#pragma once

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>

#include "tests/support/text_files.h"

namespace ringtol::testing {

struct Running {
  pid_t pid = -1;  // the shell's, which execs the command (so ringtol's, or mpirun's)
  std::filesystem::path out;
  std::filesystem::path err;
};

// How a background run ended: by itself with an exit code, or killed by a signal.
struct Ended {
  bool killed = false;
  int code = -1;  // exit code, or the signal that killed it
  std::string out;
  std::string err;
};

// `command` (a shell command line; prefix it with `exec ` so that the pid is the command's)
// in the background, its stdout and stderr in `folder`/`name`.out and .err.
inline Running Start(const std::string& command, const std::filesystem::path& folder, const std::string& name) {
  Running run{-1, folder / (name + ".out"), folder / (name + ".err")};
  const std::string line = command + " >" + run.out.string() + " 2>" + run.err.string();
  run.pid = fork();
  if (run.pid == 0) {
    execl("/bin/sh", "sh", "-c", line.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  return run;
}

// How `run` ended, if it did within `seconds`; otherwise it is killed (SIGKILL) and reaped,
// and the result is empty.
inline std::optional<Ended> WaitWithin(const Running& run, double seconds) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  int status = 0;
  while (waitpid(run.pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      kill(run.pid, SIGKILL);
      waitpid(run.pid, &status, 0);
      return std::nullopt;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return Ended{WIFSIGNALED(status), WIFSIGNALED(status) ? WTERMSIG(status) : WEXITSTATUS(status), ReadText(run.out),
               ReadText(run.err)};
}

// The longest any test's run may take, under the sanitizers on two loaded cores [s].
inline constexpr double kLongestRunSeconds = 600.0;

// How `run` ended. One still going after `seconds` fails the test and is killed, so that a
// run that never stops (a stop that hangs, say) fails its test by name rather than holding
// the suite until CI's limit.
inline Ended Wait(const Running& run, double seconds = kLongestRunSeconds) {
  if (std::optional<Ended> ended = WaitWithin(run, seconds)) return *std::move(ended);
  ADD_FAILURE() << "still running " << seconds << " s after it started waiting, killed; its stderr: "
                << ReadText(run.err);
  return {true, SIGKILL, ReadText(run.out), ReadText(run.err)};
}

// Polls until `ready` or two minutes have passed; false on the latter.
template <typename Ready>
bool WaitFor(Ready ready) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(2);
  while (!ready()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

}  // namespace ringtol::testing
