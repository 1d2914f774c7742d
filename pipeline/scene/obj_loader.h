#pragma once
// Wavefront OBJ meshes through the packaged tinyobjloader (double precision). texsim first
// reads the file itself for what the library lets through silently — non-finite numbers
// ("nan" parses as 0), face indices out of range, faces with fewer than three corners — so
// every error names the file and line. Polygons are split into fans of triangles.
#include <string>

#include "pipeline/scene/mesh.h"

namespace texsim {

// `path` relative to `base_dir` unless absolute. With `projection` None every face corner
// must have a texture coordinate (`f v/vt`); otherwise the projection supplies them all.
// Throws InputError "FILE:LINE: what" (or "FILE: what" for the file as a whole).
Mesh load_obj(const std::string& path, const std::string& base_dir, UvProjection projection);

}  // namespace texsim
