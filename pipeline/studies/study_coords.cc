#include "pipeline/studies/study_coords.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <map>
#include <memory>
#include <sstream>

#include "blocks/base/config_reader.h"
#include "blocks/base/tech_table.h"
#include "pipeline/kernel/clocked_pipeline.h"
#include "pipeline/kernel/parallel_range.h"
#include "pipeline/report/plot.h"
#include "pipeline/studies/study_table.h"

namespace texsim {

namespace {

const std::vector<std::string>& or_all(const std::vector<std::string>& v,
                                       const std::vector<std::string>& all) {
  return v.empty() ? all : v;
}

StageConfig filter_stage(uint32_t latency, uint32_t ii) {
  StageConfig s;
  s.name = "filter";
  s.timing.latency = latency;
  s.timing.ii = ii;
  return s;
}

double per_pixel(uint64_t v, uint64_t pixels) {
  return pixels ? static_cast<double>(v) / static_cast<double>(pixels) : 0.0;
}

// Cycles per pixel of a chain of stages for the given per-item costs (costs[i*S + s]).
double run_cycles(const std::vector<StageConfig>& stages, const std::vector<ItemCost>& costs,
                  uint64_t items) {
  if (items == 0) return 0;
  ClockedPipeline p(stages);
  const size_t s = stages.size();
  for (uint64_t i = 0; i < items; ++i) p.issue(0, costs.data() + i * s);
  return static_cast<double>(p.cycles()) / static_cast<double>(items);
}

std::string fmt(double v, int prec = 3) {
  if (!std::isfinite(v)) return "—";
  std::ostringstream os;
  if (v != 0 && (std::fabs(v) < 1e-3 || std::fabs(v) >= 1e5)) {
    os << std::scientific << std::setprecision(prec - 1) << v;
  } else {
    os << std::fixed << std::setprecision(prec) << v;
  }
  return os.str();
}

std::string pct(double ratio) {
  std::ostringstream os;
  os << std::showpos << std::fixed << std::setprecision(0) << (ratio - 1) * 100 << " %";
  return os.str();
}

std::string tilt_name(double t) {
  std::ostringstream os;
  os << t;
  return os.str();
}

}  // namespace

StudyPlane make_study_plane(const StudyCoordsOptions& o, double tilt) {
  StudyPlane sp;
  sp.tilt = tilt;
  PlaneView pv;
  pv.tilt_deg = tilt;
  pv.azimuth_deg = o.azimuth_deg;
  pv.distance = 1;
  pv.texels_per_pixel = 1;
  pv.u_offset = pv.v_offset = o.plane_texels / 2;
  pv.camera.width = o.width;  // f = width / 2: a 90° horizontal field of view
  pv.camera.height = o.height;
  pv.camera.tan_half_fov_y = static_cast<long double>(o.height) / o.width;
  const PlaneFrame f = plane_frame(pv);
  const ProjectiveMap raw = ProjectiveMap::from_plane(f.origin, f.axis_u, f.axis_v, pv.camera);
  sp.map = raw;
  if (!raw.finite()) return sp;
  const long double tile = o.plane_texels / std::max(1, o.tiles);
  auto at = [&](long double u, long double v) {
    return Vec3L{f.origin.x + u * f.axis_u.x + v * f.axis_v.x,
                 f.origin.y + u * f.axis_u.y + v * f.axis_v.y,
                 f.origin.z + u * f.axis_u.z + v * f.axis_v.z};
  };
  for (int tj = 0; tj < std::max(1, o.tiles); ++tj) {
    for (int ti = 0; ti < std::max(1, o.tiles); ++ti) {
      const long double u0 = ti * tile, v0 = tj * tile;
      std::vector<Vec3L> poly = {at(u0, v0), at(u0 + tile, v0), at(u0 + tile, v0 + tile),
                                 at(u0, v0 + tile)};
      poly = clip_polygon_z(poly, o.z_near, true);
      poly = clip_polygon_z(poly, o.z_far, false);
      if (poly.size() < 3) continue;
      std::vector<long double> px(poly.size()), py(poly.size());
      for (size_t i = 0; i < poly.size(); ++i) project_to_pixel(poly[i], pv.camera, px[i], py[i]);
      for (size_t i = 1; i + 1 < poly.size(); ++i) {
        CoordTriangle t;
        const size_t idx[3] = {0, i, i + 1};
        for (int k = 0; k < 3; ++k) {
          t.x[k] = static_cast<double>(px[idx[k]]);
          t.y[k] = static_cast<double>(py[idx[k]]);
        }
        t.rows = triangle_rows(t.x, t.y, o.width, o.height);
        if (t.rows.empty()) continue;
        sp.tris.push_back(std::move(t));
      }
    }
  }
  // Normalise q to (0.5, 1] over the covered pixels: the range fixed-point formats expect.
  long double qmax = 0;
  for (const auto& t : sp.tris) {
    for (const auto& r : t.rows) {
      qmax = std::max({qmax, raw.den(r.x0, r.y), raw.den(r.x0 + r.n - 1, r.y)});
      sp.pixels += static_cast<uint64_t>(r.n);
    }
    sp.rows += t.rows.size();
  }
  const long double one_x[1] = {0}, one_y[1] = {0};
  ProjectiveMap probe = raw;
  probe.I = qmax;  // den(0,0) of the probe = qmax: normalised() then scales by the same 2^-e
  probe.G = probe.H = 0;
  const long double scale = probe.normalised(one_x, one_y, 1).I / qmax;
  sp.map = raw.scaled(scale);
  for (auto& t : sp.tris) t.map = sp.map;
  return sp;
}

uint32_t ewa_texels(const DerivsL& d, uint32_t max_aniso) {
  // Singular values of the Jacobian: the footprint's semi-axes in texels per pixel.
  const long double s = d.ux * d.ux + d.uy * d.uy + d.vx * d.vx + d.vy * d.vy;
  const long double det = std::fabs(d.ux * d.vy - d.uy * d.vx);
  const long double p = std::sqrt(std::max<long double>(0, s + 2 * det));
  const long double m = std::sqrt(std::max<long double>(0, s - 2 * det));
  const long double major = (p + m) / 2, minor = (p - m) / 2;
  if (!std::isfinite(major)) return 1;
  // Mip level where the minor semi-axis is one texel; anisotropy clamped.
  const long double level = std::max<long double>(1, minor);
  const long double r1 = std::max<long double>(1, std::min(major, max_aniso * level) / level);
  const long double r2 = std::max<long double>(1, minor / level);
  return static_cast<uint32_t>(std::ceil(4 * r1 * r2));  // bounding box of the ellipse
}

namespace {

// A coordinate method's format-independent figures: ops, set-ups and cycles of
// [coords -> filter] in both datapaths.
CoordStudyRow coord_method_costs(const StudyCoordsOptions& o, const StudyPlane& sp,
                                 const std::string& method, const TechTable& tech) {
  CoordStudyRow base;
  base.tilt = sp.tilt;
  base.method = method;
  for (Datapath dp : {Datapath::Spatial, Datapath::Shared}) {
    const auto gen = CoordGenerator::create(method, "double", dp);
    std::vector<CoordFragment> frags;
    std::vector<ItemCost> costs;
    OpCounts ops;
    CoordGeneratorStats st;
    for (const auto& tri : sp.tris) gen->generate(tri, tech, frags, costs, ops, st);
    std::vector<ItemCost> c2(costs.size() * 2);
    for (size_t i = 0; i < costs.size(); ++i) c2[2 * i] = costs[i];
    auto& out = dp == Datapath::Spatial ? base.cpp_spatial : base.cpp_shared;
    for (uint32_t fii : o.filter_ii) {
      out.push_back(
          run_cycles({gen->stage(tech), filter_stage(o.filter_latency, fii)}, c2, costs.size()));
    }
    if (dp == Datapath::Spatial) {
      base.ops = ops;
      base.rows = st.rows;
      base.triangles = st.triangles;
      base.divisions = st.divisions;
    }
  }
  return base;
}

double reference_tilt(const StudyCoordsOptions& o);  // below

// The method's generator with `lanes` lanes, as a material's `coords = { method, lanes,
// datapath }` table makes it.
std::unique_ptr<CoordGenerator> lane_generator(const std::string& method, int lanes,
                                               const std::string& format, Datapath dp) {
  const toml::table t{
      {"method", method}, {"lanes", lanes}, {"datapath", datapath_name(dp)}, {"format", format}};
  const CoordUnitConfig c = CoordUnitConfig::from_toml(ConfigReader(t, "<lane sweep>", "coords"));
  return c.coord_block(format);
}

// One row of the lane sweep on plane `sp`.
LaneSweepRow lane_sweep_row(const StudyCoordsOptions& o, const StudyPlane& sp,
                            const std::string& method, int lanes, const TechTable& tech) {
  LaneSweepRow row;
  row.method = method;
  row.lanes = lanes;
  for (Datapath dp : {Datapath::Spatial, Datapath::Shared}) {
    const auto gen = lane_generator(method, lanes, "double", dp);
    std::vector<CoordFragment> frags;
    std::vector<ItemCost> costs;
    OpCounts ops;
    CoordGeneratorStats st;
    for (const auto& tri : sp.tris) gen->generate(tri, tech, frags, costs, ops, st);
    const double unit = run_cycles({gen->stage(tech)}, costs, costs.size());
    (dp == Datapath::Spatial ? row.cpp_unit_spatial : row.cpp_unit_shared) = unit;
    if (dp == Datapath::Shared) continue;
    std::vector<ItemCost> c2(costs.size() * 2);
    for (size_t i = 0; i < costs.size(); ++i) c2[2 * i] = costs[i];
    row.cpp_spatial =
        run_cycles({gen->stage(tech), filter_stage(o.filter_latency, 1)}, c2, costs.size());
    row.area = gen->stage(tech).timing.area;
  }
  const auto gen = lane_generator(method, lanes, "float", Datapath::Spatial);
  std::vector<CoordFragment> frags;
  std::vector<ItemCost> costs;
  OpCounts ops;
  CoordGeneratorStats st;
  for (const auto& tri : sp.tris) gen->generate(tri, tech, frags, costs, ops, st);
  for (const auto& f : frags) {
    if (!f.uv.valid) continue;
    row.max_err_float = std::max(
        row.max_err_float, std::max(std::fabs(f.uv.u - static_cast<double>(sp.map.u(f.x, f.y))),
                                    std::fabs(f.uv.v - static_cast<double>(sp.map.v(f.x, f.y)))));
  }
  return row;
}

// The method's coordinate errors in one format, against the projective map.
void coord_errors(const StudyPlane& sp, const std::string& format, const TechTable& tech,
                  CoordStudyRow& row) {
  row.format = format;
  const auto gen = CoordGenerator::create(row.method, format);
  std::vector<CoordFragment> frags;
  std::vector<ItemCost> costs;
  OpCounts ops;
  CoordGeneratorStats st;
  for (const auto& tri : sp.tris) gen->generate(tri, tech, frags, costs, ops, st);
  double sum = 0, sum_px = 0;
  uint64_t good = 0;
  for (const auto& f : frags) {
    ++row.pixels;
    if (!f.uv.valid) {
      ++row.rejected;
      continue;
    }
    const double eu = std::fabs(f.uv.u - static_cast<double>(sp.map.u(f.x, f.y)));
    const double ev = std::fabs(f.uv.v - static_cast<double>(sp.map.v(f.x, f.y)));
    const double e = std::max(eu, ev);
    const DerivsL j = analytic_derivs(sp.map, f.x, f.y);
    const auto rho = static_cast<double>(std::max(std::hypot(j.ux, j.vx), std::hypot(j.uy, j.vy)));
    const double epx = rho > 0 ? e / rho : e;
    row.max_err = std::max(row.max_err, e);
    row.max_err_px = std::max(row.max_err_px, epx);
    sum += e;
    sum_px += epx;
    ++good;
  }
  row.mean_err = good ? sum / static_cast<double>(good) : 0;
  row.mean_err_px = good ? sum_px / static_cast<double>(good) : 0;
  if (good == 0) row.max_err = row.mean_err = row.max_err_px = row.mean_err_px = INFINITY;
}

// References in raster-row order: analytic (true) and forward-difference derivatives, and the
// EWA stage's cost from the exact footprint's texel count.
struct DerivRefs {
  std::vector<DerivsL> truth, fd;
  std::vector<int32_t> px, py;
  std::vector<ItemCost> ewa_cost;
  size_t size() const { return truth.size(); }
};

DerivRefs deriv_refs(const StudyPlane& sp, uint32_t max_aniso) {
  DerivRefs r;
  for (const auto& tri : sp.tris) {
    for (const auto& row : tri.rows) {
      for (int32_t k = 0; k < row.n; ++k) {
        const int32_t x = row.x0 + k;
        r.truth.push_back(analytic_derivs(sp.map, x, row.y));
        r.fd.push_back(forward_diff_derivs(sp.map, x, row.y));
        r.px.push_back(x);
        r.py.push_back(row.y);
        r.ewa_cost.push_back({0, ewa_texels(r.truth.back(), max_aniso) - 1});
      }
    }
  }
  return r;
}

// Cycles per pixel of [incremental coords -> derivs -> ellipse (determinant) -> EWA] for the
// spatial, shared and fused datapaths; `dops` gets the derivative block's ops (spatial).
void deriv_cycles(const StudyCoordsOptions& o, const StudyPlane& sp, const DerivRefs& refs,
                  const std::string& method, const TechTable& tech, double cpp[3], OpCounts& dops) {
  const size_t npix = refs.size();
  for (int v = 0; v < 3; ++v) {
    const Datapath dp = v == 0 ? Datapath::Spatial : Datapath::Shared;
    const auto cg = CoordGenerator::create("incremental", "double", dp);
    const auto dg = DerivGenerator::create(method, "double", dp);
    const auto eg = EllipseGenerator::create("determinant", "double", dp);
    std::vector<CoordFragment> frags;
    std::vector<ItemCost> ccost, dcost;
    std::vector<CoordDerivs> ders;
    OpCounts cops, ops;
    CoordGeneratorStats st;
    for (const auto& tri : sp.tris) {
      cg->generate(tri, tech, frags, ccost, cops, st);
      dg->generate(tri, tech, ders, dcost, ops);
    }
    if (v == 0) dops = ops;
    const StageConfig ewa = filter_stage(o.filter_latency, 1);
    if (v < 2) {
      std::vector<ItemCost> c4(npix * 4);
      for (size_t i = 0; i < npix; ++i) {
        c4[4 * i] = ccost[i];
        c4[4 * i + 1] = dcost[i];
        c4[4 * i + 3] = refs.ewa_cost[i];
      }
      cpp[v] = run_cycles({cg->stage(tech), dg->stage(tech), eg->stage(tech), ewa}, c4, npix);
      continue;
    }
    // Fused: coords + derivs + ellipse on one shared ALU set, as one stage (a shader-like
    // core): ii = max over kinds of the three blocks' summed per-pixel ops; latency = the
    // three shared-datapath latencies in sequence.
    const OpCounts sum = cg->pixel_ops() + dg->pixel_ops() + eg->pixel_ops();
    uint64_t ii = 1;
    for (int k = 0; k < kOpKinds; ++k) ii = std::max(ii, sum.get(static_cast<OpKind>(k)));
    StageConfig fused;
    fused.name = "front-end";
    fused.timing.ii = static_cast<uint32_t>(ii);
    fused.timing.latency = cg->stage(tech).timing.latency + dg->stage(tech).timing.latency +
                           eg->stage(tech).timing.latency;
    std::vector<ItemCost> c2(npix * 2);
    for (size_t i = 0; i < npix; ++i) {
      c2[2 * i].extra_ii = ccost[i].extra_ii + dcost[i].extra_ii;
      c2[2 * i + 1] = refs.ewa_cost[i];
    }
    cpp[v] = run_cycles({fused, ewa}, c2, npix);
  }
}

// Largest absolute difference of the four derivatives, relative to the largest of `r`'s.
double rel_deriv_error(const CoordDerivs& d, const DerivsL& r) {
  const auto scale = static_cast<double>(
      std::max({std::fabs(r.ux), std::fabs(r.vx), std::fabs(r.uy), std::fabs(r.vy)}));
  const double e = std::max(
      {std::fabs(d.ux - static_cast<double>(r.ux)), std::fabs(d.vx - static_cast<double>(r.vx)),
       std::fabs(d.uy - static_cast<double>(r.uy)), std::fabs(d.vy - static_cast<double>(r.vy))});
  return scale > 0 ? e / scale : e;
}

// The same for the normalised ellipse A/F, B/F, C/F against the exact footprint of `rt`.
double rel_ellipse_error(const EllipseCoeffs& e, const DerivsL& rt) {
  const EllipseL er = ellipse_reference(rt);
  const long double an = er.a / er.f, bn = er.b / er.f, cn = er.c / er.f;
  const auto scale = static_cast<double>(std::max({std::fabs(an), std::fabs(bn), std::fabs(cn)}));
  return std::max({std::fabs(e.an - static_cast<double>(an)),
                   std::fabs(e.bn - static_cast<double>(bn)),
                   std::fabs(e.cn - static_cast<double>(cn))}) /
         (scale > 0 ? scale : 1.0);
}

// Errors of one derivative method's results `ders` (one format) and of an ellipse form on them.
void deriv_errors(const StudyPlane& sp, const DerivRefs& refs, const std::vector<CoordDerivs>& ders,
                  const EllipseGenerator& eg, DerivStudyRow& row) {
  double sum_d = 0, sum_e = 0;
  uint64_t good_d = 0, good_e = 0;
  for (size_t i = 0; i < refs.size(); ++i) {
    ++row.pixels;
    const CoordDerivs& d = ders[i];
    if (!d.valid) {
      ++row.rejected;
      ++row.ellipse_rejected;
      continue;
    }
    const DerivsL& rt = refs.truth[i];
    DerivsL own = row.method == "analytic" ? rt : refs.fd[i];
    if (row.method == "quad") own = forward_diff_derivs(sp.map, refs.px[i] & ~1, refs.py[i] & ~1);
    const double et = rel_deriv_error(d, rt);
    row.max_rel_true = std::max(row.max_rel_true, et);
    row.max_rel_own = std::max(row.max_rel_own, rel_deriv_error(d, own));
    sum_d += et;
    ++good_d;
    const EllipseCoeffs e = eg.eval(d);
    if (!e.valid) {
      ++row.ellipse_rejected;
      continue;
    }
    const double ee = rel_ellipse_error(e, rt);
    row.max_rel_ellipse = std::max(row.max_rel_ellipse, ee);
    sum_e += ee;
    ++good_e;
  }
  row.mean_rel_true = good_d ? sum_d / static_cast<double>(good_d) : INFINITY;
  row.mean_rel_ellipse = good_e ? sum_e / static_cast<double>(good_e) : INFINITY;
  if (!good_d) row.max_rel_true = row.max_rel_own = INFINITY;
  if (!good_e) row.max_rel_ellipse = INFINITY;
}

// One derivative method on one plane, in every format and both ellipse forms.
void measure_derivs(const StudyCoordsOptions& o, const StudyPlane& sp, const DerivRefs& refs,
                    const std::string& method, const std::vector<std::string>& formats,
                    const TechTable& tech, std::vector<DerivStudyRow>& out) {
  {
    double cpp[3] = {0, 0, 0};
    OpCounts dops;
    deriv_cycles(o, sp, refs, method, tech, cpp, dops);
    for (const auto& format : formats) {
      const auto dg = DerivGenerator::create(method, format);
      std::vector<CoordDerivs> ders;
      std::vector<ItemCost> dcost;
      OpCounts ops;
      for (const auto& tri : sp.tris) dg->generate(tri, tech, ders, dcost, ops);
      for (const char* eform : {"determinant", "ac-b2"}) {
        const auto eg = EllipseGenerator::create(eform, format);
        DerivStudyRow row;
        row.tilt = sp.tilt;
        row.method = method;
        row.ellipse = eform;
        row.format = format;
        row.ops = dops + eg->pixel_ops() * refs.size();
        row.cpp_spatial = cpp[0];
        row.cpp_shared = cpp[1];
        row.cpp_fused = cpp[2];
        deriv_errors(sp, refs, ders, *eg, row);
        out.push_back(std::move(row));
      }
    }
  }
}

}  // namespace

StudyCoordsResult measure_study_coords(const StudyCoordsOptions& o, std::ostream* log) {
  const TechTable tech = TechTable::defaults();
  const auto& cmethods = or_all(o.coord_methods, CoordGenerator::method_names());
  const auto& dmethods = or_all(o.deriv_methods, DerivGenerator::method_names());
  const auto& formats = or_all(o.formats, coord_format_names());
  StudyCoordsResult res;
  const auto t0 = std::chrono::steady_clock::now();
  // Tasks: every tilt's plane and derivative references, then per tilt one task per
  // coordinate method and one per derivative method; each writes its own slot, and the slots
  // are joined in the serial order.
  const size_t nt = o.tilts.size(), nc = cmethods.size(), per = nc + dmethods.size();
  std::vector<StudyPlane> planes(nt);
  std::vector<DerivRefs> refs(nt);
  parallel_tasks(nt, o.threads, [&](size_t t) {
    planes[t] = make_study_plane(o, o.tilts[t]);
    refs[t] = deriv_refs(planes[t], o.max_aniso);
  });
  std::vector<std::vector<CoordStudyRow>> coords(nt * nc);
  std::vector<std::vector<DerivStudyRow>> derivs(nt * dmethods.size());
  // The derivative tasks are the longest: they go first.
  parallel_tasks(nt * per, o.threads, [&](size_t k) {
    const size_t nd = nt * dmethods.size();
    if (k < nd) {
      const size_t t = k / dmethods.size();
      measure_derivs(o, planes[t], refs[t], dmethods[k % dmethods.size()], formats, tech,
                     derivs[k]);
      return;
    }
    const size_t t = (k - nd) / nc, m = (k - nd) % nc;
    const CoordStudyRow base = coord_method_costs(o, planes[t], cmethods[m], tech);
    for (const auto& format : formats) {
      CoordStudyRow row = base;
      coord_errors(planes[t], format, tech, row);
      coords[t * nc + m].push_back(std::move(row));
    }
  });
  // The lane sweep on the reference tilt's plane.
  const std::vector<std::string> lane_methods = {"incremental-k4", "incremental-direct"};
  const size_t rt = static_cast<size_t>(
      std::find(o.tilts.begin(), o.tilts.end(), reference_tilt(o)) - o.tilts.begin());
  if (rt < nt) {
    res.lanes.resize(lane_methods.size() * o.lane_counts.size());
    parallel_tasks(res.lanes.size(), o.threads, [&](size_t k) {
      res.lanes[k] = lane_sweep_row(o, planes[rt], lane_methods[k / o.lane_counts.size()],
                                    o.lane_counts[k % o.lane_counts.size()], tech);
    });
  }
  for (size_t t = 0; t < nt; ++t) {
    StudyPlane& sp = planes[t];
    if (log) {
      *log << "study coords: tilt " << sp.tilt << "°: " << sp.tris.size() << " triangles, "
           << sp.pixels << " pixels, " << sp.rows << " rows\n";
    }
    for (size_t m = 0; m < nc; ++m) {
      for (auto& row : coords[t * nc + m]) res.coords.push_back(std::move(row));
    }
    for (size_t d = 0; d < dmethods.size(); ++d) {
      for (auto& row : derivs[t * dmethods.size() + d]) res.derivs.push_back(std::move(row));
    }
    sp.tris.clear();  // keep the summary only
    refs[t] = {};
    res.planes.push_back(std::move(sp));
  }
  if (log) {
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    *log << "study coords: measured in " << fmt(secs, 2) << " s\n";
  }
  return res;
}

}  // namespace texsim

namespace texsim {

namespace {

// The tilt the per-method cost tables quote (ops per pixel depend on row lengths): the
// largest studied tilt not above 60°, else the first.
double reference_tilt(const StudyCoordsOptions& o) {
  double best = o.tilts.empty() ? 0 : o.tilts.front();
  for (double t : o.tilts) {
    if (t <= 60 && t >= best) best = t;
  }
  return best;
}

const CoordStudyRow* find_coord(const StudyCoordsResult& r, double tilt, const std::string& m,
                                const std::string& f) {
  for (const auto& c : r.coords) {
    if (c.tilt == tilt && c.method == m && c.format == f) return &c;
  }
  return nullptr;
}

const DerivStudyRow* find_deriv(const StudyCoordsResult& r, double tilt, const std::string& m,
                                const std::string& e, const std::string& f) {
  for (const auto& c : r.derivs) {
    if (c.tilt == tilt && c.method == m && c.ellipse == e && c.format == f) return &c;
  }
  return nullptr;
}

const StudyPlane* find_plane(const StudyCoordsResult& r, double tilt) {
  for (const auto& p : r.planes) {
    if (p.tilt == tilt) return &p;
  }
  return nullptr;
}

std::string err_cell(double max_err, uint64_t rejected, uint64_t pixels) {
  std::string s = fmt(max_err);
  if (rejected > 0 && pixels > 0) {
    s += " (rej " + fmt(100.0 * static_cast<double>(rejected) / static_cast<double>(pixels), 1) +
         " %)";
  }
  return s;
}

std::string ops_cell(const OpCounts& ops, uint64_t pixels) {
  std::ostringstream os;
  os << fmt(per_pixel(ops.add, pixels), 2) << " / " << fmt(per_pixel(ops.mul, pixels), 2) << " / "
     << fmt(per_pixel(ops.div, pixels), 2) << " / " << fmt(per_pixel(ops.rcp, pixels), 2) << " / "
     << fmt(per_pixel(ops.cmp, pixels), 2);
  return os.str();
}

std::vector<std::string> unique_in_order(const std::vector<std::string>& v) {
  std::vector<std::string> u;
  for (const auto& s : v) {
    if (std::find(u.begin(), u.end(), s) == u.end()) u.push_back(s);
  }
  return u;
}

}  // namespace

namespace {

// What the Markdown sections share: the study's options and results, the methods and formats
// in table order, the tilt of the cost tables and the format they quote.
struct CoordsDoc {
  const StudyCoordsOptions& o;
  const StudyCoordsResult& r;
  std::vector<std::string> cm, dm, fm;  // coordinate methods, derivative methods, formats
  double rt = 0;
  std::string ref_fmt;

  CoordsDoc(const StudyCoordsOptions& opt, const StudyCoordsResult& res) : o(opt), r(res) {
    for (const auto& c : r.coords) {
      cm.push_back(c.method);
      fm.push_back(c.format);
    }
    for (const auto& d : r.derivs) dm.push_back(d.method);
    cm = unique_in_order(cm);
    dm = unique_in_order(dm);
    fm = unique_in_order(fm);
    rt = reference_tilt(o);
    ref_fmt =
        fm.empty() || std::find(fm.begin(), fm.end(), "double") != fm.end() ? "double" : fm.front();
  }
  // Header cells "<t>°<suffix>" for every tilt.
  std::vector<std::string> tilt_cells(const std::string& suffix = "") const {
    std::vector<std::string> h;
    for (double t : o.tilts) h.push_back(tilt_name(t) + "°" + suffix);
    return h;
  }
};

std::vector<std::string> cat(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

std::string md_conditions(const StudyCoordsOptions& o) {
  const TechTable tech = TechTable::defaults();
  std::ostringstream md;
  md << "# Study: texture-coordinate generation and footprint set-up — accuracy vs cost\n\n"
     << "Generated by `texsim study coords`; the method and the discussion are in "
        "docs/studies/study-coords.md.\n\n## Conditions\n\n"
     << "- Viewport " << o.width << "×" << o.height << " pixels, pinhole camera, focal length "
     << o.width / 2 << " px (90° horizontal field of view).\n"
     << "- A textured square of " << o.plane_texels << "×" << o.plane_texels
     << " texels as a mesh of " << o.tiles << "×" << o.tiles
     << " quads (two triangles each), one texel per pixel where it meets the view axis when "
        "screen-parallel, "
        "tilted by the angle in the tables about an axis at "
     << o.azimuth_deg << "° from the screen x axis; clipped to view depths [" << o.z_near << ", "
     << o.z_far
     << "] × the view-axis distance (each quad clipped, then fan-triangulated), "
        "pixel centres rasterized (edges inclusive). One map (A..I) for the whole plane.\n"
     << "- Reference: the projective map in long double (64-bit significand). Errors: "
        "max over pixels of max(|Δu|, |Δv|) in texels; derivatives: max |Δ| over the four, "
        "relative to the largest of the four exact derivatives; ellipse: the normalised "
        "A/F, B/F, C/F likewise, against the exact footprint.\n"
     << "- Technology table: defaults (latency add " << tech.lat(OpKind::Add) << ", mul "
     << tech.lat(OpKind::Mul) << ", div " << tech.lat(OpKind::Div) << ", rcp "
     << tech.lat(OpKind::Rcp)
     << " cycles). Datapaths: *spatial* = one pipelined operator per "
        "operation (II 1); *shared* = one operator per kind per block (II = most ops of one "
        "kind); *fused* = the whole front end (coordinates, derivatives, ellipse) on one "
        "shared operator set, as in a shader core.\n"
     << "- Cycles come from the clocked pipeline: the coordinate stage, then a texel fetch + "
        "filter stage of latency "
     << o.filter_latency << " and II " << (o.filter_ii.empty() ? 1u : o.filter_ii.front())
     << " (a bilinear unit reading 4 texels per cycle); for derivatives the chain is "
        "incremental coordinates → derivative block → ellipse set-up → an EWA stage that "
        "reads one texel per cycle, the texel count from the exact footprint (mip level at "
        "the minor axis, anisotropy ≤ "
     << o.max_aniso
     << ", bounding box of the ellipse). Row and triangle set-ups stall the stage on the "
        "first pixel of each row (ItemCost::extra_ii = set-up latency; not overlapped).\n\n";
  return md.str();
}

std::string md_planes_and_costs(const CoordsDoc& d) {
  StudyTable planes({"tilt °", "triangles", "pixels T", "raster rows q", "constant-depth lines"},
                    "rrrrr");
  for (const auto& p : d.r.planes) {
    const CoordStudyRow* cd = find_coord(d.r, p.tilt, "constant-depth", d.ref_fmt);
    const CoordStudyRow* any = find_coord(d.r, p.tilt, d.cm.empty() ? "" : d.cm.front(), d.ref_fmt);
    planes.add({tilt_name(p.tilt), std::to_string(any ? any->triangles : 0),
                std::to_string(p.pixels), std::to_string(p.rows),
                cd ? std::to_string(cd->rows) : "—"});
  }
  StudyTable costs({"method", "ops per pixel", "set-ups (rows, triangles)", "cycles/px spatial",
                    "cycles/px shared"},
                   "llrrr");
  const auto list = [](const std::vector<double>& v) {
    std::string s;
    for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + fmt(v[i], 2);
    return s;
  };
  for (const auto& m : d.cm) {
    const CoordStudyRow* c = find_coord(d.r, d.rt, m, d.ref_fmt);
    if (!c) continue;
    costs.add({m, ops_cell(c->ops, c->pixels),
               std::to_string(c->rows) + ", " + std::to_string(c->triangles), list(c->cpp_spatial),
               list(c->cpp_shared)});
  }
  std::ostringstream md;
  md << "## Planes\n\n"
     << planes.markdown() << "\n## Coordinate methods: operations and cycles per pixel (tilt "
     << tilt_name(d.rt)
     << "°)\n\nOps per pixel include the row/triangle set-ups amortised over this plane's "
        "pixels (add / mul / div / rcp / cmp). Cycles per pixel with filter II ";
  for (size_t i = 0; i < d.o.filter_ii.size(); ++i) md << (i ? ", " : "") << d.o.filter_ii[i];
  md << ".\n\n" << costs.markdown();
  return md.str();
}

// Coordinate errors by tilt and format (max_err/mean_err: in texels or in pixels).
std::string md_coord_errors(const CoordsDoc& d, const char* heading, double CoordStudyRow::*max_err,
                            double CoordStudyRow::*mean_err) {
  const std::vector<double>& tilts = d.o.tilts;
  StudyTable t(cat(cat({"method", "format"}, d.tilt_cells()),
                   {"mean at " + tilt_name(tilts.empty() ? 0 : tilts.back()) + "°"}),
               "ll" + std::string(tilts.size() + 1, 'r'));
  for (const auto& m : d.cm) {
    for (const auto& f : d.fm) {
      std::vector<std::string> c = {m, f};
      for (double tilt : tilts) {
        const CoordStudyRow* row = find_coord(d.r, tilt, m, f);
        c.push_back(row ? err_cell(row->*max_err, row->rejected, row->pixels) : "—");
      }
      const CoordStudyRow* last = tilts.empty() ? nullptr : find_coord(d.r, tilts.back(), m, f);
      c.push_back(last ? fmt(last->*mean_err) : "—");
      t.add(std::move(c));
    }
  }
  return heading + t.markdown();
}

std::string md_deriv_errors(const CoordsDoc& d) {
  const size_t nt = d.o.tilts.size();
  StudyTable dt(cat(cat({"method", "format"}, d.tilt_cells()), {"own, worst tilt"}),
                "ll" + std::string(nt + 1, 'r'));
  for (const auto& m : d.dm) {
    for (const auto& f : d.fm) {
      std::vector<std::string> c = {m, f};
      double own = 0;
      for (double t : d.o.tilts) {
        const DerivStudyRow* row = find_deriv(d.r, t, m, "determinant", f);
        c.push_back(row ? err_cell(row->max_rel_true, row->rejected, row->pixels) : "—");
        if (row) own = std::max(own, row->max_rel_own);
      }
      c.push_back(fmt(own));
      dt.add(std::move(c));
    }
  }
  StudyTable et(cat({"F form", "format"}, d.tilt_cells()), "ll" + std::string(nt, 'r'));
  const std::string ell_m = std::find(d.dm.begin(), d.dm.end(), "analytic") != d.dm.end()
                                ? "analytic"
                                : (d.dm.empty() ? "" : d.dm.front());
  for (const char* e : {"determinant", "ac-b2"}) {
    for (const auto& f : d.fm) {
      std::vector<std::string> c = {e, f};
      for (double t : d.o.tilts) {
        const DerivStudyRow* row = find_deriv(d.r, t, ell_m, e, f);
        c.push_back(row ? err_cell(row->max_rel_ellipse, row->ellipse_rejected, row->pixels) : "—");
      }
      et.add(std::move(c));
    }
  }
  return "\n## Derivative blocks: maximum relative error against the exact derivatives\n\n"
         "(own = against the exact value of the block's own formula, i.e. arithmetic error "
         "only; the forward-difference methods differ from the derivative by their "
         "discretisation.)\n\n" +
         dt.markdown() +
         "\n## Ellipse set-up: maximum relative error of A/F, B/F, C/F (from analytic "
         "derivatives)\n\n" +
         et.markdown();
}

std::string md_deriv_costs(const CoordsDoc& d) {
  StudyTable t(cat({"method", "ops/px at " + tilt_name(d.rt) + "° (add / mul / div / rcp / cmp)"},
                   d.tilt_cells(" spatial / shared / fused")),
               "ll" + std::string(d.o.tilts.size(), 'r'));
  for (const auto& m : d.dm) {
    const DerivStudyRow* d0 = find_deriv(d.r, d.rt, m, "determinant", d.ref_fmt);
    std::vector<std::string> c = {m, d0 ? ops_cell(d0->ops, d0->pixels) : "—"};
    for (double tilt : d.o.tilts) {
      const DerivStudyRow* row = find_deriv(d.r, tilt, m, "determinant", d.ref_fmt);
      c.push_back(row ? fmt(row->cpp_spatial, 2) + " / " + fmt(row->cpp_shared, 2) + " / " +
                            fmt(row->cpp_fused, 2)
                      : "—");
    }
    t.add(std::move(c));
  }
  return "\n## Derivative blocks + ellipse: operations and cycles per pixel\n\n" + t.markdown();
}

// The seeds' claims on coordinates: ops per pixel, and incremental against Heckbert.
std::string md_coord_claims(const CoordsDoc& d) {
  StudyTable ops({"tilt °", "incremental add+mul per pixel, set-up amortised",
                  "per pixel without set-up", "Heckbert add+mul per pixel"},
                 "rrrr");
  std::vector<std::string> sh = {"tilt °"};
  for (uint32_t f : d.o.filter_ii) sh.push_back("spatial, filter II " + std::to_string(f));
  for (uint32_t f : d.o.filter_ii) sh.push_back("shared, filter II " + std::to_string(f));
  StudyTable speed(sh, std::string(sh.size(), 'r'));
  for (double t : d.o.tilts) {
    const CoordStudyRow* i = find_coord(d.r, t, "incremental", d.ref_fmt);
    const CoordStudyRow* h = find_coord(d.r, t, "heckbert", d.ref_fmt);
    if (!i || !h) continue;
    const OpCounts pp = CoordGenerator::create("incremental", "double")->pixel_ops();
    ops.add({tilt_name(t), fmt(per_pixel(i->ops.add + i->ops.mul, i->pixels), 2),
             std::to_string(pp.add + pp.mul),
             fmt(per_pixel(h->ops.add + h->ops.mul, h->pixels), 2)});
    std::vector<std::string> c = {tilt_name(t)};
    for (size_t k = 0; k < d.o.filter_ii.size(); ++k)
      c.push_back(pct(h->cpp_spatial[k] / i->cpp_spatial[k]));
    for (size_t k = 0; k < d.o.filter_ii.size(); ++k)
      c.push_back(pct(h->cpp_shared[k] / i->cpp_shared[k]));
    speed.add(std::move(c));
  }
  return "\n## The seeds' claims, re-measured\n\n"
         "**Incremental coordinates: \"adds + mults per pixel reduced to 4\"** (thesis ch. "
         "3).\n\n" +
         ops.markdown() +
         "\n**Incremental vs Heckbert: \"+26 % speed in all tests\"** — speed-up = cycles per "
         "pixel of Heckbert (division form) ÷ incremental − 1, per filter II.\n\n" +
         speed.markdown();
}

// The seeds' claims on iterative derivatives and constant-depth lines.
std::string md_deriv_claims(const CoordsDoc& d) {
  StudyTable it_t({"tilt °", "vs classic: spatial / shared / fused",
                   "vs accelerated: spatial / shared / fused"},
                  "rll");
  for (double t : d.o.tilts) {
    const DerivStudyRow* it = find_deriv(d.r, t, "iterative", "determinant", d.ref_fmt);
    const DerivStudyRow* cl = find_deriv(d.r, t, "heckbert-fd", "determinant", d.ref_fmt);
    const DerivStudyRow* ac = find_deriv(d.r, t, "accelerated-fd", "determinant", d.ref_fmt);
    if (!it || !cl || !ac) continue;
    const auto vs = [&](const DerivStudyRow* o) {
      return pct(o->cpp_spatial / it->cpp_spatial) + " / " + pct(o->cpp_shared / it->cpp_shared) +
             " / " + pct(o->cpp_fused / it->cpp_fused);
    };
    it_t.add({tilt_name(t), vs(cl), vs(ac)});
  }
  StudyTable cd_t({"tilt °", "T pixels", "q raster rows", "lines walked",
                   "divisions Heckbert (rcp form)", "divisions constant-depth", "removed",
                   "seed's T − q", "max error, double (texels / pixels)"},
                  "rrrrrrrrr");
  for (double t : d.o.tilts) {
    const CoordStudyRow* cd = find_coord(d.r, t, "constant-depth", d.ref_fmt);
    const CoordStudyRow* hr = find_coord(d.r, t, "heckbert-rcp", d.ref_fmt);
    const StudyPlane* p = find_plane(d.r, t);
    if (!cd || !hr || !p) continue;
    cd_t.add(
        {tilt_name(t), std::to_string(p->pixels), std::to_string(p->rows), std::to_string(cd->rows),
         std::to_string(hr->divisions), std::to_string(cd->divisions),
         std::to_string(static_cast<int64_t>(hr->divisions) - static_cast<int64_t>(cd->divisions)),
         std::to_string(static_cast<int64_t>(p->pixels) - static_cast<int64_t>(p->rows)),
         fmt(cd->max_err) + " / " + fmt(cd->max_err_px)});
  }
  return "\n**Iterative derivatives: \"+18 % AF vs classic Heckbert derivatives, +8 % vs "
         "accelerated, up to +40 % at small tilt\"** — speed-up of the iterative block in "
         "cycles per pixel of [coordinates → derivatives → ellipse → EWA].\n\n" +
         it_t.markdown() +
         "\n**Constant-depth lines: \"T − q divisions removed per triangle\"** (seed 002), "
         "summed over the plane's triangles. Divisions = div + rcp operations.\n\n" +
         cd_t.markdown();
}

}  // namespace

std::string md_lane_sweep(const CoordsDoc& d) {
  if (d.r.lanes.empty()) return "";
  StudyTable t({"method", "lanes", "cycles/px, coordinate unit spatial", "shared",
                "cycles/px with the filter (II 1)", "area (adder eq.)", "float max error (texels)"},
               "lrrrrrr");
  for (const LaneSweepRow& l : d.r.lanes) {
    t.add({l.method, std::to_string(l.lanes), fmt(l.cpp_unit_spatial), fmt(l.cpp_unit_shared),
           fmt(l.cpp_spatial), fmt(l.area, 1), fmt(l.max_err_float)});
  }
  return "\n## Parallel lanes (\"GPU cores\") at " + tilt_name(d.rt) +
         "°\n\nThe thesis varied the number of parallel lanes: the k-lane (`incremental-k4` with "
         "its `lanes`) and direct-n (`incremental-direct`) forms, each lane a datapath of its own. "
         "The coordinate unit alone, then followed by a filter that takes one fragment per "
         "cycle (which bounds the pair at 1 cycle per pixel).\n\n" +
         t.markdown();
}

std::string study_coords_markdown(const StudyCoordsOptions& o, const StudyCoordsResult& r) {
  const CoordsDoc d(o, r);
  return md_conditions(o) + md_planes_and_costs(d) +
         md_coord_errors(
             d,
             "\n## Coordinate methods: maximum error in texels\n\n(rej = pixels the block "
             "rejected: denominator below its limit or a result out of the format's range.)\n\n",
             &CoordStudyRow::max_err, &CoordStudyRow::mean_err) +
         md_coord_errors(
             d,
             "\n## Coordinate methods: maximum error in pixels (error ÷ texels per pixel)\n\n"
             "The same errors divided by the pixel's footprint size: how far the sample point "
             "moves, in pixels. Below 1/256 a texture address of 8 sub-texel bits is exact.\n\n",
             &CoordStudyRow::max_err_px, &CoordStudyRow::mean_err_px) +
         md_lane_sweep(d) + md_deriv_errors(d) + md_deriv_costs(d) + md_coord_claims(d) +
         md_deriv_claims(d);
}

std::string study_coords_csv(const StudyCoordsOptions& o, const StudyCoordsResult& r) {
  const auto num = [](auto v) {  // as a stream with 9 significant digits writes it
    std::ostringstream s;
    s << std::setprecision(9) << v;
    return s.str();
  };
  std::vector<std::string> head = {"study",
                                   "tilt_deg",
                                   "method",
                                   "ellipse",
                                   "format",
                                   "pixels",
                                   "rejected",
                                   "err_max_texels",
                                   "err_mean_texels",
                                   "err_max_px",
                                   "err_mean_px",
                                   "deriv_rel_max",
                                   "deriv_rel_mean",
                                   "deriv_rel_own_max",
                                   "ellipse_rel_max",
                                   "ellipse_rel_mean",
                                   "ellipse_rejected",
                                   "add_px",
                                   "mul_px",
                                   "div_px",
                                   "rcp_px",
                                   "cmp_px",
                                   "rows",
                                   "triangles",
                                   "divisions"};
  for (uint32_t f : o.filter_ii) head.push_back("cpp_spatial_f" + std::to_string(f));
  for (uint32_t f : o.filter_ii) head.push_back("cpp_shared_f" + std::to_string(f));
  for (const char* c : {"cpp_ewa_spatial", "cpp_ewa_shared", "cpp_ewa_fused"}) head.emplace_back(c);
  StudyTable t(head);
  const auto ops = [&](const OpCounts& c, uint64_t px, std::vector<std::string>& cells) {
    for (uint64_t v : {c.add, c.mul, c.div, c.rcp, c.cmp}) cells.push_back(num(per_pixel(v, px)));
  };
  const std::vector<std::string> blank(2 * o.filter_ii.size(), "");
  for (const auto& c : r.coords) {
    std::vector<std::string> cells = {"coords",
                                      num(c.tilt),
                                      c.method,
                                      "",
                                      c.format,
                                      num(c.pixels),
                                      num(c.rejected),
                                      num(c.max_err),
                                      num(c.mean_err),
                                      num(c.max_err_px),
                                      num(c.mean_err_px),
                                      "",
                                      "",
                                      "",
                                      "",
                                      "",
                                      ""};
    ops(c.ops, c.pixels, cells);
    for (uint64_t v : {c.rows, c.triangles, c.divisions}) cells.push_back(num(v));
    for (double v : c.cpp_spatial) cells.push_back(num(v));
    for (double v : c.cpp_shared) cells.push_back(num(v));
    cells.insert(cells.end(), 3, "");
    t.add(std::move(cells));
  }
  for (const auto& d : r.derivs) {
    std::vector<std::string> cells = {"derivs",
                                      num(d.tilt),
                                      d.method,
                                      d.ellipse,
                                      d.format,
                                      num(d.pixels),
                                      num(d.rejected),
                                      "",
                                      "",
                                      "",
                                      "",
                                      num(d.max_rel_true),
                                      num(d.mean_rel_true),
                                      num(d.max_rel_own),
                                      num(d.max_rel_ellipse),
                                      num(d.mean_rel_ellipse),
                                      num(d.ellipse_rejected)};
    ops(d.ops, d.pixels, cells);
    cells.insert(cells.end(), 3, "");
    cells.insert(cells.end(), blank.begin(), blank.end());
    for (double v : {d.cpp_spatial, d.cpp_shared, d.cpp_fused}) cells.push_back(num(v));
    t.add(std::move(cells));
  }
  return t.csv();
}

int run_study_coords(const std::string& out_dir, std::ostream& log, int threads) {
  StudyCoordsOptions o;
  o.threads = threads;
  const StudyCoordsResult r = measure_study_coords(o, &log);
  const StudyFiles files(out_dir);
  // Plot: error against cycles at the steepest tilt not above 85°: one series per number
  // format, one point per method, labelled with it;
  // errors in pixels, those below 1e-12 drawn at 1e-12.
  double pt = o.tilts.empty() ? 0 : o.tilts.front();
  for (double t : o.tilts) {
    if (t <= 85 && t >= pt) pt = t;
  }
  PlotSpec spec;
  spec.title = "Texture coordinates at " + tilt_name(pt) +
               "° tilt: max error vs cycles per pixel (shared datapath), one point per method";
  spec.xlabel = "cycles per pixel (coordinate stage + filter II " +
                std::to_string(o.filter_ii.empty() ? 1u : o.filter_ii.front()) + ")";
  spec.ylabel = "max |error| (pixels of footprint)";
  spec.logy = true;
  spec.pareto = ParetoFront::lower_y_better;
  std::map<std::string, std::vector<LabelledPoint>> by_format;
  std::vector<std::string> formats;
  for (const auto& c : r.coords) {
    if (c.tilt != pt || c.cpp_shared.empty()) continue;
    if (!by_format.count(c.format)) formats.push_back(c.format);
    by_format[c.format].push_back({c.cpp_shared.front(), std::max(c.max_err_px, 1e-12), c.method});
  }
  for (const auto& f : formats) spec.series.push_back(labelled_series(f, by_format[f]));
  files.plot("coords.png", spec);
  files.text("coords.csv", study_coords_csv(o, r));
  files.text("coords.md", study_coords_markdown(o, r));
  log << "study coords: wrote " << out_dir << "/coords.csv, coords.md, coords.png\n";
  return 0;
}

}  // namespace texsim
