#pragma once
// Ground truth of layered textures (docs/texture-types.md): a cube's level 0 reconstructed
// bilinearly on the face its direction selects, in double, integrated over the pixel through
// the primitive's direction map; an array layer's truth is the 2-D truth on the layer's level 0.
// Written from the spec's rules, apart from the blocks, but for CubeSeam's integer fold of a
// texel over an edge (exact, and itself checked against the spec's projection in
// test_conformance_cube).
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <map>
#include <memory>
#include <mutex>
#include <utility>

#include "blocks/texture/memory/texture_memory.h"
#include "pipeline/geometry/direction_map.h"
#include "pipeline/reference/ground_truth.h"
#include "pipeline/reference/operation_reference.h"

namespace texsim {

// The face of direction r (the major axis; ties Z over Y over X, the unit's deterministic
// choice; a ±0 major component's sign bit; a zero or non-finite direction: +Z at the centre)
// and s, t = ½·sc/|rc| + ½ in [0, 1].
struct ReferenceFace {
  int face = 4;
  double s = 0.5, t = 0.5;
};
ReferenceFace reference_cube_face(glm::dvec3 r);

// Level 0 of cube `cube` at direction r, bilinear with i0 = ⌊s·n − ½⌋. Seamless: a tap beyond
// an edge is the neighbouring face's texel, beyond a corner the mean of the three texels that
// meet there. Otherwise each face is addressed alone with au, av (border: `border`).
glm::dvec4 reference_cube_bilinear(const Texture& tex, int cube, glm::dvec3 r, bool seamless,
                                   AddressMode au, AddressMode av, glm::dvec4 border = {});

// A cube fragment's truth at pixel (px, py): reference_cube_bilinear over the pixel through
// `map`, integrated by `integrate` (its grid shaped by the face-space footprint).
glm::dvec4 ground_truth_cube(const Texture& tex, int cube, bool seamless, AddressMode au,
                             AddressMode av, glm::dvec4 border, const DirectionMap& map, int px,
                             int py, const PixelIntegrator& integrate, int* samples = nullptr,
                             int* reach = nullptr);

// Level 0 of a 3-D texture (Texture::volume) at (u, v, r), trilinear in double: i0 = ⌊u·w − ½⌋,
// j0, k0 alike and their +1 neighbours, each axis under its mode m[0..2] (a border texel reads
// `border`); non-finite coordinates are taken as 0.
glm::dvec4 reference_volume_trilinear(const Texture& tex, const AddressMode m[3], glm::dvec4 border,
                                      double u, double v, double r);

// A 3-D texture fragment's truth at pixel (px, py): reference_volume_trilinear integrated over
// the pixel. With `map` and `r_of_uv` (a scene: r = a·u + b·v + c, the material's lookup.r)
// (u, v) come from the plane's projective map; otherwise (a trace) (u, v, r) from the fragment
// and its derivatives (the footprint's parallelogram).
glm::dvec4 ground_truth_volume(const Texture& tex, const AddressMode m[3], glm::dvec4 border,
                               const Fragment& f, const ProjectiveMap* map, const double* r_of_uv,
                               int px, int py, const PixelIntegrator& integrate,
                               int* samples = nullptr, int* reach = nullptr);

// An explicit LOD's or explicit gradients' truth on a 3-D texture (docs/texture-types.md §8,
// extended to the 3-D footprint), reference_volume_trilinear integrated over: for `lod` the
// axis-aligned cube of 2^λ' level-0 texels on each axis at (u, v, r), λ' = operation_lod(lod)
// (integrate over u, v; r by the midpoint rule, four points a texel, at most 64); for `grad`
// the parallelogram the gradients (∂r included) span, scaled by 2^(λ' − λ), λ = log2 ρ of
// the 3-D gradients (no direction to scale: the cube of the clamped λ).
glm::dvec4 ground_truth_volume_operation(const Texture& tex, const AddressMode m[3],
                                         glm::dvec4 border, const OperationSampler& s,
                                         const Fragment& f, const PixelIntegrator& integrate,
                                         int* samples = nullptr, int* reach = nullptr);

// The layer of array coordinate a among `layers`: round to nearest even, clamped (Vulkan
// "Array Layer Selection"); a non-finite a selects layer 0.
int reference_layer(double a, int layers);

// Level 0 of slice `slice` of a layered texture as a 2-D texture of its own (no mips): the
// array truth samples it as ground_truth_exact samples a 2-D texture.
Texture layer_texture(const Texture& tex, int slice);

// layer_texture made once per (texture, slice) and kept; safe to call from several threads.
class LayerTextures {
 public:
  const Texture& get(const Texture& tex, int slice);

 private:
  std::mutex mutex_;
  std::map<std::pair<const Texture*, int>, std::unique_ptr<const Texture>> made_;
};

}  // namespace texsim
