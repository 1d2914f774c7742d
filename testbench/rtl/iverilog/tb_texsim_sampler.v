// Icarus Verilog cycle-trace testbench of texsim_sampler (tb_trace.vh): inputs {in_valid, u, v,
// dudx, dvdx, dudy, dvdy, the cfg_* state in port order, rd_data} (rd_data as the Verilated
// run's memory answered), outputs {rd_valid, rd_addr, out_valid, out_rgba, out_level_hi,
// out_level_lo, out_delta, op counters}.
`timescale 1ns / 1ps
module tb_texsim_sampler;
  parameter int S = 8, M = 8, LOD_LAT = 1, ADDR_LAT = 1, MUL_LAT = 3, ADD_LAT = 1, MIP_LAT = 1;
  localparam int IW = 1 + 6 * 48 + 1 + 3 + 3 + 5 + 5 + 3 * 32 + 16 + 16 + 5 + 2 + 1 + 4 + 32 +
      4 * 16 + 256;
  localparam int OW = 1 + 256 + 1 + 32 + 4 + 4 + M + 5 * 64;
  logic clk, rst;
  logic [IW-1:0] vin;
  logic [OW-1:0] vout;
  logic in_valid, cfg_trilinear, cfg_base_we, rd_valid, out_valid;
  logic signed [47:0] u, v, dudx, dvdx, dudy, dvdy;
  logic [2:0] cfg_mode_u, cfg_mode_v;
  logic signed [4:0] cfg_offset_u, cfg_offset_v;
  logic signed [31:0] cfg_bias, cfg_min_lod, cfg_max_lod;
  logic [15:0] cfg_w0, cfg_h0, cfg_add_n, cfg_mul_n, cfg_div_n, cfg_cmp_n;
  logic [4:0] cfg_levels;
  logic [1:0] cfg_layout;
  logic [3:0] cfg_base_idx, out_level_hi, out_level_lo;
  logic [31:0] cfg_base_data, out_rgba;
  logic [255:0] rd_addr, rd_data;
  logic [M-1:0] out_delta;
  logic [63:0] ops_add, ops_mul, ops_div, ops_cmp, items;
  assign {in_valid, u, v, dudx, dvdx, dudy, dvdy, cfg_trilinear, cfg_mode_u, cfg_mode_v,
          cfg_offset_u, cfg_offset_v, cfg_bias, cfg_min_lod, cfg_max_lod, cfg_w0, cfg_h0,
          cfg_levels, cfg_layout, cfg_base_we, cfg_base_idx, cfg_base_data, cfg_add_n, cfg_mul_n,
          cfg_div_n, cfg_cmp_n, rd_data} = vin;
  texsim_sampler #(.S(S), .M(M), .LOD_LAT(LOD_LAT), .ADDR_LAT(ADDR_LAT), .MUL_LAT(MUL_LAT),
                   .ADD_LAT(ADD_LAT), .MIP_LAT(MIP_LAT)) dut (
      .clk(clk), .rst(rst), .in_valid(in_valid), .u(u), .v(v), .dudx(dudx), .dvdx(dvdx),
      .dudy(dudy), .dvdy(dvdy), .cfg_trilinear(cfg_trilinear), .cfg_mode_u(cfg_mode_u),
      .cfg_mode_v(cfg_mode_v), .cfg_offset_u(cfg_offset_u), .cfg_offset_v(cfg_offset_v),
      .cfg_bias(cfg_bias), .cfg_min_lod(cfg_min_lod), .cfg_max_lod(cfg_max_lod), .cfg_w0(cfg_w0),
      .cfg_h0(cfg_h0), .cfg_levels(cfg_levels), .cfg_layout(cfg_layout),
      .cfg_base_we(cfg_base_we), .cfg_base_idx(cfg_base_idx), .cfg_base_data(cfg_base_data),
      .cfg_add_n(cfg_add_n), .cfg_mul_n(cfg_mul_n), .cfg_div_n(cfg_div_n), .cfg_cmp_n(cfg_cmp_n),
      .rd_valid(rd_valid), .rd_addr(rd_addr), .rd_data(rd_data), .out_valid(out_valid),
      .out_rgba(out_rgba), .out_level_hi(out_level_hi), .out_level_lo(out_level_lo),
      .out_delta(out_delta), .ops_add(ops_add), .ops_mul(ops_mul), .ops_div(ops_div),
      .ops_cmp(ops_cmp), .items(items));
  assign vout = {rd_valid, rd_addr, out_valid, out_rgba, out_level_hi, out_level_lo, out_delta,
                 ops_add, ops_mul, ops_div, ops_cmp, items};
`include "tb_trace.vh"
endmodule
