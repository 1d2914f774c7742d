#pragma once
// The geometry (ПГП) and rasterisation (ПРП) sections of a scene run's report: what the vertex
// transform and each material's rasteriser did and cost (docs/reports.md).
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "blocks/base/op_counts.h"
#include "pipeline/geometry/geometry_unit.h"
#include "pipeline/raster/primitive_raster.h"

namespace texsim {

struct MaterialRaster {
  std::string material;
  std::string block;  // raster.edge or raster.rect_scan
  RasterCounters counters;
  // rect_scan: where its fragments' coordinates came from, "constant_depth" or "exact".
  std::string coords;
  bool parity = false;  // rect_scan with coverage = "outline_parity": its hazards reported
};

struct SubsystemsInfo {
  std::optional<GeometryCounters> geometry;  // absent: fragments came from a trace
  std::vector<MaterialRaster> raster;        // empty: not drawn by the fragment generator
};

nlohmann::ordered_json ops_json(const OpCounts& ops);
void add_subsystems_json(nlohmann::ordered_json& j, const SubsystemsInfo& s);
void subsystems_markdown(std::ostream& md, const SubsystemsInfo& s);

}  // namespace texsim
