#pragma once
// Ground truth for image accuracy: the level-0 texture, reconstructed bilinearly in double,
// box-filtered over the pixel's area with n×n stratified samples (docs/architecture.md#accuracy).
#include "blocks/base/fragment.h"
#include "blocks/texture/memory/texture_memory.h"
#include "pipeline/geometry/plane_projection.h"

namespace texsim {

// Level-0 texel lookup with bilinear reconstruction at normalised (u, v), in double.
glm::dvec4 reference_bilinear(const Texture& tex, AddressMode au, AddressMode av, double u,
                              double v);

// Exact: sub-pixel positions mapped through the plane's projective map.
glm::dvec4 ground_truth_exact(const Texture& tex, AddressMode au, AddressMode av,
                              const PlaneProjection& map, int px, int py, int n);

// From a fragment alone: the pixel footprint is the parallelogram spanned by its derivatives
// (first-order approximation of the projective map; used for traces without a scene).
glm::dvec4 ground_truth_footprint(const Texture& tex, AddressMode au, AddressMode av,
                                  const Fragment& f, int n);

}  // namespace texsim
