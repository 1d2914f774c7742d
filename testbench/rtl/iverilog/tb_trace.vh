// Shared body of the Icarus Verilog cycle-trace testbenches (docs/rtl/blocks.md, "Cycle
// traces"): replays +n=N lines of the file +trace=PATH ($readmemh), one per clock. A line is
// {inputs [IW], mask [OW], expected outputs [OW]}: the inputs the Verilated block was given
// before one rising edge and its outputs after it, with the mask saying which output bits count
// (valid and ready flags and counters always, data only while their valid is set). The
// including module declares clk, rst, vin [IW], vout [OW], the parameters IW, OW and the block
// (wired to slices of vin and vout). Reset is held for two edges with every input 0, as in
// RtlHarness::reset. Prints "iverilog: N cycles, M mismatches" and at most eight mismatches.
  localparam int MAXN = 1 << 15;  // lines per run at most
  logic [IW+2*OW-1:0] mem[MAXN];
  int n = 0, k = 0, errors = 0, edges = 0;
  string path;

  always #5 clk = ~clk;

  initial begin
    clk = 0;
    rst = 1;
    vin = '0;
    if (!$value$plusargs("trace=%s", path) || !$value$plusargs("n=%d", n) || n < 1 ||
        n > MAXN) begin
      $display("iverilog: usage: +trace=FILE +n=N (1..%0d)", MAXN);
      $finish;
    end
    $readmemh(path, mem, 0, n - 1);
  end

  // Outputs are read and the next inputs applied on the falling edge; the block samples on the
  // rising one. Reset covers the first two rising edges.
  always @(negedge clk) begin
    edges++;
    if (edges == 2) begin
      rst = 0;
      vin = mem[0][IW+2*OW-1:2*OW];
    end else if (edges > 2) begin
      if (((vout ^ mem[k][OW-1:0]) & mem[k][2*OW-1:OW]) !== '0) begin
        errors++;
        if (errors <= 8)
          $display("iverilog: cycle %0d: out %h expected %h mask %h", k, vout, mem[k][OW-1:0],
                   mem[k][2*OW-1:OW]);
      end
      k++;
      if (k >= n) begin
        $display("iverilog: %0d cycles, %0d mismatches", n, errors);
        $finish;
      end
      vin = mem[k][IW+2*OW-1:2*OW];
    end
  end
