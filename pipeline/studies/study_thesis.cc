#include "pipeline/studies/study_thesis.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <stdexcept>

#include "blocks/base/tech_table.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/texture_loader.h"
#include "pipeline/studies/study_filter_methods.h"
#include "pipeline/studies/study_table.h"

namespace texsim {

namespace {

std::string fmt(double v, const char* f = "%.4g") {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

std::string pct(double v) {
  if (!std::isfinite(v)) return "—";
  return fmt(100.0 * v, "%+.1f") + " %";
}

// NMSE sums of image a against image b over RGB.
void nmse_sums(const std::vector<Rgba>& a, const std::vector<Rgba>& b, double& se, double& sref) {
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const double e = static_cast<double>(a[i][c]) - b[i][c];
      se += e * e;
      sref += static_cast<double>(b[i][c]) * b[i][c];
    }
  }
}

// The pairs the study reports: each map against its computed weights, and the thesis's
// computed weights against the exact ones of the same (no-reconstruction) configuration.
const std::vector<std::pair<std::string, std::string>>& nmse_pairs() {
  static const std::vector<std::pair<std::string, std::string>> pairs = {
      {"texsim map", "texsim computed"},
      {"thesis map", "thesis computed"},
      {"exact, no reconstruction, map jacobian", "exact, no reconstruction, computed"},
      {"thesis map", "exact, no reconstruction, computed"},
      {"thesis computed", "exact, no reconstruction, computed"},
  };
  return pairs;
}

struct Accum {
  std::map<std::string, ThesisMethodFigures> methods;
  std::map<std::pair<std::string, std::string>, std::pair<double, double>> sums;
};

void measure_into(TextureSet& textures, const std::vector<Fragment>& fragments, Accum& acc) {
  const TechTable tech = TechTable::defaults();
  std::map<std::string, std::vector<Rgba>> images;
  for (const StudyFilterMethod& m : thesis_filter_methods()) {
    const StudyFilterRun r4 = run_study_filter_method(m, textures, fragments, tech);
    const StudyFilterRun r16 =
        run_study_filter_method(m, textures, fragments, tech, nullptr, ShaderIssue::rx460());
    ThesisMethodFigures& f = acc.methods[m.name];
    f.method = m.name;
    f.fragments += fragments.size();
    f.texels += r4.tally.texels;
    f.cycles += r4.cycles;
    f.shader_4to1 += r4.tally.shader_cycles;
    f.shader_16to1 += r16.tally.shader_cycles;
    images[m.name] = r4.colours;
  }
  for (const auto& p : nmse_pairs()) {
    auto& [se, sref] = acc.sums[p];
    nmse_sums(images.at(p.first), images.at(p.second), se, sref);
  }
}

ThesisFigures figures_of(const std::string& source, const Accum& acc) {
  ThesisFigures out;
  out.source = source;
  for (const StudyFilterMethod& m : thesis_filter_methods())
    out.methods.push_back(acc.methods.at(m.name));
  for (const auto& p : nmse_pairs()) {
    const auto& [se, sref] = acc.sums.at(p);
    out.nmse.push_back({p.first, p.second, sref > 0 ? se / sref : 0.0});
  }
  return out;
}

// Every [[planes]] entry's pixels (hidden or not: each method filters the same fragments),
// grouped by the texture of the plane's material, so each group runs on its own texture.
Accum measure_scene(const std::string& path, std::ostream& log) {
  const Scene scene = load_scene(path);
  std::map<int, std::vector<Fragment>> by_texture;
  for (const ScenePrimitive& prim : scene.primitives) {
    if (prim.mesh >= 0) continue;
    const PlaneProjection proj(scene, prim);
    if (proj.culled()) continue;
    std::vector<Fragment>& frags =
        by_texture[scene.materials[static_cast<size_t>(prim.material)].texture];
    const std::vector<Fragment> more = pixel_fragments(proj, scene.width, scene.height);
    frags.insert(frags.end(), more.begin(), more.end());
  }
  Accum acc;
  for (auto& [tex, frags] : by_texture) {
    TextureSet set;
    set.add(load_scene_texture(scene, static_cast<size_t>(tex)));
    set.place(TexelLayout::Tiled4x4);
    log << "  " << path << ": texture " << scene.textures[static_cast<size_t>(tex)].name << ", "
        << frags.size() << " fragments\n";
    measure_into(set, frags, acc);
  }
  return acc;
}

double per(double v, uint64_t n) { return n ? v / static_cast<double>(n) : 0.0; }

// cycles(base)/cycles(x) − 1 under the three models.
struct Gain {
  double pipelined = 0, s4 = 0, s16 = 0;
};
Gain gain(const ThesisFigures& f, const std::string& base, const std::string& x) {
  const ThesisMethodFigures &b = f.at(base), &m = f.at(x);
  return {static_cast<double>(b.cycles) / static_cast<double>(m.cycles) - 1,
          b.shader_4to1 / m.shader_4to1 - 1, b.shader_16to1 / m.shader_16to1 - 1};
}

void write_source(std::ostream& md, StudyTable& csv, const ThesisFigures& f) {
  md << "## " << f.source << "\n\n";
  StudyTable t({"method", "fragments", "texels/frag", "cycles/frag (pipelined)",
                "shader cycles/frag 4:1", "shader cycles/frag 16:1"},
               "lrrrrr");
  for (const ThesisMethodFigures& m : f.methods) {
    const std::vector<std::string> cells = {m.method,
                                            std::to_string(m.fragments),
                                            fmt(per(static_cast<double>(m.texels), m.fragments)),
                                            fmt(per(static_cast<double>(m.cycles), m.fragments)),
                                            fmt(per(m.shader_4to1, m.fragments)),
                                            fmt(per(m.shader_16to1, m.fragments))};
    t.add(cells);
    std::vector<std::string> row = {"\"" + f.source + "\"", "\"" + m.method + "\""};
    row.insert(row.end(), cells.begin() + 1, cells.end());
    csv.add(row);
  }
  md << t.markdown() << "\n";
  StudyTable n({"image", "against", "NMSE", "seed"}, "llrr");
  for (const ThesisFigures::Pair& p : f.nmse) n.add({p.image, p.against, fmt(p.nmse), "0.000708"});
  md << "NMSE (Σ(a − b)²/Σb² over RGB):\n\n" << n.markdown() << "\n";
  StudyTable g({"claim", "configuration", "baseline → method", "pipelined", "shader 4:1",
                "shader 16:1", "seed"},
               "lllrrrr");
  for (const std::string tag : {"texsim", "thesis"}) {
    const Gain a = gain(f, tag + " computed", tag + " map");
    g.add({"weight maps: speed-up", tag, "computed → map", pct(a.pipelined), pct(a.s4), pct(a.s16),
           "+25 %"});
    const Gain b = gain(f, tag + " computed + edge V(d) P2 fx16", tag + " map");
    g.add({"weight maps: speed-up", tag, "computed + edge V(d) → map", pct(b.pipelined), pct(b.s4),
           pct(b.s16), "+25 %"});
    const Gain c = gain(f, tag + " computed", tag + " uniform");  // = cost of computing
    g.add({"computed weights: slow-down", tag, "uniform → computed", pct(c.pipelined), pct(c.s4),
           pct(c.s16), "≤ 5 %"});
  }
  const Gain s = gain(f, "spaf V(d) P2 fx16, budget 64", "texsim map");
  g.add({"weight maps: speed-up", "texsim", "SPAF V(d) coverage → map", pct(s.pipelined), pct(s.s4),
         pct(s.s16), "+25 %"});
  md << "Speed (cycles(baseline)/cycles(method) − 1; a slow-down is cycles(computed)/"
        "cycles(uniform) − 1):\n\n"
     << g.markdown() << "\n";
}

}  // namespace

const ThesisMethodFigures& ThesisFigures::at(const std::string& method) const {
  for (const ThesisMethodFigures& m : methods) {
    if (m.method == method) return m;
  }
  throw std::out_of_range("thesis study: no method " + method);
}

ThesisFigures measure_thesis(const std::string& source, TextureSet& textures,
                             const std::vector<Fragment>& fragments) {
  Accum acc;
  measure_into(textures, fragments, acc);
  return figures_of(source, acc);
}

int run_study_thesis(const std::string& out_dir, std::ostream& log, const StudyThesisOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  const StudyFiles files(out_dir);
  std::ostringstream md;
  md << "# The thesis configuration beside texsim's (docs/studies/thesis-configuration.md)\n\n"
     << "Shader-like issue model: ALU ops and texture fetches per cycle 16 : 4 (4 : 1, the "
        "filter study's) and 64 : 4 (16 : 1, the Radeon RX 460's 896 ALU lanes : 56 texture "
        "units).\n\n";
  StudyTable csv({"source", "method", "fragments", "texels_per_fragment", "cycles_per_fragment",
                  "shader_cycles_per_fragment_4to1", "shader_cycles_per_fragment_16to1"});
  for (const std::string& path : opt.scenes) {
    const ThesisFigures f = figures_of(path, measure_scene(path, log));
    write_source(md, csv, f);
  }
  files.text("thesis.md", md.str());
  files.csv("thesis.csv", csv);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log << "study thesis: wrote " << out_dir << "/thesis.md, thesis.csv in " << fmt(secs, "%.3g")
      << " s\n";
  return 0;
}

}  // namespace texsim
