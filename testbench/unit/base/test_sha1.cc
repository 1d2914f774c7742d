// SHA-1 against the FIPS 180 examples and sha1sum, fed whole and in uneven pieces (block
// boundaries and the padding's two cases: room for the length in the last block or not).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "blocks/base/sha1.h"

namespace {

using texsim::Sha1;

std::string sha1(const std::string& s) {
  Sha1 h;
  h.append(s.data(), s.size());
  return h.hex_digest();
}

TEST(Sha1, MatchesTheStandardsExamples) {
  EXPECT_EQ(sha1(""), "da39a3ee5e6b4b0d3255bfef95601890afd80709");
  EXPECT_EQ(sha1("abc"), "a9993e364706816aba3e25717850c26c9cd0d89d");
  EXPECT_EQ(sha1("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "84983e441c3bd26ebaae4aa1f95129e5e54670f1");
  EXPECT_EQ(sha1(std::string(1000000, 'a')), "34aa973cd4c4daa4f61eeb2bdbad27316534016f");
  // sha1sum of 55, 56 and 64 bytes: the lengths around one block's padding.
  EXPECT_EQ(sha1(std::string(55, 'x')), "cef734ba81a024479e09eb5a75b6ddae62e6abf1");
  EXPECT_EQ(sha1(std::string(56, 'x')), "901305367c259952f4e7af8323f480d59f81335b");
  EXPECT_EQ(sha1(std::string(64, 'x')), "bb2fa3ee7afb9f54c6dfb5d021f14b1ffe40c163");
}

TEST(Sha1, PiecesGiveTheDigestOfTheWhole) {
  std::string text;
  for (int i = 0; i < 1000; ++i) text += static_cast<char>((i * 37 + 11) & 0xFF);
  const std::string whole = sha1(text);
  for (size_t piece : {1u, 3u, 63u, 64u, 65u, 200u}) {
    Sha1 h;
    for (size_t i = 0; i < text.size(); i += piece)
      h.append(text.data() + i, std::min(piece, text.size() - i));
    EXPECT_EQ(h.hex_digest(), whole) << "pieces of " << piece;
  }
}

}  // namespace
