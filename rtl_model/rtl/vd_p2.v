// V(d) evaluator P2 (METHODS §5.4; C++ core blocks/texture/subtexel/vd_evaluator_p2.h):
// V = (c2·d + c1)·d + c0 in Horner form, 2 multipliers and 2 adders in series.
// Formats (VdFixedFormat<FIN, FC>): d u0.FIN; coefficients and intermediates s3.FC; V u1.FC.
// Each product is exact, then rounded HalfUp to FC fraction bits and saturated; each sum is
// saturated; the output is clamped to u1.FC. Latency 2·MUL_LAT + 2·ADD_LAT, one item per cycle.
// Retimed: each multiplier spreads product, rounding and saturation over its MUL_LAT stages
// (texsim_mul_rs) and each adder saturates from the sum's top bits (texsim_add_sat), so no
// stage holds more than one carry chain. ref/vd_p2_comb.v is the earlier form (all of an
// operator's logic before its registers), proved equal to this one (test_rtl_equiv).
module vd_p2 #(
    parameter int FIN = 16,
    parameter int FC = 15,
    parameter int MUL_LAT = 3,
    parameter int ADD_LAT = 1,
    parameter int C0 = 0,  // coefficients: raw s3.FC, from the generated parameters
    parameter int C1 = 0,
    parameter int C2 = 0
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
  localparam int CW = FC + 3;  // s3.FC
  localparam int LAT = 2 * MUL_LAT + 2 * ADD_LAT;
  localparam logic signed [CW-1:0] K0 = CW'(C0);
  localparam logic signed [CW-1:0] K1 = CW'(C1);
  localparam logic signed [CW-1:0] K2 = CW'(C2);

  // t = c2·d; t += c1; t = t·d; V = t + c0 (saturated, clamped into u1.FC)
  logic [CW-1:0] t1, t2, t3;
  logic [FIN-1:0] d2;
  texsim_mul_rs #(.AW(CW), .BW(FIN), .IN_F(FC + FIN), .OUT_W(CW), .OUT_F(FC), .LAT(MUL_LAT))
      u_m1 (.clk, .a(K2), .b(d), .out(t1));
  texsim_add_sat #(.W(CW), .LAT(ADD_LAT)) u_a2 (.clk, .a(t1), .b(K1), .out(t2));
  texsim_pipe #(.W(FIN), .N(MUL_LAT + ADD_LAT), .RST(0)) u_d2 (.clk, .rst, .d(d), .q(d2));
  texsim_mul_rs #(.AW(CW), .BW(FIN), .IN_F(FC + FIN), .OUT_W(CW), .OUT_F(FC), .LAT(MUL_LAT))
      u_m3 (.clk, .a(t2), .b(d2), .out(t3));
  texsim_add_sat #(.W(CW), .OUT_SIGNED(0), .OUT_W(FC + 1), .LAT(ADD_LAT)) u_a4 (
      .clk, .a(t3), .b(K0), .out(v));

  texsim_pipe #(.W(1), .N(LAT)) u_valid (.clk, .rst, .d(in_valid), .q(out_valid));
  texsim_op_counters u_ops (
      .clk, .rst, .retire(out_valid), .add_n(16'd2), .mul_n(16'd2), .div_n(16'd0), .cmp_n(16'd0),
      .ops_add, .ops_mul, .ops_div, .ops_cmp, .items);
endmodule
