#pragma once
// Little-endian loads and stores and the CRC-32 of the binary trace formats (FORMAT.md,
// DRAWS.md); the byte reversal only exists on a big-endian host.
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace texsim {

template <class T>
T load_le(const unsigned char* p) {
  T v;
  if constexpr (std::endian::native == std::endian::little) {
    std::memcpy(&v, p, sizeof v);
  } else {
    unsigned char b[sizeof(T)];
    for (size_t i = 0; i < sizeof(T); ++i) b[i] = p[sizeof(T) - 1 - i];
    std::memcpy(&v, b, sizeof v);
  }
  return v;
}

template <class T>
void store_le(unsigned char* p, T v) {
  if constexpr (std::endian::native == std::endian::little) {
    std::memcpy(p, &v, sizeof v);
  } else {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof v);
    for (size_t i = 0; i < sizeof(T); ++i) p[i] = b[sizeof(T) - 1 - i];
  }
}

template <class T>
void append_le(std::vector<unsigned char>& out, T v) {
  const size_t n = out.size();
  out.resize(n + sizeof(T));
  store_le(out.data() + n, v);
}

// zlib's crc32(0, p, n): CRC-32/ISO-HDLC (FORMAT.md, "CRC-32").
uint32_t trace_crc32(const unsigned char* p, size_t n);

}  // namespace texsim
