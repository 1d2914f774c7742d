#pragma once
// The ARM reference codec (astcenc 4.2, /usr/bin/astcenc) as the independent decoder of the
// ASTC tests: .astc files (16-byte header: magic 0x5CA1AB13, block dims, 24-bit sizes) written
// and read here, `astcenc -dl` decoding them to an FP16 OpenEXR file, and the comparison of
// every texel of every block with AstcDecoder (docs/derivations/astc.md §9 states the rules).
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <span>
#include <string>
#include <vector>

#include "blocks/base/shell_quote.h"
#include "blocks/texture/decode/astc_decoder.h"

namespace texsim::astc_reference {

inline constexpr const char* kAstcenc = "/usr/bin/astcenc";

struct AstcFile {
  int block_width = 0, block_height = 0;
  int width = 0, height = 0;  // texels
  std::vector<uint8_t> blocks;
  int blocks_x() const { return (width + block_width - 1) / block_width; }
  int blocks_y() const { return (height + block_height - 1) / block_height; }
  std::span<const uint8_t, 16> block(int bx, int by) const {
    const auto i = static_cast<size_t>(by * blocks_x() + bx) * 16;
    return std::span<const uint8_t, 16>(blocks.data() + i, 16);
  }
};

// Runs astcenc with the arguments (each shell-quoted, -silent added); true on exit status 0.
inline bool run_astcenc(const std::vector<std::string>& args) {
  std::string cmd = kAstcenc;
  for (const auto& a : args) {
    cmd += ' ';
    cmd += shell_quote(a);
  }
  cmd += " -silent >/dev/null 2>&1";
  return std::system(cmd.c_str()) == 0;  // NOLINT(cert-env33-c): the test's own command line
}

inline bool read_astc(const std::string& path, AstcFile* f) {
  std::ifstream in(path, std::ios::binary);
  const std::vector<uint8_t> b((std::istreambuf_iterator<char>(in)),
                               std::istreambuf_iterator<char>());
  if (b.size() < 16 || b[0] != 0x13 || b[1] != 0xAB || b[2] != 0xA1 || b[3] != 0x5C) return false;
  const auto u24 = [&](size_t i) { return b[i] | (b[i + 1] << 8) | (b[i + 2] << 16); };
  f->block_width = b[4];
  f->block_height = b[5];
  f->width = u24(7);
  f->height = u24(10);
  f->blocks.assign(b.begin() + 16, b.end());
  return f->blocks.size() == static_cast<size_t>(f->blocks_x() * f->blocks_y()) * 16;
}

inline bool write_astc(const std::string& path, const AstcFile& f) {
  std::vector<uint8_t> b = {0x13,
                            0xAB,
                            0xA1,
                            0x5C,
                            static_cast<uint8_t>(f.block_width),
                            static_cast<uint8_t>(f.block_height),
                            1};
  for (const int v : {f.width, f.height, 1}) {
    for (int k = 0; k < 3; ++k) b.push_back(static_cast<uint8_t>(v >> (8 * k)));
  }
  b.insert(b.end(), f.blocks.begin(), f.blocks.end());
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
  return static_cast<bool>(out);
}

struct Image {
  int width = 0, height = 0;
  std::vector<float> rgba;  // top row first
  const float* at(int x, int y) const {
    return rgba.data() + (static_cast<size_t>(y) * static_cast<size_t>(width) + x) * 4;
  }
};

inline bool read_exr(const std::string& path, Image* img) {
  auto in = OIIO::ImageInput::open(path);
  if (!in || in->spec().nchannels != 4) return false;
  img->width = in->spec().width;
  img->height = in->spec().height;
  img->rgba.resize(static_cast<size_t>(img->width) * static_cast<size_t>(img->height) * 4);
  return in->read_image(0, 0, 0, 4, OIIO::TypeDesc::FLOAT, img->rgba.data());
}

// What a comparison saw: the rows of the validation table in docs/derivations/astc.md.
struct Tally {
  uint64_t blocks = 0, texels = 0, mismatches = 0;
  uint64_t void_extent = 0, error_blocks = 0, hdr_partition_texels = 0;
  uint64_t multi_partition = 0, dual_plane = 0;
};

// One texel against astcenc's FP16 value. astcenc 4.2 differs from the spec in two documented
// places, where the spec's magenta is required of AstcDecoder and astcenc's own value of it:
//  - an illegal block: astcenc returns NaN in all four channels;
//  - a texel of a partition with an HDR endpoint mode: astcenc interpolates the endpoints
//    (0xFF00, 0, 0xFF00, 0xFF00), which its FP16 conversion gives as 0.99609375.
inline bool texel_matches(const AstcBlockInfo& info, int t, const glm::vec4& ours, const float* ref,
                          Tally* tally) {
  const glm::vec4 magenta(1, 0, 1, 1);
  const bool block_error =
      info.error != AstcError::None && info.error != AstcError::HdrEndpointMode;
  if (block_error) {
    return ours == magenta && std::isnan(ref[0]) && std::isnan(ref[1]) && std::isnan(ref[2]) &&
           std::isnan(ref[3]);
  }
  if ((info.hdr_partitions >> info.partition[static_cast<size_t>(t)]) & 1U) {
    ++tally->hdr_partition_texels;
    const float f = 65280.0F / 65536.0F;
    return ours == magenta && ref[0] == f && ref[1] == 0.0F && ref[2] == f && ref[3] == f;
  }
  for (int c = 0; c < 4; ++c) {
    if (std::bit_cast<uint32_t>(ours[c]) != std::bit_cast<uint32_t>(ref[c])) return false;
  }
  return true;
}

// Compares every texel of every block of `f` (inside the image) with astcenc's decoding `ref`,
// decoding each block in the three output modes: Float16 must equal astcenc bit for bit;
// Unorm16 and Unorm8 must be C / 65535 and (C >> 8) / 255 of the same interpolation results.
inline void compare_blocks(const AstcFile& f, const Image& ref, Tally* tally) {
  ASSERT_EQ(ref.width, f.width);
  ASSERT_EQ(ref.height, f.height);
  AstcDecoder::Config cfg;
  cfg.block_width = f.block_width;
  cfg.block_height = f.block_height;
  cfg.mode = AstcDecoder::Mode::Float16;
  const AstcDecoder f16(cfg);
  cfg.mode = AstcDecoder::Mode::Unorm16;
  const AstcDecoder u16(cfg);
  cfg.mode = AstcDecoder::Mode::Unorm8;
  const AstcDecoder u8(cfg);
  int reported = 0;
  for (int by = 0; by < f.blocks_y(); ++by) {
    for (int bx = 0; bx < f.blocks_x(); ++bx) {
      AstcBlockInfo info;
      const DecodedBlock a = f16.decode(f.block(bx, by), &info);
      const DecodedBlock b = u16.decode(f.block(bx, by));
      const DecodedBlock c = u8.decode(f.block(bx, by));
      ++tally->blocks;
      tally->void_extent += info.void_extent && info.error == AstcError::None;
      tally->error_blocks +=
          info.error != AstcError::None && info.error != AstcError::HdrEndpointMode;
      tally->multi_partition += info.error == AstcError::None && info.partitions > 1;
      tally->dual_plane += info.error == AstcError::None && info.mode.dual_plane;
      const bool plain = info.error == AstcError::None;
      for (int y = 0; y < f.block_height; ++y) {
        for (int x = 0; x < f.block_width; ++x) {
          const int px = bx * f.block_width + x, py = by * f.block_height + y;
          if (px >= f.width || py >= f.height) continue;
          const int t = y * f.block_width + x;
          ++tally->texels;
          bool ok = texel_matches(info, t, a.at(x, y), ref.at(px, py), tally);
          for (int ch = 0; ch < 4 && plain; ++ch) {
            const int cu = info.unorm16[static_cast<size_t>(t)][static_cast<size_t>(ch)];
            ok = ok && b.at(x, y)[ch] == static_cast<float>(cu) / 65535.0F &&
                 c.at(x, y)[ch] == static_cast<float>(cu >> 8) / 255.0F;
          }
          if (!ok) {
            ++tally->mismatches;
            if (reported++ < 5) {
              const float* r = ref.at(px, py);
              ADD_FAILURE() << "block (" << bx << ", " << by << ") texel (" << x << ", " << y
                            << "): texsim " << a.at(x, y)[0] << " " << a.at(x, y)[1] << " "
                            << a.at(x, y)[2] << " " << a.at(x, y)[3] << ", astcenc " << r[0] << " "
                            << r[1] << " " << r[2] << " " << r[3] << ", error "
                            << static_cast<int>(info.error);
            }
          }
        }
      }
    }
  }
}

inline std::string tally_row(const std::string& what, const Tally& t) {
  char row[256];
  std::snprintf(row, sizeof row,
                "%s: blocks %llu, texels %llu, mismatches %llu, void-extent %llu, error blocks "
                "%llu, HDR-partition texels %llu, multi-partition %llu, dual-plane %llu",
                what.c_str(), static_cast<unsigned long long>(t.blocks),
                static_cast<unsigned long long>(t.texels),
                static_cast<unsigned long long>(t.mismatches),
                static_cast<unsigned long long>(t.void_extent),
                static_cast<unsigned long long>(t.error_blocks),
                static_cast<unsigned long long>(t.hdr_partition_texels),
                static_cast<unsigned long long>(t.multi_partition),
                static_cast<unsigned long long>(t.dual_plane));
  return row;
}

}  // namespace texsim::astc_reference
