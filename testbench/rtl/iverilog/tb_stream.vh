// Shared body of the Icarus Verilog testbenches (docs/rtl/blocks.md, "Vector files"): reads
// +n=N vectors of IW input bits and OW expected output bits from the file +vectors=PATH
// ($readmemh, one vector per line), streams them into the block one per clock with an idle
// cycle (in_valid low, inputs inverted) after every fifth, and compares every result with its
// vector's expected bits and its latency with LAT. The including module declares clk, rst,
// in_valid, vin [IW], out_valid, vout [OW], the parameters IW, OW, LAT, and the block itself.
// Prints "iverilog: N vectors, M mismatches" and at most eight mismatches.
  localparam int MAXN = 1 << 16;  // vectors per run at most
  logic [IW+OW-1:0] mem[MAXN];
  int presented[MAXN];
  int n = 0, i_in = 0, i_out = 0, errors = 0, cycle = 0;
  string path;

  always #5 clk = ~clk;

  initial begin
    clk = 0;
    rst = 1;
    in_valid = 0;
    vin = '0;
    if (!$value$plusargs("vectors=%s", path) || !$value$plusargs("n=%d", n) || n < 1 ||
        n > MAXN) begin
      $display("iverilog: usage: +vectors=FILE +n=N (1..%0d)", MAXN);
      $finish;
    end
    $readmemh(path, mem, 0, n - 1);
    repeat (3) @(negedge clk);
    rst = 0;
  end

  // Inputs change and outputs are read on the falling edge; the block samples on the rising.
  always @(negedge clk) begin
    if (!rst) begin
      if (out_valid) begin
        if (i_out >= n) begin
          errors++;
          $display("iverilog: result %0d beyond the %0d vectors", i_out, n);
        end else begin
          if (vout !== mem[i_out][OW-1:0]) begin
            errors++;
            if (errors <= 8)
              $display("iverilog: vector %0d (in %h): out %h expected %h", i_out,
                       mem[i_out][IW+OW-1:OW], vout, mem[i_out][OW-1:0]);
          end else if (cycle - presented[i_out] != LAT) begin
            errors++;
            if (errors <= 8)
              $display("iverilog: vector %0d: latency %0d, expected %0d", i_out,
                       cycle - presented[i_out], LAT);
          end
        end
        i_out++;
      end
      if (i_in < n && cycle % 6 != 5) begin
        in_valid <= 1;
        vin <= mem[i_in][IW+OW-1:OW];
        presented[i_in] = cycle;
        i_in++;
      end else begin
        in_valid <= 0;
        vin <= ~vin;
      end
      cycle++;
      if (i_out >= n || cycle > 6 * n + LAT + 100) begin
        if (i_out < n) errors += n - i_out;
        $display("iverilog: %0d vectors, %0d mismatches", n, errors);
        $finish;
      end
    end
  end
