#pragma once
// The host side of the link (docs/rtl/link.md), the same code for every transport: requests
// with tags, at most `window` outstanding, responses matched by tag and checked (CRC, echoed
// command, status, the vectors they claim to carry), timeouts and retransmission. A response
// that fails any check is never used: its request is sent again on the next timeout. Whatever
// a board sends, every call ends (a result or a LinkError) within bounded reads and time:
// between two accepted responses at most `retries` timeouts, stray_budget() unexpected
// messages, report_budget() reports and deadline_ms() milliseconds (docs/rtl/link.md).
#include <chrono>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "rtl_model/link/commands.h"
#include "rtl_model/link/framing.h"
#include "rtl_model/link/transport.h"

namespace texsim::link {

struct LinkOptions {
  uint32_t channel = 0x7E570001;  // any nonzero id; responses on other channels are ignored
  int timeout_ms = 250;           // wait for a report before retransmitting
  int retries = 4;       // timeouts in a row (each followed by a retransmission) before giving up
  int window = 4;        // requests in flight (also capped by the board's)
  uint16_t batch = 250;  // vectors per STREAM message
  // The oldest outstanding request must be answered within this many ms of its first send;
  // 0: 2 * (retries + 1) * timeout_ms + 1000.
  int deadline_ms = 0;
};

struct LinkStats {
  uint64_t requests = 0;
  uint64_t accepted = 0;  // responses used (one per request that succeeded)
  uint64_t reports_out = 0, reports_in = 0;
  uint64_t timeouts = 0;       // reads that returned nothing
  uint64_t retransmits = 0;    // requests sent again
  uint64_t malformed = 0;      // reports or messages dropped (bad CRC, framing, size)
  uint64_t stray = 0;          // valid messages that answer no outstanding request
  std::string last_malformed;  // the last reason a response was dropped
};

class LinkHost {
 public:
  LinkHost(Transport& transport, LinkOptions options);

  // Asked once, then cached.
  const Capabilities& capabilities();
  // Selects a block by name; throws LinkError listing the board's blocks if it has no such one.
  void select(const std::string& block);
  void configure(std::vector<uint8_t> config);
  // Streams the inputs through the selected block; returns one result per input, in order.
  std::vector<uint32_t> stream(std::span<const uint32_t> inputs);
  Counters counters();

  const LinkStats& stats() const { return stats_; }
  const LinkOptions& options() const { return opt_; }  // as clamped by the constructor
  // The bounds between two accepted responses (docs/rtl/link.md, "Bounds").
  int stray_budget() const;
  int report_budget() const;
  int deadline_ms() const;
  Transport& transport() { return transport_; }

 private:
  struct Pending {
    Message request;
    int sends = 0;
    int answers = 0;  // valid responses received: at most sends
    std::chrono::steady_clock::time_point first_sent;
    bool done = false;
    std::vector<uint8_t> response;  // payload after the OK status
  };
  // Runs the requests, at most window_ at once; fills each one's response.
  void exchange(std::vector<Pending>& requests);
  Pending make(Command c, std::vector<uint8_t> payload);
  void send(Pending& p);
  // `sent`: requests [0, sent) have been sent.
  void receive(std::vector<Pending>& requests, std::vector<size_t>& outstanding, size_t sent);
  bool retransmission_answer(std::vector<Pending>& requests, size_t sent, const Message& m);
  // Throws LinkError once a budget since the last accepted response is spent.
  void check_budgets(const Pending& oldest);
  [[noreturn]] void give_up(const Pending& oldest, const std::string& why);
  void stray(std::string why);
  static std::string mismatch(const Message& request, const Message& response);
  void accept(Pending& p, Message&& m);
  std::vector<uint8_t> call(Command c, std::vector<uint8_t> payload);

  Transport& transport_;
  LinkOptions opt_;
  Reassembler reassembler_;
  LinkStats stats_;
  uint8_t next_tag_ = 0;
  bool have_caps_ = false;
  Capabilities caps_;
  int window_ = 1;
  // Since the last accepted response: reads that timed out, messages that answered nothing
  // outstanding, reports read.
  int silent_ = 0;
  int strays_ = 0;
  int reports_ = 0;
};

}  // namespace texsim::link
