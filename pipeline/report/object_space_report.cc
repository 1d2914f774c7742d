#include "pipeline/report/object_space_report.h"

#include <cstdio>

#include "pipeline/report/number_text.h"
#include "pipeline/report/subsystems_report.h"

namespace texsim {

namespace {

using Json = nlohmann::ordered_json;

double ratio(uint64_t a, uint64_t b) {
  return b > 0 ? static_cast<double>(a) / static_cast<double>(b) : 0.0;
}

Json material_json(const ObjectSpaceMaterialInfo& m) {
  const ObjectSpaceResult& r = m.result;
  Json e;
  e["max_step_px"] = m.config.raster.max_step_px;
  e["band_ratio"] = m.config.band_ratio;
  e["lanes"] = m.config.raster.lanes;
  e["primitives"] = r.primitives;
  e["culled"] = r.culled;
  e["clipped_away"] = r.clipped_away;
  e["edge_on"] = r.edge_on;
  e["degenerate"] = r.degenerate;
  e["bands"] = r.bands;
  e["lod_mean"] = r.bands > 0 ? r.lod_sum / static_cast<double>(r.bands) : 0.0;
  e["samples"] = r.samples;
  e["grid_samples"] = r.raster.grid_samples;
  e["edge_samples"] = r.raster.edge_samples;
  e["pixels_shown"] = m.pixels_shown;
  e["samples_per_pixel"] = ratio(r.samples, m.pixels_shown);
  e["cycles"] = {{"total", r.cycles},          {"texture", r.texture_cycles},
                 {"raster", r.raster_cycles},  {"projection", r.projection_cycles},
                 {"splat", r.splat_cycles},    {"setup", r.setup_cycles},
                 {"resolve", r.resolve_cycles}};
  e["ops"] = {{"geometry.polygon_rotation", ops_json(r.rotation_ops)},
              {"raster.object_space", ops_json(r.raster_ops)},
              {"texture", ops_json(r.texture_ops)},
              {"geometry.sample_projection", ops_json(r.projection_ops)},
              {"raster.splat_resolve", ops_json(r.splat_ops)}};
  e["texels"] = r.texels;
  e["cache"] = {{"hits", r.cache.hits},
                {"misses", r.cache.misses},
                {"accesses", r.cache.accesses},
                {"fill_bytes", r.cache.fill_bytes}};
  e["dram_bytes"] = r.dram_bytes;
  e["splat_buffer"] = {{"splat_read_bytes", r.splat.bytes_read},
                       {"splat_written_bytes", r.splat.bytes_written},
                       {"resolve_read_bytes", r.resolve.bytes_read},
                       {"resolve_written_bytes", r.resolve.bytes_written},
                       {"bytes", r.buffer_bytes()},
                       {"targets", r.splat.targets},
                       {"offscreen", r.splat.offscreen},
                       {"depth_resets", r.splat.depth_resets},
                       {"depth_dropped", r.splat.depth_dropped}};
  e["holes"] = {
      {"covered", r.resolve.expected}, {"holes", r.resolve.holes}, {"shown", m.holes_shown}};
  return e;
}

}  // namespace

std::vector<std::string> ObjectSpaceMaterialInfo::blocks() const {
  std::vector<std::string> b = {PolygonRotation().name(), ObjectSpaceRaster().name()};
  b.insert(b.end(), result.texture_blocks.begin(), result.texture_blocks.end());
  b.push_back(SampleProjection().name());
  b.push_back(SplatResolve().name());
  return b;
}

uint64_t ObjectSpaceInfo::cycles() const {
  uint64_t c = 0;
  for (const ObjectSpaceMaterialInfo& m : materials) c += m.result.cycles;
  return c;
}

const ObjectSpaceMaterialInfo* ObjectSpaceInfo::find(const std::string& material) const {
  for (const ObjectSpaceMaterialInfo& m : materials)
    if (m.material == material) return &m;
  return nullptr;
}

void add_object_space_json(Json& j, const ObjectSpaceInfo& info) {
  if (!info.active()) return;
  Json names = Json::array();
  for (const ObjectSpaceMaterialInfo& m : info.materials) {
    j["materials"][m.material]["object_space"] = material_json(m);
    names.push_back(m.material);
  }
  j["object_space"] = {
      {"materials", names},
      {"cycles", info.cycles()},
      {"screen_space_cycles", info.screen_cycles},
      {"frame_cycles", info.frame_cycles()},
      {"visibility",
       "one depth test at pixel centres over every primitive decides what each pixel shows "
       "(the screen-space path's and the reference's); object-space splats are depth-tested "
       "among themselves in their accumulation buffer"}};
}

void object_space_markdown(std::ostream& md, const ObjectSpaceInfo& info) {
  if (!info.active()) return;
  md << "\n## Object space (materials with `object_space`)\n\n"
        "| material | primitives | bands | samples | samples/pixel | mean LOD | cycles | texels | "
        "DRAM bytes | splat-buffer bytes | holes (covered pixels) | holes shown |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const ObjectSpaceMaterialInfo& m : info.materials) {
    const ObjectSpaceResult& r = m.result;
    md << "| " << m.material << " | " << r.primitives << " | " << r.bands << " | " << r.samples
       << " | " << fmt(ratio(r.samples, m.pixels_shown)) << " | "
       << fmt(r.bands > 0 ? r.lod_sum / static_cast<double>(r.bands) : 0.0) << " | " << r.cycles
       << " | " << r.texels << " | " << r.dram_bytes << " | " << r.buffer_bytes() << " | "
       << r.resolve.holes << " (" << r.resolve.expected << ") | " << m.holes_shown << " |\n";
  }
  md << "\nFrame cycles: " << info.cycles() << " object space + " << info.screen_cycles
     << " screen space (the larger of the texture unit's and its rasterisers') = "
     << info.frame_cycles()
     << ". Visibility: one depth test at pixel centres over every primitive decides what each "
        "pixel shows; a pixel won by an object-space material takes its resolved colour.\n";
}

}  // namespace texsim
