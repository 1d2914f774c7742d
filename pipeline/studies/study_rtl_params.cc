#include "pipeline/studies/study_rtl_params.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "blocks/texture/sampler/bilinear_lerp.h"
#include "pipeline/studies/study_vd.h"
#include "rtl_model/params/rtl_params.h"

namespace texsim {

namespace {

using Params = std::vector<std::pair<std::string, int64_t>>;
using Sweep = std::vector<std::pair<std::string, int>>;

std::string fmt_e(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2e", v);
  return b;
}

const int* swept(const Sweep& sweep, const std::string& name) {
  for (const auto& [n, v] : sweep) {
    if (n == name) return &v;
  }
  return nullptr;
}

void set(Params& p, const std::string& name, int64_t value) {
  for (auto& [n, v] : p) {
    if (n == name) {
      v = value;
      return;
    }
  }
  p.emplace_back(name, value);
}

// V(d) blocks: a swept FIN picks the C++ fixed format u0.FIN / s3.(FIN-1) (only those the C++
// evaluators have), whose coefficients, breakpoints and exhaustive error come with it.
void vd_point(const std::string& module, const Sweep& sweep, RtlStudyPoint& pt) {
  const int* fin = swept(sweep, "FIN");
  const int w = fin ? *fin : rtl_params::kVdFin;
  const NumberFormat f = w == 16   ? NumberFormat::Fx16
                         : w == 12 ? NumberFormat::Fx12
                         : w == 8  ? NumberFormat::Fx8
                                   : NumberFormat::Double;
  if (f == NumberFormat::Double) {
    pt.problem = "no C++ V(d) format with FIN = " + std::to_string(w) + " (8, 12 or 16)";
    return;
  }
  const bool p2 = module == "vd_p2";
  pt.params =
      w == 16   ? (p2 ? rtl_params::vd_p2_params<VdFx16>() : rtl_params::vd_p1_params<VdFx16>())
      : w == 12 ? (p2 ? rtl_params::vd_p2_params<VdFx12>() : rtl_params::vd_p1_params<VdFx12>())
                : (p2 ? rtl_params::vd_p2_params<VdFx8>() : rtl_params::vd_p1_params<VdFx8>());
  const VdEvaluatorKind kind = p2 ? VdEvaluatorKind::P2 : VdEvaluatorKind::P1;
  pt.max_error = fmt_e(measure_vd_error(kind, f).max_abs);
}

// u/v adder: a swept W without F gives Fixed<W/2, W/2>; the minimum denominator follows F.
void uv_point(const Sweep& sweep, RtlStudyPoint& pt) {
  pt.params = rtl_params::uv_incremental_params();
  const int* w = swept(sweep, "W");
  const int* f = swept(sweep, "F");
  const int fb = f ? *f : (w ? *w / 2 : rtl_params::UvFixed::kFracBits);
  set(pt.params, "F", fb);
  set(pt.params, "MIN_DEN", std::llround(std::ldexp(rtl_params::uv_config().min_denominator, fb)));
}

}  // namespace

double bilinear_weight_error_lsb(int texel_bits, int sub_bits) {
  const uint32_t hi = (1u << texel_bits) - 1;
  const uint32_t cells = 1u << sub_bits;
  const uint32_t stride = std::max(1u, cells / 1024);  // every cell up to S = 10
  const double h = std::ldexp(0.5, -sub_bits);         // half a weight LSB
  double worst = 0;
  for (uint32_t kx = 0; kx < cells; kx += stride) {
    for (uint32_t ky = 0; ky < cells; ky += stride) {
      const double qx = std::ldexp(kx, -sub_bits), qy = std::ldexp(ky, -sub_bits);
      for (const double fx : {std::max(0.0, qx - h), qx + h}) {
        for (const double fy : {std::max(0.0, qy - h), qy + h}) {
          for (uint32_t corners = 0; corners < 16; ++corners) {
            const double t[4] = {corners & 1 ? hi : 0.0, corners & 2 ? hi : 0.0,
                                 corners & 4 ? hi : 0.0, corners & 8 ? hi : 0.0};
            const double top = t[0] + (t[1] - t[0]) * fx, bot = t[2] + (t[3] - t[2]) * fx;
            const double exact = top + (bot - top) * fy;
            const uint32_t got = BilinearLerp::lerp_channel(
                corners & 1 ? hi : 0, corners & 2 ? hi : 0, corners & 4 ? hi : 0,
                corners & 8 ? hi : 0, kx, ky, sub_bits);
            worst = std::max(worst, std::abs(got - exact));
          }
        }
      }
    }
  }
  return worst;
}

bool rtl_study_known_block(const std::string& module) {
  const auto blocks = rtl_params::rtl_blocks();
  return std::any_of(blocks.begin(), blocks.end(),
                     [&](const rtl_params::RtlBlock& b) { return b.module == module; });
}

bool rtl_study_is_generated(const std::string& module, const Params& params) {
  for (const rtl_params::RtlBlock& b : rtl_params::rtl_blocks()) {
    if (b.module != module) continue;
    Params a = b.params, c = params;
    std::sort(a.begin(), a.end());
    std::sort(c.begin(), c.end());
    return a == c;
  }
  return false;
}

std::string rtl_report_block(const std::string& module) {
  // uv_incremental is UvIncrementalAdder in Fixed<16,16>, which reports name by method and
  // format. The V(d) evaluators sit inside the filters' cut-offs, bilinear_lerp is the
  // fixed-point form beside the float TexelBlend ("blend"), and the rectangle-scan blocks
  // belong to the rasteriser: none is a report block of its own.
  return module == "uv_incremental" ? "coords.incremental[s16.16]" : "";
}

RtlStudyPoint rtl_study_point(const std::string& module, const Sweep& sweep) {
  RtlStudyPoint pt;
  const auto blocks = rtl_params::rtl_blocks();
  const auto b = std::find_if(blocks.begin(), blocks.end(),
                              [&](const rtl_params::RtlBlock& r) { return r.module == module; });
  if (b == blocks.end()) {
    for (const auto& [n, v] : sweep) pt.params.emplace_back(n, v);
    return pt;
  }
  pt.latency = b->latency ? std::to_string(b->latency) : "sequential";
  pt.params = b->params;
  if (module == "vd_p2" || module == "vd_p1") {
    vd_point(module, sweep, pt);
  } else if (module == "uv_incremental") {
    uv_point(sweep, pt);
  }
  for (const auto& [n, v] : sweep) set(pt.params, n, v);
  if (module == "bilinear_lerp") {
    int t = 0, s = 0;
    for (const auto& [n, v] : pt.params) {
      if (n == "T") t = static_cast<int>(v);
      if (n == "S") s = static_cast<int>(v);
    }
    if (t >= 1 && t <= 16 && s >= 1 && s <= 16) {
      char buf[48];
      std::snprintf(buf, sizeof buf, "%.3f LSB", bilinear_weight_error_lsb(t, s));
      pt.max_error = buf;
    }
  }
  return pt;
}

}  // namespace texsim
