#pragma once
// The link's commands and the layout of their payloads (docs/rtl/link.md). Every response
// echoes its request's command and tag; its payload starts with a status byte (0: OK, else an
// error code followed by a message text). Integers are big endian.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace texsim::link {

enum class Command : uint8_t {
  Capabilities = 0x01,  // -> packet size, firmware version, window, max payload, blocks
  Select = 0x02,        // block index (u8) -> OK; resets the block's counters
  Configure = 0x03,     // block-specific bytes -> OK
  Stream = 0x04,        // first index (u32), n (u16), n inputs (u32) -> same header, n results
  Counters = 0x05,      // -> vectors (u64), cycles (u64), bad requests (u32)
};
std::string command_name(uint8_t c);

enum class Status : uint8_t {
  Ok = 0,
  UnknownCommand = 1,
  BadLength = 2,
  BadBlock = 3,
  BadConfig = 4,
  NoBlock = 5,
  BadInput = 6,
};

// Appends big-endian integers and bytes.
class ByteWriter {
 public:
  ByteWriter& u8(uint8_t v);
  ByteWriter& u16(uint16_t v);
  ByteWriter& u32(uint32_t v);
  ByteWriter& u64(uint64_t v);
  ByteWriter& str8(const std::string& s);  // length (u8), then the bytes
  ByteWriter& bytes(std::span<const uint8_t> b);
  ByteWriter& text(const std::string& s);  // the bytes, no length
  std::vector<uint8_t> take() { return std::move(bytes_); }

 private:
  std::vector<uint8_t> bytes_;
};

// Reads them back; a read past the end throws LinkError naming `what` and the offset.
class ByteReader {
 public:
  ByteReader(std::span<const uint8_t> bytes, std::string what)
      : bytes_(bytes), what_(std::move(what)) {}
  uint8_t u8();
  uint16_t u16();
  uint32_t u32();
  uint64_t u64();
  std::string str8();
  size_t left() const { return bytes_.size() - pos_; }
  // Throws unless every byte was read.
  void expect_end() const;

 private:
  void need(size_t n) const;
  std::span<const uint8_t> bytes_;
  std::string what_;
  size_t pos_ = 0;
};

struct BlockCaps {
  std::string name;
  uint8_t in_bits = 0, out_bits = 0;  // widths of one input and one result (default config)
  uint8_t latency = 0;                // cycles from input to result
};

struct Capabilities {
  uint16_t packet_size = 0;
  uint8_t fw_major = 0, fw_minor = 0, fw_patch = 0;
  uint8_t max_in_flight = 0;  // requests the host may have outstanding
  uint16_t max_payload = 0;
  std::vector<BlockCaps> blocks;
};
std::vector<uint8_t> encode_capabilities(const Capabilities& c);  // after the status byte
Capabilities decode_capabilities(ByteReader& r);

// Header of a Stream request and of its response: which vectors they carry.
struct StreamHeader {
  uint32_t first = 0;  // index of the first vector in the run
  uint16_t count = 0;
};
// Largest vector count of one Stream message.
inline constexpr uint16_t kMaxStreamVectors = 1000;
// Bytes of StreamHeader on the wire, and the smallest payload a board must take: one vector.
inline constexpr size_t kStreamHeader = 6;
inline constexpr size_t kMinStreamPayload = kStreamHeader + 4;

struct Counters {
  uint64_t vectors = 0;
  uint64_t cycles = 0;
  uint32_t bad_requests = 0;  // malformed reports or messages the board dropped
};

}  // namespace texsim::link
