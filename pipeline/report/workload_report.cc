#include "pipeline/report/workload_report.h"

#include <bit>
#include <cstdio>
#include <map>
#include <vector>

#include "pipeline/report/number_text.h"
#include "traces/trace_file.h"

namespace texsim {

namespace {

using Json = nlohmann::ordered_json;

template <size_t N>
Json array_json(const std::array<uint64_t, N>& a) {
  Json j = Json::array();
  for (uint64_t v : a) j.push_back(v);
  return j;
}

const char* const kAnisoNames[] = {"1", "2", "4", "8", "16", ">16"};

}  // namespace

Json workload_frame_json(const FrameWorkload& f) {
  const double frags = static_cast<double>(f.fragments);
  Json j;
  j["frame"] = f.frame;
  j["fragments"] = f.fragments;
  j["quads"] = f.quads;
  j["textures"] = f.textures;
  j["texels_level0"] = f.texels_level0;
  j["texels_lod"] = f.texels_lod;
  j["texels_per_fragment"] = f.per_fragment(static_cast<double>(f.texels_lod));
  j["footprint_texels_per_fragment"] = f.per_fragment(f.footprint_texels);
  j["lines"] = array_json(f.lines);
  Json bytes = Json::array();
  for (size_t k = 0; k < f.lines.size(); ++k)
    bytes.push_back(f.lines[k] * static_cast<uint64_t>(FrameWorkload::kLineBytes[k]));
  j["working_set_bytes"] = bytes;
  j["lod_under"] = f.lod_under;
  j["lod"] = array_json(f.lod);
  j["lod_over"] = f.lod_over;
  j["aniso"] = array_json(f.aniso);
  j["magnified"] = f.magnified;
  j["minified"] = f.minified;
  j["magnified_share"] = frags > 0 ? static_cast<double>(f.magnified) / frags : 0.0;
  j["line_uses"] = f.line_uses;
  j["first_uses"] = f.first_uses;
  j["untracked_uses"] = f.untracked_uses;
  j["reuse"] = array_json(f.reuse);
  return j;
}

void add_workload_json(Json& j, const WorkloadStats& w) {
  Json& e = j["workload"];
  e["layout"] = w.layout();
  e["line_bytes"] = FrameWorkload::kLineBytes;
  e["lod_lo"] = FrameWorkload::kLodLo;
  e["lod_step"] = FrameWorkload::kLodStep;
  e["aniso_bins"] = kAnisoNames;
  e["reuse_line_bytes"] = FrameWorkload::kReuseLineBytes;
  e["reuse_max_lines"] = ReuseDistance::kMaxLines;
  e["total"] = workload_frame_json(w.total());
  e["frames"] = Json::array();
  for (const FrameWorkload& f : w.frames()) e["frames"].push_back(workload_frame_json(f));
}

double reuse_within(const FrameWorkload& f, uint64_t lines) {
  uint64_t all = 0, within = 0;
  for (size_t b = 0; b < f.reuse.size(); ++b) {
    all += f.reuse[b];
    // Bin b holds distances below 2^b (bin 0: distance 0).
    if ((uint64_t{1} << b) <= lines) within += f.reuse[b];
  }
  return all > 0 ? static_cast<double>(within) / static_cast<double>(all) : 0.0;
}

void workload_markdown(std::ostream& md, const WorkloadStats& w) {
  md << "\n## Workload\n\nWhat the fragments ask of a texture unit, whatever its configuration "
        "(docs/reports.md \"workload\"): bilinear footprints at level 0 and at the level nearest "
        "to the isotropic λ, lines at "
     << w.layout()
     << " addresses; reuse distance in distinct 64-byte lines within the frame.\n\n"
        "| frame | fragments | quads | textures | texels (level 0) | texels (λ level) | "
        "texels/fragment | lines 32 B | lines 64 B | lines 128 B | magnified | reuse < 256 "
        "lines |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  auto row = [&](const std::string& name, const FrameWorkload& f) {
    md << "| " << name << " | " << f.fragments << " | " << f.quads << " | " << f.textures << " | "
       << f.texels_level0 << " | " << f.texels_lod << " | "
       << fmt(f.per_fragment(static_cast<double>(f.texels_lod))) << " | " << f.lines[0] << " | "
       << f.lines[1] << " | " << f.lines[2] << " | "
       << fmt(100 * f.per_fragment(static_cast<double>(f.magnified))) << "% | "
       << fmt(100 * reuse_within(f, 256)) << "% |\n";
  };
  size_t n = 0;
  for (const FrameWorkload& f : w.frames()) {
    if (n++ == 16) {
      md << "| … | | | | | | | | | | | |\n";
      break;
    }
    row(std::to_string(f.frame), f);
  }
  const FrameWorkload t = w.total();
  if (w.frames().size() > 1) row("all (distinct counts summed over frames)", t);
  md << "\nLOD λ (bins of " << FrameWorkload::kLodStep << " from " << FrameWorkload::kLodLo
     << "): below " << t.lod_under << ",";
  for (uint64_t c : t.lod) md << " " << c;
  md << ", from " << FrameWorkload::kLodLo + FrameWorkload::kLodStep * FrameWorkload::kLodBins
     << " " << t.lod_over << ". Anisotropy (η rounded to a power of two):";
  for (size_t k = 0; k < t.aniso.size(); ++k) md << " " << kAnisoNames[k] << ": " << t.aniso[k];
  md << ". Footprint: " << fmt(t.per_fragment(t.footprint_texels))
     << " level-0 texels per fragment. Line uses " << t.line_uses << ", first uses "
     << t.first_uses;
  if (t.untracked_uses > 0) md << ", untracked " << t.untracked_uses;
  md << "; reuse distances (bins 0, [1,2), [2,4), …):";
  for (uint64_t c : t.reuse) md << " " << c;
  md << ".\n";
}

WorkloadStats trace_workload(const std::string& path) {
  TraceReader reader(path);
  std::vector<std::array<int, 2>> sizes;
  std::map<uint32_t, uint32_t> index;
  for (const TraceTexture& t : reader.header().textures) {
    index[t.id] = static_cast<uint32_t>(sizes.size());
    sizes.push_back({static_cast<int>(t.width), static_cast<int>(t.height)});
  }
  WorkloadStats w(place_workload_textures(sizes, TexelLayout::Tiled4x4));
  std::vector<Fragment> chunk;
  // The reader has checked every texture id against the table.
  while (reader.next_chunk(chunk) > 0)
    for (const Fragment& f : chunk) w.add(f, index.at(f.tex));
  w.finish();
  return w;
}

void print_trace_workload(const std::string& path, std::ostream& out) {
  const WorkloadStats w = trace_workload(path);
  if (w.frames().empty()) return;
  out << "workload:   tiled4x4 addresses, full RGBA8 mip chains (docs/reports.md \"workload\")\n";
  auto line = [&](const std::string& name, const FrameWorkload& f) {
    out << "  " << name << ": " << f.fragments << " fragments, " << f.quads << " quads, "
        << f.textures << " textures, distinct texels " << f.texels_level0 << " (level 0) "
        << f.texels_lod << " (λ level), " << fmt(f.per_fragment(static_cast<double>(f.texels_lod)))
        << " texels/fragment, lines " << f.lines[0] << "/" << f.lines[1] << "/" << f.lines[2]
        << " (32/64/128 B), magnified "
        << fmt(100 * f.per_fragment(static_cast<double>(f.magnified)))
        << "%, reuse below 256 lines " << fmt(100 * reuse_within(f, 256)) << "%\n";
  };
  size_t n = 0;
  for (const FrameWorkload& f : w.frames()) {
    if (n++ == 16) {
      out << "  ...\n";
      break;
    }
    line("frame " + std::to_string(f.frame), f);
  }
  const FrameWorkload t = w.total();
  if (w.frames().size() > 1) line("all frames", t);
  out << "  LOD λ (0.5 bins from " << FrameWorkload::kLodLo << "): below " << t.lod_under << ",";
  for (uint64_t c : t.lod) out << " " << c;
  out << ", above " << t.lod_over << "\n  anisotropy:";
  for (size_t k = 0; k < t.aniso.size(); ++k) out << " " << kAnisoNames[k] << ": " << t.aniso[k];
  out << "\n  footprint: " << fmt(t.per_fragment(t.footprint_texels))
      << " level-0 texels per fragment\n  reuse distance (64 B lines; bins 0, [1,2), [2,4), ...): "
      << t.line_uses << " uses, " << t.first_uses << " first";
  if (t.untracked_uses > 0) out << ", " << t.untracked_uses << " untracked";
  out << ";";
  for (uint64_t c : t.reuse) out << " " << c;
  out << "\n";
}

}  // namespace texsim
