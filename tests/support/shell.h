// Running a command line the way a user's shell does, for tests of the executable.
#pragma once

#include <sys/wait.h>

#include <gmock/gmock.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <ostream>
#include <string>

#include "tests/support/text_files.h"

namespace ringtol::testing {

struct ShellOutcome {
  int exit_code = -1;  // the shell's: 128 + signal for a child killed by a signal
  std::string out;
  std::string err;
};

// How a failed expectation shows a run: its exit code and what it said on stderr.
inline void PrintTo(const ShellOutcome& run, std::ostream* out) {
  *out << "exit code " << run.exit_code << ", stderr \"" << run.err << "\"";
}

// A run that ended with exit code `code` and said `message` on stderr.
inline ::testing::Matcher<const ShellOutcome&> ExitsWith(const ::testing::Matcher<int>& code,
                                                         const ::testing::Matcher<const std::string&>& message) {
  return ::testing::AllOf(::testing::Field("exit_code", &ShellOutcome::exit_code, code),
                          ::testing::Field("err", &ShellOutcome::err, message));
}

// Runs `command` through /bin/sh with stderr captured in `err_file` (give each test its
// own: ctest runs tests in parallel).
inline ShellOutcome RunShell(const std::string& command, const std::filesystem::path& err_file) {
  ShellOutcome run;
  FILE* pipe = popen((command + " 2>" + err_file.string()).c_str(), "r");
  if (pipe == nullptr) return run;
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), static_cast<int>(buffer.size()), pipe) != nullptr) run.out += buffer.data();
  const int status = pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.err = ReadText(err_file);
  return run;
}

}  // namespace ringtol::testing
