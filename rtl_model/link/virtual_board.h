#pragma once
// A board in process: the firmware side of the link protocol (docs/rtl/link.md) in front of
// BoardBlocks, reached through the Transport interface like a USB device, so the host code
// above the transport is the same for it and for real hardware. Each report the host writes
// is handled at once; the response's reports wait in a queue for read().
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "rtl_model/link/board_block.h"
#include "rtl_model/link/commands.h"
#include "rtl_model/link/framing.h"
#include "rtl_model/link/transport.h"

namespace texsim::link {

class VirtualBoard : public Transport {
 public:
  static constexpr uint8_t kFwMajor = 1, kFwMinor = 0, kFwPatch = 0;
  static constexpr uint8_t kMaxInFlight = 4;
  // Responses kept to answer a retransmitted request without running it twice.
  static constexpr size_t kReplayDepth = 16;
  static_assert(kReplayDepth >= kMaxInFlight);

  explicit VirtualBoard(std::vector<std::unique_ptr<BoardBlock>> blocks);

  void write(const Report& report) override;
  std::vector<uint8_t> read(int timeout_ms) override;
  std::string describe() const override { return "virtual board"; }

  const Counters& counters() const { return counters_; }

 private:
  struct Replay {
    uint32_t channel;
    uint8_t command, tag;
    uint16_t request_crc;
    Message response;
  };
  Message handle(const Message& request);
  std::vector<uint8_t> run(const Message& request);  // the response payload
  std::vector<uint8_t> stream(ByteReader& r);
  Capabilities capabilities() const;

  std::vector<std::unique_ptr<BoardBlock>> blocks_;
  BoardBlock* selected_ = nullptr;
  Reassembler reassembler_;
  std::deque<Report> outbox_;
  std::deque<Replay> replay_;
  Counters counters_;
};

}  // namespace texsim::link
