#pragma once
// Per-transaction lockstep of a Verilated block against its C++ core (docs/rtl/blocks.md):
// every transaction's outputs bit for bit, its latency against the C++ TimingSpec, and the
// block's op counters against the C++ model's count after that transaction. The first
// mismatches are printed; any mismatch fails the test.
#include <array>
#include <cstdint>
#include <cstdlib>
#include <deque>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "blocks/base/op_counts.h"
#include "rtl_model/verilator/rtl_harness.h"

namespace texsim::rtl {

// Random vectors per block: $TEXSIM_RTL_VECTORS, or `def` (CI uses the default 10^5;
// scripts/rtl-lockstep.sh runs 10^6).
inline uint64_t lockstep_vectors(uint64_t def = 100000) {
  const char* s = std::getenv("TEXSIM_RTL_VECTORS");  // NOLINT(concurrency-mt-unsafe)
  return s != nullptr && *s != '\0' ? std::strtoull(s, nullptr, 10) : def;
}

inline constexpr int kOutWords = 16;
using OutWords = std::array<int64_t, kOutWords>;

inline std::string words_text(const OutWords& w) {
  int used = kOutWords;
  while (used > 1 && w[static_cast<size_t>(used - 1)] == 0) --used;
  std::ostringstream s;
  s << "{";
  for (int i = 0; i < used; ++i) s << (i > 0 ? ", " : "") << w[static_cast<size_t>(i)];
  s << "}";
  return s.str();
}

inline std::string ops_text(const OpCounts& o) {
  std::ostringstream s;
  s << "add " << o.add << " mul " << o.mul << " div " << o.div << " cmp " << o.cmp;
  return s.str();
}

// A transaction's input for the mismatch report: numbers as they are, structs by text().
template <class In>
std::string input_text(const In& in) {
  if constexpr (std::is_arithmetic_v<In>)
    return std::to_string(in);
  else
    return in.text();
}

// Expected transactions in issue order, compared with what the block retires.
class Scoreboard {
 public:
  Scoreboard(std::string block, uint32_t latency, int max_print = 8)
      : block_(std::move(block)), latency_(latency), max_print_(max_print) {}

  // Transaction `in` (text for the report) issued at `cycle`, expected to give `out`; `ops`
  // are the C++ model's counts after it.
  void expect(const std::string& in, uint64_t cycle, const OutWords& out, const OpCounts& ops) {
    pending_.push_back({in, cycle, out, ops});
  }
  // A retirement seen at `cycle` with outputs `out` and counters `ops`.
  void observe(uint64_t cycle, const OutWords& out, const OpCounts& ops) {
    if (pending_.empty()) {
      fail("retired with no transaction pending at cycle " + std::to_string(cycle));
      return;
    }
    const Pending e = pending_.front();
    pending_.pop_front();
    ++compared_;
    std::string why;
    if (out != e.out) why += " out " + words_text(out) + " expected " + words_text(e.out) + ";";
    if (cycle - e.cycle != latency_)
      why += " latency " + std::to_string(cycle - e.cycle) + " expected " +
             std::to_string(latency_) + ";";
    if (!(ops == e.ops)) why += " ops [" + ops_text(ops) + "] expected [" + ops_text(e.ops) + "];";
    if (!why.empty())
      fail("transaction " + std::to_string(compared_ - 1) + " (" + e.in + "):" + why);
  }
  // Call after draining: transactions that never retired are mismatches too.
  void finish() {
    if (!pending_.empty()) fail(std::to_string(pending_.size()) + " transactions never retired");
    pending_.clear();
  }

  size_t pending() const { return pending_.size(); }
  uint64_t compared() const { return compared_; }
  uint64_t mismatches() const { return mismatches_; }
  const std::string& report() const { return report_; }
  std::string summary() const {
    return block_ + ": " + std::to_string(compared_) + " transactions, " +
           std::to_string(mismatches_) + " mismatches";
  }

 private:
  struct Pending {
    std::string in;
    uint64_t cycle;
    OutWords out;
    OpCounts ops;
  };
  void fail(const std::string& what) {
    if (mismatches_ < static_cast<uint64_t>(max_print_)) report_ += block_ + ": " + what + "\n";
    ++mismatches_;
  }

  std::string block_;
  uint32_t latency_;
  int max_print_;
  std::deque<Pending> pending_;
  uint64_t compared_ = 0;
  uint64_t mismatches_ = 0;
  std::string report_;
};

// Streams `vectors` through a block that takes one input word per cycle, with random idle
// cycles between them (probability `bubble`), comparing each retirement. `set_in(top, x)`
// drives the data ports, `read_out(top)` reads the outputs, `ref(x, ops)` is the C++ core:
// it returns the expected outputs and adds the transaction's operations to `ops`.
// `perturb` (negative control) is added to word 0 of transaction `perturb_at`'s expectation.
template <class Model, class In, class SetIn, class ReadOut, class Ref>
void stream_lockstep(RtlHarness<Model>& h, Scoreboard& sb, const std::vector<In>& vectors,
                     SetIn set_in, ReadOut read_out, Ref ref, uint64_t seed, double bubble,
                     int64_t perturb = 0, size_t perturb_at = 0) {
  std::mt19937_64 rng(seed);
  std::bernoulli_distribution idle(bubble);
  OpCounts ops;
  Model& top = h.top();
  auto clock = [&] {
    h.step();
    if (top.out_valid) sb.observe(h.cycle(), read_out(top), h.ops());
  };
  for (size_t i = 0; i < vectors.size(); ++i) {
    while (bubble > 0 && idle(rng)) {
      top.in_valid = 0;
      clock();
    }
    OutWords want = ref(vectors[i], ops);
    if (perturb != 0 && i == perturb_at) want[0] += perturb;
    sb.expect(input_text(vectors[i]), h.cycle(), want, ops);
    top.in_valid = 1;
    set_in(top, vectors[i]);
    clock();
  }
  top.in_valid = 0;
  for (int i = 0; i < (1 << 16) && sb.pending() > 0; ++i) clock();
  sb.finish();
}

}  // namespace texsim::rtl
