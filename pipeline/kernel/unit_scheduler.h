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
#include <algorithm>
#include <cstdint>
#include <queue>
#include <utility>
#include <vector>

namespace texsim {

template <class Item, class Unit>
class UnitScheduler {
 public:
  // Unit: `uint64_t begin(int unit, Item&)`, `void commit(int unit, Item&)`.
  UnitScheduler(int units, Unit& hooks, size_t window) : hooks_(hooks), window_(window) {
    units_.resize(static_cast<size_t>(units));
  }
  // The next item of unit u (items of one unit in their order).
  void add(int u, Item item) {
    Lane& l = units_[static_cast<size_t>(u)];
    l.queue.push_back(std::move(item));
    ++waiting_;
    if (!l.begun) begin_next(u);
    drain(false);
  }
  // No more items: commit everything in cycle order.
  void finish() { drain(true); }
  uint64_t forced_commits() const { return forced_; }
  uint64_t late_items() const { return late_; }
  uint64_t committed() const { return committed_; }
  // The cycle of the latest commit: commits never go back in time unless forced.
  uint64_t last_commit_cycle() const { return last_cycle_; }

 private:
  // A unit's waiting items: a ring of a power-of-two size that grows when full (a deque
  // allocated and freed a block every few items).
  class Ring {
   public:
    bool empty() const { return head_ == tail_; }
    Item& front() { return items_[head_ & mask_]; }
    void pop_front() { ++head_; }
    void push_back(Item&& it) {
      if (tail_ - head_ == items_.size()) grow();
      items_[tail_++ & mask_] = std::move(it);
    }

   private:
    void grow() {
      std::vector<Item> bigger(std::max<size_t>(16, items_.size() * 2));
      for (size_t i = head_; i != tail_; ++i) bigger[i - head_] = std::move(items_[i & mask_]);
      tail_ -= head_;
      head_ = 0;
      items_ = std::move(bigger);
      mask_ = items_.size() - 1;
    }
    std::vector<Item> items_;
    size_t head_ = 0, tail_ = 0, mask_ = 0;
  };
  struct Lane {
    Ring queue;  // front: the begun item, when begun
    bool begun = false;
    uint64_t start = 0;  // begun item's cycle at the memory stage
  };
  struct Key {
    uint64_t start;
    int unit;
    bool operator>(const Key& o) const {
      return start != o.start ? start > o.start : unit > o.unit;
    }
  };
  void begin_next(int u) {
    Lane& l = units_[static_cast<size_t>(u)];
    if (l.queue.empty()) return;
    l.start = hooks_.begin(u, l.queue.front());
    l.begun = true;
    if (committed_ > 0 && l.start < last_cycle_) ++late_;
    ready_.push({l.start, u});
  }
  void drain(bool all) {
    for (;;) {
      if (ready_.empty()) return;
      const bool exact = all || ready_.size() == units_.size();
      if (!exact && waiting_ <= window_) return;
      const Key k = ready_.top();
      ready_.pop();
      if (!exact) ++forced_;
      Lane& l = units_[static_cast<size_t>(k.unit)];
      hooks_.commit(k.unit, l.queue.front());
      l.queue.pop_front();
      l.begun = false;
      --waiting_;
      ++committed_;
      last_cycle_ = k.start;
      begin_next(k.unit);
    }
  }

  Unit& hooks_;
  size_t window_;
  std::vector<Lane> units_;
  std::priority_queue<Key, std::vector<Key>, std::greater<Key>> ready_;
  size_t waiting_ = 0;
  uint64_t forced_ = 0, late_ = 0, committed_ = 0, last_cycle_ = 0;
};

}  // namespace texsim
