// Icarus Verilog testbench of vd_p2 (or, with -DTB_VD_P1, vd_p1): a vector is {d, v}
// (FIN + FC + 1 bits); the parameters come from rtl_params.h as the lockstep's (-P tb_vd.X=v).
`timescale 1ns / 1ps
module tb_vd;
  parameter int FIN = 16, FC = 15, MUL_LAT = 3, ADD_LAT = 1, CMP_LAT = 1;
  parameter int C0 = 0, C1 = 0, C2 = 0;
  parameter int B0 = 0, B1 = 0, A0 = 0, S0 = 0, A1 = 0, S1 = 0, A2 = 0, S2 = 0;
  parameter int LAT = 8;
  localparam int IW = FIN, OW = FC + 1;
  logic clk, rst, in_valid, out_valid;
  logic [IW-1:0] vin;
  logic [OW-1:0] vout;
`ifdef TB_VD_P1
  vd_p1 #(.FIN(FIN), .FC(FC), .MUL_LAT(MUL_LAT), .ADD_LAT(ADD_LAT), .CMP_LAT(CMP_LAT), .B0(B0),
          .B1(B1), .A0(A0), .S0(S0), .A1(A1), .S1(S1), .A2(A2), .S2(S2))
`else
  vd_p2 #(.FIN(FIN), .FC(FC), .MUL_LAT(MUL_LAT), .ADD_LAT(ADD_LAT), .C0(C0), .C1(C1), .C2(C2))
`endif
      dut (.clk(clk), .rst(rst), .in_valid(in_valid), .d(vin), .out_valid(out_valid), .v(vout),
           .ops_add(), .ops_mul(), .ops_div(), .ops_cmp(), .items());
`include "tb_stream.vh"
endmodule
