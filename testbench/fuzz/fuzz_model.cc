// libFuzzer harness: a model for [[models]] through Assimp and texsim's conversion of it
// (model_loader.h): the first byte picks the format Assimp is told (OBJ, 3DS, glTF, MD3, PLY,
// STL), the rest is the file, read from memory (nothing else is opened). Then every uv
// projection. Bad input must end in InputError; a triangle that refers to no vertex or no
// material, or a non-finite position or texture coordinate, is a finding like a crash. The
// target is texsim's conversion and its limits: Assimp's parsers are Debian's, and a finding
// inside one is reported to Assimp rather than worked around here (docs/scenes.md#models).
#include <cmath>
#include <cstdlib>
#include <string>

#include "blocks/base/input_error.h"
#include "pipeline/scene/model_loader.h"
#include "testbench/fuzz/fuzz_input.h"

namespace {

using namespace texsim;

void check(const Model& m) {
  if (m.triangle_material.size() != m.mesh.triangles.size()) std::abort();
  for (size_t i = 0; i < m.mesh.triangles.size(); ++i) {
    const MeshTriangle& t = m.mesh.triangles[i];
    const int mat = m.triangle_material[i];
    if (mat < 0 || static_cast<size_t>(mat) >= m.materials.size()) std::abort();
    for (int k = 0; k < 3; ++k) {
      if (t.v[k] < 0 || static_cast<size_t>(t.v[k]) >= m.mesh.positions.size()) std::abort();
      const glm::dvec3& p = m.mesh.positions[static_cast<size_t>(t.v[k])];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) std::abort();
      if (!std::isfinite(t.uv[k].x) || !std::isfinite(t.uv[k].y)) std::abort();
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const char* const kHints[] = {"obj", "3ds", "gltf", "md3", "ply", "stl"};
  const char* hint = kHints[data[0] % 6];
  const std::string bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  MeshBudget budget;
  budget.max_bytes = uint64_t{512} << 20;
  budget.bytes_per_triangle = 1024;
  texsim::fuzz::expect_clean([&] {
    Model m = parse_model(bytes, hint, std::string("fuzz.") + hint, budget);
    check(m);
    for (const UvProjection p :
         {UvProjection::Planar, UvProjection::Box, UvProjection::Spherical}) {
      Model q = m;
      project_uvs(q.mesh, p);
      check(q);
    }
  });
  return 0;
}
