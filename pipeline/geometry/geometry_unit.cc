#include "pipeline/geometry/geometry_unit.h"

namespace texsim {

GeometryCounters run_geometry(const Scene& scene, const std::vector<PlaneProjection>& maps) {
  const VertexTransform vt(scene.camera);
  GeometryCounters g;
  uint64_t triangles = 0;
  for (size_t p = 0; p < scene.primitives.size(); ++p) {
    const ScenePrimitive& sp = scene.primitives[p];
    const bool triangle = sp.shape == ScenePrimitive::Shape::Triangle;
    ++g.primitives;
    triangles += triangle ? 1 : 2;
    if (!triangle) g.vertices += 4;
    const glm::dvec3 corners[4] = {sp.origin, sp.origin + sp.edge_u, sp.origin + sp.edge_v,
                                   sp.origin + sp.edge_u + sp.edge_v};
    ScreenVertex v[4];
    int in_front = 0;
    const int n = triangle ? 3 : 4;
    for (int k = 0; k < n; ++k) in_front += vt.to_screen(vt.clip(corners[k]), v[k]) ? 1 : 0;
    const PlaneProjection& m = maps[p];
    if (m.degenerate()) {
      ++g.degenerate;
      continue;
    }
    if (in_front == 0) {
      ++g.behind_eye;
      continue;
    }
    if (in_front < n) ++g.near_clipped;
    if (in_front == n) {
      const bool back = !(VertexTransform::front_area(v) > 0);
      if (back != m.back_facing()) ++g.cull_disagreements;
    }
    if (m.culled()) ++g.culled_back;
  }
  for (const SceneMesh& sm : scene.meshes) g.vertices += sm.vertices;
  g.ops = vt.ops_per_item() * g.vertices + vt.triangle_ops() * triangles;
  const TimingSpec t = vt.timing(scene.tech);
  g.cycles = (g.vertices * t.ii + t.lanes - 1) / t.lanes;
  g.time_ns = static_cast<double>(g.cycles) * 1000.0 / scene.tech.clock_mhz;
  return g;
}

}  // namespace texsim
