#pragma once
// CRC-16/CCITT-FALSE (polynomial 0x1021, initial value 0xFFFF, no reflection, no final XOR;
// check value 0x29B1 for "123456789"): the link's end-to-end check over a whole message, on top
// of USB's own per-packet CRC (docs/rtl/link.md).
#include <cstddef>
#include <cstdint>
#include <span>

namespace texsim::link {

inline constexpr uint16_t kCrc16Init = 0xFFFF;

// Continues a CRC over `bytes` from `crc` (kCrc16Init for a new message).
uint16_t crc16_update(uint16_t crc, std::span<const uint8_t> bytes);

inline uint16_t crc16(std::span<const uint8_t> bytes) { return crc16_update(kCrc16Init, bytes); }

}  // namespace texsim::link
