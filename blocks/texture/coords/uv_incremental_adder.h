#pragma once
// UvIncrementalAdder: the thesis's modified Heckbert: per raster row one set-up of the
// numerators w, t and denominator z, then +A, +D, +G per pixel and a division pair; in the
// sequential, k-lane (w_n = w_{n-k} + k·A), bidirectional two-lane and direct-n
// (w_n = w_0 + A·n, thesis fig. 7) forms (docs/derivations/coords-derivations.md §3, error
// bounds §3.3).
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/raster/raster_types.h"
#include "blocks/texture/coords/coord_types.h"

namespace texsim {

class ConfigReader;

class UvIncrementalAdder {
 public:
  enum class Form { Sequential, KLane, Bidirectional, DirectN };
  enum class Division { Divide, Reciprocal };
  struct Config {
    Form form = Form::Sequential;
    int lanes = 4;  // k of the k-lane and direct-n forms (ignored by the others)
    Division division = Division::Divide;
    Datapath datapath = Datapath::Spatial;
    double min_denominator = 1.0 / 4096;  // as UvHeckbertDirect: q below it is rejected
    static Config from_toml(const ConfigReader& r);
  };

  UvIncrementalAdder() = default;
  explicit UvIncrementalAdder(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }
  // Parallel datapaths: k for the k-lane and direct-n forms, 2 for the bidirectional form,
  // else 1.
  uint32_t lane_count() const;

  // Functional core in T. Every add and the division round to T; in Fixed<I,F> the adds are
  // exact (so every form gives w_0 + n·A_q bit for bit), in float each add rounds.
  template <class T>
  void eval_row(const MapCoeffs<T>& m, const RowSpan& s, CoordSample* out) const {
    if (s.n <= 0) return;
    if (!m.ok) {
      std::fill(out, out + s.n, CoordSample{});
      return;
    }
    const T yt = static_cast<T>(s.y);
    auto form_at = [&](T a, T b, T c, int32_t x) { return a * static_cast<T>(x) + b * yt + c; };
    const int32_t x0 = s.x0;
    T w = form_at(m.A, m.B, m.C, x0), z = form_at(m.G, m.H, m.I, x0),
      t = form_at(m.D, m.E, m.F, x0);
    if (!is_finite_value(w) || !is_finite_value(z) || !is_finite_value(t)) {
      std::fill(out, out + s.n, CoordSample{});
      return;
    }
    switch (cfg_.form) {
      case Form::Sequential:
        for (int32_t n = 0; n < s.n; ++n) {
          out[n] = divide(w, z, t);
          w += m.A;
          z += m.G;
          t += m.D;
        }
        break;
      case Form::KLane: {
        const int32_t k = std::max(1, cfg_.lanes);
        const T kt = static_cast<T>(k);
        const T ka = kt * m.A, kg = kt * m.G, kd = kt * m.D;
        // Lane j starts at pixel j; the first k values come from the sequential form.
        std::vector<T> lw(static_cast<size_t>(k)), lz(static_cast<size_t>(k)),
            lt(static_cast<size_t>(k));
        for (int32_t j = 0; j < k; ++j) {
          lw[j] = w;
          lz[j] = z;
          lt[j] = t;
          w += m.A;
          z += m.G;
          t += m.D;
        }
        for (int32_t n = 0; n < s.n; ++n) {
          const size_t j = static_cast<size_t>(n % k);
          out[n] = divide(lw[j], lz[j], lt[j]);
          lw[j] += ka;
          lz[j] += kg;
          lt[j] += kd;
        }
        break;
      }
      case Form::DirectN:
        // Every pixel from the row's start values: a multiply by n instead of a running sum,
        // so any lane computes any pixel. In fixed point n·A is exact and equals the sums.
        for (int32_t n = 0; n < s.n; ++n) {
          const T nt = static_cast<T>(n);
          out[n] = divide(w + m.A * nt, z + m.G * nt, t + m.D * nt);
        }
        break;
      case Form::Bidirectional: {
        // Left lane: pixels 0 .. mid-1 with +A; right lane: pixels n-1 down to mid with -A,
        // started from its own exactly evaluated end values.
        const int32_t mid = (s.n + 1) / 2;
        const int32_t xe = x0 + s.n - 1;
        T we = form_at(m.A, m.B, m.C, xe), ze = form_at(m.G, m.H, m.I, xe),
          te = form_at(m.D, m.E, m.F, xe);
        for (int32_t n = 0; n < mid; ++n) {
          out[n] = divide(w, z, t);
          w += m.A;
          z += m.G;
          t += m.D;
        }
        for (int32_t n = s.n - 1; n >= mid; --n) {
          out[n] = divide(we, ze, te);
          we -= m.A;
          ze -= m.G;
          te -= m.D;
        }
        break;
      }
    }
  }

  // A-priori bound (texels) on |u - u_exact| and |v - v_exact| at pixel n of span s for number
  // format T, derived in docs/derivations/coords-derivations.md §3.3. Returns +inf where the bound
  // does not apply (denominator within its own error of zero).
  template <class T>
  double error_bound(const ProjectiveMap& m, const RowSpan& s, int32_t n) const;

  // Item: one pixel (per lane).
  OpCounts ops_per_item() const;  // per pixel (per lane)
  OpCounts pixel_critical_path() const;
  OpCounts row_setup_ops() const;
  OpCounts row_setup_critical_path() const;
  TimingSpec timing(const TechTable& t) const;  // per pixel, lanes = lane_count()
  // Report name; the number format is the caller's T, so arithmetic() names the datapath.
  std::string name() const { return "coords.incremental"; }
  std::string arithmetic() const { return std::string(datapath_name(cfg_.datapath)) + " datapath"; }
  TimingSpec row_setup_timing(const TechTable& t) const;

 private:
  template <class T>
  CoordSample divide(T w, T z, T t) const {
    if (!is_finite_value(z) || !(z >= static_cast<T>(cfg_.min_denominator))) return {};
    T u{}, v{};
    if (cfg_.division == Division::Divide) {
      u = w / z;
      v = t / z;
    } else {
      const T r = static_cast<T>(1) / z;
      u = w * r;
      v = t * r;
    }
    if (out_of_range(u) || out_of_range(v)) return {};
    return {to_double(u), to_double(v), true};
  }

  // Accumulation steps (roundings) and increments accumulated before pixel n, and the x at
  // which the lane's start value was evaluated.
  void lane_history(const RowSpan& s, int32_t n, double& roundings, double& increments,
                    int32_t& x_start) const;
  // Bound from the per-format constants: `fixed` = true with lsb, else unit roundoff mu.
  double bound_impl(const ProjectiveMap& m, const RowSpan& s, int32_t n, bool fixed,
                    double unit) const;

  Config cfg_{};
};

template <class T>
double UvIncrementalAdder::error_bound(const ProjectiveMap& m, const RowSpan& s, int32_t n) const {
  if constexpr (is_fixed_v<T>) {
    return bound_impl(m, s, n, true, T::lsb());
  } else {
    return bound_impl(m, s, n, false, static_cast<double>(std::numeric_limits<T>::epsilon()) / 2);
  }
}

}  // namespace texsim
