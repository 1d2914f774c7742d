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

  // Stage s input: partial remainder, the numerator bits not yet used (MSB aligned), the
  // quotient so far, the divisor and the tag.
  logic [DW:0] rem[LAT+1];
  logic [NW-1:0] num[LAT+1];
  logic [NW-1:0] quo[LAT+1];
  logic [DW-1:0] den[LAT+1];
  logic [TW-1:0] tg[LAT+1];
  assign rem[0] = '0;
  assign num[0] = n;
  assign quo[0] = '0;
  assign den[0] = d;
  assign tg[0]  = tag;

  for (genvar s = 0; s < LAT; s++) begin : g_stage
    localparam int FIRST = s * BPS;
    localparam int BITS = FIRST >= NW ? 0 : (NW - FIRST < BPS ? NW - FIRST : BPS);
    logic [DW:0] r;
    logic [NW-1:0] nm, qu;
    always_comb begin
      r  = rem[s];
      nm = num[s];
      qu = quo[s];
      for (int b = 0; b < BITS; b++) begin
        r  = {r[DW-1:0], nm[NW-1]};
        nm = nm << 1;
        qu = qu << 1;
        if (r >= {1'b0, den[s]}) begin
          r = r - {1'b0, den[s]};
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
        den[s+1] <= den[s];
        tg[s+1]  <= tg[s];
      end
    end
  end
  assign q = quo[LAT];
  assign rem_nz = rem[LAT] != '0;
  assign tag_q = tg[LAT];
endmodule
