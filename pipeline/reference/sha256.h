#pragma once
// SHA-256 (FIPS 180-4), the digest of the ground-truth cache's keys (truth_cache.h): 256 bits,
// so two different sets of truth inputs never share a key by accident. Written small and
// checked against the standard's test vectors (test_truth_cache); no library the project
// already links offers it without OpenImageIO, which a run may not load.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace texsim {

class Sha256 {
 public:
  using Digest = std::array<uint8_t, 32>;
  Sha256();
  void update(const void* data, size_t n);
  // The digest of everything updated so far; the object is spent afterwards.
  Digest finish();
  static std::string hex(const Digest& d);

 private:
  void block(const uint8_t* p);
  std::array<uint32_t, 8> h_;
  std::array<uint8_t, 64> buf_{};
  size_t used_ = 0;     // bytes waiting in buf_
  uint64_t bytes_ = 0;  // total bytes updated
};

}  // namespace texsim
