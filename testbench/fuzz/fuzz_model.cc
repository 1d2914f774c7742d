// libFuzzer harness: a model for [[models]] (model_loader.h), in two modes by the first byte.
// - Below 0x80: the byte picks the format Assimp is told (OBJ, 3DS, glTF, MD3, PLY, STL), the
//   rest is the file, read from memory (nothing else is opened), imported as texsim does: in a
//   child process. A child killed by a signal or timed out is Assimp's crash, made an error
//   (testbench/fuzz/known-crashes); a child that exits otherwise or sends a stream its parent
//   refuses is a finding. When the child survived, the import runs again in this process, so
//   the fuzzer sees the coverage of Assimp and texsim's conversion (a child's is lost to it):
//   it must give the same model or the same message. Then every uv projection.
// - 0x80 and above: the rest is the child's stream itself (model_stream.h), fed to the
//   parent's strict reader; what it accepts is written and read again, unchanged.
// Bad input must end in InputError; a triangle that refers to no vertex or no material, or a
// non-finite position or texture coordinate, is a finding like a crash.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "blocks/base/input_error.h"
#include "pipeline/scene/isolated_child.h"
#include "pipeline/scene/model_loader.h"
#include "pipeline/scene/model_stream.h"
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

bool same(const Model& a, const Model& b) {
  if (a.mesh.has_uvs != b.mesh.has_uvs || a.mesh.positions != b.mesh.positions ||
      a.triangle_material != b.triangle_material || a.materials.size() != b.materials.size() ||
      a.mesh.triangles.size() != b.mesh.triangles.size())
    return false;
  for (size_t i = 0; i < a.materials.size(); ++i) {
    if (a.materials[i].name != b.materials[i].name ||
        a.materials[i].texture != b.materials[i].texture)
      return false;
  }
  for (size_t i = 0; i < a.mesh.triangles.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      if (a.mesh.triangles[i].v[k] != b.mesh.triangles[i].v[k] ||
          a.mesh.triangles[i].uv[k] != b.mesh.triangles[i].uv[k])
        return false;
    }
  }
  return true;
}

MeshBudget fuzz_budget() {
  MeshBudget budget;
  budget.max_bytes = uint64_t{512} << 20;
  budget.bytes_per_triangle = 1024;
  return budget;
}

void fuzz_import(const std::string& bytes, const char* hint) {
  const std::string file = std::string("fuzz.") + hint;
  Model isolated;
  std::string error;
  try {
    isolated = parse_model(bytes, hint, file, fuzz_budget());
  } catch (const ChildFailure& e) {
    if (e.kind == ChildFailure::Kind::Signal || e.kind == ChildFailure::Kind::Timeout) return;
    std::fprintf(stderr, "the child failed otherwise: %s\n", e.what());
    std::abort();
  } catch (const InputError& e) {
    error = e.what();
  }
  texsim::fuzz::expect_clean([&] {
    try {
      Model m = parse_model(bytes, hint, file, fuzz_budget(), ImportIn::ThisProcess);
      if (!error.empty() || !same(m, isolated)) {
        std::fprintf(stderr, "in-process model differs from the child's (%s)\n", error.c_str());
        std::abort();
      }
    } catch (const InputError& e) {
      if (error != e.what()) {
        std::fprintf(stderr, "in-process: '%s', the child's: '%s'\n", e.what(), error.c_str());
        std::abort();
      }
      throw;
    }
    check(isolated);
    for (const UvProjection p :
         {UvProjection::Planar, UvProjection::Box, UvProjection::Spherical}) {
      Model q = isolated;
      project_uvs(q.mesh, p);
      check(q);
    }
  });
}

void fuzz_stream(const std::string& bytes) {
  texsim::fuzz::expect_clean([&] {
    StringSource in(bytes);
    const ModelMessage m = read_model_message(in, "fuzz.stream", "the importer", fuzz_budget());
    if (!m.failed) check(m.model);
    StringSink again;
    write_model_message(again, m);
    StringSource back(again.bytes);
    const ModelMessage n = read_model_message(back, "fuzz.stream", "the importer", fuzz_budget());
    if (n.opened != m.opened || n.failed != m.failed || n.error != m.error ||
        !same(n.model, m.model))
      std::abort();
  });
}

}  // namespace

// Memory Assimp itself leaks on some malformed files is not texsim's: texsim imports in a child
// process that exits (isolated_child.h), so such a leak ends with it. Only the in-process import
// above, run for the fuzzer's coverage, can see one; LeakSanitizer is told to ignore allocations
// made inside Assimp, and still reports every other leak.
extern "C" const char* __lsan_default_suppressions() { return "leak:libassimp.so\n"; }

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const std::string bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  if (data[0] >= 0x80) {
    fuzz_stream(bytes);
  } else {
    static const char* const kHints[] = {"obj", "3ds", "gltf", "md3", "ply", "stl"};
    fuzz_import(bytes, kHints[data[0] % 6]);
  }
  return 0;
}
