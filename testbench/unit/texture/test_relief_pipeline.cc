// The relief stage inside the timed texture unit: its height (or distance-map) reads go through
// the texture cache and DRAM and are reported as the relief block's texels; the
// visibility-aware filter is selectable per material (relief table `visibility_filter`), with
// its reads through the cache and its cycles in the frame.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "blocks/base/input_error.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/geometry/surface_frame.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/texture_loader.h"
#include "pipeline/texture/effect_registry.h"
#include "pipeline/texture/texture_unit.h"

namespace texsim {
namespace {

// One wall seen at a grazing angle; `relief` is the wall's relief table.
std::string scene_text(const std::string& relief,
                       const std::string& height = "procedural:noise?size=64") {
  return R"(
[output]
width = 48
height = 32
[camera]
position = [0.0, 1.0, 0.0]
look_at = [0.0, 1.0, -10.0]
[textures.t]
source = "procedural:checker?size=64&cells=4"
[textures.h]
source = ")" +
         height + R"("
[materials.wall]
texture = "t"
filter = { mode = "trilinear", address = "wrap" }
lod = { aniso = "vulkan", max_aniso = 8 }
relief = )" +
         relief +
         R"(
[[planes]]
material = "wall"
origin = [-1.0, 0.0, -1.0]
edge_u = [0.0, 0.0, -8.0]
edge_v = [0.0, 2.0, 0.0]
)";
}

struct UnitRun {
  uint64_t cycles = 0, cache_reads = 0, misses = 0, relief_fetches = 0;
  uint64_t texels = 0;  // Σ texels of the material's blocks
  std::set<std::string> blocks;
  std::vector<Rgba> colours;
};

UnitRun run(const std::string& relief, const std::string& height = "procedural:noise?size=64") {
  const Scene s = parse_scene(scene_text(relief, height), "s.toml", "");
  TextureSet tex;
  for (size_t i = 0; i < s.textures.size(); ++i) tex.add(load_scene_texture(s, i));
  TextureUnit unit(tex, build_materials(s), PipelineSetup{}, s.tech, true);
  std::vector<SurfaceFrame> frames;
  for (const auto& p : s.primitives) frames.emplace_back(s, p);
  unit.set_surfaces(frames);
  const PlaneProjection map(s, s.primitives[0]);
  UnitRun r;
  for (int y = 0; y < s.height; ++y) {
    for (int x = 0; x < s.width; ++x) {
      const UvSample u = map.at(x + 0.5, y + 0.5);
      if (!u.inside) continue;
      const Fragment f = u.fragment(static_cast<uint32_t>(x), static_cast<uint32_t>(y));
      r.colours.push_back(unit.process(f, 0));
    }
  }
  unit.check_timing_invariants();
  r.cycles = unit.cycles();
  r.cache_reads = unit.cache().stats().texel_reads;
  r.misses = unit.cache().stats().misses;
  r.relief_fetches = unit.material_relief_fetches(0);
  for (const BlockUse& b : unit.material_blocks(0)) {
    r.texels += b.texels;
    r.blocks.insert(b.name);
  }
  return r;
}

TEST(ReliefPipeline, HeightReadsGoThroughTheCache) {
  const UnitRun r = run(R"({ method = "steep", height_texture = "h", scale = 4.0 })");
  ASSERT_GT(r.colours.size(), 200u);
  ASSERT_GT(r.relief_fetches, r.colours.size());
  // Every texel a block read, the relief's heights included, is one read through the cache.
  EXPECT_EQ(r.cache_reads, r.texels);
  const UnitRun flat = run(R"({ method = "parallax", height_texture = "h", scale = 4.0 })");
  EXPECT_EQ(flat.relief_fetches, 4 * flat.colours.size());  // one bilinear read each
  EXPECT_EQ(flat.cache_reads, flat.texels);
  EXPECT_LT(flat.cache_reads, r.cache_reads);
}

TEST(ReliefPipeline, DistanceMapVoxelsGoThroughTheCache) {
  const UnitRun r = run(R"({ method = "distance_map", height_texture = "h", scale = 4.0 })");
  ASSERT_GT(r.relief_fetches, 0u);
  EXPECT_EQ(r.cache_reads, r.texels);
  EXPECT_TRUE(r.blocks.count("relief.sphere_tracer"));
}

TEST(ReliefPipeline, VisibilityAwareFilterIsAPerMaterialStage) {
  const std::string base = R"(method = "steep", height_texture = "h", scale = 4.0)";
  const UnitRun plain = run("{ " + base + " }");
  const UnitRun ewa = run("{ " + base + ", visibility_filter = { visibility = false } }");
  const UnitRun vis = run("{ " + base + ", visibility_filter = {} }");
  // The filter replaces the material's LOD → address → blend blocks.
  EXPECT_TRUE(vis.blocks.count("relief.visibility_aware_filter"));
  EXPECT_FALSE(vis.blocks.count("lod"));
  EXPECT_FALSE(plain.blocks.count("relief.visibility_aware_filter"));
  // Its colour and trace reads go through the cache, and its cycles are the frame's.
  EXPECT_EQ(vis.cache_reads, vis.texels);
  EXPECT_EQ(ewa.cache_reads, ewa.texels);
  EXPECT_GT(vis.cache_reads, ewa.cache_reads);  // the traces' height reads
  EXPECT_GT(vis.cycles, ewa.cycles);
  EXPECT_NE(vis.cycles, plain.cycles);
  // The relief stage is the same in all three.
  EXPECT_EQ(vis.relief_fetches, plain.relief_fetches);
}

TEST(ReliefPipeline, VisibilityFilterOverFlatReliefIsPlainEwaAtTheCostOfItsTraces) {
  // One checker cell: every height is 0.95, nothing hides anything; deep enough (1.2 texels
  // below the polygon) that the traces read heights before they leave the relief.
  const std::string flat = "procedural:checker?size=64&cells=1";
  const std::string base = R"(method = "steep", height_texture = "h", scale = 24.0)";
  const UnitRun ewa = run("{ " + base + ", visibility_filter = { visibility = false } }", flat);
  const UnitRun vis = run("{ " + base + ", visibility_filter = {} }", flat);
  ASSERT_EQ(vis.colours.size(), ewa.colours.size());
  for (size_t i = 0; i < vis.colours.size(); ++i) ASSERT_EQ(vis.colours[i], ewa.colours[i]) << i;
  EXPECT_GT(vis.cache_reads, ewa.cache_reads);
  EXPECT_GT(vis.cycles, ewa.cycles);
}

TEST(ReliefPipeline, VisibilityFilterDepthIsTheReliefScale) {
  try {
    (void)build_materials(parse_scene(
        scene_text(
            R"({ method = "steep", height_texture = "h", visibility_filter = { depth_texels = 2.0 } })"),
        "s.toml", ""));
    FAIL() << "accepted visibility_filter.depth_texels";
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("depth_texels"), std::string::npos) << w;
    EXPECT_NE(w.find("relief.scale"), std::string::npos) << w;
  }
}

TEST(ReliefPipeline, AFragmentsOwnViewVectorReplacesTheCameras) {
  const Scene s = parse_scene(
      scene_text(R"({ method = "steep", height_texture = "h", scale = 4.0 })"), "s.toml", "");
  TextureSet tex;
  for (size_t i = 0; i < s.textures.size(); ++i) tex.add(load_scene_texture(s, i));
  const std::vector<MaterialSetup> mats = build_materials(s);
  TextureUnit camera(tex, mats, PipelineSetup{}, s.tech, false);
  TextureUnit carried(tex, mats, PipelineSetup{}, s.tech, false);
  TextureUnit overhead(tex, mats, PipelineSetup{}, s.tech, false);
  const SurfaceFrame sf(s, s.primitives[0]);
  for (TextureUnit* u : {&camera, &carried, &overhead}) u->set_surfaces({sf});
  const PlaneProjection map(s, s.primitives[0]);
  size_t n = 0, moved = 0;
  for (int y = 0; y < s.height; ++y) {
    for (int x = 0; x < s.width; ++x) {
      const UvSample u = map.at(x + 0.5, y + 0.5);
      if (!u.inside) continue;
      const Fragment f = u.fragment(static_cast<uint32_t>(x), static_cast<uint32_t>(y));
      // The camera's view vector as a version-2 trace carries it (float).
      const glm::dvec3 v = sf.to_tangent(sf.view(x + 0.5, y + 0.5));
      Fragment g = f;
      g.view_x = static_cast<float>(v.x);
      g.view_y = static_cast<float>(v.y);
      g.view_z = static_cast<float>(v.z);
      const Rgba a = camera.process(f, 0), b = carried.process(g, 0);
      EXPECT_NEAR(a.r, b.r, 1e-3) << x << "," << y;
      EXPECT_NEAR(a.g, b.g, 1e-3) << x << "," << y;
      // Seen from straight above, the relief does not shift the coordinates.
      Fragment o = f;
      o.view_z = 1;
      const Rgba c = overhead.process(o, 0);
      moved += (c.r != a.r || c.g != a.g) ? 1 : 0;
      ++n;
    }
  }
  ASSERT_GT(n, 200u);
  EXPECT_GT(moved, n / 10);
  EXPECT_LT(overhead.material_relief_steps(0), camera.material_relief_steps(0));
}

// relief.footprint: the derivatives LOD gets after the shift. Over a flat height map (one
// checker cell) the analytic ones are the unshifted ones exactly and the quad ones nearly, so
// the colours are the same; over relief both change the image, and only they add a block.
TEST(ReliefPipeline, FootprintAfterTheShiftIsASelectableStage) {
  const std::string base = R"(method = "steep", height_texture = "h", scale = 4.0)";
  const std::string flat = "procedural:checker?size=64&cells=1";
  const UnitRun un = run("{ " + base + " }", flat);
  const UnitRun an = run("{ " + base + R"(, footprint = "analytic" })", flat);
  const UnitRun qd = run("{ " + base + R"(, footprint = "quad" })", flat);
  ASSERT_EQ(un.colours.size(), an.colours.size());
  ASSERT_EQ(un.colours.size(), qd.colours.size());
  for (size_t i = 0; i < un.colours.size(); ++i) {
    ASSERT_EQ(un.colours[i], an.colours[i]) << i;
    ASSERT_NEAR(un.colours[i].r, qd.colours[i].r, 2e-3) << i;
  }
  EXPECT_FALSE(un.blocks.count("relief.footprint[unshifted]"));
  EXPECT_TRUE(an.blocks.count("relief.footprint[analytic]"));
  EXPECT_TRUE(qd.blocks.count("relief.footprint[quad]"));
  EXPECT_EQ(an.relief_fetches, un.relief_fetches);  // the shift itself is the same
  const UnitRun bump = run("{ " + base + " }");
  size_t changed_an = 0, changed_qd = 0;
  const UnitRun bump_an = run("{ " + base + R"(, footprint = "analytic" })");
  const UnitRun bump_qd = run("{ " + base + R"(, footprint = "quad_coarse" })");
  for (size_t i = 0; i < bump.colours.size(); ++i) {
    changed_an += bump.colours[i] != bump_an.colours[i];
    changed_qd += bump.colours[i] != bump_qd.colours[i];
  }
  EXPECT_GT(changed_an, bump.colours.size() / 10);
  EXPECT_GT(changed_qd, bump.colours.size() / 10);
}

TEST(ReliefPipeline, FootprintKeyIsValidated) {
  for (const char* bad : {R"(footprint = "shifted")", R"(footprint = 2)",
                          R"(footprint = "analytic", footprint_max_stretch = 0.0)"}) {
    try {
      (void)build_materials(parse_scene(
          scene_text(std::string(R"({ method = "steep", height_texture = "h", )") + bad + " }"),
          "s.toml", ""));
      ADD_FAILURE() << "accepted " << bad;
    } catch (const InputError& e) {
      const std::string w = e.what();
      EXPECT_NE(w.find("footprint"), std::string::npos) << w;
      EXPECT_NE(w.find("s.toml"), std::string::npos) << w;
    }
  }
}

}  // namespace
}  // namespace texsim
