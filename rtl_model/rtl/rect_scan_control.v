// Rectangle-scan texturing control (METHODS §3; C++ elements OutlineComparator and
// TexturingControl in blocks/raster/rect_scan/): the foreground register РГп with the
// comparator БП (hits = memory word AND РГп, one plane per edge) and the texturing-control
// state machine БКТ: per-edge inside flags toggled by their plane's hits (the parity rule kept
// per edge), the decision "texture" (all flags inside and within the scissor's minor range; the
// Outline convention also textures the first pixel after an inside run) and end of row (an edge
// along which the row only moves outward is outside).
// Load (per triangle): foreground, closing (per edge), outline, minor_lo..minor_hi. Per row
// start: row_start with inside0, the sides of the row's first pixel from the edge-value unit
// (EdgeRasterizer's row-start edge values are not in this block). Per later pixel: pixel with
// the memory word. Both with the pixel's minor coordinate; the decision leaves LAT cycles later
// (TexturingControl::timing), one pixel per cycle.
module rect_scan_control #(
    parameter int CW  = 16,
    parameter int LAT = 2
) (
    input  logic          clk,
    input  logic          rst,
    input  logic          load,
    input  logic [   2:0] foreground,
    input  logic [   2:0] closing,
    input  logic          outline,
    input  logic [CW-1:0] minor_lo,
    input  logic [CW-1:0] minor_hi,
    input  logic          in_valid,
    input  logic          row_start,
    input  logic [   2:0] inside0,
    input  logic [   2:0] word,
    input  logic [CW-1:0] minor,
    output logic          out_valid,
    output logic          out_texture,
    output logic          out_end_of_row,
    output logic [   2:0] out_hits,
    output logic [  63:0] ops_add,
    output logic [  63:0] ops_mul,
    output logic [  63:0] ops_div,
    output logic [  63:0] ops_cmp,
    output logic [  63:0] items
);
  logic [2:0] fg, cl, flags, flags_next, hits;
  logic ol, was_inside;
  logic signed [CW-1:0] lo, hi;
  logic in_scissor, all_in, texture, end_of_row;

  assign hits = row_start ? 3'b000 : word & fg;  // БП
  assign flags_next = row_start ? inside0 : flags ^ hits;
  assign in_scissor = $signed(minor) >= lo && $signed(minor) <= hi;
  assign all_in = &flags_next && in_scissor;
  assign texture = all_in || (ol && !row_start && was_inside && in_scissor);
  assign end_of_row = |(cl & ~flags_next);

  always_ff @(posedge clk) begin
    if (rst) begin
      flags <= '0;
      was_inside <= 1'b0;
    end else begin
      if (load) begin
        fg <= foreground;
        cl <= closing;
        ol <= outline;
        lo <= $signed(minor_lo);
        hi <= $signed(minor_hi);
      end
      if (in_valid) begin
        flags <= flags_next;
        was_inside <= all_in;
      end
    end
  end

  logic first_q;
  texsim_pipe #(.W(7), .N(LAT)) u_out (
      .clk, .rst, .d({in_valid, row_start, texture, end_of_row, hits}),
      .q({out_valid, first_q, out_texture, out_end_of_row, out_hits}));
  // Ops: БКТ's decision (3 compares) on every pixel, БП's compare on every later pixel.
  texsim_op_counters u_ops (
      .clk, .rst, .retire(out_valid), .add_n(16'd0), .mul_n(16'd0), .div_n(16'd0),
      .cmp_n(first_q ? 16'd3 : 16'd4), .ops_add, .ops_mul, .ops_div, .ops_cmp, .items);
endmodule
