#pragma once
// Ground truth of sampler operations (docs/texture-types.md §8): what each operation asks of
// the unit, computed in double from level 0, apart from the blocks.
//  - The footprint: an implicit-LOD sample's is the pixel's (through the plane's map in a
//    scene, else the parallelogram of the fragment's derivatives: the plain truth's); explicit
//    LOD's the axis-aligned square of 2^λ' × 2^λ' level-0 texels at (u, v), λ' = clamp(lod +
//    the sampler's bias, min_lod, max_lod); explicit gradients' the parallelogram they span,
//    scaled by 2^(λ' − λ) (λ = log2 ρ of the gradients, λ' its biased and clamped value;
//    where λ' ≤ 0, λ + bias unclamped: level 0's reconstruction is not blurred by a clamp up
//    to min_lod = 0); an unnormalised sampler's the point (a filtered texel fetch on level 0).
//  - Over it: the level-0 bilinear reconstruction integrated (a plain filter); with a depth
//    comparison each texel compared with the reference first, then the bilinear weights
//    (percentage-closer filtering, the result (v, v, v, 1)); with a min/max reduction the
//    channel-wise min/max of every texel the bilinear reconstruction reads with non-zero
//    weight somewhere in the footprint (not an integral).
//  - Gather: the four texels of the base level's bilinear quad at (u, v), exactly, in the
//    spec's order (i0,j1), (i1,j1), (i1,j0), (i0,j0) (compared when the sampler compares).
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "blocks/base/fragment.h"
#include "blocks/geometry/projective_map.h"
#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/sampler/sampler_modes.h"
#include "pipeline/reference/ground_truth.h"

namespace texsim {

// The sampler state an operation's truth follows (the fragment's sampler: its own, or the
// material's).
struct OperationSampler {
  AddressMode au = AddressMode::Wrap, av = AddressMode::Wrap;
  glm::dvec4 border{0.0};          // the border colour as the stored format reads it
  int offset_u = 0, offset_v = 0;  // the sampler's and the fragment's constant offsets
  CompareOp compare = CompareOp::None;
  Reduction reduction = Reduction::WeightedAverage;
  bool unnormalized = false;
  bool unorm_depth = false;  // the stored format is UNORM depth (D16): the reference clamps
  double lod_bias = 0, min_lod = 0, max_lod = 1000;
};

// Whether fragment f on sampler s has an operation's truth (an explicit LOD, gradients or a
// gather; a comparison, a min/max reduction or unnormalised coordinates); otherwise its truth
// is the plain one (ground_truth.h).
bool operation_truth_applies(const Fragment& f, const OperationSampler& s);

// A footprint on level 0: the pixel's square through a plane's map, or the parallelogram
// centre + (dx − ½)·a + (dy − ½)·b for (dx, dy) in [0, 1]² (normalised coordinates), both
// shifted by the constant offset.
struct OperationFootprint {
  const PixelMap* map = nullptr;
  glm::dvec2 centre{0.0}, a{0.0}, b{0.0};
  glm::dvec2 shift{0.0};  // the constant offset, added to every point
  glm::dvec2 at(double dx, double dy) const;
  glm::dvec2 texels_across(int w, int h) const;  // level-0 texels along dx and dy
};

// The footprint of f's operation on a w × h level 0 (map: the plane's at f's pixel, or null).
OperationFootprint operation_footprint(const Fragment& f, const OperationSampler& s, int w, int h,
                                       const PixelMap* map);

// λ' = clamp(λ + bias, min_lod, max_lod) (NaN λ: 0 before the bias, as the unit); where that
// is ≤ 0, the smaller of it and λ + bias (a clamp up to min_lod ≤ 0 does not widen the
// footprint).
double operation_lod(double lambda, const OperationSampler& s);

// The bilinear weights on level 0 applied to [reference OP texel] (red; border taps compare
// the border colour); (v, v, v, 1).
glm::dvec4 reference_compare_bilinear(const Texture& tex, const OperationSampler& s, double u,
                                      double v, float reference);

// Channel-wise min (or max) of the texels the bilinear reconstruction reads with non-zero
// weight at some point of the convex quad q (normalised coordinates, in order round it).
glm::dvec4 reference_minmax(const Texture& tex, const OperationSampler& s, const glm::dvec2 q[4]);

// The four gathered texels' component (compared with the reference if s compares).
glm::dvec4 reference_gather(const Texture& tex, const OperationSampler& s, double u, double v,
                            int component, float reference);

// f's truth: the operation's result on the reference texture `tex` (level 0). map: the plane's
// projective map in a scene (null: from the fragment's fields).
glm::dvec4 ground_truth_operation(const Texture& tex, const OperationSampler& s, const Fragment& f,
                                  const ProjectiveMap* map, int px, int py,
                                  const PixelIntegrator& integrate, int* samples = nullptr,
                                  int* reach = nullptr);

}  // namespace texsim
