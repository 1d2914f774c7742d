#include "rtl_model/link/framing.h"

#include <algorithm>
#include <cstdio>

#include "rtl_model/link/crc16.h"

namespace texsim::link {

namespace {

std::string hex(uint32_t v, int digits) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%0*X", digits, v);
  return buf;
}

uint32_t read_u32(std::span<const uint8_t> b) {
  return (uint32_t{b[0]} << 24) | (uint32_t{b[1]} << 16) | (uint32_t{b[2]} << 8) | b[3];
}

void write_u32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (24 - 8 * i));
}

Decoded malformed(std::string error) {
  Decoded d;
  d.status = Decoded::Status::Malformed;
  d.error = std::move(error);
  return d;
}

}  // namespace

uint16_t message_crc(const Message& m) {
  const std::array<uint8_t, 4> head = {m.command, m.tag,
                                       static_cast<uint8_t>(m.payload.size() >> 8),
                                       static_cast<uint8_t>(m.payload.size())};
  return crc16_update(crc16(head), m.payload);
}

std::vector<Report> encode_message(const Message& m) {
  if (m.payload.size() > kMaxPayload) {
    throw LinkError("message payload of " + std::to_string(m.payload.size()) +
                    " bytes exceeds the link's maximum of " + std::to_string(kMaxPayload));
  }
  if (m.command == 0 || (m.command & kInitBit) != 0) {
    throw LinkError("command " + hex(m.command, 2) + " is outside 0x01..0x7F");
  }
  std::vector<uint8_t> body = m.payload;
  const uint16_t crc = message_crc(m);
  body.push_back(static_cast<uint8_t>(crc >> 8));
  body.push_back(static_cast<uint8_t>(crc));

  std::vector<Report> out;
  Report r{};
  write_u32(r.data(), m.channel);
  r[4] = static_cast<uint8_t>(kInitBit | m.command);
  r[5] = m.tag;
  r[6] = static_cast<uint8_t>(m.payload.size() >> 8);
  r[7] = static_cast<uint8_t>(m.payload.size());
  size_t pos = std::min(body.size(), kInitData);
  std::copy_n(body.begin(), pos, r.begin() + kInitHeader);
  out.push_back(r);
  for (uint8_t seq = 0; pos < body.size(); ++seq) {
    Report c{};
    write_u32(c.data(), m.channel);
    c[4] = seq;
    c[5] = m.tag;
    const size_t n = std::min(body.size() - pos, kContData);
    std::copy_n(body.begin() + static_cast<std::ptrdiff_t>(pos), n, c.begin() + kContHeader);
    pos += n;
    out.push_back(c);
  }
  return out;
}

std::vector<Decoded> Reassembler::feed(std::span<const uint8_t> r) {
  if (r.size() != kReportSize) {
    return {malformed("report of " + std::to_string(r.size()) + " bytes (expected " +
                      std::to_string(kReportSize) + ")")};
  }
  const uint32_t channel = read_u32(r);
  if (channel == 0) return {malformed("report on channel 0, which is reserved")};
  if ((r[4] & kInitBit) != 0) return feed_init(r, channel);
  std::vector<Decoded> out;
  if (auto d = feed_cont(r, channel)) out.push_back(std::move(*d));
  return out;
}

std::vector<Decoded> Reassembler::feed_init(std::span<const uint8_t> r, uint32_t channel) {
  std::vector<Decoded> out;
  if (open_) {
    out.push_back(malformed("INIT of tag " + std::to_string(r[5]) + " interrupted tag " +
                            std::to_string(msg_.tag) + " after " + std::to_string(data_.size()) +
                            " of " + std::to_string(length_ + kCrcSize) + " bytes"));
    open_ = false;
  }
  const size_t length = (size_t{r[6]} << 8) | r[7];
  if (length > kMaxPayload) {
    out.push_back(malformed("INIT announces " + std::to_string(length) +
                            " payload bytes, more than the maximum " +
                            std::to_string(kMaxPayload)));
    return out;
  }
  msg_ = Message{channel, static_cast<uint8_t>(r[4] & ~kInitBit), r[5], {}};
  length_ = length;
  data_.assign(r.begin() + kInitHeader,
               r.begin() + static_cast<std::ptrdiff_t>(kInitHeader +
                                                       std::min(kInitData, length + kCrcSize)));
  next_seq_ = 0;
  open_ = true;
  if (data_.size() == length_ + kCrcSize) out.push_back(finish());
  return out;
}

std::optional<Decoded> Reassembler::feed_cont(std::span<const uint8_t> r, uint32_t channel) {
  const size_t seq = r[4];
  if (!open_) return malformed("CONT seq " + std::to_string(seq) + " with no message started");
  if (channel != msg_.channel) {
    open_ = false;
    return malformed("CONT on channel " + hex(channel, 8) + " inside a message on channel " +
                     hex(msg_.channel, 8));
  }
  if (r[5] != msg_.tag) {
    open_ = false;
    return malformed("CONT of tag " + std::to_string(r[5]) + " inside the message of tag " +
                     std::to_string(msg_.tag));
  }
  if (seq != next_seq_) {
    open_ = false;
    return malformed("CONT seq " + std::to_string(seq) + " out of order (expected " +
                     std::to_string(next_seq_) + ", tag " + std::to_string(msg_.tag) + ")");
  }
  ++next_seq_;
  const size_t n = std::min(kContData, length_ + kCrcSize - data_.size());
  data_.insert(data_.end(), r.begin() + kContHeader,
               r.begin() + static_cast<std::ptrdiff_t>(kContHeader + n));
  if (data_.size() < length_ + kCrcSize) return std::nullopt;
  return finish();
}

Decoded Reassembler::finish() {
  open_ = false;
  msg_.payload.assign(data_.begin(), data_.begin() + static_cast<std::ptrdiff_t>(length_));
  const uint16_t got = static_cast<uint16_t>((data_[length_] << 8) | data_[length_ + 1]);
  const uint16_t want = message_crc(msg_);
  if (check_crc_ && got != want) {
    return malformed("CRC mismatch in the message of command " + hex(msg_.command, 2) + ", tag " +
                     std::to_string(msg_.tag) + ": it carries " + hex(got, 4) +
                     ", its bytes give " + hex(want, 4));
  }
  Decoded d;
  d.message = std::move(msg_);
  return d;
}

}  // namespace texsim::link
