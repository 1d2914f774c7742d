#pragma once
// Block-compressed textures of a scene (docs/formats.md#block-compressed-formats): a loaded
// texture encoded by one of Debian's encoders (`compress = { … }`), or blocks read from a DDS
// or .astc file.
#include <string>

#include "blocks/texture/memory/texture_memory.h"
#include "pipeline/scene/scene.h"

namespace texsim {

// `src` (every level) encoded as `c` says; the result keeps `src` as the truth's texture and
// the encoder's provenance in its blocks.
Texture compress_texture(const Texture& src, const SceneTexture::Compress& c);
// Whether `path` names a compressed texture file (.dds or .astc, by its extension).
bool is_compressed_file(const std::string& path);
// The blocks of a DDS or .astc file, decoded once; sRGB formats decoded to linear colours.
// The file's texels are their own truth. Errors name the file.
Texture load_compressed_file(const std::string& path);

}  // namespace texsim
