#pragma once
// A pass-through in front of a memory level: forwards every line request and shows it (the
// cycle it was made, the cycle its data arrived, the unit) to an observer — the timeline's
// memory tracks (`texsim run --timeline`). Without an observer it only forwards; the timing is
// the level's own either way.
#include <cstdint>
#include <functional>
#include <utility>

#include "blocks/texture/memory/line_memory.h"

namespace texsim {

class LevelProbe final : public LineMemory {
 public:
  using Observer = std::function<void(uint64_t now, uint64_t ready, int unit)>;
  explicit LevelProbe(LineMemory* next = nullptr) : next_(next) {}
  void set_next(LineMemory* next) { next_ = next; }
  void set_observer(Observer o) { observer_ = std::move(o); }
  uint64_t read_line(uint64_t now, uint64_t addr, uint32_t bytes, int unit) override {
    const uint64_t ready = next_->read_line(now, addr, bytes, unit);
    if (observer_) observer_(now, ready, unit);
    return ready;
  }

 private:
  LineMemory* next_;
  Observer observer_;
};

}  // namespace texsim
