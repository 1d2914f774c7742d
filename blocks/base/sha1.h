#pragma once
// SHA-1 (FIPS 180-4) of a byte stream, for the input digests of the reports' provenance (the
// same hex digest sha1sum prints). Here rather than from an image library, so that digesting
// the scene file loads nothing at start-up.
#include <array>
#include <cstddef>
#include <cstdint>
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
  void block(const uint8_t* p);  // one 64-byte block into the state
  std::array<uint32_t, 5> h_;
  std::array<uint8_t, 64> buf_{};
  size_t used_ = 0;      // bytes in buf_
  uint64_t length_ = 0;  // bytes appended
};

}  // namespace texsim
