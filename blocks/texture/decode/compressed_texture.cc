#include "blocks/texture/decode/compressed_texture.h"

#include <stdexcept>

#include "blocks/texture/decode/block_decoder.h"

namespace texsim {

Texture texture_from_blocks(std::string name, std::shared_ptr<const Texture::Blocks> blocks,
                            const std::vector<int>& widths, const std::vector<int>& heights,
                            std::shared_ptr<const Texture> reference) {
  const CompressedFormatInfo& f = format_info(blocks->format);
  if (widths.size() != blocks->levels.size() || heights.size() != blocks->levels.size())
    throw std::invalid_argument("compressed texture: level lists disagree");
  std::vector<std::vector<float>> levels;
  for (size_t l = 0; l < widths.size(); ++l) {
    const int w = widths[l], h = heights[l];
    const int bw = (w + f.block_w - 1) / f.block_w, bh = (h + f.block_h - 1) / f.block_h;
    const std::vector<uint8_t>& bytes = blocks->levels[l];
    if (bytes.size() !=
        static_cast<size_t>(bw) * static_cast<size_t>(bh) * static_cast<size_t>(f.block_bytes))
      throw std::invalid_argument("compressed texture: a level's blocks do not match its size");
    std::vector<float> px(static_cast<size_t>(w) * static_cast<size_t>(h) * 4);
    for (int by = 0; by < bh; ++by) {
      for (int bx = 0; bx < bw; ++bx) {
        const size_t at =
            (static_cast<size_t>(by) * static_cast<size_t>(bw) + static_cast<size_t>(bx)) *
            static_cast<size_t>(f.block_bytes);
        const DecodedBlock d = decode_block(blocks->format, bytes.data() + at);
        // Texels of edge blocks past the level's size are padding: dropped.
        for (int y = 0; y < f.block_h && by * f.block_h + y < h; ++y) {
          for (int x = 0; x < f.block_w && bx * f.block_w + x < w; ++x) {
            const glm::vec4& c = d.at(x, y);
            float* o = &px[(static_cast<size_t>(by * f.block_h + y) * static_cast<size_t>(w) +
                            static_cast<size_t>(bx * f.block_w + x)) *
                           4];
            for (int k = 0; k < 4; ++k) o[k] = c[k];
          }
        }
      }
    }
    levels.push_back(std::move(px));
  }
  Texture t = Texture::from_levels(std::move(name), widths, heights, levels, TexelFormat::Rgba32f);
  t.set_blocks(std::move(blocks));
  t.set_reference(std::move(reference));
  return t;
}

}  // namespace texsim
