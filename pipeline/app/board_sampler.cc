#include "pipeline/app/board_sampler.h"

#include <algorithm>
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

// HID reports of a message with `payload` bytes (framing.h: INIT, then CONTs, CRC at the end).
size_t reports_of(size_t payload) {
  const size_t bytes = payload + link::kCrcSize;
  return bytes <= link::kInitData
             ? 1
             : 1 + (bytes - link::kInitData + link::kContData - 1) / link::kContData;
}

// Over USB, hidraw queues at most 64 input reports per device: two responses in flight must fit.
constexpr int kHidWindow = 2;
constexpr size_t kHidQueue = 64;

}  // namespace

namespace board {
size_t fragments_per_stream(size_t max_payload, size_t max_reports) {
  const size_t payload = std::min(max_payload, link::kMaxPayload);
  size_t k = 1;
  for (;;) {
    const size_t next = (k + 1) * link::kSamplerWords;
    // The response: status byte, index and count, the results.
    if (next > link::kMaxStreamVectors || link::kStreamHeader + 4 * next > payload ||
        reports_of(1 + link::kStreamHeader + 4 * next) > max_reports)
      return k;
    ++k;
  }
}
}  // namespace board

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
    if (link == "hid") opt.window = kHidWindow;
    const size_t max_reports = link == "hid" ? kHidQueue / kHidWindow : link::kMaxReportsPerMessage;
    per_stream_ = board::fragments_per_stream(link::kMaxPayload, max_reports);
    opt.batch = static_cast<uint16_t>(per_stream_ * link::kSamplerWords);
    host_ = std::make_unique<link::LinkHost>(*transport_, opt);
    // A board that takes smaller messages: fewer fragments per STREAM, never a split fragment.
    const size_t fit = board::fragments_per_stream(host_->capabilities().max_payload, max_reports);
    if (fit < per_stream_) {
      per_stream_ = fit;
      opt.batch = static_cast<uint16_t>(per_stream_ * link::kSamplerWords);
      host_ = std::make_unique<link::LinkHost>(*transport_, opt);
    }
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
    ++streams_;
    return link::decode_result(
        std::span<const uint32_t, link::kSamplerWords>(back.data(), link::kSamplerWords));
  } catch (const link::LinkError& e) {
    throw InputError("--board " + link_, e.what());
  }
}

void BoardSampler::sample_batch(int material, std::span<const FixedSampler::Input> in,
                                std::span<FixedSampler::Result> out) {
  if (in.empty()) return;
  try {
    select(material);
    std::vector<uint32_t> w(in.size() * link::kSamplerWords);
    for (size_t i = 0; i < in.size(); ++i)
      link::encode_fragment(in[i], std::span<uint32_t, link::kSamplerWords>(
                                       w.data() + i * link::kSamplerWords, link::kSamplerWords));
    const std::vector<uint32_t> back = host_->stream(w);
    for (size_t i = 0; i < in.size(); ++i) {
      out[i] = link::decode_result(std::span<const uint32_t, link::kSamplerWords>(
          back.data() + i * link::kSamplerWords, link::kSamplerWords));
    }
    fragments_ += in.size();
    streams_ += (in.size() + per_stream_ - 1) / per_stream_;
  } catch (const link::LinkError& e) {
    throw InputError("--board " + link_, e.what());
  }
}

}  // namespace texsim
