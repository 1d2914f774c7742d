#pragma once
// The sampler on the link (docs/rtl/link.md): what the host sends a board's `texsim_sampler`
// block and what comes back. CONFIGURE carries either the sampler and texture state (kind 0)
// or a chunk of the texture's memory image (kind 1: first word, then the words); the state
// sizes the board's memory and clears it, so the chunks follow it. A STREAM carries fragments
// of kSamplerWords inputs each (the six s15.32 coordinates, each as its upper 16 and lower 32
// bits) and returns kSamplerWords results per fragment: RGBA8, the two levels, δ and the eight
// texel word addresses.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "blocks/texture/sampler/fixed_sampler.h"

namespace texsim::link {

inline constexpr size_t kSamplerWords = 12;
inline constexpr size_t kSamplerChunkWords = 1000;  // memory words per CONFIGURE (≤ 4096 bytes)
inline constexpr uint8_t kSamplerState = 0, kSamplerChunk = 1;

// What the board's sampler needs besides its memory.
struct SamplerState {
  FixedSampler::Config config;
  FixedSampler::TextureDesc texture;
  uint32_t memory_words = 0;
};

// The CONFIGURE payloads for one material and texture: the state, then the image in chunks.
std::vector<std::vector<uint8_t>> sampler_configuration(const FixedSampler::Config& c,
                                                        const FixedSampler::TextureDesc& t,
                                                        std::span<const uint32_t> memory);
// The board's side: a state payload (kind byte included) back to its fields; throws LinkError
// when it is malformed or out of range.
SamplerState read_sampler_state(std::span<const uint8_t> payload);

void encode_fragment(const FixedSampler::Input& in, std::span<uint32_t, kSamplerWords> out);
FixedSampler::Input decode_fragment(std::span<const uint32_t, kSamplerWords> in);
void encode_result(const FixedSampler::Result& r, std::span<uint32_t, kSamplerWords> out);
FixedSampler::Result decode_result(std::span<const uint32_t, kSamplerWords> in);

}  // namespace texsim::link
