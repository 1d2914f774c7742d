// libFuzzer harness: OBJ text, and an optional MTL file after a line "#MTL", through the OBJ
// loader (texsim's scan, tinyobjloader, the checks of what it returns) and the mesh build
// with each uv projection. Bad input must end in InputError; a triangle that refers to no
// vertex or a non-finite position or texture coordinate is a finding like a crash.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "pipeline/scene/obj_loader.h"
#include "testbench/fuzz/fuzz_input.h"

namespace {

using namespace texsim;

void check(const Mesh& m) {
  for (const MeshTriangle& t : m.triangles) {
    for (int k = 0; k < 3; ++k) {
      if (t.v[k] < 0 || static_cast<size_t>(t.v[k]) >= m.positions.size()) std::abort();
      const glm::dvec3& p = m.positions[static_cast<size_t>(t.v[k])];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) std::abort();
      if (!std::isfinite(t.uv[k].x) || !std::isfinite(t.uv[k].y)) std::abort();
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string obj(reinterpret_cast<const char*>(data), size), mtl;
  const size_t cut = obj.find("\n#MTL\n");
  if (cut != std::string::npos) {
    mtl = obj.substr(cut + 6);
    obj.resize(cut + 1);
  }
  // The MTL is m.mtl beside the OBJ (the seeds name it with "mtllib m.mtl").
  static const std::string dir = [] {
    std::string d = texsim::fuzz::write_input(nullptr, 0, ".d");
    std::remove(d.c_str());
    std::filesystem::create_directory(d);
    return d;
  }();
  std::ofstream(dir + "/m.mtl", std::ios::binary | std::ios::trunc) << mtl;
  MeshBudget budget;
  budget.max_bytes = uint64_t{512} << 20;
  budget.bytes_per_triangle = 1024;
  for (const UvProjection p :
       {UvProjection::None, UvProjection::Planar, UvProjection::Box, UvProjection::Spherical}) {
    texsim::fuzz::expect_clean([&] { check(parse_obj(obj, dir + "/fuzz.obj", dir, p, budget)); });
  }
  return 0;
}
