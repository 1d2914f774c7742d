#include "pipeline/texture/footprint_filter.h"

#include "blocks/base/block.h"
#include "blocks/texture/footprint/ewa_filter.h"
#include "blocks/texture/footprint/feline_filter.h"
#include "blocks/texture/footprint/multi_probe_filter.h"
#include "blocks/texture/footprint/spaf_filter.h"
#include "blocks/texture/footprint/weight_map.h"

namespace texsim {

namespace {

template <Block B>
class FootprintFilterOf final : public FootprintFilter {
 public:
  explicit FootprintFilterOf(B block) : block_(std::move(block)) {}
  FilterOutput filter(const Texture& tex, const Fragment& f, std::vector<TexelRef>* fetched,
                      OpCounts& ops) const override {
    return block_.filter(tex, f, fetched, ops);
  }
  uint32_t issue_cycles(const FilterStats& s) const override { return block_.issue_cycles(s); }
  TimingSpec timing(const TechTable& tech) const override { return block_.timing(tech); }
  std::string name() const override { return block_.name(); }
  std::string arithmetic() const override { return block_.arithmetic(); }
  AddressMode address_u() const override { return block_.config().address_u; }
  AddressMode address_v() const override { return block_.config().address_v; }

 private:
  B block_;
};

template <Block B>
std::unique_ptr<FootprintFilter> make(const ConfigReader& r, std::string_view key) {
  return std::make_unique<FootprintFilterOf<B>>(B(B::Config::from_toml(r.sub(key))));
}

// EWA, with the weight map its `weight_map` table describes when weight = "map" (the map's
// alpha defaults to the filter's).
std::unique_ptr<FootprintFilter> make_ewa(const ConfigReader& material) {
  const ConfigReader r = material.sub("ewa");
  const EwaFilter::Config cfg = EwaFilter::Config::from_toml(r);
  std::shared_ptr<const WeightMap> map;
  if (cfg.weight == EwaFilter::Weight::Map) {
    const ConfigReader mr = r.sub("weight_map");
    WeightMap::Config m = WeightMap::Config::from_toml(mr);
    if (!mr.table().contains("alpha")) m.alpha = cfg.alpha;
    map = std::make_shared<const WeightMap>(m);
  }
  return std::make_unique<FootprintFilterOf<EwaFilter>>(EwaFilter(cfg, map));
}

}  // namespace

const std::vector<std::string_view>& FootprintFilter::effect_keys() {
  static const std::vector<std::string_view> keys = {"ewa", "multi_probe", "feline", "spaf"};
  return keys;
}

std::unique_ptr<FootprintFilter> FootprintFilter::from_material(const ConfigReader& material) {
  std::unique_ptr<FootprintFilter> f;
  std::string chosen;
  for (std::string_view key : effect_keys()) {
    if (!material.table().contains(key)) continue;
    if (f)
      material.fail(key, "a material takes one footprint filter; it already has '" + chosen + "'");
    chosen = key;
    if (key == "ewa") {
      f = make_ewa(material);
    } else if (key == "multi_probe") {
      f = make<MultiProbeFilter>(material, key);
    } else if (key == "feline") {
      f = make<FelineFilter>(material, key);
    } else {
      f = make<SpafFilter>(material, key);
    }
  }
  return f;
}

}  // namespace texsim
