#include "pipeline/app/board_sampler.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <stdexcept>

#include "blocks/base/input_error.h"
#include "rtl_model/link/hid_transport.h"
#include "rtl_model/link/lerp_link.h"
#include "rtl_model/link/sampler_link.h"
#include "rtl_model/link/virtual_board.h"
#include "rtl_model/verilator/lerp_rtl_block.h"
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

constexpr int kLerpSelected = -2;       // selected_: the board's bilinear_lerp
constexpr size_t kLerpsPerCall = 4000;  // lerps gathered before they are streamed

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
  cpp_.resize(static_cast<size_t>(unit.material_count()));
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
      v.push_back(link::make_rtl_lerp_block());
      lerp_ = true;
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
      Cpp& cpp = cpp_[static_cast<size_t>(m)];
      cpp.fs = std::make_unique<FixedSampler>(FixedSampler::config_of(s.filter, s.lod));
      cpp.desc = FixedSampler::describe(tex);
      cpp.image = FixedSampler::memory_image(tex);
      for (std::vector<uint8_t>& c :
           link::sampler_configuration(cpp.fs->config(), cpp.desc, cpp.image))
        host_->configure(std::move(c));
    }
    if (lerp_) {
      host_->select("bilinear_lerp");
      selected_ = kLerpSelected;
      host_->configure(link::lerp_configuration({8, TexelAddressGen::Config{}.sub_texel_bits}));
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
    check_lerps(material, std::span<const FixedSampler::Input>(&in, 1));
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
    check_lerps(material, in);
  } catch (const link::LinkError& e) {
    throw InputError("--board " + link_, e.what());
  }
}

std::vector<std::string> BoardSampler::blocks() const {
  if (lerp_) return {"texsim_sampler", "bilinear_lerp"};
  return {"texsim_sampler"};
}

// The fragments' two lerps each (the C++ model's operands) wait for the board's bilinear_lerp.
void BoardSampler::check_lerps(int material, std::span<const FixedSampler::Input> in) {
  if (!lerp_) return;
  const Cpp& cpp = cpp_[static_cast<size_t>(material)];
  const BilinearLerp lerp({8, cpp.fs->config().sub_bits});
  for (const FixedSampler::Input& f : in) {
    std::array<FixedSampler::LerpInput, 2> ops{};
    cpp.fs->sample(f, cpp.desc, cpp.image, &ops);
    for (const FixedSampler::LerpInput& l : ops) {
      link::LerpOperands op;
      for (size_t k = 0; k < 4; ++k) op.quad[k] = static_cast<uint32_t>(l.quad[k]);
      op.fx = l.fx;
      op.fy = l.fy;
      const size_t at = lerp_words_.size();
      lerp_words_.resize(at + link::kLerpWords);
      link::encode_lerp(
          op, std::span<uint32_t, link::kLerpWords>(lerp_words_.data() + at, link::kLerpWords));
      lerp_want_.push_back(static_cast<uint32_t>(lerp.lerp(l.quad, l.fx, l.fy)));
    }
  }
  if (lerp_want_.size() >= kLerpsPerCall) stream_lerps();
}

void BoardSampler::stream_lerps() {
  if (lerp_want_.empty()) return;
  if (selected_ != kLerpSelected) {
    host_->select("bilinear_lerp");
    selected_ = kLerpSelected;
  }
  // The link's STREAMs carry per_stream_ fragments' words: whole lerps in each call, one STREAM.
  const size_t chunk = per_stream_ * link::kSamplerWords / link::kLerpWords * link::kLerpWords;
  std::vector<uint32_t> back;
  back.reserve(lerp_words_.size());
  for (size_t at = 0; at < lerp_words_.size(); at += chunk) {
    const std::vector<uint32_t> part =
        host_->stream(std::span<const uint32_t>(lerp_words_)
                          .subspan(at, std::min(chunk, lerp_words_.size() - at)));
    back.insert(back.end(), part.begin(), part.end());
  }
  for (size_t i = 0; i < lerp_want_.size(); ++i) {
    if (back[i * link::kLerpWords] != lerp_want_[i]) {
      char text[160];
      std::snprintf(text, sizeof text,
                    "--board %s: bilinear_lerp on the board gave 0x%08x for lerp %llu, "
                    "BilinearLerp 0x%08x",
                    link_.c_str(), back[i * link::kLerpWords],
                    static_cast<unsigned long long>(lerps_) + i, lerp_want_[i]);
      throw std::runtime_error(text);
    }
  }
  lerps_ += lerp_want_.size();
  lerp_words_.clear();
  lerp_want_.clear();
}

void BoardSampler::finish() {
  try {
    stream_lerps();
  } catch (const link::LinkError& e) {
    throw InputError("--board " + link_, e.what());
  }
}

}  // namespace texsim
