// The bilinear/trilinear sampler (C++ core FixedSampler, blocks/texture/sampler/fixed_sampler.h;
// docs/rtl/blocks.md): one fragment per clock through LOD (texsim_sampler_lod), texel address
// generation of the finer and coarser level (texsim_sampler_addr), eight texel reads, two
// bilinear lerps (bilinear_lerp) and the lerp between the levels.
//   cycle c            fragment on the inputs (u, v, derivatives: s15.32)
//   c + LOD_LAT        level(s) and weight δ registered
//   c + LOD_LAT+ADDR_LAT   rd_valid, rd_addr: eight texel word addresses, (x0,y0) (x1,y0)
//                      (x0,y1) (x1,y1) of the finer level, then of the coarser one
//   the next cycle     rd_data (the memory's registered read: block RAM), sampled here
//   + LERP_LAT         the two levels' RGBA8 colours
//   + MIP_LAT          out_rgba = hi·2^M + (lo − hi)·δ, rounded half up (trilinear), or hi
// The texture and sampler state (cfg_*) is static while fragments stream; the level bases are
// written through cfg_base_we. The op counters add cfg_*_n per retired fragment: the counts the
// C++ models give the configured path, loaded with it.
module texsim_sampler #(
    parameter int S = 8,
    parameter int M = 8,
    parameter int LOD_LAT = 1,
    parameter int ADDR_LAT = 1,
    parameter int MUL_LAT = 3,
    parameter int ADD_LAT = 1,
    parameter int MIP_LAT = 1
) (
    input  logic               clk,
    input  logic               rst,
    input  logic               in_valid,
    input  logic signed [47:0] u,
    input  logic signed [47:0] v,
    input  logic signed [47:0] dudx,
    input  logic signed [47:0] dvdx,
    input  logic signed [47:0] dudy,
    input  logic signed [47:0] dvdy,
    // Texture and sampler state
    input  logic               cfg_trilinear,
    input  logic        [ 2:0] cfg_mode_u,
    input  logic        [ 2:0] cfg_mode_v,
    input  logic signed [ 4:0] cfg_offset_u,
    input  logic signed [ 4:0] cfg_offset_v,
    input  logic signed [31:0] cfg_bias,
    input  logic signed [31:0] cfg_min_lod,
    input  logic signed [31:0] cfg_max_lod,
    input  logic        [15:0] cfg_w0,
    input  logic        [15:0] cfg_h0,
    input  logic        [ 4:0] cfg_levels,
    input  logic        [ 1:0] cfg_layout,
    input  logic               cfg_base_we,
    input  logic        [ 3:0] cfg_base_idx,
    input  logic        [31:0] cfg_base_data,
    input  logic        [15:0] cfg_add_n,
    input  logic        [15:0] cfg_mul_n,
    input  logic        [15:0] cfg_div_n,
    input  logic        [15:0] cfg_cmp_n,
    // Texel memory
    output logic               rd_valid,
    output logic        [255:0] rd_addr,
    input  logic        [255:0] rd_data,
    // Result
    output logic               out_valid,
    output logic        [31:0] out_rgba,
    output logic        [ 3:0] out_level_hi,
    output logic        [ 3:0] out_level_lo,
    output logic        [M-1:0] out_delta,
    output logic        [63:0] ops_add,
    output logic        [63:0] ops_mul,
    output logic        [63:0] ops_div,
    output logic        [63:0] ops_cmp,
    output logic        [63:0] items
);
  localparam int LERP_LAT = 4 * ADD_LAT + 2 * MUL_LAT;

  logic [31:0] base[16];
  always_ff @(posedge clk) if (cfg_base_we) base[cfg_base_idx] <= cfg_base_data;

  // ---- LOD: levels and δ, LOD_LAT registers (u, v wait beside them) ----
  logic [3:0] lhi, llo, lhi1, llo1;
  logic [M-1:0] dl, dl1;
  logic signed [47:0] u1, v1;
  logic vl1;
  texsim_sampler_lod #(.M(M)) u_lod (
      .dudx, .dvdx, .dudy, .dvdy, .w0(cfg_w0), .h0(cfg_h0), .levels(cfg_levels),
      .trilinear(cfg_trilinear), .bias(cfg_bias), .min_lod(cfg_min_lod), .max_lod(cfg_max_lod),
      .level_hi(lhi), .level_lo(llo), .delta(dl));
  texsim_pipe #(.W(1 + 8 + M + 96), .N(LOD_LAT)) u_p_lod (
      .clk, .rst, .d({in_valid, lhi, llo, dl, u, v}), .q({vl1, lhi1, llo1, dl1, u1, v1}));

  // ---- Addresses of both levels, ADDR_LAT registers ----
  logic [31:0] ah[4], al[4];
  logic [S-1:0] fxh, fyh, fxl, fyl;
  texsim_sampler_addr #(.S(S)) u_addr_hi (
      .u(u1), .v(v1), .level(lhi1), .w0(cfg_w0), .h0(cfg_h0), .mode_u(cfg_mode_u),
      .mode_v(cfg_mode_v), .offset_u(cfg_offset_u), .offset_v(cfg_offset_v), .layout(cfg_layout),
      .base(base[lhi1]), .a00(ah[0]), .a10(ah[1]), .a01(ah[2]), .a11(ah[3]), .fx(fxh), .fy(fyh));
  texsim_sampler_addr #(.S(S)) u_addr_lo (
      .u(u1), .v(v1), .level(llo1), .w0(cfg_w0), .h0(cfg_h0), .mode_u(cfg_mode_u),
      .mode_v(cfg_mode_v), .offset_u(cfg_offset_u), .offset_v(cfg_offset_v), .layout(cfg_layout),
      .base(base[llo1]), .a00(al[0]), .a10(al[1]), .a01(al[2]), .a11(al[3]), .fx(fxl), .fy(fyl));
  logic [4*S-1:0] w2;
  logic [3:0] lhi2, llo2;
  logic [M-1:0] dl2;
  texsim_pipe #(.W(1 + 256 + 4 * S + 8 + M), .N(ADDR_LAT)) u_p_addr (
      .clk, .rst,
      .d({vl1, al[3], al[2], al[1], al[0], ah[3], ah[2], ah[1], ah[0], fxh, fyh, fxl, fyl, lhi1,
          llo1, dl1}),
      .q({rd_valid, rd_addr, w2, lhi2, llo2, dl2}));

  // ---- Texel read: the memory's data arrive one cycle after the address ----
  logic [255:0] tex3;
  logic [4*S-1:0] w3;
  logic [3:0] lhi3, llo3;
  logic [M-1:0] dl3;
  logic vl3;
  always_ff @(posedge clk) tex3 <= rd_data;
  texsim_pipe #(.W(1 + 4 * S + 8 + M), .N(1)) u_p_mem (
      .clk, .rst, .d({rd_valid, w2, lhi2, llo2, dl2}), .q({vl3, w3, lhi3, llo3, dl3}));

  // ---- Two bilinear lerps, LERP_LAT ----
  logic [31:0] ch, cl;
  logic vl4;
  logic [3:0] lhi4, llo4;
  logic [M-1:0] dl4;
  logic tri4;
  /* verilator lint_off PINCONNECTEMPTY */
  bilinear_lerp #(.T(8), .S(S), .MUL_LAT(MUL_LAT), .ADD_LAT(ADD_LAT)) u_lerp_hi (
      .clk, .rst, .in_valid(vl3), .t00(tex3[31:0]), .t10(tex3[63:32]), .t01(tex3[95:64]),
      .t11(tex3[127:96]), .fx(w3[4*S-1:3*S]), .fy(w3[3*S-1:2*S]), .out_valid(vl4), .out(ch),
      .ops_add(), .ops_mul(), .ops_div(), .ops_cmp(), .items());
  bilinear_lerp #(.T(8), .S(S), .MUL_LAT(MUL_LAT), .ADD_LAT(ADD_LAT)) u_lerp_lo (
      .clk, .rst, .in_valid(vl3), .t00(tex3[159:128]), .t10(tex3[191:160]),
      .t01(tex3[223:192]), .t11(tex3[255:224]), .fx(w3[2*S-1:S]), .fy(w3[S-1:0]),
      .out_valid(), .out(cl), .ops_add(), .ops_mul(), .ops_div(), .ops_cmp(), .items());
  /* verilator lint_on PINCONNECTEMPTY */
  texsim_pipe #(.W(8 + M + 1), .N(LERP_LAT)) u_p_lerp (
      .clk, .rst, .d({lhi3, llo3, dl3, cfg_trilinear}), .q({lhi4, llo4, dl4, tri4}));

  // ---- The lerp between the levels, MIP_LAT ----
  localparam int AW = M + 11;
  localparam logic signed [AW-1:0] HALF = AW'(1) <<< (M - 1);
  logic [31:0] mix;
  for (genvar c = 0; c < 4; c++) begin : g_mix
    /* verilator lint_off UNUSEDSIGNAL */
    logic signed [M+10:0] acc;  // bits M+7..M are the result: the sum stays in [0, 255·2^M]
    /* verilator lint_on UNUSEDSIGNAL */
    assign acc = $signed({3'b0, ch[8*c+:8], M'(0)}) +
                 (AW'($signed({1'b0, cl[8*c+:8]})) - AW'($signed({1'b0, ch[8*c+:8]}))) *
                     AW'($signed({1'b0, dl4})) + HALF;
    assign mix[8*c+:8] = tri4 ? acc[M+:8] : ch[8*c+:8];
  end
  texsim_pipe #(.W(1 + 32 + 8 + M), .N(MIP_LAT)) u_p_mix (
      .clk, .rst, .d({vl4, mix, lhi4, llo4, dl4}),
      .q({out_valid, out_rgba, out_level_hi, out_level_lo, out_delta}));

  texsim_op_counters u_ops (
      .clk, .rst, .retire(out_valid), .add_n(cfg_add_n), .mul_n(cfg_mul_n), .div_n(cfg_div_n),
      .cmp_n(cfg_cmp_n), .ops_add, .ops_mul, .ops_div, .ops_cmp, .items);
endmodule
