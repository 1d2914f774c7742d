#pragma once
// Test-only: the fuzzers' CRC repair for the chunked, checksummed trace formats (fragment and
// draw traces): read a little-endian word, and write the CRC-32 of a byte range, so that the
// harnesses' "fix CRC" mode lets mutations reach the parser behind the checksums.
#include <zlib.h>

#include <cstdint>
#include <cstring>
#include <vector>

namespace texsim::fuzz {

inline uint32_t get_u32(const std::vector<uint8_t>& b, size_t at) {
  uint32_t v = 0;
  std::memcpy(&v, b.data() + at, 4);
  return v;
}

// b[at .. at + 4) = CRC-32 of b[from .. from + len).
inline void put_crc(std::vector<uint8_t>& b, size_t at, size_t from, size_t len) {
  const auto crc = static_cast<uint32_t>(crc32(0, b.data() + from, static_cast<uInt>(len)));
  std::memcpy(b.data() + at, &crc, 4);
}

}  // namespace texsim::fuzz
