// Text-file helpers shared by the input-reader tests.
#pragma once

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

}  // namespace ringtol::testing
