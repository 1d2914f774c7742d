// texsim_add_sat: out = a + b (signed W bits each) saturated into W signed bits, or with
// OUT_SIGNED = 0 clamped into [0, 2^OUT_W − 1] (OUT_W < W: the same as saturating into W bits
// first, as Fixed does, then clamping, since the second range lies inside the first). One
// carry chain, then one LUT per output bit from the sum's top bits (no comparators), then LAT
// registers without reset. The value equals texsim_round_sat on the W+1-bit sum.
module texsim_add_sat #(
    parameter int W = 18,
    parameter bit OUT_SIGNED = 1,
    parameter int OUT_W = W,
    parameter int LAT = 1
) (
    input  logic                 clk,
    input  logic signed [W-1:0] a,
    input  logic signed [W-1:0] b,
    output logic     [OUT_W-1:0] out
);
  logic signed [W:0] s;
  logic [OUT_W-1:0] y;
  assign s = (W + 1)'(a) + (W + 1)'(b);
  if (OUT_SIGNED) begin : g_sat
    // overflow when the carry into the sign differs from the sign: bits W and W-1 differ
    assign y = s[W] != s[W-1] ? {s[W], {(OUT_W - 1) {~s[W]}}} : s[OUT_W-1:0];
  end else begin : g_clamp
    logic over;
    assign over = |s[W-1:OUT_W];  // ≥ 2^OUT_W when not negative
    assign y = s[W] ? '0 : (over ? {OUT_W{1'b1}} : s[OUT_W-1:0]);
  end
  texsim_pipe #(.W(OUT_W), .N(LAT), .RST(0)) u_q (.clk, .rst(1'b0), .d(y), .q(out));
endmodule
