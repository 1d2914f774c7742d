// texsim_round_sat: moves a signed fixed-point value with IN_F fraction bits to OUT_W bits with
// OUT_F fraction bits, rounding and saturating exactly as Fixed<I,F> does
// (rtl_model/number/fixed.h: fixed_detail::shift_round, then fit()):
//   ROUND = 0: HalfUp   — add half an LSB, shift right (floor)
//   ROUND = 1: HalfEven — ties to the even neighbour
// then clamp to [-2^(OUT_W-1), 2^(OUT_W-1)-1] (OUT_SIGNED) or [0, 2^OUT_W-1].
module texsim_round_sat #(
    parameter int IN_W = 34,
    parameter int IN_F = 31,
    parameter int OUT_W = 18,
    parameter int OUT_F = 15,
    parameter bit OUT_SIGNED = 1,
    parameter int ROUND = 0
) (
    input  logic signed [ IN_W-1:0] in,
    output logic        [OUT_W-1:0] out
);
  localparam int S = IN_F - OUT_F;
  localparam int EW = IN_W + 2 + (S < 0 ? -S : 0) + OUT_W;
  localparam logic signed [EW-1:0] ONE = 1;
  localparam logic signed [EW-1:0] MAXV = OUT_SIGNED ? (ONE <<< (OUT_W - 1)) - ONE : (ONE <<< OUT_W) - ONE;
  localparam logic signed [EW-1:0] MINV = OUT_SIGNED ? -(ONE <<< (OUT_W - 1)) : '0;

  logic signed [EW-1:0] x, r;
  assign x = EW'(in);
  if (S > 0) begin : g_round
    logic signed [EW-1:0] fl;
    logic [S-1:0] rem;
    assign fl  = x >>> S;
    assign rem = x[S-1:0];
    if (ROUND == 0) begin : g_half_up
      assign r = rem[S-1] ? fl + ONE : fl;
    end else begin : g_half_even
      localparam logic [S-1:0] HALF = 1 << (S - 1);
      logic above, tie;
      assign above = rem > HALF;
      assign tie = rem == HALF;
      assign r = (above || (tie && fl[0])) ? fl + ONE : fl;
    end
  end else begin : g_shift_left
    assign r = x <<< (-S);
  end
  assign out = r > MAXV ? MAXV[OUT_W-1:0] : (r < MINV ? MINV[OUT_W-1:0] : r[OUT_W-1:0]);
endmodule
