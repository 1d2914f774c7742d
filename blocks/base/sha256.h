#pragma once
// SHA-256 (FIPS 180-4), the digest of the ground-truth cache's keys (truth_cache.h): 256 bits,
// so two different sets of truth inputs never share a key by accident. Computed by Nettle
// (nettle-dev); checked against the standard's test vectors (test_truth_cache).
#include <nettle/sha2.h>

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
  sha256_ctx ctx_{};
};

}  // namespace texsim
