#pragma once
// Block-compressed textures of a scene (docs/formats.md#block-compressed-formats): a loaded
// texture encoded by one of Debian's encoders or texsim's own (`compress = { … }`), or blocks
// read from a DDS, .astc or KTX file.
#include <string>
#include <vector>

#include "blocks/texture/memory/texture_memory.h"
#include "pipeline/scene/scene.h"

namespace texsim {

// The encoder a `compress` spec defaults to: the one Debian has for `f` (squish for BC1-BC3,
// nvtt for BC4/BC5, astcenc for ASTC), texsim's own for BC7 and ETC2 / EAC UNORM, or "" when none
// makes it (the SNORM formats: files only).
std::string default_encoder(CompressedFormat f);
// Whether `encoder` ("squish", "nvtt", "astcenc", "texsim") makes `f`.
bool encoder_makes(const std::string& encoder, CompressedFormat f);
// The quality levels `encoder` knows, fastest first (empty for an unknown encoder).
std::vector<std::string> encoder_qualities(const std::string& encoder);

// `src` (every level) encoded as `c` says; the result keeps `src` as the truth's texture and
// the encoder's provenance in its blocks.
Texture compress_texture(const Texture& src, const SceneTexture::Compress& c);
// Whether `path` names a compressed texture file (.dds, .astc or .ktx, by its extension).
bool is_compressed_file(const std::string& path);
// The blocks of a DDS, .astc or KTX file, decoded once; sRGB formats decoded to linear colours.
// The file's texels are their own truth. Errors name the file.
Texture load_compressed_file(const std::string& path);

}  // namespace texsim
