// Rectangle-scan rasteriser (METHODS §3, seed 002 fig. 4; C++ RectScanRasterizer in
// blocks/raster/rect_scan/): the address generator rect_scan_stepper (РГХп/ЛЧУп, ЛІ/БКП,
// ЛЧх/ЛЧу), the auxiliary outline memory addressed by those counters, and the texturing control
// rect_scan_control (РГп, БП, БКТ) wired into one datapath, one visited pixel per cycle.
// БКТ's end of row goes back to the stepper in the same cycle (the control is instantiated
// with LAT = 0: the decision is combinational after the memory read), so the row is cut where
// the C++ model cuts it and the next row starts on the next cycle.
//
// Preparation (the host's, as the C++ OutlineMemory::draw computes it): the outline planes are
// written through the memory's write port (mem_we, mem_major, mem_minor relative to the window
// major0, mem_lo; 3-bit words), then the triangle is loaded (in_valid while in_ready): the row
// line and rectangle of the stepper, the window's minor range mem_lo..mem_hi, the box's minor
// range minor_lo..minor_hi (the scissor), the closing edges, the convention (outline) and per
// edge the row-start edge value with its bias at (major0, t_lo) and its change per row. Per row
// the three edge values step by one add each; their signs are БКТ's inside0.
// Out per visited pixel: x, y, row start, texture, end of row, the comparator's hit planes.
module rect_scan_raster #(
    parameter int SLOPE_BITS = 12,
    parameter int CW = 16,
    parameter int MAJ_BITS = 8,  // memory window: 2^MAJ_BITS columns
    parameter int MIN_BITS = 9   // and 2^MIN_BITS rows of 3-bit words
) (
    input  logic                       clk,
    input  logic                       rst,
    // the auxiliary memory's write port (preparation)
    input  logic                       mem_we,
    input  logic [       MAJ_BITS-1:0] mem_major,
    input  logic [       MIN_BITS-1:0] mem_minor,
    input  logic [                2:0] mem_wdata,
    // the triangle
    input  logic                       in_valid,
    output logic                       in_ready,
    input  logic                       x_major,
    input  logic                       neg,
    input  logic [       SLOPE_BITS:0] delta_minor,
    input  logic [             CW-1:0] major0,
    input  logic [             CW-1:0] major1,
    input  logic [             CW-1:0] t_lo,
    input  logic [             CW-1:0] t_hi,
    input  logic [             CW-1:0] mem_lo,
    input  logic [             CW-1:0] mem_hi,
    input  logic [             CW-1:0] minor_lo,
    input  logic [             CW-1:0] minor_hi,
    input  logic [                2:0] closing,
    input  logic                       outline,
    input  logic [               63:0] ev0,
    input  logic [               63:0] ev1,
    input  logic [               63:0] ev2,
    input  logic [               63:0] ev_row0,
    input  logic [               63:0] ev_row1,
    input  logic [               63:0] ev_row2,
    // per visited pixel
    output logic                       out_valid,
    output logic                       out_row_start,
    output logic [             CW-1:0] out_x,
    output logic [             CW-1:0] out_y,
    output logic                       out_texture,
    output logic                       out_end_of_row,
    output logic [                2:0] out_hits,
    output logic [               63:0] ops_add,
    output logic [               63:0] ops_mul,
    output logic [               63:0] ops_div,
    output logic [               63:0] ops_cmp,
    output logic [               63:0] items
);
  // ---- auxiliary memory: the counters are its address (window-relative) ----
  logic [2:0] mem[1 << (MAJ_BITS + MIN_BITS)];
  always_ff @(posedge clk) begin
    if (mem_we) mem[{mem_minor, mem_major}] <= mem_wdata;
  end

  // ---- registers of the triangle held beside the stepper ----
  logic signed [CW-1:0] rg_major0, rg_major1, rg_mem_lo, rg_mem_hi;
  logic signed [63:0] ev[3], ev_row[3];
  logic xm;
  logic start_load;
  assign start_load = in_valid && in_ready;
  always_ff @(posedge clk) begin
    if (start_load) begin
      rg_major0 <= $signed(major0);
      rg_major1 <= $signed(major1);
      rg_mem_lo <= $signed(mem_lo);
      rg_mem_hi <= $signed(mem_hi);
      xm <= x_major;
      ev_row[0] <= $signed(ev_row0);
      ev_row[1] <= $signed(ev_row1);
      ev_row[2] <= $signed(ev_row2);
    end
  end

  // ---- address generator ----
  logic s_valid, s_first, row_end;
  logic [CW-1:0] s_x, s_y;
  logic [63:0] s_add, s_mul, s_div, s_cmp, s_items;
  rect_scan_stepper #(.SLOPE_BITS(SLOPE_BITS), .CW(CW)) u_stepper (
      .clk, .rst, .in_valid, .in_ready, .x_major, .neg, .delta_minor, .major0, .major1, .t_lo,
      .t_hi, .row_end, .out_valid(s_valid), .out_row_start(s_first), .out_x(s_x), .out_y(s_y),
      .ops_add(s_add), .ops_mul(s_mul), .ops_div(s_div), .ops_cmp(s_cmp), .items(s_items));

  // ---- memory read at the counters (background outside the window) ----
  logic signed [CW-1:0] major, minor;
  logic signed [CW:0] rel_major, rel_minor;
  logic in_window;
  logic [2:0] word;
  assign major = xm ? $signed(s_x) : $signed(s_y);
  assign minor = xm ? $signed(s_y) : $signed(s_x);
  assign rel_major = (CW + 1)'(major) - (CW + 1)'(rg_major0);
  assign rel_minor = (CW + 1)'(minor) - (CW + 1)'(rg_mem_lo);
  assign in_window = major >= rg_major0 && major <= rg_major1 && minor >= rg_mem_lo &&
      minor <= rg_mem_hi;
  assign word = in_window ? mem[{rel_minor[MIN_BITS-1:0], rel_major[MAJ_BITS-1:0]}] : 3'b000;

  // ---- row-start sides: the edge values at the row's first pixel ----
  logic [2:0] inside0;
  assign inside0 = {~ev[2][63], ~ev[1][63], ~ev[0][63]};
  // The row ends after this pixel (БКТ or the rectangle's side): the edge values step a row.
  logic row_leaves;
  assign row_leaves = s_valid && (row_end || major >= rg_major1);
  always_ff @(posedge clk) begin
    if (start_load) begin
      ev[0] <= $signed(ev0);
      ev[1] <= $signed(ev1);
      ev[2] <= $signed(ev2);
    end else if (row_leaves) begin
      for (int e = 0; e < 3; e++) ev[e] <= ev[e] + ev_row[e];
    end
  end

  // ---- texturing control, combinational (LAT = 0) ----
  logic c_valid;
  logic [63:0] c_add, c_mul, c_div, c_cmp, c_items;
  rect_scan_control #(.CW(CW), .LAT(0)) u_control (
      .clk, .rst, .load(start_load), .foreground(3'b111), .closing, .outline, .minor_lo,
      .minor_hi, .in_valid(s_valid), .row_start(s_first), .inside0, .word, .minor(minor),
      .out_valid(c_valid), .out_texture, .out_end_of_row(row_end), .out_hits, .ops_add(c_add),
      .ops_mul(c_mul), .ops_div(c_div), .ops_cmp(c_cmp), .items(c_items));

  assign out_valid = s_valid;
  assign out_row_start = s_first;
  assign out_x = s_x;
  assign out_y = s_y;
  assign out_end_of_row = row_end;
  // Ops: the stepper's and the control's (the row-start edge values' 3 adds are not counted,
  // as the C++ rasteriser counts them in its row ops, not per pixel).
  assign ops_add = s_add + c_add;
  assign ops_mul = s_mul + c_mul;
  assign ops_div = s_div + c_div;
  assign ops_cmp = s_cmp + c_cmp;
  assign items = s_items;
endmodule
