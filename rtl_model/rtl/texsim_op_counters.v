// texsim_op_counters: the block's operation counters, as OpCounts in the C++ models
// (blocks/base/op_counts.h). An item carries the operations it used along the pipeline and
// they are added when it retires; the outputs include the item retiring in this cycle, so
// with each result the counters equal the C++ model's count up to and including it.
module texsim_op_counters (
    input  logic        clk,
    input  logic        rst,
    input  logic        retire,
    input  logic [15:0] add_n,
    input  logic [15:0] mul_n,
    input  logic [15:0] div_n,
    input  logic [15:0] cmp_n,
    output logic [63:0] ops_add,
    output logic [63:0] ops_mul,
    output logic [63:0] ops_div,
    output logic [63:0] ops_cmp,
    output logic [63:0] items
);
  logic [63:0] add_r, mul_r, div_r, cmp_r, items_r;
  assign ops_add = add_r + (retire ? 64'(add_n) : 64'd0);
  assign ops_mul = mul_r + (retire ? 64'(mul_n) : 64'd0);
  assign ops_div = div_r + (retire ? 64'(div_n) : 64'd0);
  assign ops_cmp = cmp_r + (retire ? 64'(cmp_n) : 64'd0);
  assign items   = items_r + (retire ? 64'd1 : 64'd0);
  always_ff @(posedge clk) begin
    if (rst) begin
      add_r   <= '0;
      mul_r   <= '0;
      div_r   <= '0;
      cmp_r   <= '0;
      items_r <= '0;
    end else begin
      add_r   <= ops_add;
      mul_r   <= ops_mul;
      div_r   <= ops_div;
      cmp_r   <= ops_cmp;
      items_r <= items;
    end
  end
endmodule
