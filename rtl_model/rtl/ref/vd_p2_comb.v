// V(d) evaluator P2 (METHODS §5.4; C++ core blocks/texture/subtexel/vd_evaluator_p2.h):
// V = (c2·d + c1)·d + c0 in Horner form, 2 multipliers and 2 adders in series.
// Formats (VdFixedFormat<FIN, FC>): d u0.FIN; coefficients and intermediates s3.FC; V u1.FC.
// Each product is exact, then rounded HalfUp to FC fraction bits and saturated; each sum is
// saturated; the output is clamped to u1.FC. Latency 2·MUL_LAT + 2·ADD_LAT, one item per cycle.
module vd_p2_comb #(
    parameter int FIN = 16,
    parameter int FC = 15,
    parameter int MUL_LAT = 3,
    parameter int ADD_LAT = 1,
    parameter int C0 = 0,  // coefficients: raw s3.FC, from the generated parameters
    parameter int C1 = 0,
    parameter int C2 = 0
) (
    input  logic          clk,
    input  logic          rst,
    input  logic          in_valid,
    input  logic [FIN-1:0] d,
    output logic          out_valid,
    output logic [  FC:0] v,
    output logic [  63:0] ops_add,
    output logic [  63:0] ops_mul,
    output logic [  63:0] ops_div,
    output logic [  63:0] ops_cmp,
    output logic [  63:0] items
);
  localparam int CW = FC + 3;  // s3.FC
  localparam int PW = CW + FIN + 1;  // exact product of s3.FC and u0.FIN (zero-extended)
  localparam int LAT = 2 * MUL_LAT + 2 * ADD_LAT;
  localparam logic signed [CW-1:0] K0 = CW'(C0);
  localparam logic signed [CW-1:0] K1 = CW'(C1);
  localparam logic signed [CW-1:0] K2 = CW'(C2);

  // Stage 1: t = c2·d
  logic signed [PW-1:0] p1;
  logic [CW-1:0] t1, t1_q;
  logic [FIN-1:0] d1_q;
  assign p1 = PW'(K2) * $signed({1'b0, d});
  texsim_round_sat #(.IN_W(PW), .IN_F(FC + FIN), .OUT_W(CW), .OUT_F(FC)) u_r1 (.in(p1), .out(t1));
  texsim_pipe #(.W(CW), .N(MUL_LAT)) u_t1 (.clk, .rst, .d(t1), .q(t1_q));
  texsim_pipe #(.W(FIN), .N(MUL_LAT)) u_d1 (.clk, .rst, .d(d), .q(d1_q));

  // Stage 2: t += c1
  logic [CW-1:0] t2, t2_q;
  logic [FIN-1:0] d2_q;
  texsim_round_sat #(.IN_W(CW + 1), .IN_F(FC), .OUT_W(CW), .OUT_F(FC)) u_s2 (
      .in((CW + 1)'($signed(t1_q)) + (CW + 1)'(K1)), .out(t2));
  texsim_pipe #(.W(CW), .N(ADD_LAT)) u_t2 (.clk, .rst, .d(t2), .q(t2_q));
  texsim_pipe #(.W(FIN), .N(ADD_LAT)) u_d2 (.clk, .rst, .d(d1_q), .q(d2_q));

  // Stage 3: t = t·d
  logic signed [PW-1:0] p3;
  logic [CW-1:0] t3, t3_q;
  assign p3 = PW'($signed(t2_q)) * $signed({1'b0, d2_q});
  texsim_round_sat #(.IN_W(PW), .IN_F(FC + FIN), .OUT_W(CW), .OUT_F(FC)) u_r3 (.in(p3), .out(t3));
  texsim_pipe #(.W(CW), .N(MUL_LAT)) u_t3 (.clk, .rst, .d(t3), .q(t3_q));

  // Stage 4: V = t + c0, saturated into s3.FC, then clamped into u1.FC
  logic [CW-1:0] t4;
  logic [FC:0] v4;
  texsim_round_sat #(.IN_W(CW + 1), .IN_F(FC), .OUT_W(CW), .OUT_F(FC)) u_s4 (
      .in((CW + 1)'($signed(t3_q)) + (CW + 1)'(K0)), .out(t4));
  texsim_round_sat #(.IN_W(CW), .IN_F(FC), .OUT_W(FC + 1), .OUT_F(FC), .OUT_SIGNED(0)) u_o4 (
      .in(t4), .out(v4));
  texsim_pipe #(.W(FC + 1), .N(ADD_LAT)) u_v4 (.clk, .rst, .d(v4), .q(v));

  texsim_pipe #(.W(1), .N(LAT)) u_valid (.clk, .rst, .d(in_valid), .q(out_valid));
  texsim_op_counters u_ops (
      .clk, .rst, .retire(out_valid), .add_n(16'd2), .mul_n(16'd2), .div_n(16'd0), .cmp_n(16'd0),
      .ops_add, .ops_mul, .ops_div, .ops_cmp, .items);
endmodule
