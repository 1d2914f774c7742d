// Icarus Verilog cycle-trace testbench of uv_incremental (tb_trace.vh): inputs {in_valid, ca..ci,
// x0, y, n}, outputs {in_ready, out_valid, out_mask, out_ok, out_u, out_v, op counters}.
`timescale 1ns / 1ps
module tb_uv_incremental;
  parameter int W = 32, F = 16, K = 4, SETUP_LAT = 8, DIV_LAT = 12, MIN_DEN = 16, XW = 16;
  parameter int NW = 16;
  localparam int IW = 1 + 9 * W + 2 * XW + NW, OW = 2 + 2 * K + 2 * K * W + 5 * 64;
  logic clk, rst;
  logic [IW-1:0] vin;
  logic [OW-1:0] vout;
  logic in_valid, in_ready, out_valid;
  logic [W-1:0] ca, cb, cc, cd, ce, cf, cg, ch, ci;
  logic [XW-1:0] x0, y;
  logic [NW-1:0] count;
  logic [K-1:0] out_mask, out_ok;
  logic [K*W-1:0] out_u, out_v;
  logic [63:0] ops_add, ops_mul, ops_div, ops_cmp, items;
  assign {in_valid, ca, cb, cc, cd, ce, cf, cg, ch, ci, x0, y, count} = vin;
  uv_incremental #(.W(W), .F(F), .K(K), .SETUP_LAT(SETUP_LAT), .DIV_LAT(DIV_LAT),
                   .MIN_DEN(MIN_DEN), .XW(XW), .NW(NW)) dut (
      .clk(clk), .rst(rst), .in_valid(in_valid), .in_ready(in_ready), .ca(ca), .cb(cb), .cc(cc),
      .cd(cd), .ce(ce), .cf(cf), .cg(cg), .ch(ch), .ci(ci), .x0(x0), .y(y), .n(count),
      .out_valid(out_valid), .out_mask(out_mask), .out_ok(out_ok), .out_u(out_u), .out_v(out_v),
      .ops_add(ops_add), .ops_mul(ops_mul), .ops_div(ops_div), .ops_cmp(ops_cmp), .items(items));
  assign vout = {in_ready, out_valid, out_mask, out_ok, out_u, out_v, ops_add, ops_mul, ops_div,
                 ops_cmp, items};
`include "tb_trace.vh"
endmodule
