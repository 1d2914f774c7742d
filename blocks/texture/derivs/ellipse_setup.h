#pragma once
// EllipseSetup: Heckbert's EWA footprint ellipse A U² + B U V + C V² = F from the four
// derivatives (A = Vx²+Vy², B = -2(UxVx+UyVy), C = Ux²+Uy², F = (UxVy-UyVx)²), F either as the
// squared Jacobian or seed 004's F' = AC - B²/4, and the normalised A/F, B/F, C/F
// (docs/derivations/coords-derivations.md §7).
#include <cmath>
#include <cstdint>
#include <string>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/coords/coord_types.h"

namespace texsim {

class ConfigReader;

struct EllipseCoeffs {
  double a = 0, b = 0, c = 0, f = 0;  // A U² + B U V + C V² = F
  double an = 0, bn = 0, cn = 0;      // A/F, B/F, C/F (normalised: d² <= 1 is the footprint)
  bool valid = false;
};

// The exact ellipse of a footprint in long double (reference).
struct EllipseL {
  long double a = 0, b = 0, c = 0, f = 0;
};
EllipseL ellipse_reference(const DerivsL& d);

class EllipseSetup {
 public:
  enum class FForm { Determinant, AcMinusB2 };
  struct Config {
    FForm f_form = FForm::Determinant;
    bool normalise = true;
    Datapath datapath = Datapath::Spatial;
    bool seed_misprints = false;  // F = (UxVy + UyVx)² and F' = AC - B²/A, as printed
    static Config from_toml(const ConfigReader& r);
  };
  EllipseSetup() = default;
  explicit EllipseSetup(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // Functional core in T; inputs are a derivative block's outputs (T values widened to
  // double, so converting back is exact).
  template <class T>
  EllipseCoeffs eval(const CoordDerivs& d) const {
    EllipseCoeffs e;
    if (!d.valid) return e;
    const T ux = static_cast<T>(d.ux), vx = static_cast<T>(d.vx);
    const T uy = static_cast<T>(d.uy), vy = static_cast<T>(d.vy);
    const T a = vx * vx + vy * vy;
    const T b = static_cast<T>(-2) * (ux * vx + uy * vy);
    const T c = ux * ux + uy * uy;
    T f{};
    if (cfg_.f_form == FForm::Determinant) {
      const T j = cfg_.seed_misprints ? ux * vy + uy * vx : ux * vy - uy * vx;
      f = j * j;
    } else {
      f = cfg_.seed_misprints ? a * c - b * b / a : a * c - b * b / static_cast<T>(4);
    }
    if (!is_finite_value(f) || !(f > T{}) || out_of_range(a) || out_of_range(b) ||
        out_of_range(c) || out_of_range(f)) {
      return e;
    }
    e.a = to_double(a);
    e.b = to_double(b);
    e.c = to_double(c);
    e.f = to_double(f);
    if (cfg_.normalise) {
      const T r = static_cast<T>(1) / f;
      const T an = a * r, bn = b * r, cn = c * r;
      if (out_of_range(an) || out_of_range(bn) || out_of_range(cn)) return EllipseCoeffs{};
      e.an = to_double(an);
      e.bn = to_double(bn);
      e.cn = to_double(cn);
    }
    e.valid = true;
    return e;
  }

  // Item: one pixel.
  OpCounts ops_per_item() const;
  OpCounts pixel_critical_path() const;
  TimingSpec timing(const TechTable& t) const;
  // Report name; the number format is the caller's T, so arithmetic() names the datapath.
  std::string name() const { return "ellipse"; }
  std::string arithmetic() const { return std::string(datapath_name(cfg_.datapath)) + " datapath"; }

 private:
  Config cfg_{};
};

}  // namespace texsim
