#pragma once
// Ground truth of the anisotropic filter study: the level-0 texture, reconstructed bilinearly in
// double, integrated over each pixel's footprint by dense supersampling in screen space, every
// sample mapped through the exact projective map and weighted by the Gaussian pixel model
// (docs/derivations/anisotropic-filters.md §0). Not a hardware block: a testbench reference.
#include <cstdint>
#include <glm/vec4.hpp>

#include "blocks/base/fragment.h"
#include "blocks/texture/memory/texture_memory.h"
#include "pipeline/geometry/plane_projection.h"

namespace texsim {

// The pixel: a Gaussian of standard deviation sigma_px pixels, truncated at radius_px pixels.
// The defaults match EWA's ellipse Q < 1 (R = 1 pixel) with weights exp(−2Q) (σ = R/2).
struct PixelModel {
  double sigma_px = 0.5;
  double radius_px = 1.0;
  double weight(double r2) const;  // exp(−r²/(2σ²)) for r² ≤ R², else 0
};

struct FootprintReferenceConfig {
  PixelModel pixel;
  AddressMode address_u = AddressMode::Wrap;
  AddressMode address_v = AddressMode::Wrap;
  // Samples per axis: samples_per_texel × the footprint's extent in level-0 texels along that
  // screen axis, clamped to [min_samples, max_samples]; at most max_total per pixel (both
  // axes scaled down together beyond that).
  double samples_per_texel = 4.0;
  int min_samples = 32;
  int max_samples = 2048;
  int64_t max_total = int64_t{1} << 18;
};

struct ReferenceSample {
  glm::dvec4 colour{0, 0, 0, 0};
  int nx = 0, ny = 0;  // supersamples used per axis
};

// Pixel (px, py) (centre at px + ½, py + ½) through the plane's exact projective map.
ReferenceSample footprint_reference(const Texture& tex, const PlaneProjection& map, int px, int py,
                                    const FootprintReferenceConfig& cfg);

// The same from a fragment alone: the footprint through the first-order (affine) map
// u(s) = u + J·s, for tests of single footprints.
ReferenceSample footprint_reference_affine(const Texture& tex, const Fragment& f,
                                           const FootprintReferenceConfig& cfg);

}  // namespace texsim
