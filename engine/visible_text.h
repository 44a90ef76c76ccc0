// A user's text as a message shows it: every code point a reader cannot see is written as
// an escape, so that a class name with a zero-width space after it reads "IT7\u200B", not
// "IT7" beside a list that holds "IT7".
//
// Escaped, as Unicode 15.0 defines them: controls (category Cc: C0, DEL, C1), format
// characters (Cf: soft hyphen, zero-width space and joiners, bidirectional marks, the
// byte-order mark, ...), separators other than the ASCII space (Zs, Zl, Zp: the no-break
// and typographic spaces, line and paragraph separators), and the other default-ignorable
// code points (variation selectors, Hangul fillers, the combining grapheme joiner). Each
// becomes \t, \n or \r, or \uXXXX (\UXXXXXXXX beyond U+FFFF): TOML's and JSON's own escapes,
// so a quoted TOML value shown this way reads back as the same string. A byte that is not
// part of valid UTF-8 (the NUL bytes of UTF-16 text, Latin-1 text) becomes \xNN. Everything
// else, ASCII or not ("µm", "Ø"), is kept as it is.
#pragma once

#include <string>
#include <string_view>

namespace ringtol {

// `text` with every invisible code point and every byte outside valid UTF-8 escaped.
std::string VisibleText(std::string_view text);

}  // namespace ringtol
