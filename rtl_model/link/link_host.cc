#include "rtl_model/link/link_host.h"

#include <algorithm>
#include <limits>

#include "blocks/base/printable.h"

namespace texsim::link {

namespace {

// Text a board sent (refusals, block names), shown as one line: newlines and tabs escaped too.
std::string board_text(std::string_view s) {
  std::string out;
  for (const char c : printable(s)) {
    if (c == '\n') {
      out += "\\x0A";
    } else if (c == '\t') {
      out += "\\x09";
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace

LinkHost::LinkHost(Transport& transport, LinkOptions options)
    : transport_(transport), opt_(options) {
  if (opt_.channel == 0) throw LinkError("channel 0 is reserved");
  opt_.batch = std::clamp<uint16_t>(opt_.batch, 1, kMaxStreamVectors);
  // Ranges that keep every budget and the deadline finite and free of overflow.
  opt_.retries = std::clamp(opt_.retries, 0, 1000);
  opt_.timeout_ms = std::clamp(opt_.timeout_ms, 0, 600000);
  opt_.deadline_ms = std::clamp(opt_.deadline_ms, 0, 24 * 3600 * 1000);
  window_ = std::clamp(opt_.window, 1, 255);
}

LinkHost::Pending LinkHost::make(Command c, std::vector<uint8_t> payload) {
  Pending p;
  p.request = Message{opt_.channel, static_cast<uint8_t>(c), next_tag_++, std::move(payload)};
  return p;
}

void LinkHost::send(Pending& p) {
  if (p.sends > 0) ++stats_.retransmits;
  if (p.sends == 0) p.first_sent = std::chrono::steady_clock::now();
  ++p.sends;
  for (const Report& r : encode_message(p.request)) {
    transport_.write(r);
    ++stats_.reports_out;
  }
}

void LinkHost::exchange(std::vector<Pending>& requests) {
  std::vector<size_t> outstanding;  // indices into requests, oldest first
  size_t next = 0;
  silent_ = strays_ = reports_ = 0;  // each call has its own budgets
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
    receive(requests, outstanding, next);
  }
}

// Reads one report; on a timeout sends outstanding requests again (or gives up).
void LinkHost::receive(std::vector<Pending>& requests, std::vector<size_t>& outstanding,
                       size_t sent) {
  check_budgets(requests[outstanding.front()]);
  const std::vector<uint8_t> bytes = transport_.read(opt_.timeout_ms);
  if (bytes.empty()) {
    ++stats_.timeouts;
    // Give up after `retries` timeouts with no valid answer in between (an accepted response,
    // or one to a retransmission). Any other message does not count: a board answering
    // something else must not keep us here.
    if (++silent_ > opt_.retries) {
      const Pending& p = requests[outstanding.front()];
      give_up(p, std::to_string(silent_) + " timeouts of " + std::to_string(opt_.timeout_ms) +
                     " ms without a valid response");
    }
    // The first timeout of a run resends every outstanding request (several answers may have
    // been lost at once); later ones only the oldest. The board may still be sending answers
    // (a stall), and resending the whole window on every timeout would queue a window of
    // duplicates each time, a backlog that can outgrow what the board delivers between stalls.
    if (silent_ == 1) {
      for (const size_t i : outstanding) send(requests[i]);
    } else {
      send(requests[outstanding.front()]);
    }
    return;
  }
  ++stats_.reports_in;
  ++reports_;
  for (Decoded& d : reassembler_.feed(bytes)) {
    if (d.status == Decoded::Status::Malformed) {
      ++stats_.malformed;
      stats_.last_malformed = board_text(d.error);
      continue;
    }
    if (d.message.channel != opt_.channel) {
      stray("a message on another channel");
      continue;
    }
    const auto it = std::find_if(outstanding.begin(), outstanding.end(), [&](size_t i) {
      return requests[i].request.tag == d.message.tag;
    });
    if (it == outstanding.end()) {
      if (retransmission_answer(requests, sent, d.message)) {
        silent_ = 0;  // the board is alive and answering what was sent: wait on
      } else {
        stray("a response of tag " + std::to_string(d.message.tag) +
              ", which no outstanding request has");
      }
      continue;
    }
    // A stale response whose tag was reused, or a board answering something else: not ours.
    if (std::string why = mismatch(requests[*it].request, d.message); !why.empty()) {
      stray(std::move(why));
      continue;
    }
    ++requests[*it].answers;
    accept(requests[*it], std::move(d.message));
    ++stats_.accepted;
    outstanding.erase(it);
    silent_ = strays_ = reports_ = 0;  // progress: every budget starts again
  }
}

// A second answer to a request already answered, as each retransmission gives: at most one per
// send, so a board cannot keep the host waiting with them for longer than it retransmitted.
bool LinkHost::retransmission_answer(std::vector<Pending>& requests, size_t sent,
                                     const Message& m) {
  // Tags repeat every 256 requests: only the latest request with this tag can be meant.
  for (size_t i = sent; i > 0 && i + 256 > sent; --i) {
    Pending& p = requests[i - 1];
    if (p.request.tag != m.tag) continue;
    if (!p.done || p.answers >= p.sends || !mismatch(p.request, m).empty()) return false;
    ++p.answers;
    ++stats_.stray;
    return true;
  }
  return false;
}

// A message that answers nothing this call sent (or more often than it was sent).
void LinkHost::stray(std::string why) {
  ++stats_.stray;
  ++strays_;
  stats_.last_malformed = std::move(why);
}

int LinkHost::stray_budget() const { return (opt_.retries + 1) * window_; }

// Every request of the window, sent 1 + retries times, answered by the longest message, and
// one more such round for reports of earlier requests still in the pipe.
int LinkHost::report_budget() const {
  return (opt_.retries + 2) * window_ * static_cast<int>(kMaxReportsPerMessage);
}

int LinkHost::deadline_ms() const {
  if (opt_.deadline_ms > 0) return opt_.deadline_ms;
  // At most 2 * 1001 * 600000 + 1000 < 2^31 with the constructor's ranges.
  return 2 * (opt_.retries + 1) * opt_.timeout_ms + 1000;
}

void LinkHost::check_budgets(const Pending& oldest) {
  if (strays_ > stray_budget()) {
    give_up(oldest, std::to_string(strays_) + " messages in a row that answer no outstanding " +
                        "request (at most " + std::to_string(stray_budget()) + ")");
  }
  if (reports_ > report_budget()) {
    give_up(oldest, std::to_string(reports_) + " reports in a row without a valid response " +
                        "(at most " + std::to_string(report_budget()) + ")");
  }
  const auto waited = std::chrono::duration_cast<std::chrono::milliseconds>(
      std::chrono::steady_clock::now() - oldest.first_sent);
  if (waited.count() > deadline_ms()) {
    give_up(oldest, "no valid response within the deadline of " + std::to_string(deadline_ms()) +
                        " ms (" + std::to_string(waited.count()) + " ms since it was first sent)");
  }
}

void LinkHost::give_up(const Pending& p, const std::string& why) {
  throw LinkError("no valid response to " + command_name(p.request.command) + " (tag " +
                  std::to_string(p.request.tag) + ") from the " + transport_.describe() +
                  " after " + std::to_string(p.sends) + " attempts: " + why +
                  (stats_.last_malformed.empty()
                       ? std::string()
                       : "; last dropped response: " + stats_.last_malformed));
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
                    "): " + board_text(std::string(m.payload.begin() + 1, m.payload.end())));
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
    // A STREAM request of one vector (a 6-byte header and one input) must fit, else stream()
    // could never send anything.
    if (caps_.max_payload < kMinStreamPayload) {
      throw LinkError("the " + transport_.describe() + " announces a maximum payload of " +
                      std::to_string(caps_.max_payload) + " bytes; a STREAM of one vector " +
                      "needs " + std::to_string(kMinStreamPayload));
    }
    window_ = std::clamp(window_, 1, std::max<int>(1, caps_.max_in_flight));
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
    known += (known.empty() ? "" : ", ") + board_text(c.blocks[i].name);
  }
  throw LinkError("the " + transport_.describe() + " has no block '" + board_text(block) +
                  "' (it has: " + (known.empty() ? "none" : known) + ")");
}

void LinkHost::configure(std::vector<uint8_t> config) {
  call(Command::Configure, std::move(config));
}

std::vector<uint32_t> LinkHost::stream(std::span<const uint32_t> inputs) {
  capabilities();
  if (inputs.size() > std::numeric_limits<uint32_t>::max()) {
    throw LinkError("STREAM of " + std::to_string(inputs.size()) +
                    " vectors: the index field holds at most 2^32 - 1");
  }
  // capabilities() checked that one vector fits, so batch >= 1 and the loop advances.
  const size_t max_by_payload =
      (std::min<size_t>(caps_.max_payload, kMaxPayload) - kStreamHeader) / 4;
  const size_t batch = std::max<size_t>(1, std::min<size_t>(opt_.batch, max_by_payload));
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
