// Incremental u/v adder, k-lane form, with its divider stage (METHODS §2; C++ core
// UvIncrementalAdder::eval_row<Fixed<I,F>> with form = klane, division = divide,
// blocks/texture/coords/uv_incremental_adder.h). All values are Fixed<I,F> raws, W = I + F bits,
// two's complement, every add and multiply saturating as Fixed does.
//  Row set-up (one load: the map's A..I, the row's x0, y and pixel count n):
//    w0 = (A·x0 + B·y) + C, z0 = (G·x0 + H·y) + I, t0 = (D·x0 + E·y) + F;
//    lane j starts at w0 + j·A (j − 1 saturating adds), lane steps k·A, k·G, k·D.
//    Latency SETUP_LAT (the set-up arithmetic, then its registers; the last one is the lane
//    accumulators), as UvIncrementalAdder::row_setup_timing.
//  Pixels: one group of K pixels per cycle, pixel n in lane n mod K; per pixel the accumulators
//    step by k·A, k·G, k·D, z is compared with MIN_DEN and u = w / z, v = t / z go through
//    texsim_fixed_div (latency DIV_LAT, as UvIncrementalAdder::timing). A pixel is invalid
//    (u = v = 0, ok = 0) when z < MIN_DEN or u or v saturated.
//  in_ready is low while a row is set up or generated; loads then are ignored.
module uv_incremental #(
    parameter int W = 32,
    parameter int F = 16,
    parameter int K = 4,
    parameter int SETUP_LAT = 8,
    parameter int DIV_LAT = 12,
    parameter int MIN_DEN = 16,
    parameter int XW = 16,
    parameter int NW = 16
) (
    input  logic           clk,
    input  logic           rst,
    input  logic           in_valid,
    output logic           in_ready,
    input  logic [  W-1:0] ca,
    input  logic [  W-1:0] cb,
    input  logic [  W-1:0] cc,
    input  logic [  W-1:0] cd,
    input  logic [  W-1:0] ce,
    input  logic [  W-1:0] cf,
    input  logic [  W-1:0] cg,
    input  logic [  W-1:0] ch,
    input  logic [  W-1:0] ci,
    input  logic [ XW-1:0] x0,
    input  logic [ XW-1:0] y,
    input  logic [ NW-1:0] n,
    output logic           out_valid,
    output logic [  K-1:0] out_mask,
    output logic [  K-1:0] out_ok,
    output logic [K*W-1:0] out_u,
    output logic [K*W-1:0] out_v,
    output logic [   63:0] ops_add,
    output logic [   63:0] ops_mul,
    output logic [   63:0] ops_div,
    output logic [   63:0] ops_cmp,
    output logic [   63:0] items
);
  localparam int PW = W + XW;
  localparam logic signed [PW-1:0] MAXV = (PW'(1) <<< (W - 1)) - PW'(1);
  localparam logic signed [PW-1:0] MINV = -(PW'(1) <<< (W - 1));
  // Operations (as UvIncrementalAdder counts them): set-up 6 mul + 6 add for w0, z0, t0,
  // 3 mul for the k-steps, 3·(K − 1) add for the lane starts; per pixel 3 add, 1 cmp, 2 div.
  localparam int SETUP_MUL = 9;
  localparam int SETUP_ADD = 6 + 3 * (K - 1);

  function automatic logic signed [W-1:0] sat(input logic signed [PW-1:0] v);
    sat = v > MAXV ? MAXV[W-1:0] : (v < MINV ? MINV[W-1:0] : v[W-1:0]);
  endfunction
  function automatic logic signed [W-1:0] sadd(input logic signed [W-1:0] a, input logic signed [W-1:0] b);
    sadd = sat(PW'(a) + PW'(b));
  endfunction
  function automatic logic signed [W-1:0] smul(input logic signed [W-1:0] a, input logic signed [XW-1:0] x);
    smul = sat(PW'(a) * PW'(x));
  endfunction
  function automatic logic signed [W-1:0] form(input logic signed [W-1:0] a, input logic signed [W-1:0] b,
                                              input logic signed [W-1:0] c);
    form = sadd(sadd(smul(a, $signed(x0)), smul(b, $signed(y))), c);
  endfunction

  // ---- Row set-up: combinational arithmetic, then SETUP_LAT - 1 registers, then the lanes
  localparam int SW = 3 * W * (K + 1) + NW;
  logic [SW-1:0] setup, setup_q;
  logic load, load_q;
  assign load = in_valid && in_ready && n != '0;
  always_comb begin
    logic signed [W-1:0] w, z, t;
    w = form($signed(ca), $signed(cb), $signed(cc));
    z = form($signed(cg), $signed(ch), $signed(ci));
    t = form($signed(cd), $signed(ce), $signed(cf));
    for (int j = 0; j < K; j++) begin
      setup[3*W*j+:3*W] = {w, z, t};
      w = sadd(w, $signed(ca));
      z = sadd(z, $signed(cg));
      t = sadd(t, $signed(cd));
    end
    setup[3*W*K+:3*W] = {smul($signed(ca), XW'(K)), smul($signed(cg), XW'(K)), smul($signed(cd), XW'(K))};
    setup[SW-1-:NW] = n;
  end
  texsim_pipe #(.W(SW + 1), .N(SETUP_LAT - 1)) u_setup (
      .clk, .rst, .d({load, setup}), .q({load_q, setup_q}));

  // ---- Lane accumulators and the group generator
  logic signed [W-1:0] lw[K], lz[K], lt[K], kw, kz, kt;
  logic [NW-1:0] left;  // pixels not yet issued
  logic active, first, busy_setup;
  logic [SETUP_LAT-1:0] inflight;
  always_ff @(posedge clk) begin
    if (rst) begin
      active <= 1'b0;
      first <= 1'b0;
      left <= '0;
      inflight <= '0;
    end else begin
      inflight <= (inflight << 1) | SETUP_LAT'(load);
      if (load_q) begin
        for (int j = 0; j < K; j++) begin
          lw[j] <= setup_q[3*W*j+2*W+:W];
          lz[j] <= setup_q[3*W*j+W+:W];
          lt[j] <= setup_q[3*W*j+:W];
        end
        {kw, kz, kt} <= setup_q[3*W*K+:3*W];
        left <= setup_q[SW-1-:NW];
        active <= 1'b1;
        first <= 1'b1;
      end else if (active) begin
        for (int j = 0; j < K; j++) begin
          lw[j] <= sadd(lw[j], kw);
          lz[j] <= sadd(lz[j], kz);
          lt[j] <= sadd(lt[j], kt);
        end
        left <= left > NW'(K) ? left - NW'(K) : '0;
        active <= left > NW'(K);
        first <= 1'b0;
      end
    end
  end
  assign busy_setup = inflight != '0;
  assign in_ready = !active && !busy_setup;

  // ---- This cycle's group: mask, z compare, dividers
  logic [K-1:0] mask, zok, mask_q, zok_q;
  logic [NW-1:0] cnt, cnt_q;
  logic first_q, grp_q;
  always_comb begin
    for (int j = 0; j < K; j++) begin
      mask[j] = active && left > NW'(j);
      zok[j]  = lz[j] >= W'(MIN_DEN) && !lz[j][W-1];
    end
    cnt = !active ? '0 : (left > NW'(K) ? NW'(K) : left);
  end
  texsim_pipe #(.W(2 * K + NW + 2), .N(DIV_LAT)) u_grp (
      .clk, .rst, .d({active, first && active, mask, zok, cnt}), .q({grp_q, first_q, mask_q, zok_q, cnt_q}));

  for (genvar j = 0; j < K; j++) begin : g_lane
    logic signed [W-1:0] u, v;
    logic uok, vok, ok;
    texsim_fixed_div #(.W(W), .F(F), .LAT(DIV_LAT)) u_du (.clk, .rst, .a(lw[j]), .b(lz[j]), .q(u));
    texsim_fixed_div #(.W(W), .F(F), .LAT(DIV_LAT)) u_dv (.clk, .rst, .a(lt[j]), .b(lz[j]), .q(v));
    assign uok = u != MAXV[W-1:0] && u != MINV[W-1:0];
    assign vok = v != MAXV[W-1:0] && v != MINV[W-1:0];
    assign ok = mask_q[j] && zok_q[j] && uok && vok;
    assign out_ok[j] = ok;
    assign out_u[W*j+:W] = ok ? u : '0;
    assign out_v[W*j+:W] = ok ? v : '0;
  end
  assign out_valid = grp_q;
  assign out_mask = mask_q;

  texsim_op_counters u_ops (
      .clk, .rst, .retire(out_valid),
      .add_n(16'(3 * cnt_q) + (first_q ? 16'(SETUP_ADD) : 16'd0)),
      .mul_n(first_q ? 16'(SETUP_MUL) : 16'd0), .div_n(16'(2 * cnt_q)), .cmp_n(16'(cnt_q)),
      .ops_add, .ops_mul, .ops_div, .ops_cmp, .items);
endmodule
