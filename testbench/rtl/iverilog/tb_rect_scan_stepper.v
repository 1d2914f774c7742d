// Icarus Verilog cycle-trace testbench of rect_scan_stepper (tb_trace.vh): inputs {in_valid,
// x_major, neg, delta_minor, major0, major1, t_lo, t_hi, row_end}, outputs {in_ready,
// out_valid, out_row_start, out_x, out_y, op counters}.
`timescale 1ns / 1ps
module tb_rect_scan_stepper;
  parameter int SLOPE_BITS = 12, CW = 16;
  localparam int IW = 4 + (SLOPE_BITS + 1) + 4 * CW, OW = 3 + 2 * CW + 5 * 64;
  logic clk, rst;
  logic [IW-1:0] vin;
  logic [OW-1:0] vout;
  logic in_valid, in_ready, x_major, neg, row_end, out_valid, out_row_start;
  logic [SLOPE_BITS:0] delta_minor;
  logic [CW-1:0] major0, major1, t_lo, t_hi, out_x, out_y;
  logic [63:0] ops_add, ops_mul, ops_div, ops_cmp, items;
  assign {in_valid, x_major, neg, delta_minor, major0, major1, t_lo, t_hi, row_end} = vin;
  rect_scan_stepper #(.SLOPE_BITS(SLOPE_BITS), .CW(CW)) dut (
      .clk(clk), .rst(rst), .in_valid(in_valid), .in_ready(in_ready), .x_major(x_major),
      .neg(neg), .delta_minor(delta_minor), .major0(major0), .major1(major1), .t_lo(t_lo),
      .t_hi(t_hi), .row_end(row_end), .out_valid(out_valid), .out_row_start(out_row_start),
      .out_x(out_x), .out_y(out_y), .ops_add(ops_add), .ops_mul(ops_mul), .ops_div(ops_div),
      .ops_cmp(ops_cmp), .items(items));
  assign vout = {in_ready, out_valid, out_row_start, out_x, out_y, ops_add, ops_mul, ops_div,
                 ops_cmp, items};
`include "tb_trace.vh"
endmodule
