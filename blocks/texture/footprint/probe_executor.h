#pragma once
// Probe executor of the probe-based footprint filters (MultiProbeFilter, FelineFilter): runs a
// set of weighted isotropic probes through the trilinear texel address generator, blends
// their taps and normalises by the weight sum; with its op counts and timing.
#include <array>
#include <vector>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/footprint/footprint_types.h"
#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/sampler/texel_address_gen.h"

namespace texsim {

// A set of weighted isotropic probes at one LOD (normalised coordinates).
struct ProbeSet {
  static constexpr int kMax = 31;
  int n = 0;
  std::array<double, kMax> u{}, v{};
  std::array<float, kMax> w{};
  float lambda = 0;
};

// Runs each probe as a trilinear lookup (TexelAddressGen, one probe per cycle), blends its 8
// taps and sums the probes with their weights, normalised by Σw (all weights zero: the
// probes' plain mean). Appends the taps' texels to `fetched`; counts each probe's set-up
// (`probe_setup`: position and weight), address, blend and weighting operations. `bad_input`
// is the set-up's verdict on the fragment, passed to the output's stats.
FilterOutput run_probes(const TexelAddressGen& addr, const Texture& tex, const ProbeSet& probes,
                        const OpCounts& probe_setup, bool bad_input, std::vector<TexelRef>* fetched,
                        OpCounts& ops);
// One probe lane of a probe filter: its set-up, trilinear address and blend with weighting.
OpCounts probe_lane_ops(const TexelAddressGen& addr, const OpCounts& probe_setup);
// Timing of a probe filter: the set-up's critical path `setup_path`, then one probe's address
// path, blend and normalisation; II 1 (one probe per cycle); area of the set-up (`setup_ops`),
// one probe lane and the normalisation.
TimingSpec probe_filter_timing(const TechTable& tech, const OpCounts& setup_path,
                               const TexelAddressGen& addr, const OpCounts& setup_ops,
                               const OpCounts& probe_setup);
// Operations of run_probes per probe besides TexelAddressGen's (blend 8 taps, weighting) and
// per fragment (normalisation).
OpCounts probe_blend_ops();
// A trilinear probe's blend (8 taps through TexelBlend) plus its weighting.
OpCounts trilinear_probe_blend_ops();
OpCounts probe_normalise_ops();

}  // namespace texsim
