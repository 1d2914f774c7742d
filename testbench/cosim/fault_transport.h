#pragma once
// A Transport wrapper that breaks the link on purpose: drops, corrupts, duplicates, reorders
// or truncates reports in either direction, stalls the replies, or goes dead. Rules fire on a
// fixed period (deterministic tests) or with a seeded probability (soak tests).
#include <cstdint>
#include <deque>
#include <optional>
#include <random>
#include <vector>

#include "rtl_model/link/transport.h"

namespace texsim::link {

enum class Fault { Drop, Corrupt, Duplicate, Reorder, Truncate, Stall };
enum class Direction { ToBoard, FromBoard };

struct FaultRule {
  Fault fault = Fault::Drop;
  Direction dir = Direction::FromBoard;
  uint64_t period = 0;  // fires on reports phase, phase + period, …; 0: use probability
  uint64_t phase = 0;
  double probability = 0;  // with period 0
  size_t byte = 20;        // Corrupt: this byte (default: inside the data) …
  uint8_t mask = 0x01;     // … XORed with this
  int stall_reads = 3;     // Stall: reads that return nothing before the report comes
};

class FaultTransport : public Transport {
 public:
  FaultTransport(Transport& inner, std::vector<FaultRule> rules, uint64_t seed = 1);

  void write(const Report& report) override;
  std::vector<uint8_t> read(int timeout_ms) override;
  std::string describe() const override { return "faulty " + inner_.describe(); }

  // From now on nothing reaches the board and nothing comes back.
  void kill() { dead_ = true; }
  uint64_t injected() const { return injected_; }

 private:
  // The rule that fires on the n-th report of `dir`, if any.
  const FaultRule* fire(Direction dir, uint64_t n);
  std::vector<uint8_t> next_from_board(int timeout_ms);

  Transport& inner_;
  std::vector<FaultRule> rules_;
  std::mt19937_64 rng_;
  uint64_t sent_ = 0, received_ = 0, injected_ = 0;
  std::optional<Report> held_out_;               // a request report held back (Reorder)
  std::optional<std::vector<uint8_t>> held_in_;  // a response report held back (Reorder)
  std::deque<std::vector<uint8_t>> ready_;       // response reports to deliver next
  int stall_left_ = 0;
  bool dead_ = false;
};

}  // namespace texsim::link
