// Rectangle-scan address generator (METHODS §3; C++ elements in blocks/raster/rect_scan/):
// the row-start register and counter РГХп/ЛЧУп (RowStartCounter), the linear interpolator and
// step-increment block ЛІ/БКП (LineStepper: Bresenham error term, ΔX = 2^SLOPE_BITS, carry →
// minor step of the line's sign), the coordinate counters ЛЧх/ЛЧу (CoordinateCounters) and the
// row-end / triangle-end comparators. It visits every pixel of the rectangle row by row, as
// RectScanRasterizer does with no texturing-control early row end: per row one start cycle
// (counters loaded from РГХп and ЛЧУп, error term ΔX/2), then one pixel per cycle from major0
// to major1, stepping after each.
// Load (in_valid while in_ready): the row line (x_major, neg = sign < 0, delta_minor = ΔY ≤ ΔX),
// the columns major0..major1 and the rows t_lo..t_hi (signed CW bits).
// Out per pixel: out_x, out_y (the counters, i.e. the auxiliary-memory address), out_row_start.
// row_end (from БКТ in rect_scan_raster; 0 alone) ends the current row after this pixel.
module rect_scan_stepper #(
    parameter int SLOPE_BITS = 12,
    parameter int CW = 16
) (
    input  logic                clk,
    input  logic                rst,
    input  logic                in_valid,
    output logic                in_ready,
    input  logic                x_major,
    input  logic                neg,
    input  logic [SLOPE_BITS:0] delta_minor,
    input  logic [      CW-1:0] major0,
    input  logic [      CW-1:0] major1,
    input  logic [      CW-1:0] t_lo,
    input  logic [      CW-1:0] t_hi,
    input  logic                row_end,
    output logic                out_valid,
    output logic                out_row_start,
    output logic [      CW-1:0] out_x,
    output logic [      CW-1:0] out_y,
    output logic [        63:0] ops_add,
    output logic [        63:0] ops_mul,
    output logic [        63:0] ops_div,
    output logic [        63:0] ops_cmp,
    output logic [        63:0] items
);
  localparam logic [SLOPE_BITS+1:0] DX = 1 << SLOPE_BITS;
  localparam logic signed [CW-1:0] ONE = 1;
  localparam logic signed [CW-1:0] TOP = {1'b0, {(CW - 1) {1'b1}}};
  typedef enum logic [1:0] {
    IDLE,
    ROW,
    PIXEL
  } state_t;
  state_t state;
  logic xm, ng, first;
  logic [SLOPE_BITS:0] dy;
  logic [SLOPE_BITS+1:0] acc;  // ЛІ error term, < ΔX
  logic signed [CW-1:0] rg_major0, m1, th, row_t;  // РГХп, last column, last row, ЛЧУп
  logic signed [CW-1:0] major, minor;  // ЛЧх/ЛЧу in the row frame

  // БКП: the next error term and the minor increment of one major step
  logic [SLOPE_BITS+1:0] acc_next;
  logic carry;
  assign acc_next = acc + (SLOPE_BITS + 2)'(dy);
  assign carry = acc_next >= DX;

  always_ff @(posedge clk) begin
    if (rst) begin
      state <= IDLE;
      first <= 1'b0;
    end else begin
      case (state)
        IDLE:
        if (in_valid) begin
          xm <= x_major;
          ng <= neg;
          dy <= delta_minor;
          rg_major0 <= $signed(major0);
          m1 <= $signed(major1);
          th <= $signed(t_hi);
          row_t <= $signed(t_lo);
          state <= $signed(t_lo) <= $signed(t_hi) ? ROW : IDLE;
        end
        ROW: begin  // row start: counters from РГХп and ЛЧУп, error term ΔX/2
          major <= rg_major0;
          minor <= row_t;
          acc <= DX >> 1;
          first <= 1'b1;
          state <= PIXEL;
        end
        PIXEL: begin  // this pixel is on the outputs; step or end the row
          first <= 1'b0;
          if (major >= m1 || row_end) begin
            row_t <= row_t + ONE;
            state <= row_t != TOP && row_t + ONE <= th ? ROW : IDLE;
          end else begin
            major <= major + ONE;
            acc <= carry ? acc_next - DX : acc_next;
            minor <= carry ? (ng ? minor - ONE : minor + ONE) : minor;
          end
        end
        default: state <= IDLE;
      endcase
    end
  end
  assign in_ready = state == IDLE;
  assign out_valid = state == PIXEL;
  assign out_row_start = first;
  assign out_x = xm ? major : minor;
  assign out_y = xm ? minor : major;

  // Ops of the retiring pixel: a row's first pixel carries the row-start counter's increment,
  // every other pixel one step of ЛІ (2 add, 1 cmp) and of the counters (2 add).
  texsim_op_counters u_ops (
      .clk, .rst, .retire(out_valid), .add_n(first ? 16'd1 : 16'd4), .mul_n(16'd0),
      .div_n(16'd0), .cmp_n(first ? 16'd0 : 16'd1), .ops_add, .ops_mul, .ops_div, .ops_cmp,
      .items);
endmodule
