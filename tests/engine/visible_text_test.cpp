#include "engine/visible_text.h"

#include <string>

#include <gtest/gtest.h>

namespace ringtol {
namespace {

TEST(VisibleText, KeepsPrintableTextAsItIs) {
  for (const std::string text : {"IT7", "deviation_um, quality", "\xC2\xB5m", "\xC3\x98 300 mm", "\xE5\x86\x85\xE8\xBC\xAA",
                                 "C:\\exports\\ring.csv", ""}) {
    EXPECT_EQ(VisibleText(text), text);
  }
}

TEST(VisibleText, EscapesCodePointsAReaderCannotSee) {
  EXPECT_EQ(VisibleText("IT7\xE2\x80\x8B"), "IT7\\u200B");             // zero-width space (Cf)
  EXPECT_EQ(VisibleText("fixed\xC2\xA0"), "fixed\\u00A0");             // no-break space (Zs)
  EXPECT_EQ(VisibleText("lin\xC2\xAD" "ear"), "lin\\u00ADear");        // soft hyphen (Cf)
  EXPECT_EQ(VisibleText("\xEF\xBB\xBF" "angle_deg"), "\\uFEFFangle_deg");  // byte-order mark (Cf)
  EXPECT_EQ(VisibleText("a\xE2\x80\xA8" "b"), "a\\u2028b");            // line separator (Zl)
  EXPECT_EQ(VisibleText("P5\xEF\xB8\x8F"), "P5\\uFE0F");               // variation selector (default ignorable)
  EXPECT_EQ(VisibleText("P5\xF3\xA0\x81\x81"), "P5\\U000E0041");       // tag character, beyond U+FFFF
  EXPECT_EQ(VisibleText("a\tb\r\n"), "a\\tb\\r\\n");
  EXPECT_EQ(VisibleText(std::string("a\0b\x7F", 4)), "a\\u0000b\\u007F");  // controls (Cc)
  EXPECT_EQ(VisibleText("two words"), "two words");                    // the ASCII space stays
}

TEST(VisibleText, ShowsBytesOutsideUtf8AsHex) {
  EXPECT_EQ(VisibleText("\xFF\xFE" "a"), "\\xFF\\xFEa");       // UTF-16's byte-order mark
  EXPECT_EQ(VisibleText("\xB5m"), "\\xB5m");                   // Latin-1 micro sign
  EXPECT_EQ(VisibleText("\xC0\x80"), "\\xC0\\x80");            // overlong NUL
  EXPECT_EQ(VisibleText("\xED\xA0\x80"), "\\xED\\xA0\\x80");   // a surrogate
  EXPECT_EQ(VisibleText("\xF4\x90\x80\x80"), "\\xF4\\x90\\x80\\x80");  // beyond U+10FFFF
  EXPECT_EQ(VisibleText("a\xE2\x82"), "a\\xE2\\x82");          // cut short
}

}  // namespace
}  // namespace ringtol
