#pragma once
// SplatResolve: the screen-space splat and resolve of object-space texturing
// (docs/derivations/object-space.md §4). A projected sample at continuous screen position
// (x, y) (pixel centres at +0.5) lands between four pixel centres: with x̃ = x − ½, i = ⌊x̃⌋,
// fx = x̃ − i (likewise y), it adds to pixels (i, j), (i+1, j), (i, j+1), (i+1, j+1) its colour
// times the area weights S1 = (1−fx)(1−fy), S3 = fx(1−fy), S4 = (1−fx)fy, S2 = fx·fy and the
// weights themselves. The accumulation buffer holds per pixel Σ S·I (RGBA), Σ S and a depth.
// Depth visibility per sample: a sample nearer than the pixel's depth by more than its
// tolerance starts the pixel again (a nearer surface), one within the tolerance accumulates,
// a farther one is dropped. The resolve divides Σ S·I by Σ S; a pixel the scene covers whose
// Σ S is 0 is a hole: counted and given the background, never a division by zero.
// The buffer's traffic is counted in bytes: an entry is 16 (RGBA float) + 4 (Σ S) + 4 (depth)
// bytes, read and written back per target; the resolve reads every entry once and writes
// 4 bytes (RGBA8) per pixel. The buffer has four banks by pixel parity (x & 1, y & 1): the four
// targets of a sample are always in four different banks, so one sample is accepted per cycle
// per lane. Arithmetic: double accumulation (the traffic is counted for float32 entries).
#include <cstdint>
#include <string>
#include <vector>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/memory/texture_memory.h"

namespace texsim {

class ConfigReader;

struct SplatStats {
  uint64_t samples = 0;        // samples splatted
  uint64_t offscreen = 0;      // targets outside the image (no buffer access)
  uint64_t targets = 0;        // targets written
  uint64_t depth_resets = 0;   // targets restarted by a nearer sample
  uint64_t depth_dropped = 0;  // targets refused: the sample is behind the pixel's surface
  uint64_t bytes_read = 0, bytes_written = 0;
};

struct ResolveStats {
  uint64_t pixels = 0;    // pixels with Σ S > 0
  uint64_t holes = 0;     // covered pixels (per the mask) with Σ S = 0
  uint64_t expected = 0;  // covered pixels per the mask
  uint64_t bytes_read = 0, bytes_written = 0;
};

// The accumulation buffer of one frame.
struct SplatBuffer {
  int width = 0, height = 0;
  std::vector<double> rgba;    // Σ S·I, 4 per pixel
  std::vector<double> weight;  // Σ S
  std::vector<double> depth;   // depth of the surface being accumulated
  SplatBuffer(int w, int h);
  size_t index(int x, int y) const {
    return static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
  }
};

class SplatResolve {
 public:
  static constexpr uint64_t kEntryBytes = 16 + 4 + 4;
  static constexpr uint64_t kOutputBytes = 4;
  struct Config {
    int lanes = 1;  // samples accepted per cycle
    static Config from_toml(const ConfigReader& r);
  };
  SplatResolve() = default;
  explicit SplatResolve(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // The four area weights of a sample and the pixel of S1: S[0] = S1 (i, j), S[1] = S3
  // (i+1, j), S[2] = S4 (i, j+1), S[3] = S2 (i+1, j+1). They sum to 1 (up to rounding).
  static void weights(double x, double y, int& i, int& j, double s[4]);
  // Splats one sample of colour c at depth z (tolerance tol >= 0) into the buffer.
  void splat(SplatBuffer& b, double x, double y, double z, double tol, const Rgba& c,
             SplatStats& st, OpCounts& ops) const;
  // Normalises the buffer into `out` (RGBA per pixel); `covered` (one byte per pixel, may be
  // empty) marks the pixels the scene covers, where a zero weight is a hole; `background`
  // fills pixels without weight.
  ResolveStats resolve(const SplatBuffer& b, const std::vector<uint8_t>& covered,
                       const Rgba& background, std::vector<Rgba>& out, OpCounts& ops) const;

  OpCounts ops_per_item() const;  // item: one sample (weights, four depth tests and updates)
  OpCounts pixel_ops() const;     // resolve, per pixel with weight: 1 rcp 4 mul 1 cmp
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "raster.splat_resolve"; }
  std::string arithmetic() const { return "double (buffer entries counted as float32)"; }

 private:
  Config cfg_{};
};

}  // namespace texsim
