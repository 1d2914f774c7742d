#pragma once
// The one parameter source of the RTL blocks (docs/rtl/blocks.md): the number formats, the
// coefficients and the latencies each Verilog block is built with, taken from the C++ block
// models themselves (their format types, VdCoefficientsIn, timing() on the default technology
// table). gen_rtl_params turns this into the Verilog side at build time (texsim_params.vh and
// one Verilator -G file per block, both marked "generated — do not edit"); the lockstep
// tests read the same values from here, so the two sides cannot drift apart.
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/raster/rect_scan/line_stepper.h"
#include "blocks/raster/rect_scan/texturing_control.h"
#include "blocks/texture/coords/uv_incremental_adder.h"
#include "blocks/texture/sampler/bilinear_lerp.h"
#include "blocks/texture/sampler/fixed_sampler.h"
#include "blocks/texture/subtexel/vd_evaluator_p1.h"
#include "blocks/texture/subtexel/vd_evaluator_p2.h"
#include "blocks/texture/subtexel/vd_evaluator_params.h"

namespace texsim::rtl_params {

// Technology table the RTL's pipeline depths follow: one register stage per cycle of each
// operator's latency.
inline TechTable tech() { return TechTable::defaults(); }

// Cycles of one operator of kind k, which must be a whole number to be a register count.
inline int op_latency(OpKind k) {
  const double c = tech().lat(k);
  if (c != std::floor(c) || c < 0)
    throw std::logic_error("rtl_params: operator latency is not a whole number of cycles");
  return static_cast<int>(c);
}

// ---- V(d) evaluators P2 and P1 (rtl_model/rtl/vd_p2.v, vd_p1.v) ---------------------------
using VdFormat = VdFx16;  // u0.16 input, s3.15 coefficients, u1.15 output
inline constexpr int kVdFin = VdFormat::In::kFracBits;
inline constexpr int kVdFc = VdFormat::Coef::kFracBits;

// A named integer parameter of one Verilog module.
using Param = std::pair<std::string, int64_t>;

// Fmt: any VdFixedFormat (texsim study rtl builds the blocks at other widths too).
template <class Fmt = VdFormat>
std::vector<Param> vd_p2_params() {
  const auto& c = VdCoefficientsIn<Fmt>::get();
  return {{"FIN", Fmt::In::kFracBits},
          {"FC", Fmt::Coef::kFracBits},
          {"MUL_LAT", op_latency(OpKind::Mul)},
          {"ADD_LAT", op_latency(OpKind::Add)},
          {"C0", c.p2[0].raw()},
          {"C1", c.p2[1].raw()},
          {"C2", c.p2[2].raw()}};
}

template <class Fmt = VdFormat>
std::vector<Param> vd_p1_params() {
  const auto& c = VdCoefficientsIn<Fmt>::get();
  return {{"FIN", Fmt::In::kFracBits},
          {"FC", Fmt::Coef::kFracBits},
          {"MUL_LAT", op_latency(OpKind::Mul)},
          {"ADD_LAT", op_latency(OpKind::Add)},
          {"CMP_LAT", op_latency(OpKind::Cmp)},
          {"B0", c.p1_break[0].raw()},
          {"B1", c.p1_break[1].raw()},
          {"A0", c.p1[0][0].raw()},
          {"S0", c.p1[0][1].raw()},
          {"A1", c.p1[1][0].raw()},
          {"S1", c.p1[1][1].raw()},
          {"A2", c.p1[2][0].raw()},
          {"S2", c.p1[2][1].raw()}};
}

// ---- Bilinear lerp (rtl_model/rtl/bilinear_lerp.v) ----------------------------------------
inline constexpr BilinearLerp::Config kLerp{8, 8};  // RGBA8 texels, u0.8 sub-texel weights

inline std::vector<Param> bilinear_lerp_params() {
  return {{"T", kLerp.texel_bits},
          {"S", kLerp.sub_bits},
          {"MUL_LAT", op_latency(OpKind::Mul)},
          {"ADD_LAT", op_latency(OpKind::Add)}};
}

// ---- Incremental u/v adder, k-lane form, with dividers (rtl_model/rtl/uv_incremental.v) ----
using UvFixed = Fixed<16, 16>;  // s15.16 map coefficients, accumulators and u, v
inline UvIncrementalAdder::Config uv_config() {
  UvIncrementalAdder::Config c;
  c.form = UvIncrementalAdder::Form::KLane;
  c.lanes = 4;
  c.division = UvIncrementalAdder::Division::Divide;
  c.datapath = Datapath::Spatial;
  return c;
}
inline constexpr int kUvCoordBits = 16;  // signed x0 and y of the row load
inline constexpr int kUvCountBits = 16;  // pixel count of the row load

inline std::vector<Param> uv_incremental_params() {
  const UvIncrementalAdder a(uv_config());
  return {{"W", UvFixed::kBits},
          {"F", UvFixed::kFracBits},
          {"K", a.lane_count()},
          {"SETUP_LAT", a.row_setup_timing(tech()).latency},
          {"DIV_LAT", a.timing(tech()).latency},
          {"MIN_DEN", UvFixed(uv_config().min_denominator).raw()},
          {"XW", kUvCoordBits},
          {"NW", kUvCountBits}};
}

// ---- Rectangle-scan address generator (rtl_model/rtl/rect_scan_stepper.v) --------------------
inline constexpr LineStepper::Config kRectScanLine{};  // slope_bits as the C++ default
inline constexpr int kRectScanCoordBits = 16;          // signed pixel coordinates

inline std::vector<Param> rect_scan_stepper_params() {
  return {{"SLOPE_BITS", kRectScanLine.slope_bits}, {"CW", kRectScanCoordBits}};
}

inline std::vector<Param> rect_scan_control_params() {
  return {{"CW", kRectScanCoordBits}, {"LAT", TexturingControl().timing(tech()).latency}};
}

// ---- Rectangle-scan rasteriser (rtl_model/rtl/rect_scan_raster.v) -----------------------------
// The auxiliary memory's window: 2^8 columns by 2^9 rows of 3-bit words.
inline constexpr int kRectScanMemMajorBits = 8;
inline constexpr int kRectScanMemMinorBits = 9;

inline std::vector<Param> rect_scan_raster_params() {
  return {{"SLOPE_BITS", kRectScanLine.slope_bits},
          {"CW", kRectScanCoordBits},
          {"MAJ_BITS", kRectScanMemMajorBits},
          {"MIN_BITS", kRectScanMemMinorBits}};
}

// ---- Bilinear/trilinear sampler (rtl_model/rtl/texsim_sampler.v) ------------------------------
// The sub-texel and mipmap bits of the default sampler (TexelAddressGen::Config): u0.8 weights
// and an u0.8 level fraction; the stage latencies of FixedSampler (LodUnit, TexelAddressGen,
// the level lerp on the default technology table).
inline std::vector<Param> sampler_params() {
  const TexelAddressGen::Config a;
  return {{"S", a.sub_texel_bits},
          {"M", a.mipmap_bits},
          {"LOD_LAT", FixedSampler::lod_latency(tech())},
          {"ADDR_LAT", FixedSampler::address_latency(tech())},
          {"MUL_LAT", op_latency(OpKind::Mul)},
          {"ADD_LAT", op_latency(OpKind::Add)},
          {"MIP_LAT", FixedSampler::mip_latency(tech())}};
}

// The log2 table of texsim_sampler_lod.v, as the module texsim_sampler_log2 (a ROM) in the
// generated texsim_sampler_log2.v.
inline std::string sampler_log2_v() {
  std::string s =
      "module texsim_sampler_log2 (\n    input  logic [ 8:0] i,\n    output logic [20:0] v\n);\n"
      "  always_comb begin\n    case (i)\n";
  const auto& t = FixedSampler::log2_table();
  for (size_t i = 0; i < t.size(); ++i)
    s += "      9'd" + std::to_string(i) + ": v = 21'd" + std::to_string(t[i]) + ";\n";
  s += "      default: v = 21'd0;\n    endcase\n  end\nendmodule\n";
  return s;
}

// A Verilog block, its parameters and the latency the C++ timing model gives it.
struct RtlBlock {
  std::string module;
  std::vector<Param> params;
  uint32_t latency;
};

inline std::vector<RtlBlock> rtl_blocks() {
  return {
      {"vd_p2", vd_p2_params<>(), VdEvaluatorP2().timing(tech()).latency},
      {"vd_p1", vd_p1_params<>(), VdEvaluatorP1().timing(tech()).latency},
      {"bilinear_lerp", bilinear_lerp_params(), BilinearLerp(kLerp).timing(tech()).latency},
      {"uv_incremental", uv_incremental_params(),
       UvIncrementalAdder(uv_config()).timing(tech()).latency},
      // Sequential: a pixel leaves at load + rows started + pixels visited (the C++ model's
      // fast-clock cycles), checked per pixel; no pipeline latency of its own.
      {"rect_scan_stepper", rect_scan_stepper_params(), 0},
      {"rect_scan_control", rect_scan_control_params(), TexturingControl().timing(tech()).latency},
      {"rect_scan_raster", rect_scan_raster_params(), 0},
      {"texsim_sampler", sampler_params(), FixedSampler::latency(tech())}};
}

}  // namespace texsim::rtl_params
