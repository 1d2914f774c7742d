// Hostile boards (docs/rtl/link.md, "Bounds"): whatever a board sends, every LinkHost call ends
// in a result or a LinkError within a bounded number of transport calls and a bounded time.
// Each board here is scripted; its transport throws a non-LinkError once it has been called
// far more often than the bounds allow, so a host that would loop forever fails the test.
#include <gtest/gtest.h>

#include <chrono>
#include <deque>
#include <functional>
#include <string>
#include <thread>

#include "rtl_model/link/link_host.h"

namespace texsim::link {
namespace {

struct RunawayHost : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A board that answers each request message with what `respond` returns, and on a read with
// nothing queued returns `idle()` (empty: a timeout).
class ScriptedBoard : public Transport {
 public:
  using Respond = std::function<std::vector<Message>(const Message&)>;
  using Idle = std::function<std::vector<uint8_t>()>;
  explicit ScriptedBoard(Respond respond, Idle idle = {})
      : respond_(std::move(respond)), idle_(std::move(idle)) {}

  void write(const Report& report) override {
    count();
    for (Decoded& d : reassembler_.feed(report)) {
      if (d.status != Decoded::Status::Complete) continue;
      for (const Message& m : respond_(d.message)) {
        for (const Report& r : encode_message(m)) queue_.emplace_back(r.begin(), r.end());
      }
    }
  }
  std::vector<uint8_t> read(int /*timeout_ms*/) override {
    count();
    if (!queue_.empty()) {
      std::vector<uint8_t> r = std::move(queue_.front());
      queue_.pop_front();
      return r;
    }
    return idle_ ? idle_() : std::vector<uint8_t>{};
  }
  std::string describe() const override { return "scripted board"; }
  uint64_t calls() const { return calls_; }

 private:
  void count() {
    if (++calls_ > 100000) throw RunawayHost("the host called the transport 100000 times");
  }
  Respond respond_;
  Idle idle_;
  Reassembler reassembler_;
  std::deque<std::vector<uint8_t>> queue_;
  uint64_t calls_ = 0;
};

Capabilities caps_with_payload(uint16_t max_payload) {
  Capabilities c;
  c.packet_size = kReportSize;
  c.fw_major = 1;
  c.max_in_flight = 4;
  c.max_payload = max_payload;
  c.blocks.push_back(BlockCaps{"echo", 16, 16, 1});
  return c;
}

Message reply(const Message& request, std::vector<uint8_t> payload_after_status,
              uint8_t status = 0) {
  std::vector<uint8_t> p = {status};
  p.insert(p.end(), payload_after_status.begin(), payload_after_status.end());
  return Message{request.channel, request.command, request.tag, std::move(p)};
}

// A well-behaved board whose STREAM returns each input as its result.
ScriptedBoard::Respond echo_board(uint16_t max_payload) {
  return [max_payload](const Message& m) -> std::vector<Message> {
    switch (static_cast<Command>(m.command)) {
      case Command::Capabilities:
        return {reply(m, encode_capabilities(caps_with_payload(max_payload)))};
      case Command::Stream: {
        if (m.payload.size() > max_payload) return {reply(m, {}, 2)};
        std::vector<uint8_t> p(m.payload.begin(), m.payload.end());
        return {reply(m, p)};
      }
      default:
        return {reply(m, {})};
    }
  };
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const LinkError& e) {
    return e.what();
  }
  return "";
}

// A maximum payload of 6-9 bytes holds no STREAM record: the host used to compute a batch of
// zero vectors and loop forever without any I/O. The capabilities are refused instead.
TEST(LinkHostile, MaximumPayloadTooSmallForOneVectorIsRefused) {
  for (uint16_t max_payload = 0; max_payload < kMinStreamPayload; ++max_payload) {
    ScriptedBoard board(echo_board(max_payload));
    LinkHost host(board, LinkOptions{});
    const std::string e = message_of([&] { host.capabilities(); });
    ASSERT_NE(e.find("maximum payload of " + std::to_string(max_payload) + " bytes"),
              std::string::npos)
        << "max_payload " << max_payload << ": " << e;
    const std::vector<uint32_t> in = {1, 2, 3};
    EXPECT_THROW(host.stream(in), LinkError) << max_payload;
    EXPECT_LE(board.calls(), 10u) << max_payload;
  }
}

// The smallest payload that holds one vector: one STREAM per vector, the chunking advances.
TEST(LinkHostile, MaximumPayloadOfOneVectorStreamsOneVectorPerRequest) {
  ScriptedBoard board(echo_board(kMinStreamPayload));
  LinkHost host(board, LinkOptions{});
  const std::vector<uint32_t> in = {7, 8, 9, 10, 11};
  EXPECT_EQ(host.stream(in), in);
  EXPECT_EQ(host.stats().requests, 1u + in.size());  // CAPABILITIES, then one per vector
}

// Answers every request at once with a well-formed OK reply (right channel, tag and CRC) to
// another command: the host used to take any valid message as a sign of life and reset its
// timeout count, so it retransmitted forever.
TEST(LinkHostile, RepliesToAnotherCommandEndInAnErrorWithinTheRetries) {
  ScriptedBoard board([](const Message& m) -> std::vector<Message> {
    Message r = reply(m, {});
    r.command = static_cast<uint8_t>(m.command % 5 + 1);
    return {r};
  });
  LinkOptions o;
  o.retries = 4;
  LinkHost host(board, o);
  const std::string e = message_of([&] { host.capabilities(); });
  EXPECT_NE(e.find("no valid response to CAPABILITIES"), std::string::npos) << e;
  EXPECT_NE(e.find("5 timeouts"), std::string::npos) << e;
  EXPECT_NE(e.find("the response to CAPABILITIES (tag 0) is SELECT"), std::string::npos) << e;
  // 5 sends, 5 replies and 5 timeouts.
  EXPECT_LE(board.calls(), 15u);
}

// Never silent: every read returns a well-formed response whose tag no outstanding request
// has (out of the window). Counted against the stray budget, never a hang.
TEST(LinkHostile, AnEndlessStreamOfRepliesToOtherTagsEndsInAnError) {
  LinkOptions o;
  uint8_t tag = 128;  // 128..255: never the tag of the one request (0)
  ScriptedBoard board(
      [](const Message&) { return std::vector<Message>{}; },
      [&] {
        const Message m{o.channel, static_cast<uint8_t>(Command::Capabilities), tag, {0}};
        tag = static_cast<uint8_t>(tag == 255 ? 128 : tag + 1);
        const Report r = encode_message(m)[0];
        return std::vector<uint8_t>(r.begin(), r.end());
      });
  LinkHost host(board, o);
  const std::string e = message_of([&] { host.capabilities(); });
  EXPECT_NE(e.find("messages in a row that answer no outstanding request (at most " +
                   std::to_string(host.stray_budget()) + ")"),
            std::string::npos)
      << e;
  EXPECT_LE(board.calls(), static_cast<uint64_t>(host.stray_budget()) + 3);
}

// Never silent either: every read returns a report that is malformed (a CONT with no message
// started). Bounded by the report budget.
TEST(LinkHostile, AnEndlessStreamOfMalformedReportsEndsInAnError) {
  LinkOptions o;
  ScriptedBoard board([](const Message&) { return std::vector<Message>{}; },
                      [] {
                        std::vector<uint8_t> r(kReportSize, 0);
                        r[0] = 0x7E;  // a nonzero channel; byte 4 (sequence) without the INIT bit
                        return r;
                      });
  LinkHost host(board, o);
  const std::string e = message_of([&] { host.capabilities(); });
  EXPECT_NE(e.find("reports in a row without a valid response"), std::string::npos) << e;
  EXPECT_NE(e.find("with no message started"), std::string::npos) << e;
  EXPECT_LE(board.calls(), static_cast<uint64_t>(host.report_budget()) + 3);
}

// A board that trickles garbage slowly: the deadline ends the call long before the report
// budget would.
TEST(LinkHostile, ASlowTrickleEndsAtTheDeadline) {
  LinkOptions o;
  o.deadline_ms = 50;
  ScriptedBoard board([](const Message&) { return std::vector<Message>{}; },
                      [] {
                        std::this_thread::sleep_for(std::chrono::milliseconds(2));
                        std::vector<uint8_t> r(kReportSize, 0);
                        r[0] = 0x7E;
                        return r;
                      });
  LinkHost host(board, o);
  const auto t0 = std::chrono::steady_clock::now();
  const std::string e = message_of([&] { host.capabilities(); });
  const auto ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t0)
          .count();
  EXPECT_NE(e.find("within the deadline of 50 ms"), std::string::npos) << e;
  EXPECT_LT(ms, 1000) << e;
  EXPECT_LT(board.calls(), static_cast<uint64_t>(host.report_budget()));
}

// The default deadline follows the retries and the timeout.
TEST(LinkHostile, DefaultDeadlineCoversEveryRetry) {
  ScriptedBoard board(echo_board(kMaxPayload));
  LinkOptions o;
  o.retries = 4;
  o.timeout_ms = 250;
  EXPECT_EQ(LinkHost(board, o).deadline_ms(), 2 * 5 * 250 + 1000);
  o.retries = 1 << 30;  // clamped: no overflow
  o.timeout_ms = 1 << 30;
  EXPECT_GT(LinkHost(board, o).deadline_ms(), 0);
  EXPECT_GT(LinkHost(board, o).report_budget(), 0);
}

// Text from the board (a refusal's reason, block names) reaches messages escaped, on one line.
TEST(LinkHostile, BoardTextIsEscapedInErrors) {
  ScriptedBoard board([](const Message& m) -> std::vector<Message> {
    if (m.command == static_cast<uint8_t>(Command::Capabilities)) {
      Capabilities c = caps_with_payload(kMaxPayload);
      c.blocks[0].name = "ev\x1b[2Jil";
      return {reply(m, encode_capabilities(c))};
    }
    const std::string why = "no\x07\nfake line\t!";
    return {reply(m, std::vector<uint8_t>(why.begin(), why.end()), 4)};
  });
  LinkHost host(board, LinkOptions{});
  const std::string sel = message_of([&] { host.select("vd\x01"); });
  EXPECT_NE(sel.find("no block 'vd\\x01' (it has: ev\\x1B[2Jil)"), std::string::npos) << sel;
  const std::string cfg = message_of([&] { host.configure({16}); });
  EXPECT_NE(cfg.find("refused CONFIGURE (status 4): no\\x07\\x0Afake line\\x09!"),
            std::string::npos)
      << cfg;
  for (const std::string& s : {sel, cfg}) {
    for (const char c : s) EXPECT_GE(static_cast<unsigned char>(c), 0x20u) << s;
  }
}

}  // namespace
}  // namespace texsim::link
