#pragma once
// The texel decompressor as a memory level (docs/timing-model.md#decompression): placed in
// front of a cache that holds decoded texels, it answers a read of a line of decoded texels by
// reading the compressed blocks those texels come from from the level behind it, then decoding
// them. Lines of uncompressed textures pass through unchanged.
#include <cstdint>
#include <functional>

#include "blocks/texture/decode/compressed_format.h"
#include "blocks/texture/memory/line_memory.h"
#include "blocks/texture/memory/texture_memory.h"

namespace texsim {

class BlockDecompressor final : public LineMemory {
 public:
  // A decoder's timing for one block of a format: cycles from the block's bytes to its texels,
  // and cycles between blocks (one decoder per level, blocks of a line decoded in turn).
  struct Timing {
    uint32_t latency = 1;
    uint32_t ii = 1;
  };
  struct Stats {
    uint64_t lines = 0;             // lines of decoded texels made
    uint64_t blocks = 0;            // blocks decoded (decoder activations)
    uint64_t compressed_reads = 0;  // line reads sent to the level behind
    uint64_t passed = 0;            // reads of uncompressed textures passed through
    PerCompressedFormat blocks_by_format{};
  };

  BlockDecompressor(LineMemory* next, const TextureSet* textures,
                    std::function<Timing(CompressedFormat)> timing)
      : next_(next), textures_(textures), timing_(std::move(timing)) {}
  uint64_t read_line(uint64_t now, uint64_t addr, uint32_t bytes, int unit) override;
  const Stats& stats() const { return stats_; }

 private:
  LineMemory* next_;
  const TextureSet* textures_;
  std::function<Timing(CompressedFormat)> timing_;
  Stats stats_;
};

}  // namespace texsim
