#include "testbench/cosim/fault_transport.h"

namespace texsim::link {

FaultTransport::FaultTransport(Transport& inner, std::vector<FaultRule> rules, uint64_t seed)
    : inner_(inner), rules_(std::move(rules)), rng_(seed) {}

const FaultRule* FaultTransport::fire(Direction dir, uint64_t n) {
  for (const FaultRule& r : rules_) {
    if (r.dir != dir) continue;
    const bool hit = r.period > 0
                         ? n >= r.phase && (n - r.phase) % r.period == 0
                         : std::uniform_real_distribution<double>(0, 1)(rng_) < r.probability;
    if (hit) {
      ++injected_;
      return &r;
    }
  }
  return nullptr;
}

void FaultTransport::write(const Report& report) {
  if (dead_) return;
  const FaultRule* r = fire(Direction::ToBoard, sent_++);
  Report out = report;
  if (r) {
    switch (r->fault) {
      case Fault::Drop:
        return;
      case Fault::Corrupt:
        out[r->byte % out.size()] ^= r->mask;
        break;
      case Fault::Duplicate:
        inner_.write(out);
        break;
      case Fault::Reorder:
        if (held_out_) inner_.write(*held_out_);
        held_out_ = out;
        return;
      case Fault::Truncate:  // a report always reaches the board whole; treat as corruption
        out[kReportSize - 1] ^= 0xFF;
        break;
      case Fault::Stall:
        break;
    }
  }
  inner_.write(out);
  if (held_out_) {
    inner_.write(*held_out_);  // the held report overtakes nothing more: it follows this one
    held_out_.reset();
  }
}

std::vector<uint8_t> FaultTransport::next_from_board(int timeout_ms) {
  std::vector<uint8_t> got = inner_.read(timeout_ms);
  if (got.empty() && held_in_) {
    got = std::move(*held_in_);  // nothing else came: the held report is released
    held_in_.reset();
  }
  return got;
}

std::vector<uint8_t> FaultTransport::read(int timeout_ms) {
  if (dead_) return {};
  if (stall_left_ > 0) {
    --stall_left_;
    return {};
  }
  if (!ready_.empty()) {
    std::vector<uint8_t> r = std::move(ready_.front());
    ready_.pop_front();
    return r;
  }
  std::vector<uint8_t> got = next_from_board(timeout_ms);
  if (got.empty()) return got;
  const FaultRule* r = fire(Direction::FromBoard, received_++);
  if (!r) {
    if (held_in_) {
      ready_.push_back(std::move(*held_in_));  // the held report arrives after this one
      held_in_.reset();
    }
    return got;
  }
  switch (r->fault) {
    case Fault::Drop:
      return read(timeout_ms);
    case Fault::Corrupt:
      got[r->byte % got.size()] ^= r->mask;
      return got;
    case Fault::Duplicate:
      ready_.push_back(got);
      return got;
    case Fault::Reorder:
      if (held_in_) ready_.push_back(std::move(*held_in_));
      held_in_ = std::move(got);
      return read(timeout_ms);
    case Fault::Truncate:
      got.pop_back();
      return got;
    case Fault::Stall:
      ready_.push_back(std::move(got));
      stall_left_ = r->stall_reads;
      return read(timeout_ms);
  }
  return got;
}

}  // namespace texsim::link
