// Bilinear lerp datapath (C++ core blocks/texture/sampler/bilinear_lerp.h): four channels of
// T bits side by side, weights fx, fy of S fraction bits (the sub-texel precision).
//   top = t00·2^S + (t10 − t00)·fx,  bot = t01·2^S + (t11 − t01)·fx    (exact)
//   out = (top·2^S + (bot − top)·fy + 2^(2S−1)) >> 2S                  (one HalfUp rounding)
// Per channel 3 multipliers and 6 adders; latency 4·ADD_LAT + 2·MUL_LAT, one item per cycle.
module bilinear_lerp_comb #(
    parameter int T = 8,
    parameter int S = 8,
    parameter int MUL_LAT = 3,
    parameter int ADD_LAT = 1
) (
    input  logic           clk,
    input  logic           rst,
    input  logic           in_valid,
    input  logic [4*T-1:0] t00,
    input  logic [4*T-1:0] t10,
    input  logic [4*T-1:0] t01,
    input  logic [4*T-1:0] t11,
    input  logic [  S-1:0] fx,
    input  logic [  S-1:0] fy,
    output logic           out_valid,
    output logic [4*T-1:0] out,
    output logic [   63:0] ops_add,
    output logic [   63:0] ops_mul,
    output logic [   63:0] ops_div,
    output logic [   63:0] ops_cmp,
    output logic [   63:0] items
);
  localparam int LAT = 4 * ADD_LAT + 2 * MUL_LAT;
  localparam int DW = T + 1;  // signed texel difference
  localparam int XW = T + S + 2;  // x-lerp results (unsigned T+S bits) and their difference
  localparam int AW = T + 2 * S + 3;  // y-lerp accumulator

  // fy is used by the second multiplier: it waits for the first half.
  logic [S-1:0] fx1_q, fy3_q;
  texsim_pipe #(.W(S), .N(ADD_LAT)) u_fx1 (.clk, .rst, .d(fx), .q(fx1_q));
  texsim_pipe #(.W(S), .N(3 * ADD_LAT + MUL_LAT)) u_fy3 (.clk, .rst, .d(fy), .q(fy3_q));

  for (genvar c = 0; c < 4; c++) begin : g_ch
    logic [T-1:0] a00, a10, a01, a11;
    assign a00 = t00[c*T+:T];
    assign a10 = t10[c*T+:T];
    assign a01 = t01[c*T+:T];
    assign a11 = t11[c*T+:T];

    // Stage 1: the two x differences
    logic signed [DW-1:0] dx0, dx1, dx0_q, dx1_q;
    logic [T-1:0] a00_q, a01_q;
    assign dx0 = $signed({1'b0, a10}) - $signed({1'b0, a00});
    assign dx1 = $signed({1'b0, a11}) - $signed({1'b0, a01});
    texsim_pipe #(.W(2 * DW), .N(ADD_LAT)) u_d (.clk, .rst, .d({dx0, dx1}), .q({dx0_q, dx1_q}));
    texsim_pipe #(.W(2 * T), .N(ADD_LAT + MUL_LAT)) u_a (.clk, .rst, .d({a00, a01}), .q({a00_q, a01_q}));

    // Stage 2: ×fx
    logic signed [XW-1:0] px0, px1, px0_q, px1_q;
    assign px0 = XW'(dx0_q) * $signed({1'b0, fx1_q});
    assign px1 = XW'(dx1_q) * $signed({1'b0, fx1_q});
    texsim_pipe #(.W(2 * XW), .N(MUL_LAT)) u_px (.clk, .rst, .d({px0, px1}), .q({px0_q, px1_q}));

    // Stage 3: top, bot
    logic signed [XW-1:0] top, bot, top_q, bot_q;
    assign top = $signed({2'b0, a00_q, S'(0)}) + px0_q;
    assign bot = $signed({2'b0, a01_q, S'(0)}) + px1_q;
    texsim_pipe #(.W(2 * XW), .N(ADD_LAT)) u_tb (.clk, .rst, .d({top, bot}), .q({top_q, bot_q}));

    // Stage 4: bot − top
    logic signed [XW-1:0] dy, dy_q, top4_q;
    assign dy = bot_q - top_q;
    texsim_pipe #(.W(XW), .N(ADD_LAT)) u_dy (.clk, .rst, .d(dy), .q(dy_q));
    texsim_pipe #(.W(XW), .N(ADD_LAT + MUL_LAT)) u_t4 (.clk, .rst, .d(top_q), .q(top4_q));

    // Stage 5: ×fy
    logic signed [AW-1:0] py, py_q;
    assign py = AW'(dy_q) * $signed({1'b0, fy3_q});
    texsim_pipe #(.W(AW), .N(MUL_LAT)) u_py (.clk, .rst, .d(py), .q(py_q));

    // Stage 6: top·2^S + py + half, >> 2S
    /* verilator lint_off UNUSEDSIGNAL */
    logic signed [AW-1:0] acc;
    /* verilator lint_on UNUSEDSIGNAL */
    logic [T-1:0] res;
    localparam logic signed [AW-1:0] HALF = AW'(1) <<< (2 * S - 1);
    assign acc = (AW'(top4_q) <<< S) + py_q + HALF;
    assign res = acc[2*S+:T];  // the sum never exceeds (2^T - 1)·2^2S + half: high bits unused
    texsim_pipe #(.W(T), .N(ADD_LAT)) u_o (.clk, .rst, .d(res), .q(out[c*T+:T]));
  end

  texsim_pipe #(.W(1), .N(LAT)) u_valid (.clk, .rst, .d(in_valid), .q(out_valid));
  texsim_op_counters u_ops (
      .clk, .rst, .retire(out_valid), .add_n(16'd24), .mul_n(16'd12), .div_n(16'd0),
      .cmp_n(16'd0), .ops_add, .ops_mul, .ops_div, .ops_cmp, .items);
endmodule
