// Example block for `texsim study rtl --rtl rtl_model/synth/examples --param W=8,12,16`: a
// pipelined second-degree Horner evaluator y = (c2*d + c1)*d + c0 on unsigned W-bit operands
// (W <= 16; two multipliers and two adders, like the V(d) P2 evaluator), each product truncated
// back to its top W bits. The coefficients are arbitrary constants cut to W bits.
module horner2 #(parameter W = 16) (
  input clk,
  input [W-1:0] d,
  output reg [W-1:0] y
);
  localparam [15:0] K2 = 16'h89AB, K1 = 16'hC3A5, K0 = 16'h2D41;
  localparam [W-1:0] C2 = K2[15 -: W], C1 = K1[15 -: W], C0 = K0[15 -: W];
  reg [W-1:0] d1, d2, t1, t2;
  reg [2*W-1:0] p1, p2;
  always @(posedge clk) begin
    p1 <= C2 * d;
    d1 <= d;
    t1 <= p1[2*W-1 -: W] + C1;
    d2 <= d1;
    p2 <= t1 * d2;
    t2 <= p2[2*W-1 -: W] + C0;
    y <= t2;
  end
endmodule
