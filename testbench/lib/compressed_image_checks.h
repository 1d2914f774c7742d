#pragma once
// Test helpers shared by the compressed-file readers' tests (DDS, KTX): little-endian header
// edits and the field-by-field comparison of two compressed images.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "pipeline/image_io/compressed_image.h"

namespace texsim::test {

inline void set_u32(std::string& s, size_t at, uint32_t v) {
  for (size_t i = 0; i < 4; ++i) s[at + i] = static_cast<char>(v >> (8 * i));
}

inline void expect_same(const CompressedImage& a, const CompressedImage& b) {
  EXPECT_EQ(a.format, b.format);
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_EQ(a.block_w, b.block_w);
  EXPECT_EQ(a.block_h, b.block_h);
  EXPECT_EQ(a.block_bytes, b.block_bytes);
  ASSERT_EQ(a.levels.size(), b.levels.size());
  for (size_t i = 0; i < a.levels.size(); ++i) {
    EXPECT_EQ(a.levels[i].width, b.levels[i].width) << "level " << i;
    EXPECT_EQ(a.levels[i].height, b.levels[i].height) << "level " << i;
    EXPECT_EQ(a.levels[i].bytes, b.levels[i].bytes) << "level " << i;
  }
}

}  // namespace texsim::test
