#include "pipeline/scene/compressed_loader.h"

#include <algorithm>
#include <filesystem>
#include <memory>

#include "blocks/base/input_error.h"
#include "blocks/texture/decode/compressed_texture.h"
#include "pipeline/image_io/astc_file.h"
#include "pipeline/image_io/astcenc_encoder.h"
#include "pipeline/image_io/bc7_encoder.h"
#include "pipeline/image_io/dds_file.h"
#include "pipeline/image_io/encoded_level_cache.h"
#include "pipeline/image_io/etc_encoder.h"
#include "pipeline/image_io/ktx_file.h"
#include "pipeline/image_io/nvtt_encoder.h"
#include "pipeline/image_io/squish_encoder.h"

namespace texsim {

namespace {

// A level of `t` as 8-bit RGBA (the encoders' input): each channel clamped and rounded.
Rgba8Image rgba8_level(const Texture& t, int level) {
  Rgba8Image img;
  img.width = t.width(level);
  img.height = t.height(level);
  img.rgba.resize(static_cast<size_t>(img.width) * static_cast<size_t>(img.height) * 4);
  size_t i = 0;
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const Rgba c = t.texel(level, x, y);
      for (int k = 0; k < 4; ++k) {
        // Nearest, halves up (the 8-bit store's rule); NaN gives 0.
        const float v = c[k] == c[k] ? std::clamp(c[k], 0.0f, 1.0f) * 255.0f : 0.0f;
        const auto whole = static_cast<int>(v);
        img.rgba[i++] =
            static_cast<uint8_t>(whole + (v - static_cast<float>(whole) >= 0.5f ? 1 : 0));
      }
    }
  }
  return img;
}

FileBlockFormat file_format(CompressedFormat f) {
  switch (f) {
    case CompressedFormat::Bc1Rgb:
    case CompressedFormat::Bc1Rgba:
      return FileBlockFormat::Bc1Unorm;
    case CompressedFormat::Bc2:
      return FileBlockFormat::Bc2Unorm;
    case CompressedFormat::Bc3:
      return FileBlockFormat::Bc3Unorm;
    case CompressedFormat::Bc4:
      return FileBlockFormat::Bc4Unorm;
    case CompressedFormat::Bc5:
      return FileBlockFormat::Bc5Unorm;
    case CompressedFormat::Bc7:
      return FileBlockFormat::Bc7Unorm;
    case CompressedFormat::Etc2Rgb8:
      return FileBlockFormat::Etc2Rgb8;
    case CompressedFormat::Etc2Rgb8A1:
      return FileBlockFormat::Etc2Rgb8A1;
    case CompressedFormat::Etc2Rgba8:
      return FileBlockFormat::Etc2Rgba8;
    case CompressedFormat::EacR11:
      return FileBlockFormat::EacR11Unorm;
    case CompressedFormat::EacRg11:
      return FileBlockFormat::EacRg11Unorm;
    default:
      return FileBlockFormat::Astc;
  }
}

EncodedLevel encode_level(const Rgba8Image& img, const SceneTexture::Compress& c) {
  const CompressedFormatInfo& info = format_info(c.format);
  if (c.encoder == "squish") {
    const SquishFit fit = c.quality == "range"               ? SquishFit::Range
                          : c.quality == "iterative-cluster" ? SquishFit::IterativeCluster
                                                             : SquishFit::Cluster;
    return squish_encode(img, file_format(c.format), fit);
  }
  if (c.encoder == "nvtt") {
    const NvttQuality q = c.quality == "fastest"      ? NvttQuality::Fastest
                          : c.quality == "production" ? NvttQuality::Production
                                                      : NvttQuality::Normal;
    return nvtt_encode(img, file_format(c.format), q);
  }
  if (c.encoder == "texsim" && c.format == CompressedFormat::Bc7)
    return bc7_encode(img, FileBlockFormat::Bc7Unorm,
                      c.quality == "fast" ? Bc7Quality::Fast : Bc7Quality::Normal);
  if (c.encoder == "texsim") {
    const EtcEffort effort = c.quality == "fast" ? EtcEffort::Fast : EtcEffort::Normal;
    return etc_encode(img, file_format(c.format), effort);
  }
  AstcencOptions o;
  o.block_w = info.block_w;
  o.block_h = info.block_h;
  o.preset = c.quality == "fastest"    ? AstcPreset::Fastest
             : c.quality == "fast"     ? AstcPreset::Fast
             : c.quality == "thorough" ? AstcPreset::Thorough
                                       : AstcPreset::Medium;
  return astcenc_encode(img, o);
}

// The texsim format of a file's blocks, and whether its colours are sRGB.
CompressedFormat texsim_format(const CompressedImage& img, bool& srgb, const std::string& path) {
  using F = FileBlockFormat;
  srgb = img.format == F::Bc1Srgb || img.format == F::Bc1RgbSrgb || img.format == F::Bc2Srgb ||
         img.format == F::Bc3Srgb || img.format == F::Bc7Srgb || img.format == F::Etc2Rgb8Srgb ||
         img.format == F::Etc2Rgb8A1Srgb || img.format == F::Etc2Rgba8Srgb ||
         img.format == F::AstcSrgb;
  switch (img.format) {
    case F::Bc1Unorm:
    case F::Bc1Srgb:
      return CompressedFormat::Bc1Rgba;  // DDS BC1 has the 1-bit alpha of its 3-colour mode
    case F::Bc1RgbUnorm:
    case F::Bc1RgbSrgb:
      return CompressedFormat::Bc1Rgb;
    case F::Bc2Unorm:
    case F::Bc2Srgb:
      return CompressedFormat::Bc2;
    case F::Bc3Unorm:
    case F::Bc3Srgb:
      return CompressedFormat::Bc3;
    case F::Bc4Unorm:
      return CompressedFormat::Bc4;
    case F::Bc4Snorm:
      return CompressedFormat::Bc4Snorm;
    case F::Bc5Unorm:
      return CompressedFormat::Bc5;
    case F::Bc5Snorm:
      return CompressedFormat::Bc5Snorm;
    case F::Bc7Unorm:
    case F::Bc7Srgb:
      return CompressedFormat::Bc7;
    case F::Etc2Rgb8:
    case F::Etc2Rgb8Srgb:
      return CompressedFormat::Etc2Rgb8;
    case F::Etc2Rgb8A1:
    case F::Etc2Rgb8A1Srgb:
      return CompressedFormat::Etc2Rgb8A1;
    case F::Etc2Rgba8:
    case F::Etc2Rgba8Srgb:
      return CompressedFormat::Etc2Rgba8;
    case F::EacR11Unorm:
      return CompressedFormat::EacR11;
    case F::EacR11Snorm:
      return CompressedFormat::EacR11Snorm;
    case F::EacRg11Unorm:
      return CompressedFormat::EacRg11;
    case F::EacRg11Snorm:
      return CompressedFormat::EacRg11Snorm;
    case F::Astc:
    case F::AstcSrgb:
      break;
  }
  const std::string name =
      "astc_" + std::to_string(img.block_w) + "x" + std::to_string(img.block_h);
  const auto f = compressed_format_from_name(name);
  if (!f) throw InputError(path, "unsupported ASTC footprint " + name);
  return *f;
}

}  // namespace

namespace {
bool made_by_squish(CompressedFormat f) {
  return f == CompressedFormat::Bc1Rgb || f == CompressedFormat::Bc1Rgba ||
         f == CompressedFormat::Bc2 || f == CompressedFormat::Bc3;
}
bool made_by_nvtt_only(CompressedFormat f) {
  return f == CompressedFormat::Bc4 || f == CompressedFormat::Bc5;
}
// texsim's own encoders: BC7, ETC2 / EAC (UNORM; the SNORM EAC formats come only from files,
// as BC4 / BC5 SNORM do: an 8-bit texture has no signed view).
bool made_by_texsim(CompressedFormat f) {
  return f == CompressedFormat::Bc7 || f == CompressedFormat::Etc2Rgb8 ||
         f == CompressedFormat::Etc2Rgb8A1 || f == CompressedFormat::Etc2Rgba8 ||
         f == CompressedFormat::EacR11 || f == CompressedFormat::EacRg11;
}
}  // namespace

std::string default_encoder(CompressedFormat f) {
  if (made_by_squish(f)) return "squish";
  if (made_by_nvtt_only(f)) return "nvtt";
  if (made_by_texsim(f)) return "texsim";
  return format_info(f).family == CodecFamily::Astc ? "astcenc" : "";
}

bool encoder_makes(const std::string& encoder, CompressedFormat f) {
  if (encoder == "squish") return made_by_squish(f);
  if (encoder == "nvtt") return made_by_squish(f) || made_by_nvtt_only(f);
  if (encoder == "astcenc") return format_info(f).family == CodecFamily::Astc;
  if (encoder == "texsim") return made_by_texsim(f);
  return false;
}

std::vector<std::string> encoder_qualities(const std::string& encoder) {
  if (encoder == "squish") return {"range", "cluster", "iterative-cluster"};
  if (encoder == "nvtt") return {"fastest", "normal", "production"};
  if (encoder == "astcenc") return {"fastest", "fast", "medium", "thorough"};
  if (encoder == "texsim") return {"fast", "normal"};
  return {};
}

Texture compress_texture(const Texture& src, const SceneTexture::Compress& c) {
  auto blocks = std::make_shared<Texture::Blocks>();
  blocks->format = c.format;
  std::vector<int> ws, hs;
  for (int l = 0; l < src.levels(); ++l) {
    const Rgba8Image img = rgba8_level(src, l);
    const std::string identity =
        c.encoder + " " + c.quality + " " + std::string(to_string(c.format));
    EncodedLevel e = EncodedLevelCache::process().get(encoded_level_key(identity, img),
                                                      [&] { return encode_level(img, c); });
    if (l == 0) blocks->provenance = e.provenance;
    blocks->levels.push_back(std::move(e.bytes));
    ws.push_back(src.width(l));
    hs.push_back(src.height(l));
  }
  return texture_from_blocks(src.name(), std::move(blocks), ws, hs,
                             std::make_shared<const Texture>(src.reference()));
}

bool is_compressed_file(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return ext == ".dds" || ext == ".astc" || ext == ".ktx";
}

Texture load_compressed_file(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  const CompressedImage img = ext == ".dds"   ? read_dds_file(path)
                              : ext == ".ktx" ? read_ktx_file(path)
                                              : read_astc_file(path);
  bool srgb = false;
  auto blocks = std::make_shared<Texture::Blocks>();
  blocks->format = texsim_format(img, srgb, path);
  blocks->provenance =
      "file " + std::filesystem::path(path).filename().string() + " (" + img.format_label() + ")";
  std::vector<int> ws, hs;
  for (const CompressedLevel& l : img.levels) {
    ws.push_back(static_cast<int>(l.width));
    hs.push_back(static_cast<int>(l.height));
    blocks->levels.push_back(l.bytes);
  }
  const std::string name = std::filesystem::path(path).filename().string();
  Texture t = texture_from_blocks(name, blocks, ws, hs, nullptr);
  if (!srgb) return t;
  // sRGB blocks: the decoded colours taken to linear, before any filtering.
  Texture linear = t.linearised();
  linear.set_blocks(std::move(blocks));
  return linear;
}

}  // namespace texsim
