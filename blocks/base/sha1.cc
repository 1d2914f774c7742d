#include "blocks/base/sha1.h"

namespace texsim {

Sha1::Sha1() { sha1_init(&ctx_); }

void Sha1::append(const void* data, size_t n) {
  sha1_update(&ctx_, n, static_cast<const uint8_t*>(data));
}

std::string Sha1::hex_digest() {
  uint8_t d[SHA1_DIGEST_SIZE];
  sha1_digest(&ctx_, sizeof d, d);
  return hex_bytes(d, sizeof d);
}

std::string hex_bytes(const unsigned char* p, size_t n) {
  static const char* const kHex = "0123456789abcdef";
  std::string s;
  s.reserve(2 * n);
  for (size_t i = 0; i < n; ++i) {
    s += kHex[p[i] >> 4];
    s += kHex[p[i] & 15];
  }
  return s;
}

}  // namespace texsim
