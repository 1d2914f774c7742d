#pragma once
// The host side of the link (docs/rtl/link.md), the same code for every transport: requests
// with tags, at most `window` outstanding, responses matched by tag and checked (CRC, echoed
// command, status, the vectors they claim to carry), timeouts and retransmission. A response
// that fails any check is never used: its request is sent again on the next timeout, and after
// `retries` timeouts in a row without a valid answer the call throws LinkError.
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
};

struct LinkStats {
  uint64_t requests = 0;
  uint64_t reports_out = 0, reports_in = 0;
  uint64_t timeouts = 0;       // reads that returned nothing
  uint64_t retransmits = 0;    // requests sent again
  uint64_t malformed = 0;      // reports or messages dropped (bad CRC, framing, size)
  uint64_t stray = 0;          // valid responses to no outstanding request (duplicates, late)
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
  Transport& transport() { return transport_; }

 private:
  struct Pending {
    Message request;
    int sends = 0;
    bool done = false;
    std::vector<uint8_t> response;  // payload after the OK status
  };
  // Runs the requests, at most window_ at once; fills each one's response.
  void exchange(std::vector<Pending>& requests);
  Pending make(Command c, std::vector<uint8_t> payload);
  void send(Pending& p);
  void receive(std::vector<Pending>& requests, std::vector<size_t>& outstanding);
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
  int silent_ = 0;  // timeouts since the last valid response
};

}  // namespace texsim::link
