#pragma once
// How `texsim run` hands fragments to the texture units (pipeline/app/run.cc): one unit in
// batches for its batched datapath, or several units (each fragment to its tile's unit);
// through quads when [pipeline] derivatives come from quad differences; an object-space
// material's pixels take their resolved colours in arrival order.
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include "blocks/base/fragment.h"
#include "pipeline/app/run_object_space.h"
#include "pipeline/texture/pipeline_setup.h"
#include "pipeline/texture/quad_assembler.h"
#include "pipeline/texture/unit_array.h"

namespace texsim {

// Fragments of one material gathered for the texture unit's batched datapath
// (TextureUnit::process_batch: the same colours, counts and cycles as one by one), then passed
// on in arrival order. A batch of one processes each fragment as it comes.
class UnitBatch {
 public:
  UnitBatch(TextureUnit& unit, size_t size) : unit_(unit), size_(size) {}
  // The unit filters u (g, or g with derivatives from its quad); record gets f and g.
  template <class Record>
  void add(const Fragment& f, const Fragment& g, const Fragment& u, int material, uint64_t index,
           Record& record) {
    if (size_ <= 1) {
      const Rgba c = unit_.process(u, material);
      record(f, g, material, &c, index);
      return;
    }
    if (!g_.empty() && material != material_) flush(record);
    material_ = material;
    f_.push_back(f);
    g_.push_back(g);
    u_.push_back(u);
    index_.push_back(index);
    if (g_.size() == size_) flush(record);
  }
  template <class Record>
  void flush(Record& record) {
    out_.resize(g_.size());
    unit_.process_batch(u_.data(), u_.size(), material_, out_.data());
    for (size_t i = 0; i < g_.size(); ++i) record(f_[i], g_[i], material_, &out_[i], index_[i]);
    f_.clear();
    g_.clear();
    u_.clear();
    index_.clear();
  }

 private:
  TextureUnit& unit_;
  size_t size_;
  int material_ = 0;
  std::vector<Fragment> f_, g_, u_;
  std::vector<uint64_t> index_;
  std::vector<Rgba> out_;
};

// [pipeline] derivatives = "coarse" | "fine": fragments grouped into quads (QuadAssembler's
// rule) go on, in arrival order, once their quad is complete, with derivatives from the quad's
// differences for the unit; the ground truth keeps each fragment's own.
class QuadFeed {
 public:
  explicit QuadFeed(QuadDerivatives mode) : quads_(mode) {}
  // send(f, g, u, material, index), u: g with the quad's derivatives.
  template <class Send>
  void add(const Fragment& f, const Fragment& g, int material, uint64_t index, Send&& send) {
    if (const Quad* q = quads_.push(g)) release(*q, send);
    open_.push_back({f, g, material, index});
  }
  template <class Send>
  void flush(Send&& send) {
    if (const Quad* q = quads_.flush()) release(*q, send);
  }
  const QuadCounts& counts() const { return quads_.counts(); }

 private:
  struct Entry {
    Fragment f, g;
    int material;
    uint64_t index;
  };
  template <class Send>
  void release(const Quad& q, Send& send) {
    for (const Entry& e : open_)
      send(e.f, e.g, q.lane[static_cast<size_t>((e.g.x & 1) | (e.g.y & 1) << 1)], e.material,
           e.index);
    open_.clear();
  }
  QuadAssembler quads_;
  std::vector<Entry> open_;
};

// Fragments on their way to the texture units: one unit (batched), or several (each to the
// unit of its tile); through their quads when [pipeline] derivatives come from quads; an
// object-space material's pixel takes its resolved colour, after every earlier fragment.
class FragmentRouter {
 public:
  FragmentRouter(UnitArray& units, const PipelineSetup& setup, ObjectSpaceFrame& os,
                 UnitArray::Record record, bool one_by_one)
      : units_(units),
        os_(os),
        record_(std::move(record)),
        batch_(units.unit(0), one_by_one ? 1 : LinearBatch::kMax) {
    if (setup.derivatives != QuadDerivatives::Own)
      quads_ = std::make_unique<QuadFeed>(setup.derivatives);
  }
  // QuadFeed's send: to send().
  struct Sender {
    FragmentRouter* r;
    void operator()(const Fragment& a, const Fragment& b, const Fragment& c, int m,
                    uint64_t i) const {
      r->send(a, b, c, m, i);
    }
  };
  Sender sender() { return {this}; }
  // f as given, g with its loaded texture's id.
  void add(const Fragment& f, const Fragment& g, int material, uint64_t index) {
    if (!os_.drawn_by(material)) {
      if (quads_) {
        quads_->add(f, g, material, index, sender());
      } else {
        send(f, g, g, material, index);
      }
      return;
    }
    flush();  // in arrival order
    const Rgba c = os_.shade(material, f.x, f.y);
    record_(f, g, material, &c, index);
  }
  // Everything added so far through the units.
  void flush() {
    if (quads_) quads_->flush(sender());
    batch_.flush(record_);
  }
  const QuadFeed* quads() const { return quads_.get(); }

 private:
  // To the fragment's unit; u is what the unit filters (g, or g with its quad's derivatives).
  void send(const Fragment& f, const Fragment& g, const Fragment& u, int material, uint64_t index) {
    if (units_.several()) {
      units_.add(f, g, u, material, index);
    } else {
      batch_.add(f, g, u, material, index, record_);
    }
  }
  UnitArray& units_;
  ObjectSpaceFrame& os_;
  UnitArray::Record record_;
  UnitBatch batch_;
  std::unique_ptr<QuadFeed> quads_;
};

// A camera path on several units: the units record fragments in their commit order, which may
// reach a frame's last fragments after the next frame's first. The records are passed on frame
// by frame (each frame's in the order they came), as the images and the ground truth take them;
// the simulation itself runs on across frames, untouched.
class FrameOrder {
 public:
  explicit FrameOrder(UnitArray::Record next) : next_(std::move(next)) {}
  // One more fragment of `frame` goes to the units (frames in increasing order), before it can
  // be recorded.
  void emitted(uint32_t frame) {
    // Most fragments continue the newest frame: one increment, nothing can move on.
    if (started_ && frame == newest_) {
      ++*newest_count_;
      return;
    }
    newest_count_ = &emitted_[frame];
    ++*newest_count_;
    newest_ = frame;
    if (!started_) {
      started_ = true;
      current_ = frame;
    }
    advance();
  }
  void record(const Fragment& f, const Fragment& g, int material, const Rgba* colour,
              uint64_t index) {
    if (f.frame != current_) {
      held_[f.frame].push_back(
          {f, g, material, colour != nullptr, colour ? *colour : Rgba{}, index});
      return;
    }
    next_(f, g, material, colour, index);
    ++recorded_;
    advance();
  }
  UnitArray::Record recorder() {
    return [this](const Fragment& f, const Fragment& g, int m, const Rgba* c, uint64_t i) {
      record(f, g, m, c, i);
    };
  }
  // After the units have finished: every record passed on (a defect of the model otherwise).
  void check_drained() const {
    if (!held_.empty()) throw std::logic_error("FrameOrder: records of later frames left held");
  }

 private:
  struct Held {
    Fragment f, g;
    int material;
    bool has_colour;
    Rgba colour;
    uint64_t index;
  };
  // While the current frame is complete and a later one has begun: move on, and pass the
  // later frame's held records.
  void advance() {
    for (;;) {
      const auto next = emitted_.upper_bound(current_);
      if (next == emitted_.end() || recorded_ < emitted_[current_]) return;
      current_ = next->first;
      recorded_ = 0;
      emitted_.erase(emitted_.begin(), next);
      const auto it = held_.find(current_);
      if (it == held_.end()) continue;
      const std::vector<Held> held = std::move(it->second);
      held_.erase(it);
      for (const Held& h : held) {
        next_(h.f, h.g, h.material, h.has_colour ? &h.colour : nullptr, h.index);
        ++recorded_;
      }
    }
  }
  UnitArray::Record next_;
  std::map<uint32_t, uint64_t> emitted_;  // fragments sent to the units, by frame
  std::map<uint32_t, std::vector<Held>> held_;
  uint32_t current_ = 0;
  uint32_t newest_ = 0;               // the frame emitted last, and its count in emitted_
  uint64_t* newest_count_ = nullptr;  // (map nodes never move; advance() never erases it)
  uint64_t recorded_ = 0;             // of the current frame
  bool started_ = false;
};

}  // namespace texsim
