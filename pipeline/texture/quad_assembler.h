#pragma once
// Groups a fragment stream into the 2×2 quads a GPU shades together, and takes derivatives from
// quad differences by Vulkan's rules (Vulkan 1.0 §15.5, "Derivative Operations").
//
// The rule, which is also how the quads of a fragment trace are recovered (a trace holds
// fragments, not quads, so existing traces keep working): consecutive fragments with the same
// frame, the same primitive and the same square (x >> 1, y >> 1) form one quad. A fragment that
// differs in any of them, or repeats a pixel the open quad already holds, closes the quad and
// opens the next. A quad's lane is (x & 1) | (y & 1) << 1: Vulkan's order (0,0), (1,0), (0,1),
// (1,1). Lanes with no fragment are helper lanes. A stream in row order splits each square into
// two quads (one per row); the tiled raster order (pipeline/raster/raster_order.h) hands on each
// primitive's quad as one run.
#include <array>
#include <cstdint>

#include "blocks/base/fragment.h"

namespace texsim {

// Where a fragment's derivatives come from: its own (Fragment's dudx..dvdy, exact), or the
// differences of u and v between the quad's lanes. Fine: each row's own x difference, each
// column's own y difference. Coarse: one x difference (the top row, else the bottom row) and one
// y difference (the left column, else the right one) for all four lanes, the choices §15.5 lets
// a coarse derivative make, the first one its preferred.
enum class QuadDerivatives : uint8_t { Own, Coarse, Fine };

struct Quad {
  std::array<Fragment, 4> lane;  // lane[i] is valid where bit i of mask is set
  uint8_t mask = 0;
  bool has(int i) const { return (mask >> i & 1) != 0; }
  int covered() const;  // lanes with a fragment
};

struct QuadCounts {
  uint64_t quads = 0, fragments = 0;
  uint64_t helper_lanes = 0;  // 4 · quads − fragments
  // Fragments whose x (y) derivatives stayed their own because the lanes the quad difference
  // needs were helper lanes (Coarse, Fine only): a GPU would have run the helpers for them.
  uint64_t own_x = 0, own_y = 0;
};

class QuadAssembler {
 public:
  explicit QuadAssembler(QuadDerivatives mode = QuadDerivatives::Coarse) : mode_(mode) {}

  // Adds the stream's next fragment. Returns the quad it closed (derivatives applied), valid
  // until the next call, or null when f joined the open quad.
  const Quad* push(const Fragment& f);
  // Closes the open quad at the end of the stream; null when there is none.
  const Quad* flush();

  const QuadCounts& counts() const { return counts_; }

  // Replaces the covered lanes' derivatives by quad differences under `mode`, adding to c's
  // own_x and own_y where the lanes needed are missing.
  static void derive(Quad& q, QuadDerivatives mode, QuadCounts& c);

 private:
  const Quad* close();

  QuadDerivatives mode_;
  Quad open_, closed_;
  QuadCounts counts_;
};

}  // namespace texsim
