// The link's codec (rtl_model/link): CRC-16/CCITT-FALSE check values, message round trips at
// every report boundary, and a clear error for every malformed report.
#include <gtest/gtest.h>

#include <string>

#include "rtl_model/link/commands.h"
#include "rtl_model/link/crc16.h"
#include "rtl_model/link/framing.h"

namespace texsim::link {
namespace {

std::span<const uint8_t> bytes(const std::string& s) {
  return {reinterpret_cast<const uint8_t*>(s.data()), s.size()};
}

Message sample(size_t n, uint8_t tag = 7) {
  Message m{0x01020304, 0x04, tag, {}};
  for (size_t i = 0; i < n; ++i) m.payload.push_back(static_cast<uint8_t>(i * 37 + 11));
  return m;
}

// Feeds every report; returns everything the reassembler produced.
std::vector<Decoded> feed_all(Reassembler& r, const std::vector<Report>& reports) {
  std::vector<Decoded> out;
  for (const Report& rep : reports) {
    for (Decoded& d : r.feed(rep)) out.push_back(std::move(d));
  }
  return out;
}

// The single error the reports give.
std::string error_of(const std::vector<Report>& reports) {
  Reassembler r;
  const std::vector<Decoded> d = feed_all(r, reports);
  EXPECT_EQ(d.size(), 1u);
  if (d.empty()) return "";
  EXPECT_EQ(d.back().status, Decoded::Status::Malformed);
  return d.back().error;
}

TEST(LinkCrc, CcittFalseCheckValues) {
  EXPECT_EQ(crc16(bytes("123456789")), 0x29B1);
  EXPECT_EQ(crc16(bytes("")), 0xFFFF);
  EXPECT_EQ(crc16(bytes("A")), 0xB915);
  // Continuing over two halves gives the CRC of the whole.
  EXPECT_EQ(crc16_update(crc16(bytes("1234")), bytes("56789")), 0x29B1);
}

TEST(LinkFraming, RoundTripAtEveryReportBoundary) {
  for (const size_t n : {size_t{0}, size_t{1}, size_t{53}, size_t{54}, size_t{55}, size_t{56},
                         size_t{111}, size_t{112}, size_t{113}, size_t{1000}, kMaxPayload}) {
    const Message m = sample(n);
    const std::vector<Report> reports = encode_message(m);
    // INIT holds 56 bytes of payload + CRC, each CONT 58.
    const size_t body = n + kCrcSize;
    const size_t expect =
        1 + (body > kInitData ? (body - kInitData + kContData - 1) / kContData : 0);
    EXPECT_EQ(reports.size(), expect) << n;
    Reassembler r;
    const std::vector<Decoded> d = feed_all(r, reports);
    ASSERT_EQ(d.size(), 1u) << n;
    ASSERT_EQ(d[0].status, Decoded::Status::Complete) << d[0].error;
    EXPECT_EQ(d[0].message.channel, m.channel);
    EXPECT_EQ(d[0].message.command, m.command);
    EXPECT_EQ(d[0].message.tag, m.tag);
    EXPECT_EQ(d[0].message.payload, m.payload);
    EXPECT_FALSE(r.busy());
  }
}

TEST(LinkFraming, EncodeRejectsWhatCannotBeSent) {
  EXPECT_THROW(encode_message(sample(kMaxPayload + 1)), LinkError);
  Message m = sample(4);
  m.command = 0;
  EXPECT_THROW(encode_message(m), LinkError);
  m.command = 0x84;
  EXPECT_THROW(encode_message(m), LinkError);
}

TEST(LinkFraming, EveryMalformedReportHasAClearError) {
  const std::vector<Report> three = encode_message(sample(150));
  ASSERT_EQ(three.size(), 3u);

  Reassembler r;
  const std::vector<uint8_t> short_report(63, 0);
  EXPECT_NE(r.feed(short_report).at(0).error.find("report of 63 bytes (expected 64)"),
            std::string::npos);

  Report zero = three[0];
  zero[0] = zero[1] = zero[2] = zero[3] = 0;
  EXPECT_NE(error_of({zero}).find("channel 0"), std::string::npos);

  EXPECT_NE(error_of({three[1]}).find("CONT seq 0 with no message started"), std::string::npos);
  EXPECT_NE(error_of({three[0], three[2]}).find("CONT seq 1 out of order (expected 0"),
            std::string::npos);

  Report other_tag = three[1];
  other_tag[5] = 9;
  EXPECT_NE(error_of({three[0], other_tag}).find("CONT of tag 9 inside the message of tag 7"),
            std::string::npos);

  Report other_channel = three[1];
  other_channel[3] = 0x05;
  EXPECT_NE(error_of({three[0], other_channel}).find("CONT on channel 0x01020305"),
            std::string::npos);

  Report too_long = three[0];
  too_long[6] = 0x20;  // 8192 + …
  EXPECT_NE(error_of({too_long}).find("more than the maximum 4096"), std::string::npos);

  // An INIT in the middle of a message drops that message and starts its own.
  const std::vector<Report> small = encode_message(sample(4, 8));
  Reassembler r2;
  const std::vector<Decoded> d = feed_all(r2, {three[0], small[0]});
  ASSERT_EQ(d.size(), 2u);
  EXPECT_NE(d[0].error.find("INIT of tag 8 interrupted tag 7 after 56 of 152 bytes"),
            std::string::npos);
  EXPECT_EQ(d[1].status, Decoded::Status::Complete);

  Report flipped = three[1];
  flipped[30] ^= 0x40;
  EXPECT_NE(error_of({three[0], flipped, three[2]})
                .find("CRC mismatch in the message of command "
                      "0x04, tag 7"),
            std::string::npos);
}

// A corrupted result byte is accepted by a decoder without the end-to-end CRC and refused with
// it: the check this test exists for (it fails if message_crc stops covering the payload).
TEST(LinkFraming, CrcCatchesACorruptedPayloadThatANaiveDecoderAccepts) {
  const Message m = sample(100);
  std::vector<Report> reports = encode_message(m);
  reports[1][10] ^= 0x08;
  Reassembler naive(false), checked;
  const std::vector<Decoded> a = feed_all(naive, reports);
  ASSERT_EQ(a.size(), 1u);
  ASSERT_EQ(a[0].status, Decoded::Status::Complete);
  EXPECT_NE(a[0].message.payload, m.payload);  // the naive decoder took a wrong message
  const std::vector<Decoded> b = feed_all(checked, reports);
  ASSERT_EQ(b.size(), 1u);
  EXPECT_EQ(b[0].status, Decoded::Status::Malformed);
  // The header is covered too: a changed command or tag is caught.
  std::vector<Report> other_cmd = encode_message(sample(3));
  other_cmd[0][4] ^= 0x01;
  EXPECT_NE(error_of(other_cmd).find("CRC mismatch"), std::string::npos);
}

TEST(LinkCommands, CapabilitiesRoundTripAndTruncation) {
  Capabilities c;
  c.packet_size = 64;
  c.fw_major = 1;
  c.fw_minor = 2;
  c.fw_patch = 3;
  c.max_in_flight = 4;
  c.max_payload = 4096;
  c.blocks = {{"vd_p2", 16, 16, 8}, {"vd_p1", 12, 12, 6}};
  const std::vector<uint8_t> b = encode_capabilities(c);
  ByteReader r(b, "CAPABILITIES response");
  const Capabilities d = decode_capabilities(r);
  EXPECT_EQ(d.fw_minor, 2);
  ASSERT_EQ(d.blocks.size(), 2u);
  EXPECT_EQ(d.blocks[1].name, "vd_p1");
  EXPECT_EQ(d.blocks[1].latency, 6);

  const std::vector<uint8_t> cut(b.begin(), b.end() - 2);
  ByteReader rc(cut, "CAPABILITIES response");
  try {
    decode_capabilities(rc);
    FAIL() << "a truncated payload was decoded";
  } catch (const LinkError& e) {
    EXPECT_NE(std::string(e.what()).find("CAPABILITIES response is truncated"), std::string::npos);
  }
  std::vector<uint8_t> longer = b;
  longer.push_back(0);
  ByteReader rl(longer, "CAPABILITIES response");
  EXPECT_THROW(decode_capabilities(rl), LinkError);
}

}  // namespace
}  // namespace texsim::link
