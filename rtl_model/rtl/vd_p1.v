// V(d) evaluator P1 (METHODS §5.4; C++ core blocks/texture/subtexel/vd_evaluator_p1.h):
// two comparators against the breakpoints B0 < B1 pick one of three (offset, slope) pairs,
// then V = slope·d + offset with 1 multiplier and 1 adder. Formats as vd_p2 (d u0.FIN,
// coefficients s3.FC, V u1.FC; product rounded HalfUp, sums saturated).
// Latency 2·CMP_LAT (compare, select) + MUL_LAT + ADD_LAT, one item per cycle.
// Retimed as vd_p2 (texsim_mul_rs, texsim_add_sat); ref/vd_p1_comb.v is the earlier form.
module vd_p1 #(
    parameter int FIN = 16,
    parameter int FC = 15,
    parameter int MUL_LAT = 3,
    parameter int ADD_LAT = 1,
    parameter int CMP_LAT = 1,
    parameter int B0 = 0,  // breakpoints (raw u0.FIN) and pairs (raw s3.FC): generated
    parameter int B1 = 0,
    parameter int A0 = 0,
    parameter int S0 = 0,
    parameter int A1 = 0,
    parameter int S1 = 0,
    parameter int A2 = 0,
    parameter int S2 = 0
) (
    input  logic           clk,
    input  logic           rst,
    input  logic           in_valid,
    input  logic [FIN-1:0] d,
    output logic           out_valid,
    output logic [   FC:0] v,
    output logic [   63:0] ops_add,
    output logic [   63:0] ops_mul,
    output logic [   63:0] ops_div,
    output logic [   63:0] ops_cmp,
    output logic [   63:0] items
);
  localparam int CW = FC + 3;
  localparam int LAT = 2 * CMP_LAT + MUL_LAT + ADD_LAT;
  localparam logic [FIN-1:0] KB0 = FIN'(B0);
  localparam logic [FIN-1:0] KB1 = FIN'(B1);

  // Stage 1: the two comparators, side by side
  logic lt0_q, lt1_q;
  logic [FIN-1:0] d1_q;
  texsim_pipe #(.W(2), .N(CMP_LAT), .RST(0)) u_c1 (.clk, .rst, .d({d < KB0, d < KB1}),
                                                   .q({lt0_q, lt1_q}));
  texsim_pipe #(.W(FIN), .N(CMP_LAT), .RST(0)) u_d1 (.clk, .rst, .d(d), .q(d1_q));

  // Stage 2: select the segment's pair
  logic signed [CW-1:0] off, slope, off_q, slope_q;
  logic [FIN-1:0] d2_q;
  always_comb begin
    if (lt0_q) begin
      off = CW'(A0);
      slope = CW'(S0);
    end else if (lt1_q) begin
      off = CW'(A1);
      slope = CW'(S1);
    end else begin
      off = CW'(A2);
      slope = CW'(S2);
    end
  end
  texsim_pipe #(.W(2 * CW), .N(CMP_LAT), .RST(0)) u_sel (.clk, .rst, .d({off, slope}),
                                                        .q({off_q, slope_q}));
  texsim_pipe #(.W(FIN), .N(CMP_LAT), .RST(0)) u_d2 (.clk, .rst, .d(d1_q), .q(d2_q));

  // t = slope·d (MUL_LAT stages), V = t + offset (saturated, clamped into u1.FC)
  logic [CW-1:0] t3, off3_q;
  texsim_mul_rs #(.AW(CW), .BW(FIN), .IN_F(FC + FIN), .OUT_W(CW), .OUT_F(FC), .LAT(MUL_LAT))
      u_m3 (.clk, .a(slope_q), .b(d2_q), .out(t3));
  texsim_pipe #(.W(CW), .N(MUL_LAT), .RST(0)) u_o3 (.clk, .rst, .d(off_q), .q(off3_q));
  texsim_add_sat #(.W(CW), .OUT_SIGNED(0), .OUT_W(FC + 1), .LAT(ADD_LAT)) u_a4 (
      .clk, .a(t3), .b(off3_q), .out(v));

  texsim_pipe #(.W(1), .N(LAT)) u_valid (.clk, .rst, .d(in_valid), .q(out_valid));
  texsim_op_counters u_ops (
      .clk, .rst, .retire(out_valid), .add_n(16'd1), .mul_n(16'd1), .div_n(16'd0), .cmp_n(16'd3),
      .ops_add, .ops_mul, .ops_div, .ops_cmp, .items);
endmodule
