// What every input file must be before a reader looks inside: UTF-8 text (ASCII is UTF-8).
//
// Spreadsheet programs and Windows tools also save "Unicode text", which is UTF-16 (rarely
// UTF-32): read as bytes it has a NUL byte beside every ASCII character, so a reader's own
// message about it would quote nothing legible (and a message is cut at its first NUL).
// Such text is refused by its name instead.
#pragma once

#include <string>
#include <string_view>

namespace ringtol::jobs {

// `text` without a leading UTF-8 byte-order mark (which Windows tools write; accepted
// silently). Throws InputError, naming `source_name`, for text that starts with a UTF-16
// or UTF-32 byte-order mark, for text whose first NUL bytes fall where UTF-16 or UTF-32
// puts them (the encoding and byte order named, as guessed), and for any other NUL byte
// (binary data, its line named), e.g.
//   ring.csv: UTF-16 (little-endian) text; allowed: UTF-8 text (ASCII included): save the
//   file as UTF-8 (a spreadsheet's "CSV UTF-8", an editor's "UTF-8" encoding)
std::string_view Utf8Text(std::string_view text, const std::string& source_name);

}  // namespace ringtol::jobs
