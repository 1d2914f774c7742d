#include "rtl_model/link/link_host.h"

#include <algorithm>

namespace texsim::link {

LinkHost::LinkHost(Transport& transport, LinkOptions options)
    : transport_(transport), opt_(options), window_(std::max(1, options.window)) {
  if (opt_.channel == 0) throw LinkError("channel 0 is reserved");
  opt_.batch = std::clamp<uint16_t>(opt_.batch, 1, kMaxStreamVectors);
}

LinkHost::Pending LinkHost::make(Command c, std::vector<uint8_t> payload) {
  Pending p;
  p.request = Message{opt_.channel, static_cast<uint8_t>(c), next_tag_++, std::move(payload)};
  return p;
}

void LinkHost::send(Pending& p) {
  if (p.sends > 0) ++stats_.retransmits;
  ++p.sends;
  for (const Report& r : encode_message(p.request)) {
    transport_.write(r);
    ++stats_.reports_out;
  }
}

void LinkHost::exchange(std::vector<Pending>& requests) {
  std::vector<size_t> outstanding;  // indices into requests, oldest first
  size_t next = 0;
  while (next < requests.size() || !outstanding.empty()) {
    // A sliding window: nothing more than window_ past the oldest unanswered request, so a
    // lost response is noticed (the board falls idle, the read times out) while the board
    // still holds the answer for a retransmission (VirtualBoard::kReplayDepth >= window).
    const size_t oldest = outstanding.empty() ? next : outstanding.front();
    while (next < requests.size() && next < oldest + static_cast<size_t>(window_)) {
      ++stats_.requests;
      send(requests[next]);
      outstanding.push_back(next++);
    }
    receive(requests, outstanding);
  }
}

// Reads one report; on a timeout sends every outstanding request again (or gives up).
void LinkHost::receive(std::vector<Pending>& requests, std::vector<size_t>& outstanding) {
  const std::vector<uint8_t> bytes = transport_.read(opt_.timeout_ms);
  if (bytes.empty()) {
    ++stats_.timeouts;
    // Give up after `retries` timeouts in a row with no valid message in between.
    if (++silent_ > opt_.retries) {
      const Pending& p = requests[outstanding.front()];
      throw LinkError(
          "no valid response to " + command_name(p.request.command) + " (tag " +
          std::to_string(p.request.tag) + ") from the " + transport_.describe() + " after " +
          std::to_string(p.sends) + " attempts, " + std::to_string(silent_) + " timeouts of " +
          std::to_string(opt_.timeout_ms) + " ms in a row" +
          (stats_.last_malformed.empty() ? std::string()
                                         : "; last dropped response: " + stats_.last_malformed));
    }
    for (const size_t i : outstanding) send(requests[i]);
    return;
  }
  ++stats_.reports_in;
  for (Decoded& d : reassembler_.feed(bytes)) {
    if (d.status == Decoded::Status::Malformed) {
      ++stats_.malformed;
      stats_.last_malformed = d.error;
      continue;
    }
    // The board is alive: late or repeated answers to retransmissions count too. They are
    // bounded (only outstanding requests are sent again), so this cannot loop forever.
    if (d.message.channel == opt_.channel) silent_ = 0;
    const auto it = std::find_if(outstanding.begin(), outstanding.end(), [&](size_t i) {
      return requests[i].request.tag == d.message.tag;
    });
    if (d.message.channel != opt_.channel || it == outstanding.end()) {
      ++stats_.stray;
      continue;
    }
    // A stale response whose tag was reused, or a board answering something else: not ours.
    if (std::string why = mismatch(requests[*it].request, d.message); !why.empty()) {
      ++stats_.stray;
      stats_.last_malformed = why;
      continue;
    }
    accept(requests[*it], std::move(d.message));
    outstanding.erase(it);
  }
}

std::string LinkHost::mismatch(const Message& request, const Message& m) {
  const std::string what =
      command_name(request.command) + " (tag " + std::to_string(request.tag) + ")";
  if (m.command != request.command)
    return "the response to " + what + " is " + command_name(m.command);
  if (m.payload.empty()) return "the response to " + what + " has no status";
  if (m.command != static_cast<uint8_t>(Command::Stream) ||
      m.payload[0] != static_cast<uint8_t>(Status::Ok))
    return "";
  // A STREAM response must carry exactly the vectors its request sent.
  ByteReader req(request.payload, "STREAM request");
  const uint32_t first = req.u32(), count = req.u16();
  if (m.payload.size() < 7) return "the response to " + what + " is truncated";
  ByteReader r(std::span<const uint8_t>(m.payload).subspan(1), "STREAM response");
  const uint32_t got_first = r.u32(), got_count = r.u16();
  if (got_first != first || got_count != count || r.left() != 4 * size_t{count}) {
    return "the response to " + what + " for vectors " + std::to_string(first) + "+" +
           std::to_string(count) + " carries vectors " + std::to_string(got_first) + "+" +
           std::to_string(got_count) + " in " + std::to_string(r.left()) + " bytes";
  }
  return "";
}

// The board's answer to this request (CRC, command and vectors checked): OK, or a refusal.
void LinkHost::accept(Pending& p, Message&& m) {
  if (m.payload[0] != static_cast<uint8_t>(Status::Ok)) {
    throw LinkError("the board refused " + command_name(p.request.command) + " (status " +
                    std::to_string(m.payload[0]) +
                    "): " + std::string(m.payload.begin() + 1, m.payload.end()));
  }
  p.response.assign(m.payload.begin() + 1, m.payload.end());
  p.done = true;
}

std::vector<uint8_t> LinkHost::call(Command c, std::vector<uint8_t> payload) {
  std::vector<Pending> one;
  one.push_back(make(c, std::move(payload)));
  exchange(one);
  return std::move(one[0].response);
}

const Capabilities& LinkHost::capabilities() {
  if (!have_caps_) {
    const std::vector<uint8_t> p = call(Command::Capabilities, {});
    ByteReader r(p, "CAPABILITIES response");
    caps_ = decode_capabilities(r);
    if (caps_.packet_size != kReportSize) {
      throw LinkError("the board uses " + std::to_string(caps_.packet_size) +
                      "-byte reports; this host speaks " + std::to_string(kReportSize));
    }
    window_ = std::clamp(opt_.window, 1, std::max<int>(1, caps_.max_in_flight));
    have_caps_ = true;
  }
  return caps_;
}

void LinkHost::select(const std::string& block) {
  const Capabilities& c = capabilities();
  std::string known;
  for (size_t i = 0; i < c.blocks.size(); ++i) {
    if (c.blocks[i].name == block) {
      call(Command::Select, {static_cast<uint8_t>(i)});
      return;
    }
    known += (known.empty() ? "" : ", ") + c.blocks[i].name;
  }
  throw LinkError("the " + transport_.describe() + " has no block '" + block +
                  "' (it has: " + (known.empty() ? "none" : known) + ")");
}

void LinkHost::configure(std::vector<uint8_t> config) {
  call(Command::Configure, std::move(config));
}

std::vector<uint32_t> LinkHost::stream(std::span<const uint32_t> inputs) {
  capabilities();
  const size_t max_by_payload = (std::min<size_t>(caps_.max_payload, kMaxPayload) - 6) / 4;
  const size_t batch = std::min<size_t>(opt_.batch, max_by_payload);
  std::vector<Pending> requests;
  for (size_t first = 0; first < inputs.size(); first += batch) {
    const size_t n = std::min(batch, inputs.size() - first);
    ByteWriter w;
    w.u32(static_cast<uint32_t>(first)).u16(static_cast<uint16_t>(n));
    for (size_t i = 0; i < n; ++i) w.u32(inputs[first + i]);
    requests.push_back(make(Command::Stream, w.take()));
  }
  exchange(requests);
  std::vector<uint32_t> results;
  results.reserve(inputs.size());
  for (const Pending& p : requests) {
    // Header and size were checked when the response was matched (mismatch()).
    ByteReader r(std::span<const uint8_t>(p.response).subspan(6), "STREAM response");
    while (r.left() > 0) results.push_back(r.u32());
  }
  return results;
}

Counters LinkHost::counters() {
  const std::vector<uint8_t> p = call(Command::Counters, {});
  ByteReader r(p, "COUNTERS response");
  Counters c;
  c.vectors = r.u64();
  c.cycles = r.u64();
  c.bad_requests = r.u32();
  r.expect_end();
  return c;
}

}  // namespace texsim::link
