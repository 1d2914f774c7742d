#include "blocks/base/sha256.h"

#include "blocks/base/sha1.h"

namespace texsim {

Sha256::Sha256() { sha256_init(&ctx_); }

void Sha256::update(const void* data, size_t n) {
  sha256_update(&ctx_, n, static_cast<const uint8_t*>(data));
}

Sha256::Digest Sha256::finish() {
  Digest d{};
  sha256_digest(&ctx_, d.size(), d.data());
  return d;
}

std::string Sha256::hex(const Digest& d) { return hex_bytes(d.data(), d.size()); }

}  // namespace texsim
