#include "pipeline/footprint_filter.h"

#include "blocks/feline_filter.h"
#include "blocks/multi_probe_filter.h"
#include "blocks/spaf_filter.h"

namespace texsim {

namespace {

template <class Block>
class FootprintFilterOf final : public FootprintFilter {
 public:
  FootprintFilterOf(const typename Block::Config& c, std::string name, std::string arith)
      : block_(c), name_(std::move(name)), arith_(std::move(arith)) {}
  FilterOutput filter(const Texture& tex, const Fragment& f, std::vector<TexelRef>* fetched,
                      OpCounts& ops) const override {
    return block_.filter(tex, f, fetched, ops);
  }
  uint32_t issue_cycles(const FilterStats& s) const override { return block_.issue_cycles(s); }
  TimingSpec timing(const TechTable& tech) const override { return block_.timing(tech); }
  std::string name() const override { return name_; }
  std::string arithmetic() const override { return arith_; }
  AddressMode address_u() const override { return block_.config().address_u; }
  AddressMode address_v() const override { return block_.config().address_v; }

 private:
  Block block_;
  std::string name_, arith_;
};

template <class Block>
std::unique_ptr<FootprintFilter> make(const ConfigReader& r, const char* key, std::string arith) {
  const auto cfg = Block::Config::from_toml(r.sub(key));
  return std::make_unique<FootprintFilterOf<Block>>(cfg, std::string("filter.") + key, std::move(arith));
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
    if (f) material.fail(key, "a material takes one footprint filter; it already has '" + chosen + "'");
    chosen = key;
    if (key == "ewa") {
      const auto cfg = EwaFilter::Config::from_toml(material.sub(key));
      const EwaFilter probe(cfg);
      f = std::make_unique<FootprintFilterOf<EwaFilter>>(cfg, "filter.ewa", probe.arithmetic());
    } else if (key == "multi_probe") {
      f = make<MultiProbeFilter>(material, "multi_probe", "float32; Gaussian probe weights");
    } else if (key == "feline") {
      f = make<FelineFilter>(material, "feline", "float32 trilinear probes");
    } else {
      const auto cfg = SpafFilter::Config::from_toml(material.sub(key));
      f = std::make_unique<FootprintFilterOf<SpafFilter>>(cfg, "filter.spaf", SpafFilter(cfg).arithmetic());
    }
  }
  return f;
}

}  // namespace texsim
