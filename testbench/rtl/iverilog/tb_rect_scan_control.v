// Icarus Verilog cycle-trace testbench of rect_scan_control (tb_trace.vh): inputs {load,
// foreground, closing, outline, minor_lo, minor_hi, in_valid, row_start, inside0, word, minor},
// outputs {out_valid, out_texture, out_end_of_row, out_hits, op counters}.
`timescale 1ns / 1ps
module tb_rect_scan_control;
  parameter int CW = 16, LAT = 2;
  localparam int IW = 16 + 3 * CW, OW = 6 + 5 * 64;
  logic clk, rst;
  logic [IW-1:0] vin;
  logic [OW-1:0] vout;
  logic load, outline, in_valid, row_start, out_valid, out_texture, out_end_of_row;
  logic [2:0] foreground, closing, inside0, word, out_hits;
  logic [CW-1:0] minor_lo, minor_hi, minor;
  logic [63:0] ops_add, ops_mul, ops_div, ops_cmp, items;
  assign {load, foreground, closing, outline, minor_lo, minor_hi, in_valid, row_start, inside0,
          word, minor} = vin;
  rect_scan_control #(.CW(CW), .LAT(LAT)) dut (
      .clk(clk), .rst(rst), .load(load), .foreground(foreground), .closing(closing),
      .outline(outline), .minor_lo(minor_lo), .minor_hi(minor_hi), .in_valid(in_valid),
      .row_start(row_start), .inside0(inside0), .word(word), .minor(minor),
      .out_valid(out_valid), .out_texture(out_texture), .out_end_of_row(out_end_of_row),
      .out_hits(out_hits), .ops_add(ops_add), .ops_mul(ops_mul), .ops_div(ops_div),
      .ops_cmp(ops_cmp), .items(items));
  assign vout = {out_valid, out_texture, out_end_of_row, out_hits, ops_add, ops_mul, ops_div,
                 ops_cmp, items};
`include "tb_trace.vh"
endmodule
