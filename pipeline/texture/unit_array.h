#pragma once
// The texture units of a run: one (today's unit, with its own L1 and DRAM) or several, each
// with its own clocked pipeline and L1, sharing the levels behind the L1s. Fragments go to the
// unit of their screen tile (PipelineSetup::unit_of_pixel); the units run on one global clock
// (UnitScheduler orders their requests to the shared levels by cycle). Reports read the totals
// from here. docs/timing-model.md#several-units.
#include <array>
#include <deque>
#include <functional>
#include <memory>
#include <vector>

#include "pipeline/kernel/unit_scheduler.h"
#include "pipeline/texture/memory_system.h"
#include "pipeline/texture/texture_unit.h"

namespace texsim {

class UnitArray {
 public:
  // Called once per fragment with its colour, when its unit has filtered it (for several
  // units, later than add() and not in the order of add() across units; in order per unit).
  using Record = std::function<void(const Fragment& f, const Fragment& g, int material,
                                    const Rgba* colour, uint64_t index)>;
  // Fragments a scheduler may hold before it commits out of cycle order (see UnitScheduler).
  static constexpr size_t kWindow = size_t{1} << 18;

  // Several units only when timed and setup.units > 1; otherwise one unit as today. Without
  // quad merging a unit filters each fragment as it comes and only its timing waits for its
  // turn (TextureUnit::Timing); `whole_fragments` holds each waiting fragment whole instead,
  // as with quad merging (the same figures; for tests).
  UnitArray(TextureSet& textures, const std::vector<MaterialSetup>& materials,
            const PipelineSetup& setup, const TechTable& tech, bool timing, size_t window = kWindow,
            bool whole_fragments = false);
  UnitArray(const UnitArray&) = delete;
  UnitArray& operator=(const UnitArray&) = delete;
  ~UnitArray();

  int units() const { return static_cast<int>(units_.size()); }
  TextureUnit& unit(int u) { return *units_[static_cast<size_t>(u)]; }
  const TextureUnit& unit(int u) const { return *units_[static_cast<size_t>(u)]; }
  bool several() const { return units_.size() > 1; }
  void set_surfaces(const std::vector<SurfaceFrame>& frames);

  // Several units: fragment g (f as given) of `material` to the unit of its pixel; `record`
  // gets its colour. finish() drains the units (call once, after the last fragment).
  // Several units: what gets each fragment's colour (set before the first add()).
  void set_record(Record record) { record_ = std::move(record); }
  // The unit filters u (g, or g with its quad's derivatives); the record gets f and g. `front`:
  // the fragment's front-end costs (material's front_count of them), or null.
  void add(const Fragment& f, const Fragment& g, const Fragment& u, int material, uint64_t index,
           const ItemCost* front = nullptr);
  // A fragment the coordinate front end generated that leaves after it, at pixel (x, y) (x < 0:
  // off the image, charged to unit 0): its unit takes it before its next fragment.
  void drop(int material, const ItemCost* front, bool rejected, int32_t x, int32_t y);
  void finish();
  // Several units: called after each fragment's last stage with its unit (for --timeline).
  void set_commit_observer(std::function<void(int unit, const ClockedPipeline& pipe)> f) {
    observer_ = std::move(f);
    for (auto& u : units_) u->set_early_commit(!observer_);
  }

  // Totals over the units (with one unit, that unit's figures).
  bool timing() const { return units_[0]->timing(); }
  uint64_t fragments() const;
  uint64_t cycles() const;  // the last unit's
  std::vector<BlockUse> blocks() const;
  std::vector<BlockUse> material_blocks(int m) const;
  uint64_t material_fragments(int m) const;
  TextureUnit::OpTallies material_op_tallies(int m) const;
  uint64_t quad_merged_lookups() const;
  uint64_t material_relief_steps(int m) const;
  uint64_t material_relief_fetches(int m) const;
  bool material_has_relief(int m) const { return units_[0]->material_has_relief(m); }
  const MaterialSetup& material(int m) const { return units_[0]->material(m); }
  void set_fixed_board(FixedSamplerBoard* board) {
    for (auto& u : units_) u->set_fixed_board(board);
  }
  int material_count() const { return units_[0]->material_count(); }
  // Fragments summed, cycles the last unit's (refreshed by each call).
  const std::vector<FrameStats>& frames() const;
  TextureCache::Stats l1_totals() const { return memory().l1_totals(); }
  const TextureCache::Config& l1_config() const { return units_[0]->cache().config(); }
  const MemorySystem& memory() const { return units_[0]->memory(); }
  const TextureSet& textures() const { return units_[0]->textures(); }
  const PipelineSetup& setup() const { return setup_; }
  MemorySystem& memory() { return units_[0]->memory(); }
  // Stage s's counters summed over the units (each unit has the same stages).
  StageStats stage_totals(int s) const;
  // Stage s's busy issue slots ÷ (the run's cycles × lanes × units).
  double utilisation(int s) const;
  int front_stages() const { return units_[0]->front_stages(); }
  const FrontEndStats& front_end_stats() const;  // summed over the units
  // The scheduler's figures: commits made before every unit had an item (window full) and
  // items that reached the shared levels later than a request of a later cycle.
  uint64_t forced_commits() const {
    return timed_ ? timed_->forced_commits() : sched_ ? sched_->forced_commits() : 0;
  }
  uint64_t late_items() const {
    return timed_ ? timed_->late_items() : sched_ ? sched_->late_items() : 0;
  }
  // Fragments committed at once, without waiting for the other units: their look-ups all hit
  // their unit's L1 (none with a timeline, which records items in the global order).
  uint64_t local_commits() const {
    return timed_ ? timed_->local_commits() : sched_ ? sched_->local_commits() : 0;
  }
  // Every unit's invariants, and the shared DRAM's busy cycles within the run's.
  void check_timing_invariants() const;

 private:
  struct Drop {
    int material;
    std::array<ItemCost, 2> front;
    bool rejected;
  };
  // A fragment waiting for its unit (a run may hold every fragment until its end, so kept
  // small): g is f with the loaded texture's id (g_tex); what most fragments lack waits in
  // its unit's side queues (Lane), taken in the same order.
  struct Item {
    Fragment f;
    uint64_t index = 0;
    uint32_t g_tex = 0;
    int32_t material = 0;
    uint32_t drops = 0;  // front-end drops of this unit since its previous fragment
    bool own_u = false;  // u differs from g (quad derivatives): in Lane::quads
    bool front = false;  // front-end costs: in Lane::fronts
  };
  // Unit u's side queues, in its items' order.
  struct Lane {
    std::deque<Drop> drops;
    std::deque<Fragment> quads;
    std::deque<std::array<ItemCost, 2>> fronts;
    uint32_t new_drops = 0;  // drops not yet attached to an item
  };
  struct Hooks {
    UnitArray* a;
    uint64_t begin(int u, Item& it);
    // The begun item makes no request behind the L1 (UnitScheduler commits it at once).
    // Never with a commit observer (set_commit_observer turns the units' early commit off).
    bool local(int u) const { return a->units_[static_cast<size_t>(u)]->pending_local(); }
    // The earliest cycle unit u's next fragment can start its cache stage (nothing begun).
    uint64_t next_start_bound(int u) const {
      return a->units_[static_cast<size_t>(u)]->next_start_bound();
    }
    void commit(int u, Item& /*it*/) {
      TextureUnit& unit = *a->units_[static_cast<size_t>(u)];
      unit.commit();
      if (a->observer_) a->observer_(u, *unit.pipeline());
    }
  };

  // Without quad merging each fragment is filtered as it comes and only its timing waits
  // (TextureUnit::Timing), packed into one word (a run may hold most fragments for a long
  // while, and 56 bytes each do not stay in the host's cache): the issue cycles of at most
  // kPackedStages stages of up to 255 cycles, the misses (up to 255), whether it stayed local.
  // A timing that does not fit (front-end latencies, a frame's end, longer pipelines or larger
  // figures) waits whole in its unit's side queue, in order, and its word says so.
  struct Waiting {
    uint64_t bits = 0;
  };
  static constexpr int kPackedStages = 6;
  static constexpr uint64_t kEscaped = 1, kLocal = 2;
  static constexpr int kMissShift = 2, kIiShift = 16;
  // Unit u's timing written by its last process() (scratch_), packed (or queued whole).
  Waiting pack(int u);
  // The waiting timing w of unit u, unpacked into current_[u] (or taken from its side queue).
  TextureUnit::Timing& unpack(int u, Waiting w);
  struct TimedHooks {
    UnitArray* a;
    TextureUnit& unit(int u) const { return *a->units_[static_cast<size_t>(u)]; }
    uint64_t begin(int u, Waiting& w) { return unit(u).begin_timing(a->unpack(u, w)); }
    bool local(int u) const { return unit(u).timing_done(); }
    void commit(int u, Waiting& /*w*/) {
      unit(u).commit_timing(a->current_[static_cast<size_t>(u)]);
      if (a->observer_) a->observer_(u, *unit(u).pipeline());
    }
    uint64_t next_start_bound(int u) const { return unit(u).next_start_bound(); }
  };

  PipelineSetup setup_;
  std::unique_ptr<MemorySystem> memory_;  // several units: the shared memory
  std::vector<std::unique_ptr<TextureUnit>> units_;
  Hooks hooks_{this};
  std::unique_ptr<UnitScheduler<Item, Hooks>> sched_;  // with quad merging
  TimedHooks timed_hooks_{this};
  std::unique_ptr<UnitScheduler<Waiting, TimedHooks>> timed_;
  // Queued timing: where every unit's process() writes a fragment's timing (one at a time),
  // each unit's begun fragment's timing, and by unit the timings that did not pack.
  TextureUnit::Timing scratch_;
  std::vector<TextureUnit::Timing> current_;
  std::vector<std::deque<TextureUnit::Timing>> unpacked_;
  int stages_ = 0;  // the units' pipeline stages
  int front_ = 0;   // of which front-end stages with a latency of their own (at most kMaxFront)
  Record record_;
  mutable std::vector<FrameStats> frames_;
  mutable FrontEndStats front_stats_;
  std::vector<Lane> lanes_;  // by unit
  std::function<void(int, const ClockedPipeline&)> observer_;
};

}  // namespace texsim
