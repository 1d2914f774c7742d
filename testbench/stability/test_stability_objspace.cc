// Hard cases of object-space texturing (docs/derivations/object-space.md), each with a defined
// outcome: polygons already parallel to the screen (identity), edge-on polygons, back-facing
// normals, Ny = Nz = 0 (d = 0), tiny and screen-filling polygons, samples exactly on pixel
// boundaries, a pixel with zero weight (a hole: counted, never a NaN), and the hole-free rule
// over a sweep of tilts and resolutions. Independent checks: the scene's exact PlaneProjection
// (screen → texture) and the camera formula.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <sstream>
#include <string>

#include "blocks/geometry/polygon_rotation.h"
#include "blocks/geometry/sample_projection.h"
#include "blocks/raster/object_space_raster.h"
#include "blocks/raster/splat_resolve.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/raster/object_space_pipeline.h"
#include "pipeline/scene/procedural_texture.h"
#include "pipeline/scene/scene.h"
#include "pipeline/texture/effect_registry.h"

namespace texsim {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::string vec(const glm::dvec3& v) {
  std::ostringstream s;
  s.precision(17);
  s << "[" << v.x << ", " << v.y << ", " << v.z << "]";
  return s.str();
}

constexpr const char* kPerspective = "fov_y = 60.0";
constexpr const char* kOrthographic = "projection = \"orthographic\"\nheight = 3.0";

// A camera at the origin looking down −Z (world Y up), fov 60° (or orthographic, 3 units tall),
// and one plane.
Scene plane_scene(int w, int h, const glm::dvec3& o, const glm::dvec3& eu, const glm::dvec3& ev,
                  const std::string& lens = kPerspective) {
  const std::string text =
      "[output]\nwidth = " + std::to_string(w) + "\nheight = " + std::to_string(h) +
      "\n[camera]\nposition = [0.0, 0.0, 0.0]\nlook_at = [0.0, 0.0, -1.0]\n" + lens +
      "\nnear = 0.05\n"
      "[textures.t]\nsource = \"procedural:checker?size=64&cells=4\"\n"
      "[materials.m]\ntexture = \"t\"\nfilter = { mode = \"trilinear\" }\n"
      "[[planes]]\nmaterial = \"m\"\norigin = " +
      vec(o) + "\nedge_u = " + vec(eu) + "\nedge_v = " + vec(ev) + "\nuv_scale = [2.0, 2.0]\n";
  return parse_scene(text, "objspace.toml", "");
}

// A square of side 2·s centred on the view axis at depth D, tilted by `tilt` about the screen's
// x axis and turned by `azimuth` about the view axis.
Scene tilted_scene(int size, double tilt_deg, double azimuth_deg, double D, double s,
                   const std::string& lens = kPerspective) {
  const double t = tilt_deg * kPi / 180, a = azimuth_deg * kPi / 180;
  const glm::dvec3 ux{std::cos(a), std::sin(a), 0}, uy{-std::sin(a), std::cos(a), 0};
  const glm::dvec3 eu = ux * (2 * s);
  const glm::dvec3 ev = (uy * std::cos(t) + glm::dvec3(0, 0, -1) * std::sin(t)) * (2 * s);
  const glm::dvec3 o = glm::dvec3(0, 0, -D) - eu * 0.5 - ev * 0.5;
  return plane_scene(size, size, o, eu, ev, lens);
}

ObjectSpaceResult render(const Scene& scene, double step_px = 0.75) {
  TextureSet set;
  for (const SceneTexture& t : scene.textures) set.add(make_procedural_texture(t.source, "test"));
  ObjectSpaceConfig cfg;
  cfg.raster.max_step_px = step_px;
  return render_object_space(scene, set, build_materials(scene), PipelineSetup{}, cfg);
}

void expect_finite(const ObjectSpaceResult& r) {
  for (const Rgba& c : r.image) {
    ASSERT_TRUE(std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b) &&
                std::isfinite(c.a));
  }
}

TEST(ObjectSpaceHard, ParallelPolygonGetsTheExactIdentity) {
  for (const double nz : {1.0, -1.0}) {
    OpCounts ops;
    const Rotation r = PolygonRotation::setup({0, 0, nz}, ops);
    EXPECT_EQ(r.kind, RotationCase::Identity);
    EXPECT_EQ(r.flipped, nz < 0);
    const glm::dvec3 p{0.1, -2.5, 7.25};
    const glm::dvec2 xy = PolygonRotation::rotate_xy(r, p, ops);
    EXPECT_EQ(xy.x, p.x);
    EXPECT_EQ(xy.y, p.y);
    EXPECT_EQ(PolygonRotation::rotate_z(r, p, ops), p.z);
    EXPECT_EQ(PolygonRotation::inverse(r, p, ops), p);
  }
  const ObjectSpaceResult res = render(tilted_scene(48, 0, 0, 3, 1));
  EXPECT_EQ(res.resolve.holes, 0u);
  EXPECT_GT(res.resolve.expected, 0u);
  expect_finite(res);
}

TEST(ObjectSpaceHard, DZeroRotatesAboutYOnly) {
  for (const double nx : {1.0, -1.0}) {
    OpCounts ops;
    const Rotation r = PolygonRotation::setup({nx, 0, 0}, ops);
    EXPECT_EQ(r.kind, RotationCase::DZero);
    EXPECT_FALSE(std::isnan(r.cos_a + r.sin_a + r.cos_b + r.sin_b));
    const glm::dvec2 n = PolygonRotation::rotate_xy(r, {nx, 0, 0}, ops);
    EXPECT_EQ(n.x, 0);
    EXPECT_EQ(n.y, 0);
    EXPECT_EQ(PolygonRotation::rotate_z(r, {nx, 0, 0}, ops), 1);
    // Points of the plane x = 2 all get the same z'.
    EXPECT_EQ(PolygonRotation::rotate_z(r, {2, 1, 5}, ops),
              PolygonRotation::rotate_z(r, {2, -3, 9}, ops));
  }
  // A side wall (view-space normal ±X: Ny = Nz = 0), rendered without holes.
  const ObjectSpaceResult res = render(plane_scene(64, 48, {-1, -1, -1}, {0, 0, -6}, {0, 2, 0}));
  EXPECT_EQ(res.degenerate, 0u);
  EXPECT_EQ(res.primitives, 1u);
  EXPECT_GT(res.resolve.expected, 100u);
  EXPECT_EQ(res.resolve.holes, 0u);
  expect_finite(res);
}

TEST(ObjectSpaceHard, EdgeOnPolygonDrawsNothing) {
  // The plane y = 0 through the eye: seen edge-on.
  const ObjectSpaceResult res = render(plane_scene(32, 32, {-1, 0, -1}, {2, 0, 0}, {0, 0, -4}));
  EXPECT_EQ(res.edge_on, 1u);
  EXPECT_EQ(res.samples, 0u);
  EXPECT_EQ(res.resolve.holes, 0u);
  expect_finite(res);
  // Degenerate (collinear corners): no normal, defined outcome.
  OpCounts ops;
  EXPECT_EQ(PolygonRotation::unit_normal({0, 0, 1}, {1, 1, 1}, {2, 2, 1}, ops), glm::dvec3(0));
  EXPECT_EQ(PolygonRotation::setup(glm::dvec3(0), ops).kind, RotationCase::Degenerate);
  EXPECT_EQ(PolygonRotation::setup({std::nan(""), 0, 1}, ops).kind, RotationCase::Degenerate);
}

TEST(ObjectSpaceHard, BackFacingPolygons) {
  // The same square with its edges swapped: the camera sees its back.
  Scene front = tilted_scene(48, 40, 20, 3, 1);
  Scene back = front;
  ScenePrimitive& p = back.primitives[0];
  std::swap(p.edge_u, p.edge_v);
  std::swap(p.uv_edge_u, p.uv_edge_v);
  const ObjectSpaceResult rf = render(front), rb = render(back);
  EXPECT_EQ(rb.primitives, 1u);
  EXPECT_EQ(rb.resolve.holes, 0u);
  EXPECT_EQ(rb.resolve.expected, rf.resolve.expected);
  EXPECT_EQ(rb.raster.grid_samples, rf.raster.grid_samples);  // the same rotation and grid
  double max_diff = 0;
  for (size_t i = 0; i < rf.image.size(); ++i)
    max_diff = std::max(max_diff, static_cast<double>(std::fabs(rf.image[i].r - rb.image[i].r)));
  EXPECT_LT(max_diff, 0.1);  // only the edge samples' positions differ
  back.primitives[0].cull_back = true;
  const ObjectSpaceResult rc = render(back);
  EXPECT_EQ(rc.culled, 1u);
  EXPECT_EQ(rc.samples, 0u);
  // A back-facing normal (Nz < 0 in view space) is rotated the short way: |α| <= 90°.
  OpCounts ops;
  const Rotation r = PolygonRotation::setup(glm::normalize(glm::dvec3(0.2, 0.5, -0.8)), ops);
  EXPECT_TRUE(r.flipped);
  EXPECT_GE(r.cos_a, 0);
}

TEST(ObjectSpaceHard, TinyAndScreenFillingPolygons) {
  // A triangle of 0.3 pixel: samples at its vertices at least, no NaN.
  const Scene tiny = plane_scene(32, 32, {0.001, 0.001, -5}, {0.004, 0, 0}, {0, 0.004, 0});
  Scene tri = tiny;
  tri.primitives[0].shape = ScenePrimitive::Shape::Triangle;
  for (const Scene* s : std::vector<const Scene*>{&tiny, &tri}) {
    const ObjectSpaceResult r = render(*s);
    EXPECT_GE(r.samples, 3u);
    EXPECT_EQ(r.resolve.holes, 0u);
    expect_finite(r);
  }
  // Far larger than the screen, running past the near plane: clipped, every pixel covered.
  const ObjectSpaceResult big =
      render(plane_scene(40, 30, {-500, -500, 10}, {1000, 0, 0}, {0, 1000, -30}));
  EXPECT_EQ(big.resolve.expected, 40u * 30u);
  EXPECT_EQ(big.resolve.holes, 0u);
  expect_finite(big);
}

TEST(ObjectSpaceHard, SamplesExactlyOnPixelBoundaries) {
  int i = 0, j = 0;
  double s[4];
  // On a pixel centre: all weight on that pixel.
  SplatResolve::weights(3.5, 2.5, i, j, s);
  EXPECT_EQ(i, 3);
  EXPECT_EQ(j, 2);
  EXPECT_EQ(s[0], 1);
  EXPECT_EQ(s[1] + s[2] + s[3], 0);
  // On the boundary between two pixels' centres and on a pixel corner.
  SplatResolve::weights(4.0, 2.5, i, j, s);
  EXPECT_EQ(s[0], 0.5);
  EXPECT_EQ(s[1], 0.5);
  SplatResolve::weights(4.0, 3.0, i, j, s);
  for (double w : s) EXPECT_EQ(w, 0.25);
  // At the image's edges: targets off the image are skipped, the rest normalise.
  const SplatResolve sr;
  SplatBuffer b(2, 2);
  SplatStats st;
  OpCounts ops;
  sr.splat(b, 0.0, 0.0, 1, 0, Rgba(0.5f), st, ops);
  sr.splat(b, 2.0, 2.0, 1, 0, Rgba(0.5f), st, ops);
  std::vector<Rgba> out;
  const ResolveStats rs = sr.resolve(b, std::vector<uint8_t>(4, 1), Rgba(0), out, ops);
  EXPECT_EQ(rs.holes, 2u);  // (1, 0) and (0, 1) got no weight: counted, never a NaN
  EXPECT_EQ(out[0], Rgba(0.5f));
  EXPECT_EQ(out[3], Rgba(0.5f));
  EXPECT_EQ(out[1], Rgba(0));
}

TEST(ObjectSpaceHard, TooCoarseAStepLeavesHolesThatAreCounted) {
  // The rule's bound matters: four pixels per step leaves holes, counted, the image finite.
  const ObjectSpaceResult r = render(tilted_scene(64, 30, 10, 2, 1), 4.0);
  EXPECT_GT(r.resolve.holes, 0u);
  expect_finite(r);
}

TEST(ObjectSpaceHard, NoHolesOverTiltsAndResolutions) {
  for (const int size : {24, 64, 160}) {
    for (double tilt = 0; tilt <= 85; tilt += 5) {
      for (const double az : {0.0, 33.0}) {
        const ObjectSpaceResult r = render(tilted_scene(size, tilt, az, 2.5, 1));
        ASSERT_GT(r.resolve.expected, 0u);
        EXPECT_EQ(r.resolve.holes, 0u) << size << " px, tilt " << tilt << ", azimuth " << az;
      }
    }
  }
}

// The chain of blocks maps each sample to the screen position where the scene's exact
// screen → texture map gives the sample's own (affine) texture coordinates.
TEST(ObjectSpaceHard, ProjectedSamplesCarryTheExactTextureCoordinates) {
  for (const double tilt : {0.0, 45.0, 80.0}) {
    const Scene scene = tilted_scene(64, tilt, 25, 3, 1);
    const PlaneProjection map(scene, scene.primitives[0]);
    const Camera& c = scene.camera;
    const glm::dvec3 fwd{0, 0, -1}, right{1, 0, 0}, down{0, -1, 0};
    const ScenePrimitive& p = scene.primitives[0];
    auto view = [&](const glm::dvec3& w) {
      return glm::dvec3(glm::dot(w, right), glm::dot(w, down), glm::dot(w, fwd));
    };
    const glm::dvec3 v0 = view(p.origin), v1 = view(p.origin + p.edge_u),
                     v2 = view(p.origin + p.edge_u + p.edge_v);
    OpCounts ops;
    const Rotation r = PolygonRotation::setup(PolygonRotation::unit_normal(v0, v1, v2, ops), ops);
    const RotatedPolygon rp =
        PolygonRotation::rotate_polygon(r, {v0, v1, v2, view(p.origin + p.edge_v)}, ops);
    const glm::dvec2 xy[3] = {rp.xy[0], rp.xy[1], rp.xy[2]};
    const glm::dvec2 uv[3] = {p.uv_origin, p.uv_origin + p.uv_edge_u,
                              p.uv_origin + p.uv_edge_u + p.uv_edge_v};
    const PlaneUvMap m = ObjectSpaceRaster::uv_map(xy, uv, ops);
    const auto f = static_cast<double>(c.focal_px());
    const SampleProjection::Setup ps = SampleProjection::setup(
        r, rp.z, f, static_cast<double>(c.cx()), static_cast<double>(c.cy()), ops);
    const ObjectSpaceRaster raster;
    const double h = raster.step(ObjectSpaceRaster::max_screen_scale({v0, v1, v2}, f, ops), ops);
    ObjectSpaceRasterStats st;
    uint64_t n = 0;
    raster.rasterize(
        rp, h * 8, m,
        [&](const PlaneSample& s) {
          const ProjectedSample q = SampleProjection::project(ps, s.x, s.y, ops);
          ASSERT_TRUE(q.valid);
          const UvSample e = map.at(q.x, q.y);
          EXPECT_NEAR(e.u, s.u, 1e-9);
          EXPECT_NEAR(e.v, s.v, 1e-9);
          EXPECT_NEAR(e.depth, q.depth, 1e-9);
          ++n;
        },
        st, ops);
    EXPECT_GT(n, 20u);
  }
}

// Orthographic cameras: the hole-free rule with the constant screen scale f (one band per
// polygon), no division in the projection, and the exact texture coordinates at each sample.
TEST(ObjectSpaceHard, OrthographicNoHolesOverTiltsAndResolutions) {
  for (const int size : {24, 64, 160}) {
    for (double tilt = 0; tilt <= 85; tilt += 5) {
      for (const double az : {0.0, 33.0}) {
        const ObjectSpaceResult r = render(tilted_scene(size, tilt, az, 2.5, 1, kOrthographic));
        ASSERT_GT(r.resolve.expected, 0u);
        EXPECT_EQ(r.resolve.holes, 0u) << size << " px, tilt " << tilt << ", azimuth " << az;
        EXPECT_EQ(r.bands, 1u);
        expect_finite(r);
      }
    }
  }
}

TEST(ObjectSpaceHard, OrthographicProjectionIsExactWithoutDivision) {
  for (const double tilt : {0.0, 45.0, 80.0}) {
    const Scene scene = tilted_scene(64, tilt, 25, 3, 1, kOrthographic);
    const PlaneProjection map(scene, scene.primitives[0]);
    const Camera& c = scene.camera;
    const ScenePrimitive& p = scene.primitives[0];
    auto view = [](const glm::dvec3& w) { return glm::dvec3(w.x, -w.y, -w.z); };
    const glm::dvec3 v0 = view(p.origin), v1 = view(p.origin + p.edge_u),
                     v2 = view(p.origin + p.edge_u + p.edge_v);
    OpCounts ops;
    const Rotation r = PolygonRotation::setup(PolygonRotation::unit_normal(v0, v1, v2, ops), ops);
    const RotatedPolygon rp =
        PolygonRotation::rotate_polygon(r, {v0, v1, v2, view(p.origin + p.edge_v)}, ops);
    const glm::dvec2 xy[3] = {rp.xy[0], rp.xy[1], rp.xy[2]};
    const glm::dvec2 uv[3] = {p.uv_origin, p.uv_origin + p.uv_edge_u,
                              p.uv_origin + p.uv_edge_u + p.uv_edge_v};
    const PlaneUvMap m = ObjectSpaceRaster::uv_map(xy, uv, ops);
    const auto f = static_cast<double>(c.focal_px());
    const auto cx = static_cast<double>(c.cx()), cy = static_cast<double>(c.cy());
    const SampleProjection::Setup ps =
        SampleProjection::setup_orthographic(r, rp.z, f, cx, cy, ops);
    // The camera's formula for a vertex: xs = cx + f X, ys = cy + f Y, depth Z.
    OpCounts per;
    const ProjectedSample q0 = SampleProjection::project(ps, rp.xy[1].x, rp.xy[1].y, per);
    EXPECT_NEAR(q0.x, cx + f * v1.x, 1e-9);
    EXPECT_NEAR(q0.y, cy + f * v1.y, 1e-9);
    EXPECT_NEAR(q0.depth, v1.z, 1e-9);
    EXPECT_EQ(per.rcp + per.div, 0u);
    const ObjectSpaceRaster raster;
    ObjectSpaceRasterStats st;
    uint64_t n = 0;
    raster.rasterize(
        rp, 8 * raster.step(f, ops), m,
        [&](const PlaneSample& s) {
          const ProjectedSample q = SampleProjection::project(ps, s.x, s.y, ops);
          ASSERT_TRUE(q.valid);
          const UvSample e = map.at(q.x, q.y);
          EXPECT_NEAR(e.u, s.u, 1e-9);
          EXPECT_NEAR(e.v, s.v, 1e-9);
          ++n;
        },
        st, ops);
    EXPECT_GT(n, 20u);
  }
}

TEST(ObjectSpaceHard, OrthographicEdgeOnPlaneDrawsNothing) {
  // A horizontal plane below the view axis contains the (parallel) view direction.
  const ObjectSpaceResult r =
      render(plane_scene(32, 32, {-1, -0.5, -1}, {2, 0, 0}, {0, 0, -2}, kOrthographic));
  EXPECT_EQ(r.edge_on, 1u);
  EXPECT_EQ(r.primitives, 0u);
  EXPECT_EQ(r.samples, 0u);
  expect_finite(r);
}

}  // namespace
}  // namespace texsim
