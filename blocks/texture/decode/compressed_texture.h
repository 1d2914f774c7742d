#pragma once
// Textures made of compressed blocks (docs/formats.md#block-compressed-formats).
#include <memory>
#include <string>
#include <vector>

#include "blocks/texture/memory/texture_memory.h"

namespace texsim {

// A texture made of `blocks` (levels of widths[l] × heights[l] texels): every block decoded
// once into the texture's float store (the simulator's decoded-block store: a run reads
// decoded texels and never decodes again), the blocks kept for the memory model, and
// `reference` as the truth's texture.
Texture texture_from_blocks(std::string name, std::shared_ptr<const Texture::Blocks> blocks,
                            const std::vector<int>& widths, const std::vector<int>& heights,
                            std::shared_ptr<const Texture> reference);

}  // namespace texsim
