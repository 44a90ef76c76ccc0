// Files the tests read and write, and the messages of refused input.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

namespace ringtol::testing {

inline std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Writes `text` byte for byte. A file that cannot be written stops the test, which would
// otherwise go on to read an old file or none.
inline void WriteText(const std::filesystem::path& path, std::string_view text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("test cannot write " + path.string());
}

// Replaces the only occurrence of `from`: an anchor that vanished or became ambiguous
// must break the test, not silently test something else.
inline std::string ReplaceOnce(std::string text, std::string_view from, std::string_view to) {
  const std::size_t at = text.find(from);
  if (at == std::string::npos || text.find(from, at + 1) != std::string::npos) {
    throw std::logic_error("test anchor not found exactly once: " + std::string(from));
  }
  text.replace(at, from.size(), to);
  return text;
}

// The folder of the running test, <temp>/ringtol_<owner>/<suite>.<test>: ctest runs
// tests in parallel processes, which must never share a file.
inline std::filesystem::path TestFolderPath(std::string_view owner) {
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  return std::filesystem::path(::testing::TempDir()) / ("ringtol_" + std::string(owner)) /
         (std::string(test->test_suite_name()) + "." + test->name());
}

// TestFolderPath(owner), created empty: nothing left by an earlier run is read.
inline std::filesystem::path FreshTestFolder(std::string_view owner) {
  const std::filesystem::path folder = TestFolderPath(owner);
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  return folder;
}

// What the `Error` that `read` throws says; a test failure, and "", when `read` accepts
// its input.
template <typename Error, typename Read>
std::string MessageOf(Read read) {
  try {
    read();
  } catch (const Error& error) {
    return error.what();
  }
  ADD_FAILURE() << "the input was accepted";
  return "";
}

}  // namespace ringtol::testing
