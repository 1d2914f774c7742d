// Icarus Verilog testbench of bilinear_lerp: a vector is {t00, t10, t01, t11, fx, fy, out}
// (4·4T + 2S + 4T bits); parameters as the lockstep's (-P tb_bilinear_lerp.X=v).
`timescale 1ns / 1ps
module tb_bilinear_lerp;
  parameter int T = 8, S = 8, MUL_LAT = 3, ADD_LAT = 1;
  parameter int LAT = 10;
  localparam int IW = 16 * T + 2 * S, OW = 4 * T;
  logic clk, rst, in_valid, out_valid;
  logic [IW-1:0] vin;
  logic [OW-1:0] vout;
  bilinear_lerp #(.T(T), .S(S), .MUL_LAT(MUL_LAT), .ADD_LAT(ADD_LAT)) dut (
      .clk(clk), .rst(rst), .in_valid(in_valid), .t00(vin[IW-1-:4*T]), .t10(vin[IW-1-4*T-:4*T]),
      .t01(vin[IW-1-8*T-:4*T]), .t11(vin[IW-1-12*T-:4*T]), .fx(vin[2*S-1:S]), .fy(vin[S-1:0]),
      .out_valid(out_valid), .out(vout), .ops_add(), .ops_mul(), .ops_div(), .ops_cmp(),
      .items());
`include "tb_stream.vh"
endmodule
