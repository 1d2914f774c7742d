#pragma once
// Ground truth for image accuracy: the level-0 texture, reconstructed bilinearly in double,
// integrated over the pixel with stratified samples (docs/architecture.md#accuracy): a box over
// the pixel's square (n×n samples), or the Gaussian pixel of EWA's model.
#include <string>
#include <vector>

#include "blocks/base/fragment.h"
#include "blocks/texture/memory/texture_memory.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/reference/footprint_reference.h"
#include "pipeline/scene/scene.h"

namespace texsim {

// Sample positions (relative to the pixel's corner) and weights of one pixel model: the box
// takes n×n samples over the pixel's square, weight 1; the Gaussian (PixelModel defaults:
// σ = ½ px, truncated at R = 1 px) takes ⌈2R·n⌉² samples over the square ±R around the
// centre, each weighted by the Gaussian (so n samples per pixel width in both).
struct PixelSamples {
  std::vector<double> x, y, w;
  double weight_sum = 0;
  static PixelSamples make(TruthPixel p, int n);
  std::string describe(TruthPixel p, int n) const;
};

// Level-0 texel lookup with bilinear reconstruction at normalised (u, v), in double.
glm::dvec4 reference_bilinear(const Texture& tex, AddressMode au, AddressMode av, double u,
                              double v);

// Exact: sub-pixel positions mapped through the plane's projective map.
glm::dvec4 ground_truth_exact(const Texture& tex, AddressMode au, AddressMode av,
                              const PlaneProjection& map, int px, int py, const PixelSamples& s);
// The box pixel with n×n samples.
glm::dvec4 ground_truth_exact(const Texture& tex, AddressMode au, AddressMode av,
                              const PlaneProjection& map, int px, int py, int n);

// From a fragment alone: the pixel footprint is the parallelogram spanned by its derivatives
// (first-order approximation of the projective map; used for traces without a scene).
glm::dvec4 ground_truth_footprint(const Texture& tex, AddressMode au, AddressMode av,
                                  const Fragment& f, const PixelSamples& s);
glm::dvec4 ground_truth_footprint(const Texture& tex, AddressMode au, AddressMode av,
                                  const Fragment& f, int n);

}  // namespace texsim
