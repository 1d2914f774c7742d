#include "pipeline/scene/texture_loader.h"

#include <algorithm>
#include <filesystem>
#include <string_view>
#include <vector>

#include "blocks/base/input_error.h"
#include "blocks/base/input_file.h"
#include "pipeline/image_io/oiio_plugin.h"
#include "pipeline/scene/compressed_loader.h"
#include "pipeline/scene/layered_source.h"
#include "pipeline/scene/npz_height_field.h"
#include "pipeline/scene/procedural_texture.h"

namespace texsim {

namespace {
constexpr int kMaxSize = 65536;
// Largest level-0 texture, in texels (8192 × 8192): its decoding buffers (float, up to 64
// channels read as 4) then stay near 2 GiB.
constexpr uint64_t kMaxTexels = uint64_t{1} << 26;
// Largest texture file read.
constexpr uintmax_t kMaxFileBytes = uintmax_t{1} << 31;

std::vector<float> to_rgba(const std::vector<float>& src, int w, int h, int nch) {
  std::vector<float> out(static_cast<size_t>(w) * h * 4);
  for (size_t i = 0; i < static_cast<size_t>(w) * h; ++i) {
    const float* s = &src[i * static_cast<size_t>(nch)];
    float* d = &out[i * 4];
    if (nch == 1 || nch == 2) {
      d[0] = d[1] = d[2] = s[0];
      d[3] = nch == 2 ? s[1] : 1.0f;
    } else {
      d[0] = s[0];
      d[1] = s[1];
      d[2] = s[2];
      d[3] = nch >= 4 ? s[3] : 1.0f;
    }
  }
  return out;
}
// A layered source's slices, each loaded as a 2-D texture and its level 0 taken, as one
// layered texture (Texture::from_slices, every slice given its own mip chain). The slices must
// agree in size; a cube's faces are square, a 1-D array's layers one texel high. RGBA8 when
// every slice is, else RGBA32F.
Texture load_layered_texture(const std::string& source, const std::string& base_dir,
                             TexelFormatChoice format) {
  const LayeredSource ls = parse_layered_source(source, source);
  std::vector<std::vector<float>> slices;
  slices.reserve(ls.slices.size());
  int w = 0, h = 0;
  bool eight_bit = true;
  for (size_t i = 0; i < ls.slices.size(); ++i) {
    const Texture t = load_texture(ls.slices[i], base_dir, format);
    const std::string which = "slice " + std::to_string(i) + " ('" + ls.slices[i] + "')";
    if (t.layered()) throw InputError(source, which + " is itself layered");
    if (i == 0) {
      w = t.width(0);
      h = t.height(0);
    } else if (t.width(0) != w || t.height(0) != h) {
      throw InputError(source, which + " is " + std::to_string(t.width(0)) + "x" +
                                   std::to_string(t.height(0)) + ", slice 0 is " +
                                   std::to_string(w) + "x" + std::to_string(h));
    }
    if (static_cast<uint64_t>(w) * static_cast<uint64_t>(h) * (i + 1) > kMaxTexels) {
      throw InputError(source, "more than the 8192x8192 texels a texture may have");
    }
    eight_bit = eight_bit && t.format() == TexelFormat::Rgba8;
    std::vector<float> px(static_cast<size_t>(w) * static_cast<size_t>(h) * 4);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const Rgba c = t.texel(0, x, y);
        float* d =
            &px[(static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)) * 4];
        for (int k = 0; k < 4; ++k) d[k] = c[k];
      }
    slices.push_back(std::move(px));
  }
  const bool cube = ls.type == SceneTextureType::Cube || ls.type == SceneTextureType::CubeArray;
  if (cube && w != h) {
    throw InputError(
        source, "cube faces must be square, not " + std::to_string(w) + "x" + std::to_string(h));
  }
  if (ls.type == SceneTextureType::Array1D && h != 1) {
    throw InputError(source, "a 1-D array's layers are one texel high, not " + std::to_string(h));
  }
  const TexelFormat f = eight_bit ? TexelFormat::Rgba8 : TexelFormat::Rgba32f;
  if (ls.type == SceneTextureType::Volume3D)
    return Texture::from_volume(source, w, h, slices, f, true);
  return Texture::from_slices(source, cube ? TextureType::Cube : TextureType::Array, w, h, slices,
                              f, true);
}

}  // namespace

std::string resolve_texture_path(const std::string& source, const std::string& base_dir) {
  std::filesystem::path p(source);
  if (p.is_relative() && !base_dir.empty()) p = std::filesystem::path(base_dir) / p;
  return p.lexically_normal().string();
}

Texture load_texture(const std::string& source, const std::string& base_dir,
                     TexelFormatChoice format) {
  if (is_procedural_source(source)) return make_procedural_texture(source, source);
  if (is_layered_source(source)) return load_layered_texture(source, base_dir, format);
  const std::string path = resolve_texture_path(source, base_dir);
  if (is_npz_source(path)) return npz_height_texture(path);         // a DEM height field
  if (is_compressed_file(path)) return load_compressed_file(path);  // DDS, .astc or KTX blocks
  // Only regular files of at most 2 GiB: a device or FIFO (e.g. /dev/zero) would never end.
  check_input_file(path, "texture file", kMaxFileBytes);
  // Texture files of every format are read by OpenImageIO, loaded here on first use.
  std::string error;
  const auto in = oiio_plugin(path).open(path, &error);
  if (!in) throw InputError(path, "cannot read texture: " + error);
  std::vector<int> ws, hs;
  std::vector<std::vector<float>> levels;
  bool eight_bit = true;
  for (int m = 0; in->seek_level(m); ++m) {
    const oiio::LevelSpec spec = in->spec();
    const int w = spec.width, h = spec.height, nch = spec.channels;
    if (w <= 0 || h <= 0 || w > kMaxSize || h > kMaxSize || nch <= 0 || nch > 64 ||
        spec.depth > 1) {
      throw InputError(path, "unsupported texture size " + std::to_string(w) + "x" +
                                 std::to_string(h) + "x" + std::to_string(nch) +
                                 " (2-D, at most 65536 per side)");
    }
    if (m == 0 && static_cast<uint64_t>(w) * static_cast<uint64_t>(h) > kMaxTexels) {
      throw InputError(path, "texture " + std::to_string(w) + "x" + std::to_string(h) +
                                 " has more than the 8192x8192 texels a texture may have");
    }
    eight_bit = eight_bit && spec.uint8;
    std::vector<float> px(static_cast<size_t>(w) * h * nch);
    if (!in->read_float(nch, px.data())) {
      throw InputError(path, "cannot decode MIP level " + std::to_string(m) + ": " + in->error());
    }
    ws.push_back(w);
    hs.push_back(h);
    levels.push_back(to_rgba(px, w, h, nch));
  }
  if (levels.empty()) throw InputError(path, "texture has no image");
  const TexelFormat fmt = format == TexelFormatChoice::Rgba8     ? TexelFormat::Rgba8
                          : format == TexelFormatChoice::Rgba32f ? TexelFormat::Rgba32f
                          : eight_bit                            ? TexelFormat::Rgba8
                                                                 : TexelFormat::Rgba32f;
  const std::string name = std::filesystem::path(path).filename().string();
  if (levels.size() > 1) return Texture::from_levels(name, ws, hs, levels, fmt);
  return Texture::from_rgba(name, ws[0], hs[0], levels[0], fmt, true);
}

Texture store_texture(Texture loaded, const SceneTexture& t) {
  if (t.format) return loaded.converted(*t.format);
  if (!t.compress) return loaded;
  try {
    return compress_texture(loaded, *t.compress);
  } catch (const InputError& e) {
    if (t.compress->where.empty()) throw;
    throw InputError(t.compress->where, e.what());
  }
}

Texture load_scene_texture(const Scene& scene, size_t index, TexelFormatChoice format) {
  const SceneTexture& t = scene.textures.at(index);
  try {
    return store_texture(load_texture(t.source, scene.base_dir, format), t);
  } catch (const InputError& e) {
    throw InputError(t.where, e.what());
  }
}

std::string texture_storage_spec(const SceneTexture& t) {
  if (t.format) return "format=" + std::string(to_string(*t.format));
  if (!t.compress) return "";
  const SceneTexture::Compress& c = *t.compress;
  return "compress=" + std::string(to_string(c.format)) + "," + c.encoder +
         (c.quality.empty() ? "" : "," + c.quality);
}

void set_texture_storage(SceneTexture& t, const std::string& spec, const std::string& where) {
  t.format.reset();
  t.compress.reset();
  if (spec.empty()) return;
  const std::string_view s = spec;
  if (s.starts_with("format=")) {
    const std::string name(s.substr(7));
    t.format = storage_format_from_name(name);
    if (!t.format) {
      throw InputError(where, "storage '" + spec + "': unknown texel format '" + name +
                                  "' (one of " + storage_format_names() + ")");
    }
    return;
  }
  if (!s.starts_with("compress=")) {
    throw InputError(where, "storage '" + spec +
                                "' is neither \"format=NAME\" nor "
                                "\"compress=FORMAT,ENCODER[,QUALITY]\"");
  }
  std::vector<std::string> parts;  // FORMAT, ENCODER, QUALITY
  for (size_t at = 9;;) {
    const size_t comma = s.find(',', at);
    parts.emplace_back(s.substr(at, comma == std::string_view::npos ? s.npos : comma - at));
    if (comma == std::string_view::npos) break;
    at = comma + 1;
  }
  const std::string bad = "storage '" + spec + "': ";
  if (parts.size() > 3) throw InputError(where, bad + "more than FORMAT,ENCODER,QUALITY");
  SceneTexture::Compress c;
  const auto fmt = compressed_format_from_name(parts[0]);
  if (!fmt) {
    throw InputError(where, bad + "unknown compressed format '" + parts[0] + "' (one of " +
                                compressed_format_names() + ")");
  }
  c.format = *fmt;
  c.encoder = parts.size() > 1 ? parts[1] : default_encoder(*fmt);
  if (!encoder_makes(c.encoder, *fmt)) {
    throw InputError(where, bad + (c.encoder.empty() ? "no encoder makes '" + parts[0] + "'"
                                                     : "encoder '" + c.encoder + "' cannot make '" +
                                                           parts[0] + "'"));
  }
  c.quality = parts.size() > 2 ? parts[2] : "";
  const std::vector<std::string> levels = encoder_qualities(c.encoder);
  if (!c.quality.empty() && std::find(levels.begin(), levels.end(), c.quality) == levels.end()) {
    std::string list;
    for (const auto& l : levels) list += (list.empty() ? "" : ", ") + l;
    throw InputError(
        where, bad + "unknown " + c.encoder + " quality '" + c.quality + "' (one of " + list + ")");
  }
  t.compress = c;
}

}  // namespace texsim
