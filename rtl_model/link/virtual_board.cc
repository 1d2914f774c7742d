#include "rtl_model/link/virtual_board.h"

#include <algorithm>

namespace texsim::link {

namespace {

// A refusal: the status code, then the reason as text.
struct Refusal {
  Status status;
  std::string why;
};

std::vector<uint8_t> refusal_payload(const Refusal& r) {
  ByteWriter w;
  return w.u8(static_cast<uint8_t>(r.status)).text(r.why).take();
}

}  // namespace

VirtualBoard::VirtualBoard(std::vector<std::unique_ptr<BoardBlock>> blocks)
    : blocks_(std::move(blocks)) {}

void VirtualBoard::write(const Report& report) {
  for (Decoded& d : reassembler_.feed(report)) {
    // A malformed request is dropped (the host retries on its timeout) and counted.
    if (d.status == Decoded::Status::Malformed) {
      ++counters_.bad_requests;
      continue;
    }
    for (const Report& r : encode_message(handle(d.message))) outbox_.push_back(r);
  }
}

std::vector<uint8_t> VirtualBoard::read(int /*timeout_ms*/) {
  // Nothing queued means nothing will come: the board answers within write().
  if (outbox_.empty()) return {};
  const Report r = outbox_.front();
  outbox_.pop_front();
  return {r.begin(), r.end()};
}

Message VirtualBoard::handle(const Message& request) {
  const uint16_t crc = message_crc(request);
  for (const Replay& p : replay_) {
    if (p.channel == request.channel && p.command == request.command && p.tag == request.tag &&
        p.request_crc == crc) {
      return p.response;  // a retransmission: same answer, the block does not run twice
    }
  }
  Message response{request.channel, request.command, request.tag, run(request)};
  replay_.push_back({request.channel, request.command, request.tag, crc, response});
  if (replay_.size() > kReplayDepth) replay_.pop_front();
  return response;
}

std::vector<uint8_t> VirtualBoard::run(const Message& request) {
  ByteReader r(request.payload, command_name(request.command) + " request");
  try {
    ByteWriter ok;
    ok.u8(static_cast<uint8_t>(Status::Ok));
    switch (static_cast<Command>(request.command)) {
      case Command::Capabilities: {
        r.expect_end();
        return ok.bytes(encode_capabilities(capabilities())).take();
      }
      case Command::Select: {
        const uint8_t index = r.u8();
        r.expect_end();
        if (index >= blocks_.size()) {
          return refusal_payload({Status::BadBlock, "block " + std::to_string(index) +
                                                        " does not exist (the board has " +
                                                        std::to_string(blocks_.size()) + ")"});
        }
        selected_ = blocks_[index].get();
        counters_.vectors = counters_.cycles = 0;
        return ok.take();
      }
      case Command::Configure: {
        if (!selected_) return refusal_payload({Status::NoBlock, "no block selected"});
        const std::string why = selected_->configure(request.payload);
        if (!why.empty()) return refusal_payload({Status::BadConfig, why});
        return ok.take();
      }
      case Command::Stream:
        return stream(r);
      case Command::Counters:
        r.expect_end();
        ok.u64(counters_.vectors).u64(counters_.cycles).u32(counters_.bad_requests);
        return ok.take();
    }
  } catch (const LinkError& e) {
    return refusal_payload({Status::BadLength, e.what()});
  }
  return refusal_payload({Status::UnknownCommand, "unknown " + command_name(request.command)});
}

std::vector<uint8_t> VirtualBoard::stream(ByteReader& r) {
  if (!selected_) return refusal_payload({Status::NoBlock, "no block selected"});
  StreamHeader h;
  h.first = r.u32();
  h.count = r.u16();
  if (h.count > kMaxStreamVectors) {
    return refusal_payload({Status::BadLength, std::to_string(h.count) +
                                                   " vectors in one STREAM (at most " +
                                                   std::to_string(kMaxStreamVectors) + ")"});
  }
  const uint32_t in_bits = selected_->caps().in_bits;
  std::vector<uint32_t> in(h.count), out(h.count);
  for (uint32_t& x : in) {
    x = r.u32();
    if (in_bits < 32 && (x >> in_bits) != 0) {
      return refusal_payload({Status::BadInput, "input " + std::to_string(x) + " is wider than " +
                                                    std::to_string(in_bits) + " bits"});
    }
  }
  r.expect_end();
  const uint64_t cycles = selected_->apply(in, out);
  counters_.vectors += h.count;
  counters_.cycles += cycles;
  ByteWriter w;
  w.u8(static_cast<uint8_t>(Status::Ok)).u32(h.first).u16(h.count);
  for (const uint32_t y : out) w.u32(y);
  return w.take();
}

Capabilities VirtualBoard::capabilities() const {
  Capabilities c;
  c.packet_size = kReportSize;
  c.fw_major = kFwMajor;
  c.fw_minor = kFwMinor;
  c.fw_patch = kFwPatch;
  c.max_in_flight = kMaxInFlight;
  c.max_payload = kMaxPayload;
  for (const auto& b : blocks_) c.blocks.push_back(b->caps());
  return c;
}

}  // namespace texsim::link
