// The trace CRC (traces/FORMAT.md) is zlib's crc32(0, data, len); the reader and writer compute
// it with ISA-L's crc32_gzip_refl. Both must agree on every length and alignment, and in how a
// running CRC is passed in and returned, so files written before and after read the same.
#include <gtest/gtest.h>
#include <isa-l/crc.h>
#include <zlib.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "traces/trace_file.h"

namespace texsim {
namespace {

uint32_t zlib_crc(uint32_t crc, const unsigned char* p, size_t n) {
  return static_cast<uint32_t>(::crc32(crc, p, static_cast<uInt>(n)));
}

uint32_t isal_crc(uint32_t crc, const unsigned char* p, size_t n) {
  return crc32_gzip_refl(crc, p, static_cast<uint64_t>(n));
}

std::vector<unsigned char> random_bytes(size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> byte(0, 255);
  std::vector<unsigned char> v(n);
  for (auto& b : v) b = static_cast<unsigned char>(byte(rng));
  return v;
}

TEST(TraceCrc, CheckValueOfTheStandard) {
  const std::string s = "123456789";
  const auto* p = reinterpret_cast<const unsigned char*>(s.data());
  EXPECT_EQ(zlib_crc(0, p, s.size()), 0xCBF43926u);
  EXPECT_EQ(isal_crc(0, p, s.size()), 0xCBF43926u);
}

TEST(TraceCrc, EmptyInputKeepsTheRunningValue) {
  // (zlib gives a null buffer a meaning of its own, "the initial value", so pass a real one.)
  const unsigned char byte = 0;
  EXPECT_EQ(isal_crc(0, nullptr, 0), 0u);
  EXPECT_EQ(isal_crc(0, &byte, 0), zlib_crc(0, &byte, 0));
  EXPECT_EQ(isal_crc(0x12345678u, &byte, 0), zlib_crc(0x12345678u, &byte, 0));
}

TEST(TraceCrc, MatchesZlibOnEveryLengthAndAlignment) {
  constexpr size_t kMaxLen = 4096;
  constexpr size_t kMaxOffset = 16;
  const auto data = random_bytes(kMaxLen + kMaxOffset, 1234u);
  for (size_t offset = 0; offset < kMaxOffset; ++offset) {
    for (size_t n = 0; n <= kMaxLen; ++n) {
      const unsigned char* p = data.data() + offset;
      ASSERT_EQ(isal_crc(0, p, n), zlib_crc(0, p, n)) << "offset " << offset << ", length " << n;
    }
  }
}

TEST(TraceCrc, RunningCrcIsPassedInTheSameForm) {
  const auto data = random_bytes(3000, 99u);
  std::mt19937 rng(7u);
  std::uniform_int_distribution<size_t> cut(0, data.size());
  for (int i = 0; i < 500; ++i) {
    const size_t a = cut(rng);
    const uint32_t head = zlib_crc(0, data.data(), a);
    const uint32_t whole = zlib_crc(0, data.data(), data.size());
    EXPECT_EQ(isal_crc(head, data.data() + a, data.size() - a), whole) << "split at " << a;
    EXPECT_EQ(isal_crc(isal_crc(0, data.data(), a), data.data() + a, data.size() - a), whole);
  }
}

TEST(TraceCrc, MatchesZlibOnChunkSizedBuffers) {
  // A default chunk (4096 records of 72 bytes) and 3 MiB + 5, at odd starts.
  for (const size_t n : {size_t{294912}, size_t{3145733}}) {
    const auto data = random_bytes(n + 3, static_cast<uint32_t>(n));
    for (size_t offset = 0; offset < 3; ++offset) {
      const unsigned char* p = data.data() + offset;
      EXPECT_EQ(isal_crc(0, p, n), zlib_crc(0, p, n)) << "length " << n;
    }
  }
}

TEST(TraceCrc, SampleTraceReadsWithItsStoredCrcs) {
  // The reader throws on any header, chunk or trailer CRC that does not match.
  TraceReader r(std::string(TEXSIM_SOURCE_DIR) + "/traces/samples/basic.trc");
  std::vector<Fragment> chunk;
  uint64_t n = 0;
  while (const size_t got = r.next_chunk(chunk)) n += got;
  EXPECT_GT(n, 0u);
  EXPECT_EQ(n, r.records_read());
}

}  // namespace
}  // namespace texsim
