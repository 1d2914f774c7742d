#include "pipeline/report/subsystems_report.h"

namespace texsim {

using Json = nlohmann::ordered_json;

Json ops_json(const OpCounts& ops) {
  Json e;
  for (int k = 0; k < kOpKinds; ++k)
    e[std::string(kOpKindNames[k])] = ops.get(static_cast<OpKind>(k));
  return e;
}

void add_subsystems_json(Json& j, const SubsystemsInfo& s) {
  if (s.geometry) {
    const GeometryCounters& g = *s.geometry;
    j["geometry"] = {{"block", "geometry.vertex_transform"},
                     {"vertices", g.vertices},
                     {"primitives", g.primitives},
                     {"culled_back", g.culled_back},
                     {"degenerate", g.degenerate},
                     {"behind_eye", g.behind_eye},
                     {"near_clipped", g.near_clipped},
                     {"cull_disagreements", g.cull_disagreements},
                     {"cycles", g.cycles},
                     {"time_ns", g.time_ns},
                     {"ops", ops_json(g.ops)}};
  }
  for (const MaterialRaster& m : s.raster) {
    const RasterCounters& c = m.counters;
    Json e = {{"block", m.block},
              {"primitives", c.primitives},
              {"triangles", c.triangles},
              {"rejected", c.rejected},
              {"rows", c.rows},
              {"pixels_visited", c.pixels_visited},
              {"pixels_covered", c.pixels_covered},
              {"quads", c.quads},
              {"helper_lanes", c.helper_lanes},
              {"time_ns", c.time_ns},
              {"ops", ops_json(c.ops)}};
    if (m.block == "raster.rect_scan") {
      e["divisions"] = c.divisions;
      e["divisions_per_triangle"] =
          c.triangles ? static_cast<double>(c.divisions) / static_cast<double>(c.triangles) : 0.0;
      e["fast_cycles"] = c.fast_cycles;
      e["memory_cycles"] = c.memory_cycles;
      // The constant-depth coordinate block on the rows (ops per frame: runs add frames up).
      e["coords"] = m.coords;
      e["coord_pixels"] = c.coord_pixels;
      e["coord_rejected"] = c.coord_rejected;
      e["coord_ops"] = ops_json(c.coord_ops);
      if (m.parity) {
        const ParityHazards& h = c.hazards;
        e["parity_hazards"] = {
            {"extra_pixels", h.extra_pixels}, {"missed_pixels", h.missed_pixels},
            {"vertex_rows", h.vertex_rows},   {"touching_rows", h.touching_rows},
            {"run_rows", h.run_rows},         {"missed_crossing_rows", h.missed_crossing_rows}};
      }
    } else {
      e["cycles"] = c.cycles;
    }
    j["raster"][m.material] = e;
  }
}

void subsystems_markdown(std::ostream& md, const SubsystemsInfo& s) {
  if (s.geometry) {
    const GeometryCounters& g = *s.geometry;
    md << "\n## Geometry (ПГП)\n\n| vertices | primitives | culled (back) | degenerate | behind "
          "the eye | near-clipped | cull disagreements | cycles | ops |\n"
          "|---|---|---|---|---|---|---|---|---|\n| "
       << g.vertices << " | " << g.primitives << " | " << g.culled_back << " | " << g.degenerate
       << " | " << g.behind_eye << " | " << g.near_clipped << " | " << g.cull_disagreements << " | "
       << g.cycles << " | " << g.ops.total() << " |\n";
  }
  if (s.raster.empty()) return;
  md << "\n## Rasterisation (ПРП), per material, before the depth test (quads: after it)\n\n| "
        "material | block | primitives | triangles | rows | pixels visited | pixels covered | "
        "quads | helper lanes | divisions | cycles (fast / memory clock) | time (ns) "
        "|\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const MaterialRaster& m : s.raster) {
    const RasterCounters& c = m.counters;
    const bool rs = m.block == "raster.rect_scan";
    md << "| " << m.material << " | " << m.block << " | " << c.primitives << " | " << c.triangles
       << " | " << c.rows << " | " << c.pixels_visited << " | " << c.pixels_covered << " | "
       << c.quads << " | " << c.helper_lanes << " | " << (rs ? std::to_string(c.divisions) : "—")
       << " | "
       << (rs ? std::to_string(c.fast_cycles) + " / " + std::to_string(c.memory_cycles)
              : std::to_string(c.cycles))
       << " | " << static_cast<uint64_t>(c.time_ns) << " |\n";
  }
}

}  // namespace texsim
