// Icarus Verilog cycle-trace testbench of rect_scan_raster (tb_trace.vh): inputs {mem_we,
// mem_major, mem_minor, mem_wdata, in_valid, x_major, neg, delta_minor, major0, major1, t_lo,
// t_hi, mem_lo, mem_hi, minor_lo, minor_hi, closing, outline, ev0..ev2, ev_row0..ev_row2},
// outputs {in_ready, out_valid, out_row_start, out_x, out_y, out_texture, out_end_of_row,
// out_hits, op counters}.
`timescale 1ns / 1ps
module tb_rect_scan_raster;
  parameter int SLOPE_BITS = 12, CW = 16, MAJ_BITS = 8, MIN_BITS = 9;
  localparam int IW = 11 + MAJ_BITS + MIN_BITS + (SLOPE_BITS + 1) + 8 * CW + 6 * 64;
  localparam int OW = 8 + 2 * CW + 5 * 64;
  logic clk, rst;
  logic [IW-1:0] vin;
  logic [OW-1:0] vout;
  logic mem_we, in_valid, in_ready, x_major, neg, outline;
  logic out_valid, out_row_start, out_texture, out_end_of_row;
  logic [MAJ_BITS-1:0] mem_major;
  logic [MIN_BITS-1:0] mem_minor;
  logic [2:0] mem_wdata, closing, out_hits;
  logic [SLOPE_BITS:0] delta_minor;
  logic [CW-1:0] major0, major1, t_lo, t_hi, mem_lo, mem_hi, minor_lo, minor_hi, out_x, out_y;
  logic [63:0] ev0, ev1, ev2, ev_row0, ev_row1, ev_row2;
  logic [63:0] ops_add, ops_mul, ops_div, ops_cmp, items;
  assign {mem_we, mem_major, mem_minor, mem_wdata, in_valid, x_major, neg, delta_minor, major0,
          major1, t_lo, t_hi, mem_lo, mem_hi, minor_lo, minor_hi, closing, outline, ev0, ev1, ev2,
          ev_row0, ev_row1, ev_row2} = vin;
  rect_scan_raster #(.SLOPE_BITS(SLOPE_BITS), .CW(CW), .MAJ_BITS(MAJ_BITS), .MIN_BITS(MIN_BITS))
      dut (
      .clk(clk), .rst(rst), .mem_we(mem_we), .mem_major(mem_major), .mem_minor(mem_minor),
      .mem_wdata(mem_wdata), .in_valid(in_valid), .in_ready(in_ready), .x_major(x_major),
      .neg(neg), .delta_minor(delta_minor), .major0(major0), .major1(major1), .t_lo(t_lo),
      .t_hi(t_hi), .mem_lo(mem_lo), .mem_hi(mem_hi), .minor_lo(minor_lo), .minor_hi(minor_hi),
      .closing(closing), .outline(outline), .ev0(ev0), .ev1(ev1), .ev2(ev2), .ev_row0(ev_row0),
      .ev_row1(ev_row1), .ev_row2(ev_row2), .out_valid(out_valid), .out_row_start(out_row_start),
      .out_x(out_x), .out_y(out_y), .out_texture(out_texture), .out_end_of_row(out_end_of_row),
      .out_hits(out_hits), .ops_add(ops_add), .ops_mul(ops_mul), .ops_div(ops_div),
      .ops_cmp(ops_cmp), .items(items));
  assign vout = {in_ready, out_valid, out_row_start, out_x, out_y, out_texture, out_end_of_row,
                 out_hits, ops_add, ops_mul, ops_div, ops_cmp, items};
`include "tb_trace.vh"
endmodule
