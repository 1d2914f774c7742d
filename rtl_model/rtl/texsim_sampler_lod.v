// LOD and level selection of the RTL sampler (C++ core FixedSampler::lambda and the level part
// of FixedSampler::sample, blocks/texture/sampler/fixed_sampler.h). Combinational; the
// sampler registers its outputs. Formats: derivatives s15.32 in, s15.16 texels of level 0,
// ρ² u31.32, log2 ρ² and λ s11.20, the level fraction u0.M. The log2 table is the generated
// module texsim_sampler_log2 (build/rtl_model/params/texsim_sampler_log2.v, gen_rtl_params).
module texsim_sampler_lod #(
    parameter int M = 8
) (
    input  logic signed [47:0] dudx,
    input  logic signed [47:0] dvdx,
    input  logic signed [47:0] dudy,
    input  logic signed [47:0] dvdy,
    input  logic        [15:0] w0,
    input  logic        [15:0] h0,
    input  logic        [ 4:0] levels,
    input  logic               trilinear,
    input  logic signed [31:0] bias,
    input  logic signed [31:0] min_lod,
    input  logic signed [31:0] max_lod,
    output logic        [ 3:0] level_hi,
    output logic        [ 3:0] level_lo,
    output logic        [M-1:0] delta
);
  // |d·size| in s15.16 (floor, saturated), squared.
  function automatic logic [63:0] texel_square(input logic signed [47:0] d, input logic [15:0] s);
    logic signed [64:0] p;
    logic signed [31:0] t;
    logic [31:0] a;
    p = 65'(d) * $signed({49'd0, s});
    p = p >>> 16;
    if (p > 65'sd2147483647) t = 32'sh7fffffff;
    else if (p < -65'sd2147483648) t = 32'sh80000000;
    else t = p[31:0];
    a = t[31] ? 32'(-t) : 32'(t);
    texel_square = 64'(a) * 64'(a);
  endfunction

  logic [63:0] px2, py2, r2;
  /* verilator lint_off UNUSEDSIGNAL */
  logic [63:0] norm;  // bits 62..43: table index and interpolation weight
  /* verilator lint_on UNUSEDSIGNAL */
  logic [5:0] p;
  logic [20:0] l0, l1;
  logic signed [33:0] log2v, lam, lam_c, q20, d;
  logic [11:0] frac;
  logic [7:0] idx;
  texsim_sampler_log2 u_log2_0 (.i({1'b0, idx}), .v(l0));
  texsim_sampler_log2 u_log2_1 (.i(9'(idx) + 9'd1), .v(l1));
  always_comb begin
    px2 = texel_square(dudx, w0) + texel_square(dvdx, h0);
    py2 = texel_square(dudy, w0) + texel_square(dvdy, h0);
    r2 = px2 > py2 ? px2 : py2;
    p = '0;
    for (int i = 0; i < 64; i++) if (r2[i]) p = 6'(i);
    norm = r2 << (6'd63 - p);
    idx = norm[62:55];
    frac = norm[54:43];
  end
  always_comb begin
    if (r2 == 0) log2v = -(34'sd64 <<< 20);
    else
      log2v = ((34'(p) - 34'sd32) <<< 20) + 34'(l0) +
              ((34'($signed({1'b0, l1})) - 34'($signed({1'b0, l0}))) * 34'($signed({1'b0, frac})) >>> 12);
    lam = (log2v >>> 1) + 34'(bias);
    lam_c = lam < 34'(min_lod) ? 34'(min_lod) : (lam > 34'(max_lod) ? 34'(max_lod) : lam);
    q20 = (levels == 0 ? 34'sd0 : 34'(levels) - 34'sd1) <<< 20;
    d = lam_c < 0 ? 34'sd0 : (lam_c > q20 ? q20 : lam_c);
  end

  // d to M fraction bits, rounded half to even (d ≥ 0).
  localparam int K = 20 - M;
  logic [33:0] t, rem, dfix;
  logic signed [34:0] n;
  logic [3:0] q;
  always_comb begin
    t = 34'(d) >> K;
    rem = 34'(d) & ((34'd1 << K) - 34'd1);
    dfix = t + ((rem > (34'd1 << (K - 1)) || (rem == (34'd1 << (K - 1)) && t[0])) ? 34'd1 : 34'd0);
    q = levels == 0 ? 4'd0 : 4'(levels - 5'd1);
    n = '0;
    if (trilinear) begin
      level_hi = 4'(dfix >> M);
      level_lo = level_hi == q ? q : level_hi + 4'd1;
      delta = dfix[M-1:0];
    end else begin
      // Vulkan's nearest level ⌈d + ½⌉ − 1 (halves round down).
      n = $signed({1'b0, (dfix + (34'd1 << (M - 1)) + (34'd1 << M) - 34'd1) >> M}) - 35'sd1;
      level_hi = n < 0 ? 4'd0 : (n > 35'(q) ? q : 4'(n));
      level_lo = level_hi;
      delta = '0;
    end
  end
endmodule
