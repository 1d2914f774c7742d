// libFuzzer harness: the fuzz input plays the board behind LinkHost (docs/rtl/link.md,
// "Bounds"). Every read the host makes takes its answer from the input: a timeout, raw bytes,
// a well-formed message (valid CRC) with fuzzed command, tag, channel, status and payload, or
// a structured answer to a recent request (capabilities or a STREAM response with fuzzed
// fields) so that mutations reach the checks behind the CRC; a repeat makes the next answer
// the board's reply to up to 65535 reads, as a board that never stops would. Once the input is
// exhausted every read times out. The host runs capabilities, select, configure, stream and
// counters; only LinkError (or InputError) may leave them, and the transport aborts when the
// host reads more between two accepted responses than the bounds of docs/rtl/link.md allow
// (libFuzzer's -timeout catches a loop without I/O).
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <exception>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "rtl_model/link/link_host.h"

namespace {

using namespace texsim::link;

class FuzzBoard : public Transport {
 public:
  FuzzBoard(const uint8_t* data, size_t size) : data_(data), size_(size) {}

  // The host whose bounds are checked on every read.
  void watch(const LinkHost* host) { host_ = host; }
  // A new LinkHost call: its budgets start afresh.
  void new_call() { reads_ = 0; }

  void write(const Report& report) override {
    count();
    for (Decoded& d : reassembler_.feed(report)) {
      if (d.status != Decoded::Status::Complete) continue;
      channel_ = d.message.channel;
      recent_.push_back(std::move(d.message));
      if (recent_.size() > 8) recent_.pop_front();
    }
  }

  std::vector<uint8_t> read(int /*timeout_ms*/) override {
    count();
    check_bounds();
    if (!queue_.empty()) {
      std::vector<uint8_t> r = std::move(queue_.front());
      queue_.pop_front();
      return r;
    }
    if (repeat_left_ > 0) {
      --repeat_left_;
      pos_ = repeat_from_;
    } else if (left() > 0 && data_[pos_] % 5 == 4) {
      ++pos_;
      repeat_left_ = u16();
      repeat_from_ = pos_;
    }
    if (left() == 0) return {};
    switch (byte() % 5) {
      case 0:
        return {};
      case 1:
        return raw();
      case 2:
        queue(message());
        break;
      case 3:
        queue(answer());
        break;
      default:  // a repeat inside a repeat: nothing
        return {};
    }
    if (queue_.empty()) return {};
    std::vector<uint8_t> r = std::move(queue_.front());
    queue_.pop_front();
    return r;
  }

  std::string describe() const override { return "fuzzed board"; }

 private:
  size_t left() const { return size_ - pos_; }
  uint8_t byte() { return left() ? data_[pos_++] : 0; }
  uint16_t u16() { return static_cast<uint16_t>((byte() << 8) | byte()); }
  uint32_t u32() { return (uint32_t{u16()} << 16) | u16(); }
  std::vector<uint8_t> bytes(size_t n) {
    n = std::min(n, left());
    std::vector<uint8_t> b(data_ + pos_, data_ + pos_ + n);
    pos_ += n;
    return b;
  }
  void count() {
    // Far above what the bounds allow for inputs of libFuzzer's default sizes.
    if (++calls_ > 1000000) {
      std::fprintf(stderr, "the host called the transport %llu times\n",
                   static_cast<unsigned long long>(calls_));
      std::abort();
    }
  }
  // Reads between two accepted responses: at most report_budget() + 1 that return bytes, and
  // (retries + 1) timeouts before each valid answer that is not an accepted response, itself a
  // read that returned bytes.
  void check_bounds() {
    if (!host_) return;
    if (host_->stats().accepted != accepted_) {
      accepted_ = host_->stats().accepted;
      reads_ = 0;
    }
    const uint64_t budget = static_cast<uint64_t>(host_->report_budget()) + 2;
    const uint64_t bound = budget + static_cast<uint64_t>(host_->options().retries + 1) * budget;
    if (++reads_ > bound) {
      std::fprintf(stderr, "%llu reads without an accepted response (bound %llu)\n",
                   static_cast<unsigned long long>(reads_), static_cast<unsigned long long>(bound));
      std::abort();
    }
  }

  const Message* recent() {
    if (recent_.empty()) return nullptr;
    return &recent_[byte() % recent_.size()];
  }

  // Bytes as received: 64, or a short report.
  std::vector<uint8_t> raw() {
    const uint8_t n = byte();
    return bytes(n & 0x80 ? kReportSize : n % (kReportSize + 1));
  }

  // A well-formed message; each header field either copies a recent request's or is fuzzed.
  Message message() {
    const uint8_t flags = byte();
    const Message* r = recent();
    Message m;
    m.channel = flags & 1 ? u32() : channel_;
    m.command = static_cast<uint8_t>((flags & 2 || !r ? byte() : r->command) % 0x7F + 1);
    m.tag = flags & 4 || !r ? byte() : r->tag;
    m.payload = bytes(u16() % (kMaxPayload + 1));
    return m;
  }

  // An OK answer to a recent request with fuzzed contents in the right layout.
  Message answer() {
    const Message* r = recent();
    if (!r) return message();
    Message m{channel_, r->command, r->tag, {0}};
    ByteWriter w;
    if (r->command == static_cast<uint8_t>(Command::Capabilities)) {
      Capabilities c;
      c.packet_size = byte() & 1 ? u16() : kReportSize;
      c.fw_major = byte();
      c.max_in_flight = byte();
      c.max_payload = u16();
      const size_t n = byte() % 4;
      for (size_t i = 0; i < n; ++i) {
        const std::vector<uint8_t> name = bytes(byte() % 8);
        c.blocks.push_back(BlockCaps{std::string(name.begin(), name.end()), 16, 16, 8});
      }
      w.bytes(encode_capabilities(c));
    } else if (r->command == static_cast<uint8_t>(Command::Stream) && r->payload.size() >= 6) {
      ByteReader req(r->payload, "request");
      const uint32_t first = req.u32();
      const uint16_t n = req.u16();
      const uint8_t skew = byte();
      w.u32(first + (skew & 3)).u16(static_cast<uint16_t>(n + ((skew >> 2) & 3)));
      w.bytes(bytes(4 * size_t{n} + (skew >> 4)));
    } else {
      w.bytes(bytes(byte() % 24));
    }
    const std::vector<uint8_t> p = w.take();
    m.payload.insert(m.payload.end(), p.begin(), p.end());
    if (m.payload.size() > kMaxPayload) m.payload.resize(kMaxPayload);
    return m;
  }

  void queue(const Message& m) {
    if (m.channel == 0) return;
    for (const Report& r : encode_message(m)) queue_.emplace_back(r.begin(), r.end());
  }

  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
  uint64_t calls_ = 0;
  uint32_t channel_ = 1;
  const LinkHost* host_ = nullptr;
  uint64_t accepted_ = 0, reads_ = 0;
  size_t repeat_left_ = 0, repeat_from_ = 0;
  Reassembler reassembler_;
  std::deque<Message> recent_;
  std::deque<std::vector<uint8_t>> queue_;
};

template <class F>
void expect_link_error(F&& f) {
  try {
    f();
  } catch (const LinkError&) {
    // A board that breaks the protocol must end here: a clear error.
  } catch (const texsim::InputError&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "exception other than LinkError: %s\n", e.what());
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  FuzzBoard board(data + 2, size - 2);
  LinkOptions o;
  o.timeout_ms = 1;
  o.retries = data[0] % 4;
  o.window = 1 + (data[0] >> 2) % 4;
  o.batch = static_cast<uint16_t>(1 + data[1] % 64);
  LinkHost host(board, o);
  board.watch(&host);
  const auto call = [&](auto&& f) {
    board.new_call();
    expect_link_error(f);
  };
  call([&] { host.capabilities(); });
  call([&] { host.select("vd_p2"); });
  call([&] { host.configure({16}); });
  std::vector<uint32_t> in(data[1] % 200);
  for (size_t i = 0; i < in.size(); ++i) in[i] = static_cast<uint32_t>(i * 2654435761u);
  call([&] {
    const std::vector<uint32_t> got = host.stream(in);
    if (got.size() != in.size()) {
      std::fprintf(stderr, "stream gave %zu results for %zu inputs\n", got.size(), in.size());
      std::abort();
    }
  });
  call([&] { host.counters(); });
  return 0;
}
