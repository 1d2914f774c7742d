// Texture cache (LRU set-associative) and DRAM model: directed cases and an independent
// fully-explicit LRU reference on random address streams.
#include <gtest/gtest.h>

#include <algorithm>
#include <list>
#include <map>
#include <random>

#include "blocks/texture/memory/dram_model.h"
#include "blocks/texture/memory/texture_cache.h"
#include "blocks/texture/memory/texture_memory.h"

namespace texsim {
namespace {

TEST(TextureCache, DirectedLru) {
  TextureCache::Config c;
  c.size_bytes = 2 * 64;  // one set, two ways
  c.ways = 2;
  c.line_bytes = 64;
  TextureCache cache(c);
  EXPECT_FALSE(cache.access(0));    // A miss
  EXPECT_TRUE(cache.access(63));    // A hit (same line)
  EXPECT_FALSE(cache.access(64));   // B miss
  EXPECT_TRUE(cache.access(0));     // A hit: B is now LRU
  EXPECT_FALSE(cache.access(128));  // C evicts B
  EXPECT_TRUE(cache.access(0));
  EXPECT_FALSE(cache.access(64));  // B was evicted
  EXPECT_EQ(cache.stats().hits, 3u);
  EXPECT_EQ(cache.stats().misses, 4u);
  EXPECT_EQ(cache.stats().fill_bytes, 4u * 64u);
}

TEST(TextureCache, MatchesExplicitLruModel) {
  TextureCache::Config c;
  c.size_bytes = 4096;
  c.ways = 4;
  c.line_bytes = 32;
  TextureCache cache(c);
  const uint64_t sets = 4096 / (4 * 32);
  std::map<uint64_t, std::list<uint64_t>> ref;  // set -> lines, most recent first
  std::mt19937_64 rng(5);
  uint64_t hits = 0;
  for (int i = 0; i < 200000; ++i) {
    const uint64_t addr = (rng() % 4) ? rng() % 16384 : rng() % (1 << 20);
    const uint64_t line = addr / 32;
    auto& l = ref[line % sets];
    auto it = std::find(l.begin(), l.end(), line);
    const bool hit = it != l.end();
    if (hit) l.erase(it);
    l.push_front(line);
    if (l.size() > 4) l.pop_back();
    hits += hit;
    ASSERT_EQ(cache.access(addr), hit) << "access " << i;
  }
  EXPECT_EQ(cache.stats().hits, hits);
}

TEST(TextureCache, TiledLayoutBeatsLinearOnA2dWalk) {
  // A 2x2 bilinear walk down a column of a 1024-wide texture: tiling keeps rows of a
  // footprint in one line, so it must miss less than a linear layout.
  std::vector<float> rgba(size_t{1024} * 1024 * 4, 0.5f);
  Texture t = Texture::from_rgba("t", 1024, 1024, rgba, TexelFormat::Rgba8, false);
  uint64_t misses[2];
  int k = 0;
  for (TexelLayout layout : {TexelLayout::Linear, TexelLayout::Tiled4x4}) {
    t.place(0, layout);
    TextureCache cache;
    for (int y = 0; y < 1023; ++y) {
      for (int x = 0; x < 16; x += 1) {
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) cache.access(t.address(0, x + dx, y + dy));
      }
    }
    misses[k++] = cache.stats().misses;
  }
  EXPECT_LT(misses[1], misses[0]);
}

// Byte addresses under each layout against independent statements of the layouts (the
// model computes them as level base + row part + column part), on odd level sizes.
TEST(TextureMemory, AddressesMatchLayoutDefinitions) {
  std::vector<float> rgba(size_t{37} * 23 * 4, 0.25f);
  for (TexelFormat fmt : {TexelFormat::Rgba8, TexelFormat::Rgba32f}) {
    Texture t = Texture::from_rgba("t", 37, 23, rgba, fmt, true);
    for (TexelLayout layout : {TexelLayout::Linear, TexelLayout::Tiled4x4, TexelLayout::Morton}) {
      t.place(4096, layout);
      for (int l = 0; l < t.levels(); ++l) {
        const uint64_t w = static_cast<uint64_t>(t.width(l));
        const uint64_t level_base = t.address(l, 0, 0);
        for (uint64_t y = 0; y < static_cast<uint64_t>(t.height(l)); ++y) {
          for (uint64_t x = 0; x < w; ++x) {
            uint64_t index = 0;
            if (layout == TexelLayout::Linear) index = y * w + x;
            if (layout == TexelLayout::Tiled4x4) {
              index = ((y / 4) * ((w + 3) / 4) + x / 4) * 16 + (y % 4) * 4 + x % 4;
            }
            if (layout == TexelLayout::Morton) {
              for (int b = 0; b < 16; ++b) {
                index |= ((x >> b) & 1) << (2 * b) | ((y >> b) & 1) << (2 * b + 1);
              }
            }
            ASSERT_EQ(t.address(l, static_cast<int>(x), static_cast<int>(y)),
                      level_base + index * static_cast<uint64_t>(t.bytes_per_texel()))
                << to_string(layout) << " level " << l << " (" << x << ", " << y << ")";
          }
        }
      }
    }
  }
}

TEST(TextureCache, RejectsBadGeometry) {
  toml::table t{{"line_bytes", 48}};
  EXPECT_THROW(TextureCache::Config::from_toml(ConfigReader(t, "scene.toml", "cache")),
               std::runtime_error);
  toml::table u{{"size_bytes", 3000}};
  EXPECT_THROW(TextureCache::Config::from_toml(ConfigReader(u, "scene.toml", "cache")),
               std::runtime_error);
}

TEST(DramModel, LatencyAndBandwidth) {
  DramModel::Config c;
  c.latency = 100;
  c.bytes_per_cycle = 16;
  DramModel d(c);
  EXPECT_EQ(d.read(0, 64), 4u + 100u);
  EXPECT_EQ(d.read(0, 64), 8u + 100u);    // queued behind the first transfer
  EXPECT_EQ(d.read(50, 64), 54u + 100u);  // channel idle again
  EXPECT_EQ(d.stats().bytes, 192u);
  EXPECT_EQ(d.stats().requests, 3u);
}

}  // namespace
}  // namespace texsim
