#include "pipeline/app/board_sampler.h"

#include <array>

#include "blocks/base/input_error.h"
#include "rtl_model/link/hid_transport.h"
#include "rtl_model/link/sampler_link.h"
#include "rtl_model/link/virtual_board.h"
#include "rtl_model/verilator/sampler_rtl_block.h"

namespace texsim {

namespace {

// The sampler under the name the host selects it by: one per material on the virtual board.
class NamedBlock : public link::BoardBlock {
 public:
  NamedBlock(std::unique_ptr<link::BoardBlock> b, std::string name)
      : b_(std::move(b)), name_(std::move(name)) {}
  link::BlockCaps caps() const override {
    link::BlockCaps c = b_->caps();
    c.name = name_;
    return c;
  }
  std::string configure(std::span<const uint8_t> c) override { return b_->configure(c); }
  uint64_t apply(std::span<const uint32_t> in, std::span<uint32_t> out) override {
    return b_->apply(in, out);
  }

 private:
  std::unique_ptr<link::BoardBlock> b_;
  std::string name_;
};

std::string block_name(int k) { return "texsim_sampler:" + std::to_string(k); }

}  // namespace

BoardSampler::BoardSampler(const std::string& link, const UnitArray& units) : link_(link) {
  const TextureUnit& unit = units.unit(0);
  block_of_.assign(static_cast<size_t>(unit.material_count()), -1);
  int blocks = 0;
  for (int m = 0; m < unit.material_count(); ++m) {
    if (!unit.material_fixed(m)) continue;
    block_of_[static_cast<size_t>(m)] = blocks++;
    material_names_.push_back(unit.material(m).name);
  }
  if (blocks == 0) {
    throw InputError("--board " + link,
                     "no material has filter.arithmetic = \"fixed\": nothing "
                     "runs on the board");
  }
  try {
    if (link == "virtual") {
      std::vector<std::unique_ptr<link::BoardBlock>> v;
      v.reserve(static_cast<size_t>(blocks));
      for (int k = 0; k < blocks; ++k)
        v.push_back(std::make_unique<NamedBlock>(link::make_rtl_sampler_block(), block_name(k)));
      transport_ = std::make_unique<link::VirtualBoard>(std::move(v));
    } else if (link == "hid") {
      if (blocks > 1)
        throw InputError("--board hid",
                         "a USB board holds one sampler: give one material "
                         "filter.arithmetic = \"fixed\"");
      transport_ = std::make_unique<link::HidTransport>(link::kDefaultVid, link::kDefaultPid);
    } else {
      throw InputError("--board", "'" + link + "' is not virtual or hid");
    }
    link::LinkOptions opt;
    opt.batch = link::kSamplerWords;
    host_ = std::make_unique<link::LinkHost>(*transport_, opt);
    for (int m = 0; m < unit.material_count(); ++m) {
      if (block_of_[static_cast<size_t>(m)] < 0) continue;
      select(m);
      const Texture& tex = unit.texture_of(m);
      const MaterialSetup& s = unit.material(m);
      const FixedSampler::TextureDesc desc = FixedSampler::describe(tex);
      const std::vector<uint32_t> image = FixedSampler::memory_image(tex);
      for (std::vector<uint8_t>& c :
           link::sampler_configuration(FixedSampler::config_of(s.filter, s.lod), desc, image))
        host_->configure(std::move(c));
    }
  } catch (const link::LinkError& e) {
    throw InputError("--board " + link, e.what());
  }
}

BoardSampler::~BoardSampler() = default;

void BoardSampler::select(int material) {
  if (selected_ == material) return;
  const int k = block_of_[static_cast<size_t>(material)];
  host_->select(link_ == "virtual" ? block_name(k) : std::string("texsim_sampler"));
  selected_ = material;
}

FixedSampler::Result BoardSampler::sample(int material, const FixedSampler::Input& in) {
  try {
    select(material);
    std::array<uint32_t, link::kSamplerWords> w{};
    link::encode_fragment(in, w);
    const std::vector<uint32_t> back = host_->stream(w);
    ++fragments_;
    return link::decode_result(
        std::span<const uint32_t, link::kSamplerWords>(back.data(), link::kSamplerWords));
  } catch (const link::LinkError& e) {
    throw InputError("--board " + link_, e.what());
  }
}

}  // namespace texsim
