#pragma once
// SHA-1 (FIPS 180-4) of a byte stream, for the input digests of the reports' provenance (the
// same hex digest sha1sum prints), computed by Nettle (nettle-dev): a small library, so that
// digesting the scene file loads nothing heavy at start-up.
#include <nettle/sha1.h>

#include <cstddef>
#include <string>

namespace texsim {

class Sha1 {
 public:
  Sha1();
  // Feeds `n` more bytes.
  void append(const void* data, size_t n);
  // The digest of everything appended, as 40 lower-case hex digits. Ends the stream.
  std::string hex_digest();

 private:
  sha1_ctx ctx_{};
};

// Lower-case hex digits of n bytes.
std::string hex_bytes(const unsigned char* p, size_t n);

}  // namespace texsim
