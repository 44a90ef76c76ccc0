#include "engine/visible_text.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <iterator>

namespace ringtol {
namespace {

struct CodePointRange {
  char32_t first, last;
};

// Unicode 15.0's Cc, Cf, Zs (but U+0020), Zl, Zp and Default_Ignorable_Code_Point, merged
// into ranges, in order (ICU 72's u_charType and UCHAR_DEFAULT_IGNORABLE_CODE_POINT list
// exactly these).
constexpr std::array<CodePointRange, 29> kInvisible{{
    {0x0000, 0x001F},   {0x007F, 0x00A0},   {0x00AD, 0x00AD},   {0x034F, 0x034F},   {0x0600, 0x0605},
    {0x061C, 0x061C},   {0x06DD, 0x06DD},   {0x070F, 0x070F},   {0x0890, 0x0891},   {0x08E2, 0x08E2},
    {0x115F, 0x1160},   {0x1680, 0x1680},   {0x17B4, 0x17B5},   {0x180B, 0x180F},   {0x2000, 0x200F},
    {0x2028, 0x202F},   {0x205F, 0x206F},   {0x3000, 0x3000},   {0x3164, 0x3164},   {0xFE00, 0xFE0F},
    {0xFEFF, 0xFEFF},   {0xFFA0, 0xFFA0},   {0xFFF0, 0xFFFB},   {0x110BD, 0x110BD}, {0x110CD, 0x110CD},
    {0x13430, 0x1343F}, {0x1BCA0, 0x1BCA3}, {0x1D173, 0x1D17A}, {0xE0000, 0xE0FFF},
}};

bool IsInvisible(char32_t c) {
  const auto after = std::upper_bound(kInvisible.begin(), kInvisible.end(), c,
                                      [](char32_t value, const CodePointRange& range) { return value < range.first; });
  return after != kInvisible.begin() && c <= std::prev(after)->last;
}

// The code point that starts `text` and its length in bytes; length 0 when the bytes there
// are not well-formed UTF-8 (overlong forms, surrogates and values beyond U+10FFFF included).
struct Decoded {
  char32_t code_point = 0;
  std::size_t length = 0;
};

Decoded DecodeUtf8(std::string_view text) {
  const auto byte = [&](std::size_t i) { return static_cast<std::uint8_t>(text[i]); };
  const std::uint8_t lead = byte(0);
  if (lead < 0x80) return {lead, 1};
  std::size_t length = 0;
  char32_t code_point = 0;
  char32_t smallest = 0;  // below it the form is overlong
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2, code_point = lead & 0x1Fu, smallest = 0x80;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3, code_point = lead & 0x0Fu, smallest = 0x800;
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4, code_point = lead & 0x07u, smallest = 0x10000;
  } else {
    return {};
  }
  if (text.size() < length) return {};
  for (std::size_t i = 1; i < length; ++i) {
    if ((byte(i) & 0xC0u) != 0x80u) return {};
    code_point = (code_point << 6) | (byte(i) & 0x3Fu);
  }
  if (code_point < smallest || code_point > 0x10FFFF || (code_point >= 0xD800 && code_point <= 0xDFFF)) return {};
  return {code_point, length};
}

std::string Escape(const char* format, unsigned value) {
  std::array<char, 16> escaped{};
  std::snprintf(escaped.data(), escaped.size(), format, value);
  return escaped.data();
}

}  // namespace

std::string VisibleText(std::string_view text) {
  std::string shown;
  shown.reserve(text.size());
  while (!text.empty()) {
    const Decoded next = DecodeUtf8(text);
    if (next.length == 0) {
      shown += Escape("\\x%02X", static_cast<std::uint8_t>(text.front()));
      text.remove_prefix(1);
      continue;
    }
    const char32_t c = next.code_point;
    if (c == '\t') {
      shown += "\\t";
    } else if (c == '\n') {
      shown += "\\n";
    } else if (c == '\r') {
      shown += "\\r";
    } else if (IsInvisible(c)) {
      shown += Escape(c > 0xFFFF ? "\\U%08X" : "\\u%04X", static_cast<unsigned>(c));
    } else {
      shown.append(text.substr(0, next.length));
    }
    text.remove_prefix(next.length);
  }
  return shown;
}

}  // namespace ringtol
