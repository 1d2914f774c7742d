#pragma once
// Several clocked units on one global clock, sharing memory levels (docs/timing-model.md
// #several-units). Each unit takes its items in order; an item's requests to the shared levels
// are made at the cycle it starts its memory stage, and the shared levels must see requests in
// cycle order for contention to be simulated rather than averaged. The scheduler gets that
// order from per-item timestamps: a unit runs its next item up to the memory stage (`begin`,
// which returns the cycle it starts there), and the item of all units' begun items with the
// earliest such cycle (the lowest unit index on a tie, as a cycle-stepped model that visits
// units in index order) makes its requests and finishes (`commit`). An item is committed only
// when every unit has a begun item or no more items, so the order is exact — unless more than
// `window` items wait (some unit has received none for that long): then the earliest begun item
// is committed anyway (counted: forced_commits), and a later item of an idle unit may then reach
// the shared levels at an earlier cycle than requests already made (counted: late_items, the
// measure of how far the order was from exact; 0 whenever no commit was forced).
//
// Items that make no request to the shared levels need no place in that order. Hooks that say
// so (`bool local(int unit)`, asked after begin) get such an item committed at once, and the
// unit begins its next: only items that reach the shared levels wait for the others. The
// shared levels see the same requests in the same order (the earliest begun of those items
// first, on the same condition), and each unit's items keep their order, so every result is
// the same — while most items (texture look-ups that hit the L1) pass without being held.
//
// Hooks that also say how early a unit's next item can start its memory stage
// (`uint64_t next_start_bound(int unit)`, asked when the unit has nothing begun; a unit's
// stages take items in order, so no later item starts before that cycle) let a begun item be
// committed before every unit has one: when its key is below every other unit's begun key and
// every idle unit's bound, no item can come before it in the cycle order. A unit's bound is
// refreshed only when it holds the least key, so most fragments cost nothing here.
#include <algorithm>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

namespace texsim {

template <class Item, class Unit>
class UnitScheduler {
 public:
  // Unit: `uint64_t begin(int unit, Item&)`, `void commit(int unit, Item&)`.
  UnitScheduler(int units, Unit& hooks, size_t window)
      : hooks_(hooks), window_(window), units_(static_cast<size_t>(units)) {
    while ((size_t{1} << shift_) < units_.size()) ++shift_;
    max_start_ = (~uint64_t{0} >> shift_) - 1;
    // Padded to whole groups of 8 keys (idle), so the scan has no remainder loop.
    key_.assign((units_.size() + 7) / 8 * 8, kIdle);
    for (size_t u = 0; u < units_.size(); ++u) key_[u] = idle_key(u, 0);
  }
  // The next item of unit u (items of one unit in their order).
  void add(int u, Item item) {
    add_with(u, [&](Item& slot) { slot = std::move(item); });
  }
  // The same, with the item written in place by fill(Item&) (no copy of a large item).
  template <class Fill>
  void add_with(int u, Fill&& fill) {
    Lane& l = units_[static_cast<size_t>(u)];
    if constexpr (requires { hooks_.local(u); }) {
      if (!l.begun && l.queue.empty()) {
        // Nothing waits in the unit: the item begins at once from a local copy, and one that
        // stays in its unit is committed without ever being stored (the queue's slots, one
        // unit's of many, are seldom in the host's cache).
        Item item;
        fill(item);
        const uint64_t start = hooks_.begin(u, item);
        if (hooks_.local(u)) {
          hooks_.commit(u, item);
          count_local(u);
          return;
        }
        add_begun(
            u, [&](Item& slot) { slot = std::move(item); }, start);
        return;
      }
    }
    fill(l.queue.push_slot());
    ++waiting_;
    if (!l.begun) {
      begin_next(u);
      // Nothing can be committed until every unit has begun an item (or the window is full).
      if (!kBound && begun_ < units_.size() && waiting_ <= window_) return;
    } else if (waiting_ <= window_) {
      return;  // the begun items did not change
    }
    drain(false);
  }
  // Asks for the slot unit u's next item would be written to (add_with) in the cache, so that
  // the write does not wait for the line: called before the work that makes the item.
  void prefetch_slot(int u) const { units_[static_cast<size_t>(u)].queue.prefetch_tail(); }
  // Whether unit u has nothing begun and nothing waiting: an item of it may begin at once.
  bool idle(int u) const {
    const Lane& l = units_[static_cast<size_t>(u)];
    return !l.begun && l.queue.empty();
  }
  // An item of idle unit u that the caller began and committed itself (it stayed in its unit:
  // Unit::local), without handing it over. Its bound moved on: if it was what held the earliest
  // begun item back, that item may be committed now.
  void count_local(int u) {
    ++committed_;
    ++local_;
    if constexpr (kBound) {
      if (static_cast<size_t>(u) == blocker_ && begun_ > 0) drain(false);
    }
  }
  // An item of an idle unit that the caller began (its memory stage starts at `start`) and that
  // did not stay in its unit: it waits, begun, for its turn.
  template <class Fill>
  void add_begun(int u, Fill&& fill, uint64_t start) {
    fill(units_[static_cast<size_t>(u)].queue.push_slot());
    ++waiting_;
    mark_begun(u, start);
    if (!kBound && begun_ < units_.size() && waiting_ <= window_) return;
    drain(false);
  }
  // No more items: commit everything in cycle order.
  void finish() {
    finished_ = true;
    for (size_t u = 0; u < units_.size(); ++u) {
      if (!units_[u].begun) key_[u] = kIdle;
    }
    drain(true);
  }
  uint64_t forced_commits() const { return forced_; }
  uint64_t late_items() const { return late_; }
  uint64_t committed() const { return committed_; }
  // Items committed at once because they stayed in their unit (Unit::local).
  uint64_t local_commits() const { return local_; }
  // The cycle of the latest commit: commits never go back in time unless forced.
  uint64_t last_commit_cycle() const { return last_cycle_; }

 private:
  // A unit's waiting items, in blocks of kBlock (a run may hold every item until its end, so
  // growing never moves the items held); emptied blocks are reused.
  class Ring {
   public:
    bool empty() const { return head_ == tail_; }
    Item& front() { return blocks_[head_ / kBlock][head_ % kBlock]; }
    // Asks for the item k after the front in the cache (held items are read long after they
    // were written).
    void prefetch(size_t k) const {
      const size_t i = head_ + k;
      if (i >= tail_) return;
      const char* p = reinterpret_cast<const char*>(&blocks_[i / kBlock][i % kBlock]);
      for (size_t b = 0; b < sizeof(Item); b += 64) __builtin_prefetch(p + b);
    }
    // Asks for the slot push_slot() gives next in the cache, for writing (a unit's slots are
    // written a few at a time, long after its previous ones left the cache).
    void prefetch_tail() const {
      if (tail_ < blocks_.size() * kBlock)
        __builtin_prefetch(&blocks_[tail_ / kBlock][tail_ % kBlock], 1);
    }
    void pop_front() {
      if (++head_ % kBlock == 0) {
        // The first block is spent: move it to the back for reuse.
        std::rotate(blocks_.begin(), blocks_.begin() + 1, blocks_.end());
        head_ -= kBlock;
        tail_ -= kBlock;
      }
    }
    // The slot of a new last item.
    Item& push_slot() {
      if (tail_ == blocks_.size() * kBlock) blocks_.push_back(std::make_unique<Item[]>(kBlock));
      Item& it = blocks_[tail_ / kBlock][tail_ % kBlock];
      ++tail_;
      return it;
    }

   private:
    static constexpr size_t kBlock = 512;
    std::vector<std::unique_ptr<Item[]>> blocks_;
    size_t head_ = 0, tail_ = 0;
  };
  struct Lane {
    Ring queue;  // front: the begun item, when begun
    bool begun = false;
  };
  static constexpr uint64_t kIdle = ~uint64_t{0};  // key of a unit without a begun item
  static constexpr bool kBound = requires(Unit & h) { h.next_start_bound(0); };
  // The key of unit u with nothing begun: its next item's least possible key (with a bound),
  // else one above every begun key.
  uint64_t idle_key(size_t u, uint64_t bound) const {
    if (!kBound || finished_) return kIdle;
    return std::min(bound, max_start_) << shift_ | static_cast<uint64_t>(u);
  }
  uint64_t bound_key(size_t u) {
    if constexpr (kBound) {
      return idle_key(u, hooks_.next_start_bound(static_cast<int>(u)));
    } else {
      return kIdle;
    }
  }
  // The least key of a unit with a begun item (begun_ > 0).
  uint64_t least_begun_key() const {
    uint64_t m = kIdle;
    for (size_t u = 0; u < units_.size(); ++u) {
      if (units_[u].begun) m = std::min(m, key_[u]);
    }
    return m;
  }
  // The earliest begun item: the least key, (start << shift_) | unit, so the lower unit index
  // wins a tie. A scan: at most 64 units (PipelineSetup::kMaxUnits).
  uint64_t least_key() const {
    uint64_t m[8] = {kIdle, kIdle, kIdle, kIdle, kIdle, kIdle, kIdle, kIdle};
    for (size_t i = 0; i < key_.size(); i += 8) {
      for (size_t j = 0; j < 8; ++j) m[j] = std::min(m[j], key_[i + j]);
    }
    for (size_t j = 1; j < 8; ++j) m[0] = std::min(m[0], m[j]);
    return m[0];
  }
  void begin_next(int u) {
    Lane& l = units_[static_cast<size_t>(u)];
    uint64_t start = 0;
    for (;;) {
      if (l.queue.empty()) {
        key_[static_cast<size_t>(u)] = bound_key(static_cast<size_t>(u));
        return;
      }
      l.queue.prefetch(2);
      start = hooks_.begin(u, l.queue.front());
      if constexpr (requires { hooks_.local(u); }) {
        if (hooks_.local(u)) {  // stays in the unit: committed now, out of the global order
          hooks_.commit(u, l.queue.front());
          l.queue.pop_front();
          --waiting_;
          ++committed_;
          ++local_;
          continue;
        }
      }
      break;
    }
    mark_begun(u, start);
  }
  // Unit u's front item has begun and starts its memory stage at `start`.
  void mark_begun(int u, uint64_t start) {
    units_[static_cast<size_t>(u)].begun = true;
    ++begun_;
    if (committed_ > 0 && start < last_cycle_) ++late_;
    if (start > max_start_) throw std::overflow_error("UnitScheduler: cycle out of range");
    key_[static_cast<size_t>(u)] = start << shift_ | static_cast<uint64_t>(u);
  }
  void drain(bool all) {
    const uint64_t unit_mask = (uint64_t{1} << shift_) - 1;
    while (begun_ > 0) {
      uint64_t key = least_key();
      size_t u = key & unit_mask;
      // Without bounds, idle units' keys are kIdle: the least key is exact once all have begun.
      bool exact = all || (kBound ? units_[u].begun : begun_ == units_.size());
      if (!exact && kBound) {
        // An idle unit holds the least key: its bound may have moved on since it was set.
        const uint64_t fresh = bound_key(u);
        if (fresh != key_[u]) {
          key_[u] = fresh;
          continue;
        }
        blocker_ = u;
      }
      if (!exact) {
        if (waiting_ <= window_) return;
        if constexpr (kBound) key = least_begun_key();
        u = key & unit_mask;
        ++forced_;
      }
      Lane& l = units_[u];
      hooks_.commit(static_cast<int>(u), l.queue.front());
      l.queue.pop_front();
      l.begun = false;
      --begun_;
      key_[u] = kIdle;  // set by begin_next
      --waiting_;
      ++committed_;
      last_cycle_ = key >> shift_;
      begin_next(static_cast<int>(u));
    }
  }

  Unit& hooks_;
  size_t window_;
  std::vector<Lane> units_;
  // By unit: its begun item's key (least_key), or kIdle.
  std::vector<uint64_t> key_;
  int shift_ = 0;           // bits of a unit index
  uint64_t max_start_ = 0;  // the latest cycle a key holds
  size_t begun_ = 0;
  size_t waiting_ = 0;
  size_t blocker_ = 0;  // the idle unit whose bound last held the least key
  bool finished_ = false;
  uint64_t forced_ = 0, late_ = 0, committed_ = 0, local_ = 0, last_cycle_ = 0;
};

}  // namespace texsim
