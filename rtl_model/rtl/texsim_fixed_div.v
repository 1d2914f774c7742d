// texsim_fixed_div: Fixed<I,F> division a / b for a divisor b > 0 (W = I + F bits, two's
// complement), exactly as Fixed::operator/ (rtl_model/number/fixed.h) with HalfEven rounding
// and saturation: q = floor(a·2^(F+2) / b) from |a| and the remainder, then the two guard bits
// and the sticky bit round to F fraction bits. Latency LAT (texsim_udiv_pipe), one per cycle.
module texsim_fixed_div #(
    parameter int W = 32,
    parameter int F = 16,
    parameter int LAT = 12
) (
    input  logic                clk,
    input  logic                rst,
    input  logic signed [W-1:0] a,
    input  logic signed [W-1:0] b,
    output logic signed [W-1:0] q
);
  localparam int NW = W + F + 2;  // |a|·2^(F+2)
  localparam int EW = NW + 2;
  logic neg, neg_q, rem_nz;
  logic [W-1:0] mag;
  logic [NW-1:0] uq;
  assign neg = a[W-1];
  assign mag = neg ? W'(-a) : W'(a);
  texsim_udiv_pipe #(.NW(NW), .DW(W), .LAT(LAT), .TW(1)) u_div (
      .clk, .rst, .n({mag, (F + 2)'(0)}), .d(b), .tag(neg), .q(uq), .rem_nz, .tag_q(neg_q));

  // floor of the signed quotient: −Q, or −Q − 1 when a remainder is left
  logic signed [EW-1:0] fq, fl, r;
  logic [1:0] guard;
  assign fq = neg_q ? -$signed(EW'(uq)) - (rem_nz ? EW'(1) : EW'(0)) : $signed(EW'(uq));
  assign fl = fq >>> 2;
  assign guard = fq[1:0];
  assign r = (guard > 2'd2 || (guard == 2'd2 && (rem_nz || fl[0]))) ? fl + EW'(1) : fl;
  localparam logic signed [EW-1:0] MAXV = (EW'(1) <<< (W - 1)) - EW'(1);
  localparam logic signed [EW-1:0] MINV = -(EW'(1) <<< (W - 1));
  assign q = r > MAXV ? MAXV[W-1:0] : (r < MINV ? MINV[W-1:0] : r[W-1:0]);
endmodule
