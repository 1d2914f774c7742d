#pragma once
// Small inputs the filter tests share: random textures and a fragment with its
// derivatives given in texels per pixel.
#include <cstdint>
#include <random>
#include <vector>

#include "blocks/base/fragment.h"
#include "blocks/texture/memory/texture_memory.h"

namespace texsim {

// w x h texels of uniform noise in [0.1, 0.9] (opaque), with its mip pyramid.
inline Texture noise_texture(int w, int h, uint32_t seed) {
  std::vector<float> px(static_cast<size_t>(w) * static_cast<size_t>(h) * 4);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uni(0.1f, 0.9f);
  for (size_t i = 0; i < px.size(); ++i) px[i] = (i % 4 == 3) ? 1.0f : uni(rng);
  return Texture::from_rgba("n", w, h, px, TexelFormat::Rgba8, true);
}

// w x h texels of uniform noise in [0, 1] in every channel (alpha too), stored as `fmt`, with
// its mip pyramid: the address and conformance tests' random texture.
inline Texture random_texture(int w, int h, uint64_t seed, TexelFormat fmt = TexelFormat::Rgba32f) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> c(0.0f, 1.0f);
  std::vector<float> px(static_cast<size_t>(w) * static_cast<size_t>(h) * 4);
  for (float& p : px) p = c(rng);
  return Texture::from_rgba("rnd", w, h, px, fmt, true);
}

// A fragment at normalised (u, v) whose derivatives (ux, vx, uy, vy) are in texels of a
// size x size texture.
inline Fragment texel_fragment(double u, double v, double ux, double vx, double uy, double vy,
                               int size) {
  Fragment f;
  f.u = u;
  f.v = v;
  f.dudx = ux / size;
  f.dvdx = vx / size;
  f.dudy = uy / size;
  f.dvdy = vy / size;
  return f;
}

}  // namespace texsim
