// Damage done to a file on purpose, for tests of what notices it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace ringtol::testing {

// Inverts `count` bytes at `at`, so that each surely changes.
inline void FlipBytes(const std::filesystem::path& path, std::uint64_t at, std::size_t count) {
  std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
  std::string bytes(count, '\0');
  file.seekg(static_cast<std::streamoff>(at));
  file.read(bytes.data(), static_cast<std::streamsize>(count));
  for (char& byte : bytes) byte = static_cast<char>(~static_cast<unsigned char>(byte));
  file.seekp(static_cast<std::streamoff>(at));
  file.write(bytes.data(), static_cast<std::streamsize>(count));
}

// Writes `bytes` over the file's bytes at `at`.
inline void OverwriteBytes(const std::filesystem::path& path, std::uint64_t at, const std::string& bytes) {
  std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
  file.seekp(static_cast<std::streamoff>(at));
  file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace ringtol::testing
