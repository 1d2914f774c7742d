#pragma once
// A material's effects. Every key of a material's table beside `texture` names one effect;
// the registry maps it to the factory that builds its block from the key's table (with the
// block's own Config::from_toml). The builder builds only the effects a material names: a
// material without `coords` gets no coordinate unit, one without a footprint filter key the
// classic LOD → address → blend path (whose `lod` and `filter` tables are optional).
// Adding an effect: its block, and one line in effect_registry() (effect_registry.cc).
#include <toml++/toml.h>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "blocks/base/config_reader.h"
#include "blocks/raster/edge_rasterizer.h"
#include "blocks/raster/rect_scan/rect_scan_rasterizer.h"
#include "blocks/texture/sampler/lod_unit.h"
#include "blocks/texture/sampler/texel_address_gen.h"
#include "pipeline/texture/coord_method.h"
#include "pipeline/texture/footprint_filter.h"
#include "pipeline/texture/layered_lookup.h"
#include "pipeline/texture/sampler_setup.h"
#include "pipeline/texture/surface_effects.h"

namespace texsim {

struct Scene;
struct SceneMaterial;

// The rasteriser a material's primitives are drawn with (effect `raster`; without it, the
// edge-function rasteriser with its defaults). The block's own keys sit beside `method`.
struct RasterSetup {
  enum class Method : uint8_t { Edge, RectScan };
  // Where a rect_scan material's texture coordinates come from: the constant-depth coordinate
  // block on the scan's digital rows (one reciprocal per row, the seed's datapath), or the
  // primitive's exact map at the pixel centre (the reference the ledger makes it exact with).
  enum class Coords : uint8_t { ConstantDepth, Exact };
  Method method = Method::Edge;
  Coords coords = Coords::ConstantDepth;
  EdgeRasterizer::Config edge;
  RectScanRasterizer::Config rect_scan;
  bool constant_depth() const {
    return method == Method::RectScan && coords == Coords::ConstantDepth;
  }
  static RasterSetup from_toml(const ConfigReader& r);
  std::string block_name() const {
    return method == Method::Edge ? "raster.edge" : "raster.rect_scan";
  }
};

struct MaterialSetup {
  std::string name;
  int texture = 0;
  LodUnit::Config lod;
  TexelAddressGen::Config filter;
  // A footprint filter (EWA, multi-probe, Feline, SPAF) replaces the LOD → address → blend
  // path for this material when set; null for the classic path.
  std::shared_ptr<const FootprintFilter> footprint;
  // A coordinate unit (material table `coords`) computes this material's texture coordinates
  // and derivatives in front of LOD; null when fragments arrive with their coordinates.
  std::shared_ptr<const CoordUnit> coords;
  RasterSetup raster;
  // Relief (in front of LOD) and lighting (after the blend): absent unless the material asks.
  std::optional<ReliefSetup> relief;
  std::optional<LightingSetup> lighting;
  // Effect `lookup`: a layered texture's direction and layer (fragment generation sets them).
  std::optional<LayeredLookup> lookup;
  // `sampler = "NAME"`: lod and filter come from that scene sampler, id `sampler` (0: the
  // material's own `lod` and `filter` tables). `samplers`: the scene's whole table, which a
  // fragment's own `sampler` field indexes (null: none).
  int sampler = 0;
  std::shared_ptr<const SamplerTable> samplers;
  // `operation = { op = … }`: written into every fragment the material draws.
  std::optional<OperationSetup> operation;
  // "file:line:column" of `filter.arithmetic` (set when "fixed"): refusals that depend on the
  // texture (TextureUnit) name it.
  std::string arithmetic_where;
  AddressMode address_u() const { return footprint ? footprint->address_u() : filter.address_u; }
  AddressMode address_v() const { return footprint ? footprint->address_v() : filter.address_v; }
};

struct Effect {
  std::string_view key;  // the key in a material's table
  // Effects of one group exclude each other in a material (e.g. "footprint filter"); "": none.
  std::string_view group;
  // Builds the effect from the material's table (`material.sub(key)` is the effect's own).
  void (*build)(const ConfigReader& material, std::string_view key, MaterialSetup& m);
};

// Every effect, in the order messages list them.
const std::vector<Effect>& effect_registry();

// Builds a material from its table: unknown keys and non-table effects are InputErrors naming
// file:line:column. A coordinate unit without derivatives (`derivs = "none"`) is refused for
// trilinear and footprint filters, which need them. `textures` (name -> texture id) binds the
// textures that relief and lighting name; an unknown name is an InputError. Null: unbound.
// `samplers` (null: none) is the scene's sampler table that a `sampler` key names.
MaterialSetup material_from_toml(const std::string& name, int texture, const toml::table& effects,
                                 const std::string& source,
                                 const std::map<std::string, int>* textures = nullptr,
                                 const std::shared_ptr<const SamplerTable>& samplers = nullptr);
// The scene's samplers, checked (InputError naming file:line:column).
std::shared_ptr<const SamplerTable> build_samplers(const Scene& scene);
// A material on an unnormalised sampler, or on one that compares or reduces, must sample a 2-D
// texture: otherwise an InputError at the material's `sampler` (or `filter`) key.
void check_sampler_texture(const Scene& scene, const SceneMaterial& sm, const MaterialSetup& m);
// The scene's materials, in order.
std::vector<MaterialSetup> build_materials(const Scene& scene);

}  // namespace texsim
