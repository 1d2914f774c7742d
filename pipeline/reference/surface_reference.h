#pragma once
// Ground truth of a material with relief or lighting (docs/scenes.md#relief-and-lighting),
// written apart from the blocks it checks:
//  - relief: the view ray through the pixel's centre is intersected with the height field by a
//    1024-layer linear search and 24 halvings over bilinear heights, in double; every sample
//    of the pixel's box filter (fixed or adaptive, as PixelIntegrator says) is shifted by the (u,
//    v) offset found there, or (per sample) along its own view ray to where it meets the field; for
//    the terrain method the ray is marched in steps of 1/16 texel against the finite-function
//    direct sum (40 halvings of the last step);
//  - lighting: each sample's bilinear colour is lit in double by the same Blinn-Phong model
//    with the normal at the sample's (shifted) coordinates (bilinear normal map, central
//    differences of the bilinear height map, or for terrain normals the finite-function direct
//    sum's analytic gradient or central differences at ±ε) and the pixel's view vector, then
//    averaged.
#include <glm/vec4.hpp>
#include <optional>

#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/relief/relief_types.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/geometry/surface_frame.h"
#include "pipeline/reference/ground_truth.h"
#include "pipeline/texture/effect_registry.h"

namespace texsim {

class SurfaceReference {
 public:
  // per_sample_relief: every sample shifted along its own view ray ([reference] relief =
  // "per_sample"), else by the pixel centre's offset.
  SurfaceReference(const MaterialSetup& m, const TextureSet& textures,
                   bool per_sample_relief = false);
  bool active() const { return relief_.has_value() || lighting_.has_value(); }
  // The box pixel (integrate's pixel must be the box), sampled as `integrate` says.
  glm::dvec4 operator()(const Texture& tex, const PlaneProjection& map, const SurfaceFrame& sf,
                        int px, int py, const PixelIntegrator& integrate, int* samples = nullptr,
                        int* reach = nullptr) const;
  // The reference relief's (u, v) for normalised (u, v) and a unit tangent-space view vector.
  glm::dvec2 relief_uv(double u, double v, const glm::dvec3& view_ts, double u_len,
                       double v_len) const;

 private:
  glm::dvec3 normal_at(double u, double v) const;
  // Terrain: where the unit ray d (grid axes: x along u, y up, z along v) from texel (x, y)
  // on the polygon meets the surface, in texels.
  glm::dvec2 terrain_xy(double x, double y, const glm::dvec3& d) const;
  AddressMode au_, av_;
  bool per_sample_ = false;
  std::optional<ReliefSetup> relief_;
  std::optional<LightingSetup> lighting_;
  ReliefHeightMap relief_hm_, normal_hm_;
  const Texture* normal_tex_ = nullptr;
};

}  // namespace texsim
