#pragma once
// Long-double reference of the probe filters' set-up (blocks/texture/footprint/feline_filter,
// blocks/texture/footprint/multi_probe_filter): the footprint ellipse both derive their line from,
// the comparison of a block's ProbeSet with the reference probes under a position bound, and the
// random footprints that drive it. Each filter's own rules (N, positions, weights, λ) stay in its
// test. Not a hardware block: a testbench reference, in long double throughout.
#include <random>
#include <string>

#include "blocks/base/fragment.h"
#include "blocks/texture/footprint/multi_probe_filter.h"
#include "blocks/texture/memory/texture_memory.h"

namespace texsim {

// A probe set from a filter's documented rules.
struct RefProbes {
  int n = 1;
  long double u[ProbeSet::kMax]{}, v[ProbeSet::kMax]{}, w[ProbeSet::kMax]{};
  long double lambda = 0;
  long double q = 0;     // the ratio N is taken from (each filter's test says how)
  long double len = 0;   // the half line in level-0 texels (Feline |line|, multi-ellipse R_major)
  bool special = false;  // a point or overflow: one probe, λ = ±1e30
};

// The footprint in level-0 texels: R·J, Σ = R²·J·Jᵀ, λ± = t ± |(d, Σuv)| with t and d the half
// sum and half difference of Σuu and Σvv, and the clamp λ₋ ≥ λ₊/maxA² (eigenvectors unchanged).
struct RefEllipse {
  long double ux = 0, uy = 0, vx = 0, vy = 0;  // R·(∂u/∂x, ∂u/∂y, ∂v/∂x, ∂v/∂y) in texels
  long double suu = 0, suv = 0, svv = 0;
  long double d = 0;                   // (Σuu − Σvv)/2: with Σuv, 2θ of the major axis
  long double major2 = 0, minor2 = 0;  // λ₊ and the clamped λ₋ (texels²)
};
RefEllipse reference_ellipse(const Fragment& f, int w0, int h0, double radius_px, double max_aniso);

// Worst deviations of one arithmetic from the reference.
struct Deviation {
  double pos = 0;      // worst ratio of a position error to its bound (see ProbeBound)
  double pos_abs = 0;  // texels of level 0
  double w = 0, lambda = 0;
  int compared = 0, n_mismatch = 0, near_boundary = 0;
};

// Position bound (texels of level 0): rel·(1 + len) for the angle and length roundings, plus for
// the fixed datapath the s16.32 rounding of the centre and of the per-probe offset times the
// probe's index, (N + 1)·max(w0, h0)·2^-33, and the s16.24 derivatives' 2^-24.
struct ProbeBound {
  int w0 = 1, h0 = 1;
  double rel = 0;
  bool fixed = false;
  // N is decided by q against integers: below q_clamp (where N reaches max_probes whatever the
  // rounding) a q within 10⁻⁴·q of one may go either way and is counted, not compared.
  int q_clamp = 0;
};

// Adds one fragment's probes to `d`. The line at θ or θ + π gives the same probes in reverse
// order (2θ = ±π is one point for the datapath): the closer order is compared. λ of magnified
// footprints (λ ≤ −1) only selects level 0 and is not compared.
void compare_probes(const ProbeSet& p, const RefProbes& r, const ProbeBound& b, Deviation& d);

// Counts and worst deviations, for the test log.
std::string describe(const Deviation& d);

// |a − b| over r, g and b of many lookups (one arithmetic's colours against another's).
struct ColourDeviation {
  double worst = 0, sum = 0;
  int n = 0;
  void add(const Rgba& a, const Rgba& b);
  double mean() const { return sum / n; }
};

// A footprint of axes `major` ≥ `minor` texels at angle θ, centred at (u, v).
Fragment ellipse_fragment(double u, double v, double major, double minor, double theta, int w0,
                          int h0);

// Centre in [−2, 2)², LOD bias in [−½, ½); general: independent derivative vectors of ±2^-4 to
// 2^10 texels (sheared footprints); otherwise axes major ≥ minor at angle θ, major 2^-3 to 2^12
// texels, anisotropy up to 200:1.
Fragment random_footprint(std::mt19937& rng, int w0, int h0, bool general);

// Footprints for colour comparisons on a texture: axes major ≥ minor at angle θ, major 2^-1 to
// 2^8 texels, anisotropy 1 to 64, centre in [0, 1)².
Fragment random_ellipse_footprint(std::mt19937& rng, int w0, int h0);

}  // namespace texsim
