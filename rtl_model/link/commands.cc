#include "rtl_model/link/commands.h"

#include "rtl_model/link/framing.h"

namespace texsim::link {

std::string command_name(uint8_t c) {
  switch (static_cast<Command>(c)) {
    case Command::Capabilities:
      return "CAPABILITIES";
    case Command::Select:
      return "SELECT";
    case Command::Configure:
      return "CONFIGURE";
    case Command::Stream:
      return "STREAM";
    case Command::Counters:
      return "COUNTERS";
  }
  return "command " + std::to_string(c);
}

ByteWriter& ByteWriter::u8(uint8_t v) {
  bytes_.push_back(v);
  return *this;
}
ByteWriter& ByteWriter::u16(uint16_t v) {
  return u8(static_cast<uint8_t>(v >> 8)).u8(static_cast<uint8_t>(v));
}
ByteWriter& ByteWriter::u32(uint32_t v) {
  return u16(static_cast<uint16_t>(v >> 16)).u16(static_cast<uint16_t>(v));
}
ByteWriter& ByteWriter::u64(uint64_t v) {
  return u32(static_cast<uint32_t>(v >> 32)).u32(static_cast<uint32_t>(v));
}
ByteWriter& ByteWriter::str8(const std::string& s) {
  if (s.size() > 255) throw LinkError("string '" + s.substr(0, 32) + "…' longer than 255 bytes");
  return u8(static_cast<uint8_t>(s.size())).text(s);
}

ByteWriter& ByteWriter::bytes(std::span<const uint8_t> b) {
  for (const uint8_t x : b) bytes_.push_back(x);
  return *this;
}
ByteWriter& ByteWriter::text(const std::string& s) {
  for (const char x : s) bytes_.push_back(static_cast<uint8_t>(x));
  return *this;
}

void ByteReader::need(size_t n) const {
  if (left() < n) {
    throw LinkError(what_ + " is truncated: " + std::to_string(n) +
                    " more bytes needed at offset " + std::to_string(pos_) + " of " +
                    std::to_string(bytes_.size()));
  }
}
uint8_t ByteReader::u8() {
  need(1);
  return bytes_[pos_++];
}
uint16_t ByteReader::u16() {
  const uint16_t hi = u8();
  return static_cast<uint16_t>((hi << 8) | u8());
}
uint32_t ByteReader::u32() {
  const uint32_t hi = u16();
  return (hi << 16) | u16();
}
uint64_t ByteReader::u64() {
  const uint64_t hi = u32();
  return (hi << 32) | u32();
}
std::string ByteReader::str8() {
  const size_t n = u8();
  need(n);
  std::string s(bytes_.begin() + static_cast<std::ptrdiff_t>(pos_),
                bytes_.begin() + static_cast<std::ptrdiff_t>(pos_ + n));
  pos_ += n;
  return s;
}
void ByteReader::expect_end() const {
  if (left() != 0) {
    throw LinkError(what_ + " has " + std::to_string(left()) + " unexpected trailing bytes");
  }
}

std::vector<uint8_t> encode_capabilities(const Capabilities& c) {
  ByteWriter w;
  w.u16(c.packet_size).u8(c.fw_major).u8(c.fw_minor).u8(c.fw_patch);
  w.u8(c.max_in_flight).u16(c.max_payload).u8(static_cast<uint8_t>(c.blocks.size()));
  for (const BlockCaps& b : c.blocks) w.str8(b.name).u8(b.in_bits).u8(b.out_bits).u8(b.latency);
  return w.take();
}

Capabilities decode_capabilities(ByteReader& r) {
  Capabilities c;
  c.packet_size = r.u16();
  c.fw_major = r.u8();
  c.fw_minor = r.u8();
  c.fw_patch = r.u8();
  c.max_in_flight = r.u8();
  c.max_payload = r.u16();
  const size_t n = r.u8();
  for (size_t i = 0; i < n; ++i) {
    BlockCaps b;
    b.name = r.str8();
    b.in_bits = r.u8();
    b.out_bits = r.u8();
    b.latency = r.u8();
    c.blocks.push_back(b);
  }
  r.expect_end();
  return c;
}

}  // namespace texsim::link
