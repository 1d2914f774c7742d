#include "blocks/texture/footprint/probe_executor.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>
#include <type_traits>

#include "blocks/base/derive_timing.h"
#include "blocks/texture/sampler/texel_blend.h"
#include "blocks/texture/subtexel/vd_evaluator_params.h"

namespace texsim {

OpCounts probe_blend_ops() {
  OpCounts o;
  o.mul = 4;      // w_k · probe colour
  o.add = 4 + 1;  // accumulate RGBA, Σw
  return o;
}

OpCounts trilinear_probe_blend_ops() { return TexelBlend::ops_per_item() * 8 + probe_blend_ops(); }

OpCounts probe_normalise_ops() {
  OpCounts o;
  o.cmp = 1;
  o.rcp = 1;
  o.mul = 4;
  return o;
}

FilterOutput run_probes(const TexelAddressGen& addr, const Texture& tex, const ProbeSet& probes,
                        const OpCounts& probe_setup, bool bad_input, std::vector<TexelRef>* fetched,
                        OpCounts& ops) {
  FilterOutput out;
  out.stats.bad_input = bad_input;
  ops += probe_setup * static_cast<uint64_t>(probes.n);
  FilterTaps taps;
  LodResult lod;
  lod.lambda = probes.lambda;
  lod.probes = 1;
  glm::vec4 sum(0), plain(0);
  float wsum = 0;
  int32_t finest = 1 << 30;
  for (int k = 0; k < probes.n; ++k) {
    const auto ku = static_cast<size_t>(k);
    addr.taps(tex, probes.u[ku], probes.v[ku], lod, taps, ops);
    glm::vec4 c(0);
    for (int t = 0; t < taps.count; ++t) {
      const TexelTap& tp = taps.tap[static_cast<size_t>(t)];
      c += tp.w * tex.texel(tp.level, tp.x, tp.y);
      if (fetched) fetched->push_back({tp.level, tp.x, tp.y});
      finest = std::min(finest, tp.level);
    }
    ops += TexelBlend::ops_per_item() * static_cast<uint64_t>(taps.count);
    ops += probe_blend_ops();
    out.stats.texels += static_cast<uint32_t>(taps.count);
    sum += probes.w[ku] * c;
    plain += c;
    wsum += probes.w[ku];
  }
  ops += probe_normalise_ops();
  out.stats.probes = static_cast<uint32_t>(probes.n);
  out.stats.visited = out.stats.probes;
  out.stats.level = probes.n > 0 ? finest : 0;
  if (normalisable(wsum)) {
    out.colour = sum * (1.0f / wsum);
  } else if (probes.n > 0) {
    out.stats.fallback = true;  // every Gaussian weight underflowed: the probes' mean
    out.colour = plain * (1.0f / static_cast<float>(probes.n));
  }
  return out;
}

OpCounts probe_lane_ops(const TexelAddressGen& addr, const OpCounts& probe_setup) {
  return probe_setup + addr.ops_per_item(false) + trilinear_probe_blend_ops();
}

TimingSpec probe_filter_timing(const TechTable& tech, const OpCounts& setup_path,
                               const TexelAddressGen& addr, const OpCounts& setup_ops,
                               const OpCounts& probe_setup) {
  OpCounts tail;  // blend of one probe's taps, weighting, normalisation
  tail.mem = 1;
  tail.mul = 2;
  tail.add = 4;
  tail.rcp = 1;
  // One probe per cycle; the set-up and one probe's lane and normaliser exist once.
  OpCounts lane = probe_lane_ops(addr, probe_setup);
  lane.mem = 0;
  TimingSpec t =
      derive_timing(tech, setup_ops, tech.path_latency(setup_path) + tech.path_latency(tail),
                    Datapath::Spatial, 1, lane + probe_normalise_ops());
  t.latency += addr.timing(tech).latency;  // the address generator's pipeline in series
  return t;
}

}  // namespace texsim
