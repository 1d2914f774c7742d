#pragma once
// The relief and lighting effects of a material (docs/scenes.md#relief-and-lighting):
//  - relief (a stage in front of LOD): shifts a fragment's (u, v) along the tangent-space view
//    vector over a height map, by offset parallax, steep/relief parallax (ParallaxMapper) or
//    sphere tracing a distance map (DistanceMapBuilder + SphereTracer), or marching the view ray
//    through the finite-function terrain of the height map (TerrainRayMarcher, method terrain);
//  - lighting (ПРО, a stage after the blend): the filtered colour lit per fragment by one
//    directional light (BlinnPhongShader) with a normal that is the plane's, a normal map's or
//    a height map's (NormalUnit), or the terrain relief's finite-function surface's at the
//    marched position (TerrainNormalUnit).
// Both work in the primitive's tangent frame: x along +u, y along +v, z out of the surface
// (pipeline/geometry/surface_frame.h). Normal maps use the OpenGL convention (green up, i.e.
// towards −v): their y is negated into the frame.
// Setups are read from a material's table; texture names are bound to texture ids later.
#include <cstdint>
#include <glm/vec3.hpp>
#include <memory>
#include <string>
#include <vector>

#include "blocks/base/config_reader.h"
#include "blocks/base/fragment.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/lighting/blinn_phong_shader.h"
#include "blocks/lighting/normal_unit.h"
#include "blocks/lighting/terrain_normal_unit.h"
#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/relief/distance_map_builder.h"
#include "blocks/texture/relief/parallax_mapper.h"
#include "blocks/texture/relief/relief_footprint.h"
#include "blocks/texture/relief/sphere_tracer.h"
#include "blocks/texture/relief/terrain_ray_marcher.h"
#include "blocks/texture/relief/visibility_aware_filter.h"

namespace texsim {

struct ReliefSetup;

struct LightingSetup {
  enum class Normal : uint8_t { Flat, NormalMap, HeightMap, Terrain };
  Normal normal = Normal::Flat;
  // Texture name (normal_map, height_map; terrain: the relief's height texture, set by
  // bind_terrain).
  std::string normal_texture;
  int normal_tex = -1;                  // its texture id once bound
  glm::dvec3 light_dir{0.3, 0.5, 1.0};  // world space, towards the light (normalised here)
  BlinnPhongShader::Config shader;
  NormalUnit::Config normals;  // source and bump_scale
  // Terrain: the method and ε from this table, the finite function and the height scale (in
  // texels) from the material's terrain relief (bind_terrain).
  TerrainNormalUnit::Config terrain;
  double terrain_scale = 0;
  static LightingSetup from_toml(const ConfigReader& r);
  // Terrain normals take the surface of the material's `relief = { method = "terrain" }`:
  // its height texture, scale and finite function. Fails (naming `lighting.normal`) without it.
  void bind_terrain(const ConfigReader& lighting, const ReliefSetup* relief);
};

struct ReliefSetup {
  enum class Method : uint8_t { Parallax, Steep, DistanceMap, Terrain };
  Method method = Method::Steep;
  std::string height_texture;
  int height_tex = -1;
  double scale = 8;  // depth of the relief below the polygon, in height-map texels
  ParallaxMapper::Config parallax;
  SphereTracer::Config tracer;
  DistanceMapBuilder::Config distance_map;
  TerrainRayMarcher::Config terrain;  // method terrain: function, deformation, step, caps
  bool refined = false;  // distance_map: the refined map instead of Donnelly's classic one
  // Table `visibility_filter` present: the material's colour is filtered by the
  // visibility-aware anisotropic filter at the shifted coordinates, in place of its `filter`.
  bool visibility_filter = false;
  VisibilityAwareFilter::Config visibility;  // depth_texels is `scale`
  // `footprint`: the derivatives LOD and the filters get after the shift (default: unshifted).
  ReliefFootprint::Config footprint;
  static ReliefSetup from_toml(const ConfigReader& r);
  std::string block_name() const;
};

// A height texture's level 0 as relief heights (red channel, clamped to [0, 1]).
ReliefHeightMap height_map_of(const Texture& t);

// The tangent-space view vector in height-map texel units (x, y) and relief depth units (z):
// the relief's blocks take directions in texels. u_len, v_len: world length of a unit of u, v.
glm::dvec3 view_in_texels(const glm::dvec3& view_ts, double u_len, double v_len, int hm_w,
                          int hm_h);

// The relief stage of one material.
class ReliefEffect {
 public:
  // colour: the material's texture, which the visibility-aware filter reads (it must be given
  // when the setup has one).
  ReliefEffect(const ReliefSetup& s, const Texture& height, const Texture* colour = nullptr);
  struct Shift {
    double u = 0, v = 0;   // the shifted normalised coordinates
    uint32_t steps = 0;    // iterations of the method's loop (1 for offset parallax)
    uint32_t fetches = 0;  // height (or distance) reads: bilinear reads count 4
    // For the analytic footprint: how the shift depends on the entry point, where the height
    // gradient is read and the texel shift per unit depth (texels; `moved` false: no shift).
    ReliefFootprint::Kind kind = ReliefFootprint::Kind::RayHit;
    double gx = 0, gy = 0, sx = 0, sy = 0;
    bool moved = false;
  };
  // (u, v): normalised coordinates on the polygon; view_ts: unit tangent-space view vector;
  // u_len, v_len: world length of a unit of u and of v on the plane. `reads`, when given, gets
  // the texels or voxels of the height reads (for the texture unit's cache).
  Shift shift(double u, double v, const glm::dvec3& view_ts, double u_len, double v_len,
              OpCounts& ops, std::vector<ReliefRead>* reads = nullptr) const;
  // The analytic footprint: g's derivatives (of the unshifted coordinates) through the shift
  // sh found for g; unchanged when sh did not move the point.
  void analytic_derivatives(Fragment& g, const Shift& sh, OpCounts& ops) const;
  const ReliefFootprint& footprint() const { return footprint_; }
  bool has_visibility_filter() const { return setup_.visibility_filter; }
  // The visibility-aware filter at the fragment's (shifted) coordinates and derivatives:
  // its colour, counts and (when `reads` is given) its height and colour reads.
  VisibilityAwareFilter::Result filter_visible(const Fragment& g, const glm::dvec3& view_ts,
                                               double u_len, double v_len, OpCounts& ops,
                                               std::vector<ReliefRead>* reads) const;
  const VisibilityAwareFilter& visibility_filter() const { return vaf_; }
  const ReliefHeightMap& height_map() const { return hm_; }
  const DistanceMap& distance_map() const { return dmap_; }
  std::string name() const { return setup_.block_name(); }
  std::string arithmetic() const;
  // Timing of one step of the loop.
  TimingSpec timing(const TechTable& t) const;
  const ReliefSetup& setup() const { return setup_; }

 private:
  ReliefSetup setup_;
  ReliefHeightMap hm_;
  ParallaxMapper mapper_;
  ReliefFootprint footprint_;
  SphereTracer tracer_;
  DistanceMap dmap_;
  // Method terrain: the height map as a grid of heights h·scale (texel units) under the
  // polygon at height `scale`, and the marcher with its top bound.
  TerrainRayMarcher marcher_;
  TerrainGrid grid_;
  double top_ = 0;
  // The visibility-aware filter and the colour texture at the height map's resolution.
  VisibilityAwareFilter vaf_;
  VisibilityAwareFilter::ColourMap colours_;
  Shift march_terrain(double x, double y, const glm::dvec3& vt, OpCounts& ops,
                      std::vector<ReliefRead>* reads) const;
};

// The lighting stage of one material.
class LightingEffect {
 public:
  // normal_tex: the normal or height texture (null for flat normals).
  LightingEffect(const LightingSetup& s, const Texture* normal_tex);
  // c: filtered colour; (u, v): normalised coordinates of the fragment (after relief);
  // view_ts, light_ts: unit vectors in the tangent frame. Alpha is kept.
  Rgba shade(const Rgba& c, double u, double v, const glm::dvec3& view_ts,
             const glm::dvec3& light_ts, OpCounts& normal_ops, OpCounts& shader_ops) const;
  // The normal unit of a normal or height map (none for flat or terrain normals).
  bool has_normal_unit() const {
    return setup_.normal == LightingSetup::Normal::NormalMap ||
           setup_.normal == LightingSetup::Normal::HeightMap;
  }
  const NormalUnit& normal_unit() const { return normals_; }
  bool has_terrain_normal() const { return setup_.normal == LightingSetup::Normal::Terrain; }
  const TerrainNormalUnit& terrain_normal() const { return terrain_; }
  const BlinnPhongShader& shader() const { return shader_; }
  // The stage: the normal unit then the shader.
  TimingSpec timing(const TechTable& t) const;
  const LightingSetup& setup() const { return setup_; }

 private:
  LightingSetup setup_;
  const Texture* tex_ = nullptr;
  ReliefHeightMap hm_;  // height_map normals
  NormalUnit normals_;
  TerrainGrid grid_;  // terrain normals: heights h·scale in texels, as the relief's
  TerrainNormalUnit terrain_;
  BlinnPhongShader shader_;
};

// The normal map's texel at normalised (u, v): bilinear over level 0, wrapped (RGB in [0, 1]).
glm::dvec3 normal_map_rgb(const Texture& t, double u, double v);

}  // namespace texsim
