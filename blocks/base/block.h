#pragma once
// The contract every hardware block model satisfies (docs/architecture.md), checked with a
// static_assert next to each block:
//  - a nested Config read from a scene table by Config::from_toml (errors name block and key);
//  - its own functional core (filter(), evaluate(), taps(), access(), ...: not part of the
//    concept, each block's call keeps the shape of its datapath);
//  - ops_per_item(): the operations of one item, where each block documents what its item is
//    (a pixel, a fragment, a probe, a tap, a scanned texel, a cache look-up, ...);
//  - timing(tech): latency, II, lanes and area, always through derive_timing
//    (blocks/base/derive_timing.h);
//  - name() and arithmetic(): the block's report name and the description of its number
//    formats, from the block itself.
#include <concepts>
#include <string>

#include "blocks/base/config_reader.h"
#include "blocks/base/derive_timing.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"

namespace texsim {

template <class B>
concept Block = requires(const B& b, const ConfigReader& r, const TechTable& tech) {
  typename B::Config;
  { B::Config::from_toml(r) } -> std::same_as<typename B::Config>;
  { b.ops_per_item() } -> std::convertible_to<OpCounts>;
  { b.timing(tech) } -> std::same_as<TimingSpec>;
  { b.name() } -> std::convertible_to<std::string>;
  { b.arithmetic() } -> std::convertible_to<std::string>;
};

}  // namespace texsim
