#include "jobs/inputs/text_encoding.h"

#include <algorithm>
#include <array>
#include <cstddef>

#include <fmt/format.h>

#include "jobs/inputs/input_error.h"

namespace ringtol::jobs {
namespace {

constexpr std::string_view kUtf8Allowed =
    "UTF-8 text (ASCII included): save the file as UTF-8 (a spreadsheet's \"CSV UTF-8\", an editor's \"UTF-8\" "
    "encoding)";

struct ByteOrderMark {
  std::string_view bytes;
  std::string_view encoding;
};
// UTF-32's little-endian mark starts with UTF-16's: longest first.
constexpr std::array<ByteOrderMark, 4> kForeignMarks{{{std::string_view("\xFF\xFE\0\0", 4), "UTF-32 (little-endian)"},
                                                      {std::string_view("\0\0\xFE\xFF", 4), "UTF-32 (big-endian)"},
                                                      {"\xFF\xFE", "UTF-16 (little-endian)"},
                                                      {"\xFE\xFF", "UTF-16 (big-endian)"}}};

// The encoding whose NUL bytes fall where the first four bytes have them, for ASCII
// characters; empty when no encoding puts them there.
std::string_view EncodingOfNuls(std::string_view text) {
  if (text.size() < 4) return {};
  std::array<bool, 4> nul{};
  for (std::size_t i = 0; i < 4; ++i) nul[i] = text[i] == '\0';
  if (!nul[0] && nul[1] && nul[2] && nul[3]) return "UTF-32 (little-endian)";
  if (nul[0] && nul[1] && nul[2] && !nul[3]) return "UTF-32 (big-endian)";
  if (!nul[0] && nul[1] && !nul[2] && nul[3]) return "UTF-16 (little-endian)";
  if (nul[0] && !nul[1] && nul[2] && !nul[3]) return "UTF-16 (big-endian)";
  return {};
}

}  // namespace

std::string_view Utf8Text(std::string_view text, const std::string& source_name) {
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
  for (const ByteOrderMark& mark : kForeignMarks) {
    if (text.starts_with(mark.bytes)) {
      throw InputError(fmt::format("{}: {} text (its byte-order mark says so); allowed: {}", source_name,
                                   mark.encoding, kUtf8Allowed));
    }
  }
  const std::size_t nul = text.find('\0');
  if (nul == std::string_view::npos) return text;
  if (const std::string_view encoding = EncodingOfNuls(text); !encoding.empty()) {
    throw InputError(fmt::format("{}: {} text, by its NUL bytes; allowed: {}", source_name, encoding, kUtf8Allowed));
  }
  const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(nul), '\n');
  throw InputError(fmt::format("{}:{}: a NUL byte (binary data, not text); allowed: {}", source_name, line,
                               kUtf8Allowed));
}

}  // namespace ringtol::jobs
