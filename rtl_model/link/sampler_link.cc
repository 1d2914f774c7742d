#include "rtl_model/link/sampler_link.h"

#include "rtl_model/link/commands.h"
#include "rtl_model/link/framing.h"

namespace texsim::link {

namespace {

uint32_t hi16(int64_t x) {
  return static_cast<uint32_t>((static_cast<uint64_t>(x) >> 32) & 0xFFFF);
}
uint32_t lo32(int64_t x) { return static_cast<uint32_t>(static_cast<uint64_t>(x)); }
// The s15.32 value of an upper 16 and lower 32 bits, sign-extended from bit 47.
int64_t join(uint32_t hi, uint32_t lo) {
  const uint64_t v = (uint64_t{hi & 0xFFFF} << 32) | lo;
  return static_cast<int64_t>(v << 16) >> 16;
}

// A two's-complement byte (the texel offsets, −8..7).
int signed_byte(uint8_t b) { return b < 128 ? int{b} : int{b} - 256; }

}  // namespace

std::vector<std::vector<uint8_t>> sampler_configuration(const FixedSampler::Config& c,
                                                        const FixedSampler::TextureDesc& t,
                                                        std::span<const uint32_t> memory) {
  std::vector<std::vector<uint8_t>> out;
  ByteWriter w;
  w.u8(kSamplerState)
      .u8(c.trilinear ? 1 : 0)
      .u8(static_cast<uint8_t>(c.address_u))
      .u8(static_cast<uint8_t>(c.address_v))
      .u8(static_cast<uint8_t>(c.offset_u))
      .u8(static_cast<uint8_t>(c.offset_v))
      .u8(static_cast<uint8_t>(c.sub_bits))
      .u8(static_cast<uint8_t>(c.mip_bits))
      .u32(static_cast<uint32_t>(c.bias))
      .u32(static_cast<uint32_t>(c.min_lod))
      .u32(static_cast<uint32_t>(c.max_lod))
      .u16(static_cast<uint16_t>(t.w0))
      .u16(static_cast<uint16_t>(t.h0))
      .u8(static_cast<uint8_t>(t.levels))
      .u8(static_cast<uint8_t>(t.layout));
  for (const uint32_t b : t.base) w.u32(b);
  w.u32(static_cast<uint32_t>(memory.size()));
  out.reserve(1 + (memory.size() + kSamplerChunkWords - 1) / kSamplerChunkWords);
  out.push_back(w.take());
  for (size_t i = 0; i < memory.size(); i += kSamplerChunkWords) {
    ByteWriter chunk;
    chunk.u8(kSamplerChunk).u32(static_cast<uint32_t>(i));
    for (size_t k = i; k < memory.size() && k < i + kSamplerChunkWords; ++k) chunk.u32(memory[k]);
    out.push_back(chunk.take());
  }
  return out;
}

SamplerState read_sampler_state(std::span<const uint8_t> payload) {
  ByteReader r(payload, "sampler state");
  SamplerState s;
  if (r.u8() != kSamplerState) throw LinkError("sampler state: not a state payload");
  s.config.trilinear = r.u8() != 0;
  const uint8_t mu = r.u8(), mv = r.u8();
  for (const uint8_t m : {mu, mv}) {
    if (m == static_cast<uint8_t>(AddressMode::Border) ||
        m > static_cast<uint8_t>(AddressMode::MirrorClamp))
      throw LinkError("sampler state: address mode " + std::to_string(m) + " is not covered");
  }
  s.config.address_u = static_cast<AddressMode>(mu);
  s.config.address_v = static_cast<AddressMode>(mv);
  s.config.offset_u = signed_byte(r.u8());
  s.config.offset_v = signed_byte(r.u8());
  s.config.sub_bits = r.u8();
  s.config.mip_bits = r.u8();
  s.config.bias = static_cast<int32_t>(r.u32());
  s.config.min_lod = static_cast<int32_t>(r.u32());
  s.config.max_lod = static_cast<int32_t>(r.u32());
  s.texture.w0 = r.u16();
  s.texture.h0 = r.u16();
  s.texture.levels = r.u8();
  const uint8_t layout = r.u8();
  if (s.texture.w0 < 1 || s.texture.h0 < 1 || s.texture.levels < 1 ||
      s.texture.levels > FixedSampler::kMaxLevels || layout > 2)
    throw LinkError("sampler state: texture size, levels or layout out of range");
  s.texture.layout = static_cast<TexelLayout>(layout);
  for (uint32_t& b : s.texture.base) b = r.u32();
  s.memory_words = r.u32();
  r.expect_end();
  return s;
}

void encode_fragment(const FixedSampler::Input& in, std::span<uint32_t, kSamplerWords> out) {
  const int64_t v[6] = {in.u, in.v, in.dudx, in.dvdx, in.dudy, in.dvdy};
  for (size_t k = 0; k < 6; ++k) {
    out[2 * k] = hi16(v[k]);
    out[2 * k + 1] = lo32(v[k]);
  }
}

FixedSampler::Input decode_fragment(std::span<const uint32_t, kSamplerWords> in) {
  FixedSampler::Input f;
  int64_t* v[6] = {&f.u, &f.v, &f.dudx, &f.dvdx, &f.dudy, &f.dvdy};
  for (size_t k = 0; k < 6; ++k) *v[k] = join(in[2 * k], in[2 * k + 1]);
  return f;
}

void encode_result(const FixedSampler::Result& r, std::span<uint32_t, kSamplerWords> out) {
  out[0] = r.rgba;
  out[1] = static_cast<uint32_t>(r.level_hi);
  out[2] = static_cast<uint32_t>(r.level_lo);
  out[3] = r.delta;
  for (size_t k = 0; k < FixedSampler::kQuadWords; ++k) out[4 + k] = r.addr[k];
}

FixedSampler::Result decode_result(std::span<const uint32_t, kSamplerWords> in) {
  FixedSampler::Result r;
  r.rgba = in[0];
  r.level_hi = static_cast<int32_t>(in[1]);
  r.level_lo = static_cast<int32_t>(in[2]);
  r.delta = in[3];
  for (size_t k = 0; k < FixedSampler::kQuadWords; ++k) r.addr[k] = in[4 + k];
  return r;
}

}  // namespace texsim::link
