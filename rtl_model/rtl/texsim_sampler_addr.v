// Texel address generation of one level of the RTL sampler (C++ core: the level loop of
// FixedSampler::sample, blocks/texture/sampler/fixed_sampler.h). Combinational. The level's
// size is max(1, size0 >> level); the coordinate c·size − ½ (s31.32) is rounded half to even
// to S fraction bits (integer part and weight u0.S); Vulkan's address modes on any size
// (0 wrap, 1 clamp, 2 mirror, 4 mirror-clamp; a non-power-of-two wrap or mirror is a `%`);
// word address = level base + Texture::texel_index (0 linear, 1 tiled 4x4, 2 Morton).
module texsim_sampler_addr #(
    parameter int S = 8
) (
    input  logic signed [47:0] u,
    input  logic signed [47:0] v,
    input  logic        [ 3:0] level,
    input  logic        [15:0] w0,
    input  logic        [15:0] h0,
    input  logic        [ 2:0] mode_u,
    input  logic        [ 2:0] mode_v,
    input  logic signed [ 4:0] offset_u,
    input  logic signed [ 4:0] offset_v,
    input  logic        [ 1:0] layout,
    input  logic        [31:0] base,
    output logic        [31:0] a00,
    output logic        [31:0] a10,
    output logic        [31:0] a01,
    output logic        [31:0] a11,
    output logic        [S-1:0] fx,
    output logic        [S-1:0] fy
);
  localparam int K = 32 - S;

  function automatic logic [15:0] level_size(input logic [15:0] s0, input logic [3:0] l);
    logic [15:0] s;
    s = s0 >> l;
    level_size = s == 0 ? 16'd1 : s;
  endfunction

  // Round half to even of c·size − ½ to S fraction bits; floor integer part and fraction.
  function automatic logic signed [47:0] fixed_coord(input logic signed [47:0] c,
                                                     input logic [15:0] size);
    logic signed [64:0] x, t, rem;
    x = 65'(c) * $signed({49'd0, size}) - (65'sd1 <<< 31);
    t = x >>> K;
    rem = x & ((65'sd1 <<< K) - 65'sd1);
    if (rem > (65'sd1 <<< (K - 1)) || (rem == (65'sd1 <<< (K - 1)) && t[0])) t = t + 65'sd1;
    fixed_coord = t[47:0];
  endfunction

  function automatic logic signed [48:0] mod_pos(input logic signed [48:0] i,
                                                 input logic signed [48:0] m);
    logic signed [48:0] r;
    r = i % m;
    mod_pos = r < 0 ? r + m : r;
  endfunction

  function automatic logic [15:0] address_one(input logic signed [48:0] i, input logic [15:0] size,
                                              input logic [2:0] mode);
    logic signed [48:0] sz, n, m;
    sz = $signed({33'd0, size});
    case (mode)
      3'd0: address_one = 16'(mod_pos(i, sz));
      3'd1: address_one = i < 0 ? 16'd0 : (i > sz - 1 ? size - 16'd1 : 16'(i));
      3'd2: begin
        n = mod_pos(i, sz <<< 1) - sz;
        m = n >= 0 ? n : -(49'sd1 + n);
        address_one = 16'(sz - 49'sd1 - m);
      end
      3'd4: begin
        m = i >= 0 ? i : -(49'sd1 + i);
        address_one = m > sz - 1 ? size - 16'd1 : 16'(m);
      end
      default: address_one = 16'd0;
    endcase
  endfunction

  function automatic logic [31:0] spread(input logic [15:0] x);
    logic [31:0] s;
    for (int b = 0; b < 16; b++) begin
      s[2*b] = x[b];
      s[2*b+1] = 1'b0;
    end
    spread = s;
  endfunction

  function automatic logic [31:0] row_index(input logic [15:0] y, input logic [15:0] wl,
                                            input logic [1:0] lay);
    case (lay)
      2'd0: row_index = 32'(y) * 32'(wl);
      2'd1: row_index = (32'(y) >> 2) * ((32'(wl) + 32'd3) >> 2) * 32'd16 + (32'(y) & 32'd3) * 32'd4;
      default: row_index = spread(y) << 1;
    endcase
  endfunction

  function automatic logic [31:0] col_index(input logic [15:0] x, input logic [1:0] lay);
    case (lay)
      2'd0: col_index = 32'(x);
      2'd1: col_index = (32'(x) >> 2) * 32'd16 + (32'(x) & 32'd3);
      default: col_index = spread(x);
    endcase
  endfunction

  logic [15:0] wl, hl, x0, x1, y0, y1;
  logic signed [47:0] xf, yf;
  logic signed [48:0] i, j;
  always_comb begin
    wl = level_size(w0, level);
    hl = level_size(h0, level);
    xf = fixed_coord(u, wl);
    yf = fixed_coord(v, hl);
    fx = xf[S-1:0];
    fy = yf[S-1:0];
    i = (49'(xf) >>> S) + 49'(offset_u);
    j = (49'(yf) >>> S) + 49'(offset_v);
    x0 = address_one(i, wl, mode_u);
    x1 = mode_u == 3'd0 ? (x0 + 16'd1 == wl ? 16'd0 : x0 + 16'd1) : address_one(i + 1, wl, mode_u);
    y0 = address_one(j, hl, mode_v);
    y1 = mode_v == 3'd0 ? (y0 + 16'd1 == hl ? 16'd0 : y0 + 16'd1) : address_one(j + 1, hl, mode_v);
    a00 = base + row_index(y0, wl, layout) + col_index(x0, layout);
    a10 = base + row_index(y0, wl, layout) + col_index(x1, layout);
    a01 = base + row_index(y1, wl, layout) + col_index(x0, layout);
    a11 = base + row_index(y1, wl, layout) + col_index(x1, layout);
  end
endmodule
