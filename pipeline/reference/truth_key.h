#pragma once
// The key of a cached ground truth (truth_cache.h): a SHA-256 of everything that decides the
// exact truth of a fragment besides the fragment's own identity (TruthId). Read from the truth
// code (ground_truth.h, run.cc's GroundTruth):
//  - the algorithm: kTruthVersion, the adaptive sampler's constants and the Gaussian pixel's;
//  - [reference]: the pixel model and samples;
//  - the image size and the camera the maps are made with (a camera path: every frame's);
//  - the geometry: every primitive (shape, corners, texture coordinates, culling, material);
//  - the textures' content: every texture of the run's set, by index (format, every level's
//    size and texels; never a file name);
//  - the materials: their texture, address modes, and whether relief or lighting replaces
//    the plain truth (those fragments are not cached: their reference reads a whole setup).
// The frame of a fragment is part of its TruthId.
#include <cstdint>
#include <vector>

#include "blocks/base/sha256.h"
#include "blocks/geometry/camera.h"
#include "blocks/texture/memory/texture_memory.h"
#include "pipeline/scene/scene.h"

namespace texsim {

// Bump on ANY change to the truth's arithmetic (ground_truth.{h,cc}, PlaneProjection,
// PixelMap, the bilinear reconstruction, PixelIntegrator) or to what it reads: cached truths
// of the old arithmetic then stop matching, instead of being served as the new one's.
inline constexpr uint32_t kTruthVersion = 2;

struct TruthMaterialKey {
  int texture = 0;  // index into the run's texture set
  AddressMode address_u = AddressMode::Wrap, address_v = AddressMode::Wrap;
  bool surface = false;  // relief or lighting: its fragments' truths are never cached
  Rgba border{0.0f};     // the sampler's border colour (part of the key under border mode)
  int offset_u = 0, offset_v = 0;  // constant texel offset (part of the key when not 0)
};

struct TruthKeyInputs {
  int width = 0, height = 0;
  std::vector<Camera> cameras;  // the truth's maps are made with these (one per frame of a path)
  const std::vector<ScenePrimitive>* primitives = nullptr;
  const TextureSet* textures = nullptr;
  std::vector<TruthMaterialKey> materials;
  TruthPixel pixel = TruthPixel::Box;
  int samples = 0;  // [reference] samples (0: adaptive)
};

using TruthKey = Sha256::Digest;

TruthKey truth_key(const TruthKeyInputs& in);
// The key of the same truth's finer tier `tier` (TruthSampling): its own entry, holding the
// pixels some run refined to that tier.
TruthKey truth_tier_key(const TruthKey& key, int tier);

}  // namespace texsim
