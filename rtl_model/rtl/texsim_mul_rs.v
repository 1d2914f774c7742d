// texsim_mul_rs: out = a·b (a signed AW bits, b unsigned BW bits, exact product with IN_F
// fraction bits), rounded HalfUp to OUT_F fraction bits and saturated into OUT_W signed bits —
// the same value as texsim_round_sat on the exact product — spread over LAT register stages
// so that no stage holds more than one carry chain:
//   stage 1: the product (a·b in an SB_MAC16; an a wider than DSP_W = 16 bits is cut into its
//            low 16 bits, unsigned, for the DSP and a signed rest of a few bits whose product
//            is a few gated adds in LUTs, not a second DSP);
//   stage 2: the join and the rounding, one carry chain: (p + 2^(SH-1)) >> SH = p_hi + p[SH-1]
//            with the rounding bit as the chain's carry-in (SH = IN_F − OUT_F);
//   stage 3: saturation (the dropped top bits must equal the sign), one LUT per bit;
//   further stages are plain registers. LAT = 2 joins stages 2 and 3, LAT = 1 all three.
// Data registers have no reset, so yosys can pack them into the SB_MAC16's own registers.
module texsim_mul_rs #(
    parameter int AW = 18,
    parameter int BW = 16,
    parameter int IN_F = 31,
    parameter int OUT_W = 18,
    parameter int OUT_F = 15,
    parameter int LAT = 3,
    parameter int DSP_W = 16  // the DSP's operand width (a smaller one tests the cut)
) (
    input  logic                 clk,
    input  logic signed [AW-1:0] a,
    input  logic        [BW-1:0] b,
    output logic     [OUT_W-1:0] out
);
  localparam int SH = IN_F - OUT_F;  // ≥ 1
  localparam int L = (AW > DSP_W && IN_F - OUT_F <= DSP_W) ? DSP_W : 0;  // a = a_hi·2^L + a_lo
  localparam int HW = AW - L + BW;  // a_hi·b, signed
  localparam int LW = L + BW;  // a_lo·b, unsigned (unused when L = 0)
  localparam int PW = AW + BW;  // the whole product
  localparam int RW = PW - SH + 1;  // the rounded product before saturation
  localparam int N1 = LAT >= 1 ? 1 : 0;
  localparam int N2 = LAT >= 3 ? 1 : 0;
  localparam int N3 = LAT >= 2 ? LAT - 1 - N2 : 0;

  // Stage 1: the partial products
  logic signed [HW-1:0] ph, ph_q;
  logic [LW-1:0] pl, pl_q;
  if (L > 0) begin : g_split
    logic [L-1:0] a_lo;
    assign a_lo = a[L-1:0];
    localparam int HB = AW - L;
    always_comb begin
      ph = '0;
      for (int i = 0; i < HB; i++) begin
        if (i == HB - 1) ph = ph - ({HW{a[L+i]}} & (HW'(b) << i));
        else ph = ph + ({HW{a[L+i]}} & (HW'(b) << i));
      end
    end
    assign pl = LW'(a_lo) * LW'(b);
  end else begin : g_whole
    assign ph = HW'(a) * $signed({1'b0, b});
    assign pl = '0;
  end
  texsim_pipe #(.W(HW + LW), .N(N1), .RST(0)) u_p (.clk, .rst(1'b0), .d({ph, pl}), .q({ph_q, pl_q}));

  // Stage 2: p = ph·2^L + pl; r = (p + 2^(SH-1)) >> SH in one adder with the rounding carry.
  logic signed [RW-1:0] r, r_q;
  if (L > 0) begin : g_join
    // pl ≥ 0, so r = ph·2^(L-SH) + (pl >> SH) + pl[SH-1]; {x,1} + {y,c} = 2(x + y + c) + 1.
    localparam int JW = RW + 1;
    logic signed [JW-1:0] x, y, j;
    assign x = {RW'(ph_q) <<< (L - SH), 1'b1};
    assign y = {RW'(pl_q >> SH), pl_q[SH-1]};
    assign j = x + y;
    assign r = j[JW-1:1];
  end else begin : g_round
    assign r = RW'(ph_q >>> SH) + RW'(ph_q[SH-1]);
  end
  texsim_pipe #(.W(RW), .N(N2), .RST(0)) u_r (.clk, .rst(1'b0), .d(r), .q(r_q));

  // Stage 3: saturate into OUT_W signed bits
  logic [OUT_W-1:0] s;
  if (RW > OUT_W) begin : g_sat
    logic keep;
    assign keep = r_q[RW-1:OUT_W-1] == {(RW - OUT_W + 1) {r_q[RW-1]}};
    assign s = keep ? r_q[OUT_W-1:0] : {r_q[RW-1], {(OUT_W - 1) {~r_q[RW-1]}}};
  end else begin : g_fits
    assign s = OUT_W'(r_q);
  end
  texsim_pipe #(.W(OUT_W), .N(N3), .RST(0)) u_s (.clk, .rst(1'b0), .d(s), .q(out));
endmodule
