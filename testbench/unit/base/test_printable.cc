// Echoed input text: control characters and invalid UTF-8 are escaped, valid text is kept.
#include <gtest/gtest.h>

#include "blocks/base/printable.h"

namespace texsim {
namespace {

TEST(Printable, KeepsValidTextEscapesTheRest) {
  EXPECT_EQ(printable("plain text"), "plain text");
  EXPECT_EQ(printable("line\nnext\ttab"), "line\nnext\ttab");
  EXPECT_EQ(printable("\x1b[2J"), "\\x1B[2J");
  EXPECT_EQ(printable(std::string("a\0b", 3)), "a\\x00b");
  EXPECT_EQ(printable("\x7f"), "\\x7F");
  EXPECT_EQ(printable("текстура"), "текстура");          // two-byte sequences kept
  EXPECT_EQ(printable("\xe2\x82\xac"), "\xe2\x82\xac");  // the euro sign
  EXPECT_EQ(printable("\xff\xfe"), "\\xFF\\xFE");
  EXPECT_EQ(printable("\xc0\xaf"), "\\xC0\\xAF");           // overlong
  EXPECT_EQ(printable("\xed\xa0\x80"), "\\xED\\xA0\\x80");  // a surrogate
  EXPECT_EQ(printable("\xe2\x82"), "\\xE2\\x82");           // truncated
}

TEST(Printable, NameCheck) {
  EXPECT_TRUE(is_printable_utf8("floor"));
  EXPECT_TRUE(is_printable_utf8("підлога"));
  EXPECT_FALSE(is_printable_utf8("a\nb"));
  EXPECT_FALSE(is_printable_utf8("\xff"));
}

}  // namespace
}  // namespace texsim
