// The virtual board running the Verilated RTL of the V(d) evaluators behind the link protocol:
// every result the host takes equals the C++ core's, the board's cycle counter is the RTL's
// own, and a wrong block behind the same protocol is caught (negative controls).
#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <string>
#include <vector>

#include "rtl_model/link/link_host.h"
#include "rtl_model/link/vd_core_block.h"
#include "rtl_model/link/virtual_board.h"
#include "rtl_model/verilator/vd_rtl_block.h"

namespace texsim::link {
namespace {

constexpr uint16_t kBatch = 250;

// Every u0.16 corner, then random codes over the whole 16-bit input.
std::vector<uint32_t> inputs(size_t n, uint64_t seed) {
  std::vector<uint32_t> v = {0, 1, 2, 0x7FFF, 0x8000, 0x8001, 0xFFFE, 0xFFFF};
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<uint32_t> d(0, 0xFFFF);
  while (v.size() < n) v.push_back(d(rng));
  return v;
}

std::vector<uint32_t> core_results(const std::string& block, const std::vector<uint32_t>& in) {
  std::unique_ptr<BoardBlock> core = make_core_block(block);
  std::vector<uint32_t> out(in.size());
  core->apply(in, out);
  return out;
}

size_t mismatches(const std::vector<uint32_t>& got, const std::vector<uint32_t>& want) {
  size_t n = 0;
  for (size_t i = 0; i < got.size(); ++i) n += got[i] != want[i] ? 1 : 0;
  return n;
}

// An RTL block under another name (a board wired to the wrong RTL), optionally with one result
// bit flipped on vector `flip_at` of the stream.
class Miswired : public BoardBlock {
 public:
  Miswired(std::unique_ptr<BoardBlock> rtl, std::string name, size_t flip_at = SIZE_MAX)
      : rtl_(std::move(rtl)), name_(std::move(name)), flip_at_(flip_at) {}
  BlockCaps caps() const override {
    BlockCaps c = rtl_->caps();
    c.name = name_;
    return c;
  }
  std::string configure(std::span<const uint8_t> c) override { return rtl_->configure(c); }
  uint64_t apply(std::span<const uint32_t> in, std::span<uint32_t> out) override {
    const uint64_t cycles = rtl_->apply(in, out);
    if (flip_at_ >= seen_ && flip_at_ < seen_ + in.size()) out[flip_at_ - seen_] ^= 1u;
    seen_ += in.size();
    return cycles;
  }

 private:
  std::unique_ptr<BoardBlock> rtl_;
  std::string name_;
  size_t flip_at_;
  size_t seen_ = 0;
};

struct BoardRun {
  std::vector<uint32_t> got;
  Counters counters;
  uint32_t latency;
};

BoardRun stream(std::unique_ptr<BoardBlock> block, const std::string& name,
                const std::vector<uint32_t>& in) {
  std::vector<std::unique_ptr<BoardBlock>> blocks;
  blocks.push_back(std::move(block));
  VirtualBoard board(std::move(blocks));
  LinkOptions o;
  o.batch = kBatch;
  LinkHost host(board, o);
  host.select(name);
  host.configure({16});
  BoardRun r;
  r.got = host.stream(in);
  r.counters = host.counters();
  r.latency = host.capabilities().blocks[0].latency;
  return r;
}

TEST(RtlBoard, IsAvailableInThisBuild) {
  EXPECT_TRUE(rtl_board_available());
  EXPECT_EQ(rtl_block_names(), core_block_names());
}

TEST(RtlBoard, MatchesTheCppCoresOverTheLinkWithTheRtlsCycles) {
  for (const std::string name : {"vd_p2", "vd_p1"}) {
    SCOPED_TRACE(name);
    const std::vector<uint32_t> in = inputs(10000, 11);
    const BoardRun r = stream(make_rtl_block(name), name, in);
    EXPECT_EQ(mismatches(r.got, core_results(name, in)), 0u);
    // The RTL's latency equals the C++ timing model's.
    EXPECT_EQ(r.latency, make_core_block(name)->caps().latency);
    EXPECT_EQ(r.counters.vectors, in.size());
    // 40 STREAMs of 250 vectors, each filling and draining the RTL pipeline once.
    EXPECT_EQ(r.counters.cycles, (in.size() / kBatch) * (kBatch - 1 + r.latency));
    EXPECT_EQ(r.counters.bad_requests, 0u);
  }
}

TEST(RtlBoard, TheWrongRtlBehindTheProtocolIsCaught) {
  const std::vector<uint32_t> in = inputs(10000, 12);
  const BoardRun r =
      stream(std::make_unique<Miswired>(make_rtl_block("vd_p1"), "vd_p2"), "vd_p2", in);
  EXPECT_GT(mismatches(r.got, core_results("vd_p2", in)), in.size() / 2);
}

TEST(RtlBoard, OneWrongBitIsExactlyOneMismatch) {
  const std::vector<uint32_t> in = inputs(10000, 13);
  const BoardRun r =
      stream(std::make_unique<Miswired>(make_rtl_block("vd_p2"), "vd_p2", 4321), "vd_p2", in);
  const std::vector<uint32_t> want = core_results("vd_p2", in);
  EXPECT_EQ(mismatches(r.got, want), 1u);
  EXPECT_NE(r.got[4321], want[4321]);
}

TEST(RtlBoard, RefusesFormatsTheRtlIsNotBuiltFor) {
  std::unique_ptr<BoardBlock> b = make_rtl_block("vd_p2");
  EXPECT_NE(b->configure(std::vector<uint8_t>{12}).find("u0.16 inputs only"), std::string::npos);
  EXPECT_EQ(b->configure(std::vector<uint8_t>{16}), "");
  EXPECT_THROW(make_rtl_block("vd_p7"), LinkError);
}

}  // namespace
}  // namespace texsim::link
