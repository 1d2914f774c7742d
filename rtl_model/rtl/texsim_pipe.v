// texsim_pipe: N pipeline registers on a W-bit bus (N = 0: a wire). Every block's latency is
// made of these, one run per operator, so a block's cycle count is the sum of its operators'
// latencies from the technology table, as in the C++ timing model (derive_timing).
// RST = 0 leaves the registers without reset (data that only matters while a valid bit says
// so): such registers can be packed into the iCE40 DSPs' own input and output registers.
module texsim_pipe #(
    parameter int W = 1,
    parameter int N = 1,
    parameter bit RST = 1
) (
    input  logic         clk,
    input  logic         rst,
    input  logic [W-1:0] d,
    output logic [W-1:0] q
);
  if (N == 0) begin : g_wire
    assign q = d;
  end else begin : g_regs
    // One flat vector, stage i in bits [i·W +: W]: Icarus Verilog 11 gave x for q = r[N-1] of
    // an unpacked array in the sampler, and yosys 0.23 reads no multi-dimensional packed one.
    logic [N*W-1:0] r;
    logic [N*W-1:0] next;
    if (N == 1) begin : g_one
      assign next = d;
    end else begin : g_more
      assign next = {r[(N-1)*W-1:0], d};
    end
    always_ff @(posedge clk) begin
      if (RST && rst) r <= '0;
      else r <= next;
    end
    assign q = r[N*W-1-:W];
  end
endmodule
