#pragma once
// Near/far-plane clipper of the geometry subsystem (ПГП): Sutherland–Hodgman against one
// plane of constant view-space depth (docs/derivations/coords-derivations.md, "Scenes").
#include <vector>

#include "blocks/geometry/projective_map.h"

namespace texsim {

// Clip of a view-space polygon against Z >= z (keep_above) or Z <= z.
std::vector<Vec3L> clip_polygon_z(const std::vector<Vec3L>& poly, long double z, bool keep_above);

}  // namespace texsim
