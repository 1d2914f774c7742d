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
#include <memory>
#include <utility>
#include <vector>

namespace texsim {

template <class Item, class Unit>
class UnitScheduler {
 public:
  // Unit: `uint64_t begin(int unit, Item&)`, `void commit(int unit, Item&)`.
  UnitScheduler(int units, Unit& hooks, size_t window)
      : hooks_(hooks), window_(window), units_(static_cast<size_t>(units)) {
    size_t leaves = 1;
    while (leaves < units_.size()) leaves *= 2;
    leaves_ = leaves;
    key_.assign(leaves, kIdle);
    tree_.assign(2 * leaves, 0);
    for (size_t i = 0; i < leaves; ++i) tree_[leaves + i] = static_cast<uint32_t>(i);
    for (size_t i = leaves - 1; i >= 1; --i) tree_[i] = winner(tree_[2 * i], tree_[2 * i + 1]);
  }
  // The next item of unit u (items of one unit in their order).
  void add(int u, Item item) {
    add_with(u, [&](Item& slot) { slot = std::move(item); });
  }
  // The same, with the item written in place by fill(Item&) (no copy of a large item).
  template <class Fill>
  void add_with(int u, Fill&& fill) {
    Lane& l = units_[static_cast<size_t>(u)];
    fill(l.queue.push_slot());
    ++waiting_;
    if (!l.begun) {
      begin_next(u);
      // Nothing can be committed until every unit has begun an item (or the window is full).
      if (begun_ < units_.size() && waiting_ <= window_) return;
    } else if (waiting_ <= window_) {
      return;  // the begun items did not change
    }
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
  // A unit's waiting items, in blocks of kBlock (a run may hold every item until its end, so
  // growing never moves the items held); emptied blocks are reused.
  class Ring {
   public:
    bool empty() const { return head_ == tail_; }
    Item& front() { return blocks_[head_ / kBlock][head_ % kBlock]; }
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
  // The earlier of units a and b by their begun items' cycles (the lower index on a tie).
  uint32_t winner(uint32_t a, uint32_t b) const {
    return key_[b] < key_[a] || (key_[b] == key_[a] && b < a) ? b : a;
  }
  // Unit u's key changed: replay its matches up the tree (the root holds the earliest).
  void update(size_t u) {
    for (size_t i = (leaves_ + u) / 2; i >= 1; i /= 2)
      tree_[i] = winner(tree_[2 * i], tree_[2 * i + 1]);
  }
  void begin_next(int u) {
    Lane& l = units_[static_cast<size_t>(u)];
    if (l.queue.empty()) return;
    const uint64_t start = hooks_.begin(u, l.queue.front());
    l.begun = true;
    ++begun_;
    if (committed_ > 0 && start < last_cycle_) ++late_;
    key_[static_cast<size_t>(u)] = start;
    update(static_cast<size_t>(u));
  }
  void drain(bool all) {
    while (begun_ > 0) {
      const bool exact = all || begun_ == units_.size();
      if (!exact && waiting_ <= window_) return;
      const uint32_t u = tree_[1];
      if (!exact) ++forced_;
      Lane& l = units_[u];
      const uint64_t start = key_[u];
      hooks_.commit(static_cast<int>(u), l.queue.front());
      l.queue.pop_front();
      l.begun = false;
      --begun_;
      key_[u] = kIdle;
      --waiting_;
      ++committed_;
      last_cycle_ = start;
      begin_next(static_cast<int>(u));
      if (!units_[u].begun) update(u);
    }
  }

  Unit& hooks_;
  size_t window_;
  std::vector<Lane> units_;
  // A tournament tree over the units' begun items: key_ by unit (kIdle: none begun), tree_[i]
  // the winner of node i (leaves at leaves_ + u), so the earliest item is tree_[1].
  size_t leaves_ = 1;
  std::vector<uint64_t> key_;
  std::vector<uint32_t> tree_;
  size_t begun_ = 0;
  size_t waiting_ = 0;
  uint64_t forced_ = 0, late_ = 0, committed_ = 0, last_cycle_ = 0;
};

}  // namespace texsim
