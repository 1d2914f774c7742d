#include "rtl_model/link/crc16.h"

namespace texsim::link {

// Bitwise, MSB first: small and obviously right; a message is at most a few kilobytes.
uint16_t crc16_update(uint16_t crc, std::span<const uint8_t> bytes) {
  for (const uint8_t b : bytes) {
    crc = static_cast<uint16_t>(crc ^ (static_cast<uint16_t>(b) << 8));
    for (int i = 0; i < 8; ++i) {
      const bool top = (crc & 0x8000) != 0;
      crc = static_cast<uint16_t>(crc << 1);
      if (top) crc = static_cast<uint16_t>(crc ^ 0x1021);
    }
  }
  return crc;
}

}  // namespace texsim::link
