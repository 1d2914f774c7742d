#pragma once
// A real renderer beside the simulated filters: Mesa's softpipe (whose anisotropic path is
// Heckbert's EWA) or llvmpipe drawing the same textured primitives through OpenGL 3.3 on EGL's
// surfaceless platform (no display), into an RGBA8 framebuffer object. The texture's own mip
// pyramid is uploaded level by level, so both sides filter the same texels; sampling is
// bilinear, trilinear or anisotropic (GL_TEXTURE_MAX_ANISOTROPY). Not a hardware block.
//
// The driver is chosen with GALLIUM_DRIVER and LIBGL_ALWAYS_SOFTWARE, set only around EGL's
// initialisation; Mesa's surfaceless display is one per process, so a peer of the other driver
// re-initialises it (a few ms for llvmpipe, ~60 ms for softpipe).
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "blocks/geometry/camera.h"
#include "blocks/texture/memory/texture_memory.h"
#include "pipeline/scene/scene.h"

namespace texsim {

enum class MesaDriver { Softpipe, Llvmpipe };
// Bilinear: GL_LINEAR_MIPMAP_NEAREST (texsim's FilterMode::Bilinear); Trilinear:
// GL_LINEAR_MIPMAP_LINEAR; Anisotropic: that with GL_TEXTURE_MAX_ANISOTROPY = max_aniso.
enum class MesaFilter { Bilinear, Trilinear, Anisotropic };
const char* to_string(MesaDriver d);  // "softpipe", "llvmpipe" (GALLIUM_DRIVER's values)

// One textured primitive: a parallelogram (4 corners in order) or a triangle (3), world space,
// with the texture coordinates of each corner (normalised, as texsim's u and v).
struct MesaPrimitive {
  const Texture* texture = nullptr;
  AddressMode address = AddressMode::Wrap;  // both axes
  std::vector<glm::dvec3> corners;
  std::vector<glm::dvec2> uvs;
};

struct MesaView {
  Camera camera;  // its width × height is the image
  glm::dvec3 background{0, 0, 0};
  std::vector<MesaPrimitive> primitives;  // depth-tested, so order does not matter
  MesaFilter filter = MesaFilter::Anisotropic;
  float max_aniso = 16;
};

// An RGBA8 image in texsim's pixel order (row 0 at the top).
struct MesaImage {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;
  Rgba at(int x, int y) const;
};

// The scene's primitives as Mesa draws them: texture of each primitive's material from
// `textures` (indexed as scene.textures), address mode of each material from `address`
// (indexed as scene.materials); back faces of culled primitives are left out, as texsim does.
MesaView mesa_view(const Scene& scene, const TextureSet& textures,
                   const std::vector<AddressMode>& address);

class MesaPeer {
 public:
  // Starts EGL with `driver` (or finds why it cannot): never throws.
  explicit MesaPeer(MesaDriver driver);
  bool available() const { return why_not_.empty(); }
  // "Mesa not available: <why>" (empty when available).
  const std::string& why_not() const { return why_not_; }
  // GL_RENDERER and GL_VERSION of the driver, e.g. "softpipe, 3.3 (Core Profile) Mesa 22.3.6".
  const std::string& renderer() const { return renderer_; }
  MesaDriver driver() const { return driver_; }
  // Draws the view. Throws InputError if Mesa is not available or OpenGL reports an error.
  MesaImage render(const MesaView& view) const;
  // Seconds `draws` draws of the view take once its textures are uploaded and one draw has
  // warmed the driver up (glFinish on both sides; depth test off so every draw shades every
  // pixel): the filtering rate, without set-up or read-back. Throws as render().
  double time_draws(const MesaView& view, int draws) const;
  // Mesa's own decoding of a compressed image: `data` uploaded with glCompressedTexImage2D as
  // `gl_format` (an OpenGL enum, e.g. GL_COMPRESSED_RGB8_ETC2), level 0 of width x height,
  // read back with glGetTexImage as (`read_format`, `read_type`), `texel_bytes` per texel,
  // row 0 the first row of blocks. Throws as render().
  std::vector<uint8_t> decode_compressed(uint32_t gl_format, int width, int height,
                                         std::span<const uint8_t> data, uint32_t read_format,
                                         uint32_t read_type, size_t texel_bytes) const;
  // Mesa's own codec of a block-compressed format (an OpenGL internal format, e.g.
  // GL_COMPRESSED_RGBA_BPTC_UNORM = 0x8E8C), an independent decoder for the tests of
  // blocks/texture/decode/. decode_blocks uploads `blocks` of a width × height texture (both
  // multiples of 4) with glCompressedTexImage2D and reads the texels back as RGBA8
  // (glGetTexImage; gl_type GL_UNSIGNED_BYTE = 0x1401, or GL_BYTE = 0x1400 for signed formats,
  // the bytes then two's complement), rows in upload order; encode_blocks has Mesa compress an
  // RGBA8 image (glTexImage2D into the format) and returns its blocks
  // (glGetCompressedTexImage). Throw as render().
  MesaImage decode_blocks(uint32_t gl_format, int width, int height,
                          const std::vector<uint8_t>& blocks, uint32_t gl_type = 0x1401) const;
  std::vector<uint8_t> encode_blocks(uint32_t gl_format, const MesaImage& image) const;

 private:
  MesaDriver driver_;
  std::string why_not_, renderer_;
};

}  // namespace texsim
