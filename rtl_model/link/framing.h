#pragma once
// Message framing of the FPGA link over 64-byte USB HID reports (docs/rtl/link.md).
// A message (channel, command, tag, payload) travels as one INIT report and as many CONT
// reports as its payload needs; a CRC-16/CCITT-FALSE over command, tag, length and payload
// follows the payload. Reassembler turns reports back into messages and names every way a
// report can be malformed.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace texsim::link {

inline constexpr size_t kReportSize = 64;
using Report = std::array<uint8_t, kReportSize>;

// INIT: channel (4, big endian) | 0x80|command | tag | length (2, BE) | 56 data bytes.
// CONT: channel (4) | sequence 0..127 | tag | 58 data bytes.
inline constexpr size_t kInitHeader = 8;
inline constexpr size_t kContHeader = 6;
inline constexpr size_t kInitData = kReportSize - kInitHeader;
inline constexpr size_t kContData = kReportSize - kContHeader;
inline constexpr uint8_t kInitBit = 0x80;
inline constexpr size_t kMaxSeq = 128;
inline constexpr size_t kCrcSize = 2;
// Largest payload: fits the 128 CONT reports with room to spare.
inline constexpr size_t kMaxPayload = 4096;
static_assert(kMaxPayload + kCrcSize <= kInitData + kMaxSeq * kContData);
// Reports of the longest message: one INIT and the CONTs for the rest.
inline constexpr size_t kMaxReportsPerMessage =
    1 + (kMaxPayload + kCrcSize - kInitData + kContData - 1) / kContData;

// A link failure the host cannot recover from (no device, no answer after every retry, a board
// that reports an error): its text says what happened.
class LinkError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Message {
  uint32_t channel = 0;
  uint8_t command = 0;  // 0x01..0x7F
  uint8_t tag = 0;      // matches a response to its request
  std::vector<uint8_t> payload;
};

// The CRC a message carries: over command, tag, payload length (BE) and payload.
uint16_t message_crc(const Message& m);

// The reports of a message; throws LinkError for a payload over kMaxPayload or a command
// outside 0x01..0x7F.
std::vector<Report> encode_message(const Message& m);

// One result of Reassembler::feed.
struct Decoded {
  enum class Status { Complete, Malformed };
  Status status = Status::Complete;
  Message message;    // Complete: the message
  std::string error;  // Malformed: what was wrong (the partial message is dropped)
};

class Reassembler {
 public:
  // check_crc = false only to show what a decoder without the end-to-end check would accept.
  explicit Reassembler(bool check_crc = true) : check_crc_(check_crc) {}
  // Feeds one report as received (any size); returns the messages it completes and the errors
  // it finds (at most two: an INIT that interrupts an unfinished message drops that one).
  std::vector<Decoded> feed(std::span<const uint8_t> report);
  bool busy() const { return open_; }

 private:
  std::vector<Decoded> feed_init(std::span<const uint8_t> r, uint32_t channel);
  std::optional<Decoded> feed_cont(std::span<const uint8_t> r, uint32_t channel);
  Decoded finish();

  bool check_crc_;
  bool open_ = false;  // a message is being assembled
  Message msg_;
  size_t length_ = 0;  // payload bytes announced by its INIT
  std::vector<uint8_t> data_;
  size_t next_seq_ = 0;
};

}  // namespace texsim::link
