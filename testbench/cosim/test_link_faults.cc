// The link under faults (testbench/cosim/fault_transport.h): every dropped, corrupted,
// duplicated, reordered or truncated report and every stall is retried until the results are
// right, or ends in a clear LinkError; a wrong result is never accepted. The host code is the
// one `texsim cosim` uses, over the virtual board with the V(d) cores.
#include <gtest/gtest.h>

#include <deque>
#include <memory>
#include <random>
#include <string>

#include "rtl_model/link/link_host.h"
#include "rtl_model/link/vd_core_block.h"
#include "rtl_model/link/virtual_board.h"
#include "testbench/cosim/fault_transport.h"

namespace texsim::link {
namespace {

std::unique_ptr<VirtualBoard> make_board() {
  std::vector<std::unique_ptr<BoardBlock>> blocks;
  for (const std::string& n : core_block_names()) blocks.push_back(make_core_block(n));
  return std::make_unique<VirtualBoard>(std::move(blocks));
}

std::vector<uint32_t> random_inputs(size_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<uint32_t> d(0, 1u << 15);  // d in [0, 0.5] as u0.16
  std::vector<uint32_t> v(n);
  for (uint32_t& x : v) x = d(rng);
  return v;
}

std::vector<uint32_t> core_results(const std::string& block, const std::vector<uint32_t>& in) {
  std::unique_ptr<BoardBlock> core = make_core_block(block);
  std::vector<uint32_t> out(in.size());
  core->apply(in, out);
  return out;
}

// Streams `n` vectors through vd_p2 over the transport; returns what the host accepted.
std::vector<uint32_t> run(Transport& t, const std::vector<uint32_t>& in, LinkStats* stats = nullptr,
                          uint16_t batch = 64) {
  LinkOptions o;
  o.batch = batch;
  LinkHost host(t, o);
  host.select("vd_p2");
  host.configure({16});
  std::vector<uint32_t> got = host.stream(in);
  if (stats) *stats = host.stats();
  return got;
}

struct Case {
  const char* name;
  FaultRule rule;
};

class LinkFault : public ::testing::TestWithParam<Case> {};

TEST_P(LinkFault, IsRetriedAndEveryResultIsRight) {
  const std::vector<uint32_t> in = random_inputs(3000, 5);
  const std::vector<uint32_t> want = core_results("vd_p2", in);
  std::unique_ptr<VirtualBoard> board = make_board();
  FaultTransport faulty(*board, {GetParam().rule});
  LinkStats s;
  const std::vector<uint32_t> got = run(faulty, in, &s);
  EXPECT_GT(faulty.injected(), 0u) << "the fault never fired";
  ASSERT_EQ(got.size(), want.size());
  EXPECT_EQ(got, want);
  // Each fault left a trace: a retransmission, a dropped response or a discarded duplicate.
  EXPECT_GT(s.retransmits + s.malformed + s.stray, 0u);
  // The board ran every vector exactly once (retransmissions are answered from its replay).
  EXPECT_EQ(board->counters().vectors, in.size());
}

FaultRule rule(Fault f, Direction d, uint64_t period, uint64_t phase = 3) {
  FaultRule r;
  r.fault = f;
  r.dir = d;
  r.period = period;
  r.phase = phase;
  return r;
}

INSTANTIATE_TEST_SUITE_P(
    Kinds, LinkFault,
    ::testing::Values(Case{"DropRequest", rule(Fault::Drop, Direction::ToBoard, 17)},
                      Case{"DropResponse", rule(Fault::Drop, Direction::FromBoard, 13)},
                      Case{"CorruptRequest", rule(Fault::Corrupt, Direction::ToBoard, 11)},
                      Case{"CorruptResponse", rule(Fault::Corrupt, Direction::FromBoard, 19)},
                      Case{"DuplicateRequest", rule(Fault::Duplicate, Direction::ToBoard, 23)},
                      Case{"DuplicateResponse", rule(Fault::Duplicate, Direction::FromBoard, 29)},
                      Case{"ReorderRequest", rule(Fault::Reorder, Direction::ToBoard, 31)},
                      Case{"ReorderResponse", rule(Fault::Reorder, Direction::FromBoard, 37)},
                      Case{"TruncateResponse", rule(Fault::Truncate, Direction::FromBoard, 41)},
                      Case{"StallResponse", rule(Fault::Stall, Direction::FromBoard, 43)}),
    [](const ::testing::TestParamInfo<Case>& i) { return std::string(i.param.name); });

// Every fault at once, at random: still every result right.
TEST(LinkFaults, RandomMixSoak) {
  const std::vector<uint32_t> in = random_inputs(20000, 9);
  std::vector<FaultRule> rules;
  for (const Fault f : {Fault::Drop, Fault::Corrupt, Fault::Duplicate, Fault::Reorder,
                        Fault::Truncate, Fault::Stall}) {
    for (const Direction d : {Direction::ToBoard, Direction::FromBoard}) {
      FaultRule r;
      r.fault = f;
      r.dir = d;
      r.probability = 0.002;
      rules.push_back(r);
    }
  }
  std::unique_ptr<VirtualBoard> board = make_board();
  FaultTransport faulty(*board, rules, 42);
  LinkStats s;
  EXPECT_EQ(run(faulty, in, &s), core_results("vd_p2", in));
  EXPECT_GT(faulty.injected(), 20u);
  EXPECT_GT(s.retransmits, 0u);
}

// Corrupting result bytes only (every response's first CONT, inside the results): the CRC
// rejects each such message, so no corrupted result reaches the caller.
TEST(LinkFaults, CorruptedResultsAreNeverAccepted) {
  const std::vector<uint32_t> in = random_inputs(2000, 11);
  std::unique_ptr<VirtualBoard> board = make_board();
  FaultRule r = rule(Fault::Corrupt, Direction::FromBoard, 11, 1);  // now and then inside results
  r.byte = 40;
  r.mask = 0x10;
  FaultTransport faulty(*board, {r});
  LinkStats s;
  EXPECT_EQ(run(faulty, in, &s), core_results("vd_p2", in));
  EXPECT_GT(s.malformed, 0u);
  EXPECT_NE(s.last_malformed.find("CRC mismatch"), std::string::npos) << s.last_malformed;
}

TEST(LinkFaults, DeadBoardEndsInAClearErrorWithoutHanging) {
  std::unique_ptr<VirtualBoard> board = make_board();
  FaultTransport faulty(*board, {});
  LinkOptions o;
  o.retries = 3;
  LinkHost host(faulty, o);
  host.select("vd_p2");
  faulty.kill();
  try {
    host.stream(random_inputs(100, 1));
    FAIL() << "a dead board gave results";
  } catch (const LinkError& e) {
    EXPECT_NE(std::string(e.what()).find("no valid response to STREAM"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("after 4 attempts"), std::string::npos) << e.what();
  }
}

// A board that stalls for longer than every retry waits: a clear error, not a hang.
TEST(LinkFaults, StallLongerThanTheRetriesEndsInAnError) {
  std::unique_ptr<VirtualBoard> board = make_board();
  FaultRule r = rule(Fault::Stall, Direction::FromBoard, 1000, 2);
  r.stall_reads = 10;
  FaultTransport faulty(*board, {r});
  LinkHost host(faulty, LinkOptions{});
  host.select("vd_p2");
  EXPECT_THROW(host.stream(random_inputs(500, 4)), LinkError);
}

// Every response corrupted: retries run out and the error names the CRC.
TEST(LinkFaults, PersistentCorruptionEndsInAnErrorNamingTheCrc) {
  std::unique_ptr<VirtualBoard> board = make_board();
  FaultRule r = rule(Fault::Corrupt, Direction::FromBoard, 1, 0);
  r.byte = 9;
  FaultTransport faulty(*board, {r});
  LinkHost host(faulty, LinkOptions{});
  try {
    host.capabilities();
    FAIL() << "a corrupted capabilities response was accepted";
  } catch (const LinkError& e) {
    EXPECT_NE(std::string(e.what()).find("CRC mismatch"), std::string::npos) << e.what();
  }
}

// Answers every STREAM first with a well-formed response (right channel, command and tag,
// valid CRC) for other vectors, as a stale response whose tag was reused would look.
class ForgingTransport : public Transport {
 public:
  explicit ForgingTransport(Transport& board) : board_(board) {}
  void write(const Report& r) override {
    board_.write(r);
    if (r[4] != (kInitBit | static_cast<uint8_t>(Command::Stream))) return;
    ByteReader req(std::span<const uint8_t>(r).subspan(kInitHeader, 6), "forged");
    const uint32_t first = req.u32();
    const uint16_t count = req.u16();
    ByteWriter w;
    w.u8(0).u32(first + 1000).u16(count);
    for (uint16_t i = 0; i < count; ++i) w.u32(0xDEAD);
    const Message m{(uint32_t{r[0]} << 24) | (uint32_t{r[1]} << 16) | (uint32_t{r[2]} << 8) | r[3],
                    static_cast<uint8_t>(Command::Stream), r[5], w.take()};
    for (const Report& f : encode_message(m)) forged_.emplace_back(f.begin(), f.end());
  }
  std::vector<uint8_t> read(int timeout_ms) override {
    if (forged_.empty()) return board_.read(timeout_ms);
    std::vector<uint8_t> f = std::move(forged_.front());
    forged_.pop_front();
    return f;
  }
  std::string describe() const override { return "forging board"; }

 private:
  Transport& board_;
  std::deque<std::vector<uint8_t>> forged_;
};

TEST(LinkFaults, AResponseForOtherVectorsIsNeverAccepted) {
  const std::vector<uint32_t> in = random_inputs(1000, 8);
  std::unique_ptr<VirtualBoard> board = make_board();
  ForgingTransport forging(*board);
  LinkStats s;
  EXPECT_EQ(run(forging, in, &s), core_results("vd_p2", in));
  EXPECT_GT(s.stray, 0u);
  EXPECT_NE(s.last_malformed.find("for vectors 960+40 carries vectors 1960+40"), std::string::npos)
      << s.last_malformed;
}

TEST(LinkBoard, RefusalsAreClearErrors) {
  std::unique_ptr<VirtualBoard> board = make_board();
  LinkHost host(*board, LinkOptions{});
  EXPECT_EQ(host.capabilities().blocks.size(), 2u);
  try {
    host.select("vd_p9");
    FAIL();
  } catch (const LinkError& e) {
    EXPECT_NE(std::string(e.what()).find("no block 'vd_p9' (it has: vd_p2, vd_p1)"),
              std::string::npos)
        << e.what();
  }
  try {
    host.stream(random_inputs(10, 1));
    FAIL();
  } catch (const LinkError& e) {
    EXPECT_NE(std::string(e.what()).find("refused STREAM (status 5): no block selected"),
              std::string::npos)
        << e.what();
  }
  host.select("vd_p1");
  EXPECT_THROW(host.configure({13}), LinkError);
  host.configure({8});
  try {
    host.stream(std::vector<uint32_t>{0x100});  // 9 bits into an 8-bit input
    FAIL();
  } catch (const LinkError& e) {
    EXPECT_NE(std::string(e.what()).find("wider than 8 bits"), std::string::npos) << e.what();
  }
}

// A block that is wrong on one vector: the link delivers its result faithfully, and the
// comparison with the C++ core (as `texsim cosim` does it) finds exactly that one.
class OffByOneBlock : public BoardBlock {
 public:
  explicit OffByOneBlock(uint32_t bad_input) : core_(make_core_block("vd_p2")), bad_(bad_input) {}
  BlockCaps caps() const override { return core_->caps(); }
  std::string configure(std::span<const uint8_t> c) override { return core_->configure(c); }
  uint64_t apply(std::span<const uint32_t> in, std::span<uint32_t> out) override {
    const uint64_t cycles = core_->apply(in, out);
    for (size_t i = 0; i < in.size(); ++i) out[i] ^= in[i] == bad_ ? 1u : 0u;
    return cycles;
  }

 private:
  std::unique_ptr<BoardBlock> core_;
  uint32_t bad_;
};

TEST(LinkBoard, AWrongBlockIsCaughtByTheComparison) {
  const std::vector<uint32_t> in = random_inputs(1000, 3);
  std::vector<std::unique_ptr<BoardBlock>> blocks;
  blocks.push_back(std::make_unique<OffByOneBlock>(in[500]));
  VirtualBoard board(std::move(blocks));
  const std::vector<uint32_t> got = run(board, in);
  const std::vector<uint32_t> want = core_results("vd_p2", in);
  size_t diff = 0;
  for (size_t i = 0; i < in.size(); ++i) diff += got[i] != want[i] ? 1 : 0;
  EXPECT_GE(diff, 1u);
  EXPECT_NE(got[500], want[500]);
}

TEST(LinkBoard, CountersCountVectorsAndPipelinedCycles) {
  std::unique_ptr<VirtualBoard> board = make_board();
  LinkOptions o;
  o.batch = 100;
  LinkHost host(*board, o);
  host.select("vd_p2");
  host.stream(random_inputs(1000, 2));
  const Counters c = host.counters();
  const uint32_t latency = host.capabilities().blocks[0].latency;
  EXPECT_EQ(c.vectors, 1000u);
  // Ten runs of 100 vectors, each filling and draining the pipeline once.
  EXPECT_EQ(c.cycles, 10u * (100 + latency - 1));
  EXPECT_EQ(c.bad_requests, 0u);
}

}  // namespace
}  // namespace texsim::link
