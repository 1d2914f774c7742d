#include "pipeline/texture/quad_assembler.h"

#include <bit>
#include <cstddef>

namespace texsim {

namespace {

int lane_of(const Fragment& f) { return static_cast<int>((f.x & 1u) | (f.y & 1u) << 1); }

bool same_quad(const Fragment& a, const Fragment& b) {
  return a.frame == b.frame && a.prim == b.prim && a.x >> 1 == b.x >> 1 && a.y >> 1 == b.y >> 1;
}

// u and v differences lane b − lane a.
struct Diff {
  double du, dv;
};
Diff diff(const Quad& q, int a, int b) {
  return {q.lane[b].u - q.lane[a].u, q.lane[b].v - q.lane[a].v};
}

void set_x(Fragment& f, Diff d) {
  f.dudx = d.du;
  f.dvdx = d.dv;
}
void set_y(Fragment& f, Diff d) {
  f.dudy = d.du;
  f.dvdy = d.dv;
}

// The pair (a, b) if both lanes are covered.
bool pair(const Quad& q, int a, int b) { return q.has(a) && q.has(b); }

}  // namespace

int Quad::covered() const { return std::popcount(mask); }

void QuadAssembler::derive(Quad& q, QuadDerivatives mode, QuadCounts& c) {
  if (mode == QuadDerivatives::Own) return;
  const auto n = static_cast<uint64_t>(q.covered());
  if (mode == QuadDerivatives::Coarse) {
    // x: the top row (lanes 0, 1), else the bottom one (2, 3); y: the left column (0, 2), else
    // the right one (1, 3).
    const bool top = pair(q, 0, 1), bottom = pair(q, 2, 3);
    const bool left = pair(q, 0, 2), right = pair(q, 1, 3);
    for (int i = 0; i < 4; ++i) {
      if (!q.has(i)) continue;
      if (top || bottom) set_x(q.lane[i], top ? diff(q, 0, 1) : diff(q, 2, 3));
      if (left || right) set_y(q.lane[i], left ? diff(q, 0, 2) : diff(q, 1, 3));
    }
    if (!top && !bottom) c.own_x += n;
    if (!left && !right) c.own_y += n;
    return;
  }
  // Fine: a lane's own row for x, its own column for y. Differences are taken before any lane
  // is written (u and v are not changed, so the order does not matter).
  for (int i = 0; i < 4; ++i) {
    if (!q.has(i)) continue;
    const int row = i & 2, column = i & 1;
    if (pair(q, row, row + 1))
      set_x(q.lane[i], diff(q, row, row + 1));
    else
      ++c.own_x;
    if (pair(q, column, column + 2))
      set_y(q.lane[i], diff(q, column, column + 2));
    else
      ++c.own_y;
  }
}

const Quad* QuadAssembler::close() {
  if (open_.mask == 0) return nullptr;
  closed_ = open_;
  open_.mask = 0;
  ++counts_.quads;
  const auto n = static_cast<uint64_t>(closed_.covered());
  counts_.fragments += n;
  counts_.helper_lanes += 4 - n;
  derive(closed_, mode_, counts_);
  return &closed_;
}

const Quad* QuadAssembler::push(const Fragment& f) {
  const int lane = lane_of(f);
  const Quad* done = nullptr;
  if (open_.mask != 0) {
    const Fragment& any = open_.lane[static_cast<std::size_t>(std::countr_zero(open_.mask))];
    if (!same_quad(any, f) || open_.has(lane)) done = close();
  }
  open_.lane[static_cast<std::size_t>(lane)] = f;
  open_.mask = static_cast<uint8_t>(open_.mask | 1u << lane);
  return done;
}

const Quad* QuadAssembler::flush() { return close(); }

}  // namespace texsim
