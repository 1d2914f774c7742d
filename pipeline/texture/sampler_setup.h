#pragma once
// Samplers as state (docs/scenes.md `[samplers.NAME]`): a scene's sampler table, which a
// material names as its default (`sampler = "NAME"`) and a trace record's `sampler` field
// indexes (1 + the sampler's place in name order; 0 = the material's own). And the operation a
// material's fragments ask (`operation = { op = … }`), written into each fragment it draws.
#include <memory>
#include <string>
#include <vector>

#include "blocks/base/config_reader.h"
#include "blocks/base/fragment.h"
#include "blocks/base/sample_op.h"
#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/sampler/lod_unit.h"
#include "blocks/texture/sampler/texel_address_gen.h"
#include "traces/trace_file.h"

namespace texsim {

struct SamplerSetup {
  std::string name;
  TexelAddressGen::Config filter;
  LodUnit::Config lod;
  // Keys: those of a material's `filter` table but `offset` (the instruction's, not the
  // sampler's), those of its `lod` table, and `unnormalized` (Vulkan's
  // unnormalizedCoordinates: u, v in texels on level 0; nearest or bilinear, clamp or border
  // addressing, no anisotropy, no comparison, min_lod = max_lod = 0 — others are refused).
  static SamplerSetup from_toml(const std::string& name, const ConfigReader& r);
};
// Sampler id k (1-based, as a trace record names it) is table[k - 1].
using SamplerTable = std::vector<SamplerSetup>;

// A sampler as a trace's sampler table carries it (traces/FORMAT.md "Sampler table"), and
// back. from_trace_sampler takes an entry the trace reader checked (codes in range, finite
// values) and checks the sampler's own rules as a scene's are: an unnormalised sampler's
// restrictions, a comparison only with the weighted average; throws InputError(where,
// "sampler table entry <id> ('<name>'): …").
TraceSampler to_trace_sampler(const SamplerSetup& s);
SamplerSetup from_trace_sampler(const TraceSampler& t, size_t id, const std::string& where);
// The trace's table as the unit's (null when it has none).
std::shared_ptr<const SamplerTable> sampler_table_of(const std::vector<TraceSampler>& table,
                                                     const std::string& where);

// Why an unnormalised sampler cannot serve fragment f ("" if it can). Vulkan
// (VkSamplerCreateInfo, unnormalizedCoordinates) allows no instruction with ImplicitLod, Dref
// or Proj in its name and no offsets: texsim refuses the implicit-LOD sample, an explicit LOD
// other than 0, gradients, gather and constant offsets (comparison is refused on the sampler).
std::string unnormalized_refusal(const Fragment& f);
// Why an unnormalised sampler cannot read a texture of this type ("" if it can): Vulkan allows
// 1-D and 2-D views of one layer only (no cube, array or 3-D texture).
std::string unnormalized_refusal(TextureType type);

// The operation of every fragment of a material (effect `operation`).
struct OperationSetup {
  SampleOp op = SampleOp::kSample;
  float lod = 0;          // op "lod"
  uint8_t component = 0;  // op "gather": 0..3
  // A comparing sampler's reference: ref[0] + ref[1]·u + ref[2]·v (a receiver's depth in the
  // light's view, linear over a plane), in float32.
  float ref[3] = {0, 0, 0};
  int8_t offset_u = 0, offset_v = 0;
  // Keys: op ("sample"|"lod"|"grad"|"gather"), lod (finite), component ("r"|"g"|"b"|"a"),
  // compare_ref (a number, or [a, b, c]: a + b·u + c·v; finite), offset ([i, j] in -8..7).
  static OperationSetup from_toml(const ConfigReader& r);
  void apply(Fragment& f) const {
    f.op = static_cast<uint8_t>(op);
    f.lod = lod;
    f.gather_component = component;
    f.compare_ref = ref[0] + ref[1] * static_cast<float>(f.u) + ref[2] * static_cast<float>(f.v);
    f.offset_u = offset_u;
    f.offset_v = offset_v;
  }
};

}  // namespace texsim
