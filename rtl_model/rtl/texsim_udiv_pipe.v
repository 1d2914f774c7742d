// texsim_udiv_pipe: pipelined restoring divider, q = floor(n / d) and whether a remainder is
// left, with a tag carried alongside. The NW quotient bits are produced MSB first, ⌈NW/LAT⌉
// per stage, over LAT register stages: latency LAT, one division per cycle. d = 0 gives an
// all-ones quotient (callers discard it).
module texsim_udiv_pipe #(
    parameter int NW = 49,
    parameter int DW = 32,
    parameter int LAT = 12,
    parameter int TW = 1
) (
    input  logic          clk,
    input  logic          rst,
    input  logic [NW-1:0] n,
    input  logic [DW-1:0] d,
    input  logic [TW-1:0] tag,
    output logic [NW-1:0] q,
    output logic          rem_nz,
    output logic [TW-1:0] tag_q
);
  localparam int BPS = (NW + LAT - 1) / LAT;  // quotient bits per stage

  // Register s: the output of stage s − 1, i.e. stage s's partial remainder, the numerator bits
  // not yet used (MSB aligned), the quotient so far, the divisor and the tag. Stage 0 reads the
  // ports instead (a register array with its element 0 continuously assigned is not accepted
  // by Icarus Verilog).
  logic [DW:0] rem[1:LAT];
  logic [NW-1:0] num[1:LAT];
  logic [NW-1:0] quo[1:LAT];
  logic [DW-1:0] den[1:LAT];
  logic [TW-1:0] tg[1:LAT];

  for (genvar s = 0; s < LAT; s++) begin : g_stage
    localparam int FIRST = s * BPS;
    localparam int BITS = FIRST >= NW ? 0 : (NW - FIRST < BPS ? NW - FIRST : BPS);
    logic [DW:0] r, rem_i;
    logic [NW-1:0] nm, qu, num_i, quo_i;
    logic [DW-1:0] den_i;
    logic [TW-1:0] tg_i;
    if (s == 0) begin : g_ports
      assign {rem_i, num_i, quo_i, den_i, tg_i} = {(DW + 1)'(0), n, NW'(0), d, tag};
    end else begin : g_regs
      assign {rem_i, num_i, quo_i, den_i, tg_i} = {rem[s], num[s], quo[s], den[s], tg[s]};
    end
    always_comb begin
      r  = rem_i;
      nm = num_i;
      qu = quo_i;
      for (int b = 0; b < BITS; b++) begin
        r  = {r[DW-1:0], nm[NW-1]};
        nm = nm << 1;
        qu = qu << 1;
        if (r >= {1'b0, den_i}) begin
          r = r - {1'b0, den_i};
          qu[0] = 1'b1;
        end
      end
    end
    always_ff @(posedge clk) begin
      if (rst) begin
        rem[s+1] <= '0;
        num[s+1] <= '0;
        quo[s+1] <= '0;
        den[s+1] <= '0;
        tg[s+1]  <= '0;
      end else begin
        rem[s+1] <= r;
        num[s+1] <= nm;
        quo[s+1] <= qu;
        den[s+1] <= den_i;
        tg[s+1]  <= tg_i;
      end
    end
  end
  assign q = quo[LAT];
  assign rem_nz = rem[LAT] != '0;
  assign tag_q = tg[LAT];
endmodule
