#include "pipeline/studies/study_filters.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <sstream>
#include <thread>

#include "blocks/base/tech_table.h"
#include "blocks/texture/footprint/ewa_filter.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/kernel/parallel_range.h"
#include "pipeline/reference/footprint_reference.h"
#include "pipeline/reference/ground_truth.h"
#include "pipeline/report/image_metrics.h"
#include "pipeline/scene/procedural_texture.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/texture_loader.h"
#include "pipeline/studies/study_filter_methods.h"
#include "pipeline/studies/study_filters_report.h"

namespace texsim {

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string fmt_g(double v, int prec = 4) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", prec, v);
  return buf;
}

// One view: a plane tilted by θ = acos(1/N) about the screen's x axis, seen by a camera with a
// 20° field of view, so the footprint's anisotropy at the image centre is N. The plane spans
// depths D/2 … 2D along its receding axis (no horizon: footprints stay finite) and its texture
// scale puts `tpp` level-0 texels per pixel on the minor axis at the centre.
std::string view_scene_text(double aniso, int size, double tpp, int tex_size) {
  const double D = 10.0;
  const double theta = std::acos(1.0 / aniso);
  const double cs = std::cos(theta), sn = std::sin(theta);
  const double su = 0.8 * D, sv = 1.5 * D;
  const double pixel = 2.0 * D * std::tan(10.0 * kPi / 180.0) / size;  // world size at depth D
  const double texel = pixel / tpp;
  const double ox = -su / 2, oy = -0.5 * D * cs, oz = -D + 0.5 * D * sn;
  std::ostringstream s;
  s.precision(17);
  s << "[output]\nwidth = " << size << "\nheight = " << size << "\nbackground = [0.0, 0.0, 0.0]\n"
    << "[camera]\nposition = [0.0, 0.0, 0.0]\nlook_at = [0.0, 0.0, -1.0]\nup = [0.0, 1.0, 0.0]\n"
    << "fov_y = 20.0\nnear = 0.01\n"
    << "[textures.t]\nsource = \"procedural:checker?size=4\"\n"
    << "[materials.m]\ntexture = \"t\"\n"
    << "[[planes]]\nmaterial = \"m\"\norigin = [" << ox << ", " << oy << ", " << oz << "]\n"
    << "edge_u = [" << su << ", 0.0, 0.0]\nedge_v = [0.0, " << sv * cs << ", " << -sv * sn << "]\n"
    << "uv_scale = [" << su / (texel * tex_size) << ", " << sv / (texel * tex_size) << "]\n";
  return s.str();
}

struct StudyTexture {
  std::string name;  // "checker", "photo", "noise"
  std::string source;
  TextureSet set;  // the one texture, as the texture unit reads it
};

// Textures: a checkerboard (sharp edges), a photo, high-frequency noise.
std::vector<StudyTexture> study_textures() {
  std::vector<StudyTexture> textures;
  textures.push_back({"checker", "procedural:checker?size=256&cells=16", {}});
  textures.push_back({"photo", "/usr/share/glmark2/textures/crate-base.png", {}});
  textures.push_back({"noise", "procedural:noise?size=256&cells=32", {}});
  for (StudyTexture& t : textures) {
    t.set.add(is_procedural_source(t.source) ? make_procedural_texture(t.source, "study filters")
                                             : load_texture(t.source, ""));
    t.set.place(TexelLayout::Tiled4x4);
  }
  return textures;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t i = std::min(
      v.size() - 1, static_cast<size_t>(std::llround(p * static_cast<double>(v.size() - 1))));
  return v[i];
}

void sums_vs(const ImageRgb& img, const ImageRgb& ref, double& se, double& sref) {
  se = sref = 0;
  for (size_t i = 0; i < img.covered.size(); ++i) {
    if (!img.covered[i]) continue;
    for (size_t c = 0; c < 3; ++c) {
      const double e = static_cast<double>(img.rgb[i * 3 + c]) - ref.rgb[i * 3 + c];
      se += e * e;
      sref += static_cast<double>(ref.rgb[i * 3 + c]) * ref.rgb[i * 3 + c];
    }
  }
}

// The box pixel's samples for a footprint spanning (ex, ey) level-0 texels per pixel along the
// screen axes: the density of the Gaussian reference (samples_per_texel per texel, at least
// min_samples per axis, at most max_total per pixel), over the pixel's square instead of ±R.
const PixelSamples& box_samples(const FootprintReferenceConfig& rc, double ex, double ey,
                                std::map<std::pair<int, int>, PixelSamples>& cache) {
  auto count = [&](double e) {
    const double n = std::isfinite(e) ? std::ceil(rc.samples_per_texel * e)
                                      : static_cast<double>(rc.max_samples);
    return static_cast<int>(
        std::clamp(n, static_cast<double>(rc.min_samples), static_cast<double>(rc.max_samples)));
  };
  int nx = count(ex), ny = count(ey);
  const double total = static_cast<double>(nx) * ny;
  if (total > static_cast<double>(rc.max_total)) {
    const double k = std::sqrt(static_cast<double>(rc.max_total) / total);
    nx = std::max(1, static_cast<int>(nx * k));
    ny = std::max(1, static_cast<int>(ny * k));
  }
  PixelSamples& s = cache[{nx, ny}];
  if (s.w.empty()) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        s.x.push_back((i + 0.5) / nx);
        s.y.push_back((j + 0.5) / ny);
        s.w.push_back(1.0);
      }
    }
    s.weight_sum = static_cast<double>(nx) * ny;
  }
  return s;
}

// One view of one texture: its fragments, the two ground truths and the anisotropy spread.
struct View {
  size_t texture = 0;  // index into the study's textures
  double nominal = 0;
  Scene scene;  // the view's plane and camera (what a renderer peer draws)
  std::vector<Fragment> frags;
  ImageRgb ref;      // Gaussian pixel (σ = 0.5 px, R = 1 px): the study's main truth
  ImageRgb ref_box;  // box pixel (the pixel's square)
  double p50 = 0, p90 = 0;
  double seconds[2] = {0, 0};  // time of the Gaussian and the box truth
};

View make_view(const std::vector<StudyTexture>& textures, size_t ti, double nominal,
               const StudyFiltersOptions& opt) {
  const Texture& tex = textures[ti].set[0];
  const Scene scene =
      parse_scene(view_scene_text(nominal, opt.size, opt.texels_per_pixel, tex.width(0)),
                  "study filters view", "");
  const PlaneProjection proj(scene, scene.primitives[0]);
  View v{ti,
         nominal,
         scene,
         pixel_fragments(proj, opt.size, opt.size),
         ImageRgb(opt.size, opt.size, scene.background),
         ImageRgb(opt.size, opt.size, scene.background),
         0,
         0,
         {0, 0}};
  std::vector<double> anisos;
  for (const Fragment& f : v.frags) {
    OpCounts scratch;
    anisos.push_back(
        footprint_setup<double>(f, tex.width(0), tex.height(0), 1.0, 1e12, scratch).aniso);
  }
  v.p50 = percentile(anisos, 0.5);
  v.p90 = percentile(anisos, 0.9);
  return v;
}

// One of the view's ground truths: the Gaussian pixel (footprint_reference) or the box pixel
// (the pixel's square, as `[reference] pixel = box` in `texsim run`), at the same density.
void make_truth(View& v, const Texture& tex, bool box) {
  const auto t0 = std::chrono::steady_clock::now();
  const PlaneProjection proj(v.scene, v.scene.primitives[0]);
  FootprintReferenceConfig rc;
  rc.address_u = rc.address_v = AddressMode::Wrap;
  std::map<std::pair<int, int>, PixelSamples> cache;
  for (const Fragment& f : v.frags) {
    const auto x = static_cast<int>(f.x), y = static_cast<int>(f.y);
    if (!box) {
      v.ref.set(x, y, glm::vec4(footprint_reference(tex, proj, x, y, rc).colour));
      continue;
    }
    const UvSample c = proj.at(x + 0.5, y + 0.5);
    const double w = tex.width(0), h = tex.height(0);
    const PixelSamples& s = box_samples(rc, std::hypot(c.dudx * w, c.dvdx * h),
                                        std::hypot(c.dudy * w, c.dvdy * h), cache);
    v.ref_box.set(x, y,
                  glm::vec4(ground_truth_exact(tex, rc.address_u, rc.address_v, proj, x, y, s)));
  }
  v.seconds[box ? 1 : 0] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Every view with both truths; the truths run as tasks on the pool, the most anisotropic
// views (the slowest) first.
std::vector<View> make_views(const std::vector<StudyTexture>& textures,
                             const StudyFiltersOptions& opt, std::ostream& log) {
  std::vector<View> views;
  for (size_t ti = 0; ti < textures.size(); ++ti) {
    for (double nominal : opt.anisotropies) views.push_back(make_view(textures, ti, nominal, opt));
  }
  std::vector<size_t> order(views.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return views[a].nominal > views[b].nominal; });
  parallel_tasks(2 * views.size(), opt.threads, [&](size_t i) {
    View& v = views[order[i / 2]];
    make_truth(v, textures[v.texture].set[0], i % 2 == 1);
  });
  for (const View& v : views) {
    log << "  " << textures[v.texture].name << " aniso " << v.nominal << ": " << v.frags.size()
        << " fragments, aniso p50 " << fmt_g(v.p50, 3) << " p90 " << fmt_g(v.p90, 3)
        << ", reference " << fmt_g(v.seconds[0], 3) << " s, box reference "
        << fmt_g(v.seconds[1], 3) << " s\n";
  }
  return views;
}

// Methods that run together: each method with the one it is compared to (its image is needed
// for the pairwise NMSE), in table order; groups in order of their first method.
std::vector<std::vector<size_t>> method_groups(const std::vector<StudyFilterMethod>& methods) {
  std::vector<size_t> root(methods.size());
  std::vector<std::vector<size_t>> groups;
  std::vector<size_t> group_of(methods.size());
  for (size_t i = 0; i < methods.size(); ++i) {
    root[i] = i;
    for (size_t k = 0; k < i; ++k) {
      if (!methods[i].compare_to.empty() && methods[k].name == methods[i].compare_to)
        root[i] = root[k];
    }
    if (root[i] == i) {
      group_of[i] = groups.size();
      groups.emplace_back();
    } else {
      group_of[i] = group_of[root[i]];
    }
    groups[group_of[i]].push_back(i);
  }
  return groups;
}

// One group of methods on every view: rows[view × methods + method] filled. The group works on
// its own copy of the textures (the unit places them; peers key on them).
void measure_group(const std::vector<size_t>& group, std::vector<StudyTexture> textures,
                   const std::vector<View>& views, const std::vector<StudyFilterMethod>& methods,
                   const StudyFiltersOptions& opt, const StudyFiles& files,
                   std::vector<FilterRow>& rows) {
  const TechTable tech = TechTable::defaults();
  for (size_t vi = 0; vi < views.size(); ++vi) {
    const View& v = views[vi];
    StudyTexture& st = textures[v.texture];
    std::map<size_t, ImageRgb> images;
    for (size_t mi : group) {
      const StudyFilterMethod& m = methods[mi];
      FilterRow r;
      r.texture = st.name;
      r.nominal = v.nominal;
      r.aniso_p50 = v.p50;
      r.aniso_p90 = v.p90;
      r.method = &m;
      const auto t0 = std::chrono::steady_clock::now();
      r.run = run_study_filter_method(m, st.set, v.frags, tech, &v.scene);
      r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      ImageRgb img(v.ref.width, v.ref.height, glm::dvec3(0));
      for (size_t i = 0; i < v.frags.size(); ++i)
        img.set(static_cast<int>(v.frags[i].x), static_cast<int>(v.frags[i].y), r.run.colours[i]);
      r.run.colours.clear();
      r.fragments = v.frags.size();
      r.acc = compare_images(img, v.ref);
      sums_vs(img, v.ref, r.se, r.sref);
      r.acc_box = compare_images(img, v.ref_box);
      sums_vs(img, v.ref_box, r.se_box, r.sref_box);
      for (const auto& [k, other] : images) {
        if (!m.compare_to.empty() && methods[k].name == m.compare_to)
          sums_vs(img, other, r.se_pair, r.sref_pair);
      }
      if (opt.write_images) {
        write_image(
            files.path(st.name + "_a" + fmt_g(v.nominal, 3) + "_" + std::to_string(mi) + ".png"),
            img);
      }
      rows[vi * methods.size() + mi] = std::move(r);
      images.emplace(mi, std::move(img));
    }
  }
}

}  // namespace

std::vector<Fragment> study_filter_fragments(double aniso, const StudyFiltersOptions& opt,
                                             int texture_size) {
  const Scene scene = parse_scene(
      view_scene_text(aniso, opt.size, opt.texels_per_pixel, texture_size), "study view", "");
  return pixel_fragments(PlaneProjection(scene, scene.primitives[0]), opt.size, opt.size);
}

int run_study_filters(const std::string& out_dir, std::ostream& log) {
  return run_study_filters(out_dir, log, StudyFiltersOptions{});
}

int run_study_filters(const std::string& out_dir, std::ostream& log,
                      const StudyFiltersOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  const StudyFiles files(out_dir);
  const std::vector<StudyTexture> textures = study_textures();
  const std::vector<StudyFilterMethod> methods = study_filter_methods(opt, &log);
  const std::vector<View> views = make_views(textures, opt, log);
  std::vector<ViewTruths> truths;
  for (const View& v : views) {
    truths.push_back({textures[v.texture].name, v.nominal, compare_images(v.ref_box, v.ref)});
    if (!opt.write_images) continue;
    const std::string stem = textures[v.texture].name + "_a" + fmt_g(v.nominal, 3);
    write_image(files.path(stem + "_ref.png"), v.ref);
    write_image(files.path(stem + "_ref_box.png"), v.ref_box);
  }
  // Groups of methods run as tasks; each writes only its own rows, so the tables are the same
  // for every thread count. Groups with a renderer (Mesa) run on this thread: Mesa's one
  // surfaceless context was made current here and switches drivers only from here.
  const std::vector<std::vector<size_t>> groups = method_groups(methods);
  std::vector<FilterRow> rows(views.size() * methods.size());
  std::vector<size_t> here, pool;
  for (size_t g = 0; g < groups.size(); ++g) {
    const bool renders = std::any_of(groups[g].begin(), groups[g].end(),
                                     [&](size_t m) { return bool(methods[m].render); });
    (renders ? here : pool).push_back(g);
  }
  auto measure = [&](size_t g) {
    measure_group(groups[g], textures, views, methods, opt, files, rows);
  };
  std::atomic<size_t> next{0};
  auto drain = [&] {
    for (size_t i = next.fetch_add(1); i < pool.size(); i = next.fetch_add(1)) measure(pool[i]);
  };
  {
    std::vector<std::jthread> helpers;
    const size_t t = std::min(pool.size() + 1, static_cast<size_t>(resolve_threads(opt.threads)));
    for (size_t k = 1; k < t; ++k) helpers.emplace_back(drain);
    for (size_t g : here) measure(g);
    drain();
  }  // the helpers join here
  write_study_filters_outputs(files, rows, truths, methods, opt, log);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log << "study filters: wrote " << out_dir << "/filters.csv, filters.md, filters.png in "
      << fmt_g(secs, 3) << " s\n";
  return 0;
}

}  // namespace texsim
