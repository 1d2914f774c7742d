// texsim_mul_tree: p = a·b exactly (a signed AW bits, b unsigned BW bits, p AW+BW bits) in LUTs
// and carry chains, pipelined over LAT register stages. b is cut into NC chunks of CB bits;
// stage 1 forms each chunk's partial product (CB gated copies of a, summed), the next stages
// add them pairwise, one adder level per stage, and any stages left are plain registers. CB
// is the smallest chunk that lets the adder tree fit the LAT − 1 stages after the first. No
// $mul is left for synthesis to put into a DSP: for blocks with more multipliers than the
// iCE40 UP5K has SB_MAC16s. Data registers have no reset.
module texsim_mul_tree #(
    parameter int AW = 9,
    parameter int BW = 8,
    parameter int LAT = 3
) (
    input  logic                    clk,
    input  logic signed [   AW-1:0] a,
    input  logic        [   BW-1:0] b,
    output logic        [AW+BW-1:0] p
);
  localparam int PW = AW + BW;
  localparam int NC0 = LAT >= 1 ? 1 << (LAT - 1) : 1;  // chunks whose sum fits LAT − 1 levels
  localparam int CB = LAT >= 1 ? (BW + NC0 - 1) / NC0 : BW;
  localparam int NC = (BW + CB - 1) / CB;
  localparam int LEVELS = $clog2(NC);
  localparam int NR = LAT >= 1 ? 1 : 0;  // the register after the chunks

  // lv holds the LEVELS + 1 rows of the tree, NC entries of PW bits each (unused ones 0).
  wire [(LEVELS+1)*NC*PW-1:0] lv;
  logic [NC*CB-1:0] bx;
  assign bx = (NC * CB)'(b);

  // A chunk's sum is formed at its own width (AW + CB bits, signed), so its carry chain is no
  // longer than that; it is then sign-extended and shifted into place.
  localparam int CW = AW + CB;
  for (genvar j = 0; j < NC; j++) begin : g_chunk
    logic signed [CW-1:0] c;
    always_comb begin
      c = '0;
      for (int k = 0; k < CB; k++) c = c + ({CW{bx[j*CB+k]}} & (CW'(a) << k));
    end
    logic [PW-1:0] placed;
    assign placed = PW'(c) << (j * CB);
    texsim_pipe #(.W(PW), .N(NR), .RST(0)) u_c (.clk, .rst(1'b0), .d(placed), .q(lv[j*PW+:PW]));
  end

  for (genvar l = 0; l < LEVELS; l++) begin : g_level
    localparam int NIN = (NC + (1 << l) - 1) >> l;  // entries used in row l
    for (genvar i = 0; i < NC; i++) begin : g_node
      logic [PW-1:0] s;
      if (2 * i + 1 < NIN) begin : g_add
        // The right operand's low K bits are 0: they are the left one's, and only the bits
        // above need a carry chain.
        localparam int K = (2 * i + 1) * CB << l;
        logic [PW-1:0] x, y;
        assign x = lv[(l*NC+2*i)*PW+:PW];
        assign y = lv[(l*NC+2*i+1)*PW+:PW];
        assign s = {x[PW-1:K] + y[PW-1:K], x[K-1:0]};
      end else if (2 * i < NIN) begin : g_pass
        assign s = lv[(l*NC+2*i)*PW+:PW];
      end else begin : g_zero
        assign s = '0;
      end
      texsim_pipe #(.W(PW), .N(1), .RST(0)) u_s (.clk, .rst(1'b0), .d(s),
                                                 .q(lv[((l+1)*NC+i)*PW+:PW]));
    end
  end

  localparam int NPAD = LAT - NR - LEVELS;  // stages left over
  texsim_pipe #(.W(PW), .N(NPAD > 0 ? NPAD : 0), .RST(0)) u_pad (
      .clk, .rst(1'b0), .d(lv[(LEVELS*NC)*PW+:PW]), .q(p));
endmodule
