#pragma once
// `texsim run --board virtual|hid`: the fixed-arithmetic materials' fragments go over the link
// (rtl_model/link/, the sampler's messages in sampler_link.h) to a board that runs the RTL
// sampler, and its results colour the pixels. The virtual board runs the Verilated sampler in
// process, one block per fixed material (each holds its texture's memory image, loaded once in
// CONFIGURE chunks); `hid` opens a USB board and fails cleanly when none is attached.
// The virtual board also holds the bilinear lerp's RTL: every sampled fragment's two lerps (the
// texels FixedSampler reads and its weights, from the C++ model) are streamed through it and
// each result checked against BilinearLerp; a difference ends the run (finish()).
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "pipeline/texture/unit_array.h"
#include "rtl_model/link/link_host.h"

namespace texsim {

class BoardSampler : public FixedSamplerBoard {
 public:
  // Opens the link, selects and configures the board's sampler for every fixed material of
  // `units`. Throws InputError (naming --board) when the board cannot be reached or refuses.
  BoardSampler(const std::string& link, const UnitArray& units);
  ~BoardSampler() override;
  FixedSampler::Result sample(int material, const FixedSampler::Input& in) override;
  // Packs the fragments into STREAMs of fragments_per_stream() each, all sent in one call
  // (the link keeps several in flight); results in order.
  void sample_batch(int material, std::span<const FixedSampler::Input> in,
                    std::span<FixedSampler::Result> out) override;

  const std::string& link() const { return link_; }
  // The blocks that ran on the board ("texsim_sampler", and "bilinear_lerp" on the virtual
  // board), and the fragments it sampled.
  std::vector<std::string> blocks() const;
  uint64_t fragments() const { return fragments_; }
  // Lerps through the board's bilinear_lerp, each equal to BilinearLerp (0 over hid).
  uint64_t lerps() const { return lerps_; }
  // Streams the lerps still waiting; throws std::runtime_error naming the first lerp whose
  // result differs from the C++ model's.
  void finish();
  // STREAM messages sent for them (one round trip each, several in flight).
  uint64_t streams() const { return streams_; }
  size_t fragments_per_stream() const { return per_stream_; }
  const std::vector<std::string>& materials() const { return material_names_; }

 private:
  void select(int material);
  void check_lerps(int material, std::span<const FixedSampler::Input> in);
  void stream_lerps();
  // Per fixed material: the C++ sampler and its texture, for the lerps' operands.
  struct Cpp {
    std::unique_ptr<FixedSampler> fs;
    FixedSampler::TextureDesc desc;
    std::vector<uint32_t> image;
  };
  std::vector<Cpp> cpp_;
  bool lerp_ = false;
  std::vector<uint32_t> lerp_words_, lerp_want_;
  uint64_t lerps_ = 0;
  std::string link_;
  std::unique_ptr<link::Transport> transport_;
  std::unique_ptr<link::LinkHost> host_;
  std::vector<int> block_of_;  // per material: its block on the virtual board (-1: none)
  std::vector<std::string> material_names_;
  int selected_ = -1;
  uint64_t fragments_ = 0;
  uint64_t streams_ = 0;
  size_t per_stream_ = 1;
};

namespace board {
// Fragments per STREAM: as many as a message carries (at most kMaxStreamVectors words and the
// payload limit), and no more than makes a response of at most `max_reports` HID reports.
size_t fragments_per_stream(size_t max_payload, size_t max_reports);
}  // namespace board

}  // namespace texsim
