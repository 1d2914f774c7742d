#pragma once
// The geometry subsystem (ПГП) of a scene run: every primitive's corners go through the
// vertex transform (GLM model-view-projection, perspective division, viewport), then the
// back-face test; what it did and cost is counted here. The exact projection of each primitive
// (PlaneProjection, long double) stays the reference the rasteriser and the ground truth use;
// where the double-precision back-face test disagrees with the exact one (edge-on primitives)
// the exact decision is taken and the disagreement counted.
#include <cstdint>
#include <vector>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/geometry/vertex_transform.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/scene/scene.h"

namespace texsim {

struct GeometryCounters {
  // Vertices transformed: a plane's four corners, a mesh's distinct vertices once each (a
  // post-transform vertex cache that holds the whole mesh).
  uint64_t vertices = 0;
  uint64_t primitives = 0;          // in: planes and mesh faces
  uint64_t culled_back = 0;         // back-facing with culling on
  uint64_t degenerate = 0;          // zero area
  uint64_t behind_eye = 0;          // wholly nearer than the near plane
  uint64_t near_clipped = 0;        // crossing the near plane (clipped to it)
  uint64_t cull_disagreements = 0;  // the double back-face test against the exact one
  OpCounts ops;
  uint64_t cycles = 0;  // vertices · II / lanes at the tech table's clock
  double time_ns = 0;
};

GeometryCounters run_geometry(const Scene& scene, const std::vector<PlaneProjection>& maps);

}  // namespace texsim
