#include "pipeline/texture/unit_array.h"

#include <algorithm>
#include <bit>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>

namespace texsim {

UnitArray::UnitArray(TextureSet& textures, const std::vector<MaterialSetup>& materials,
                     const PipelineSetup& setup, const TechTable& tech, bool timing, size_t window,
                     bool whole_fragments)
    : setup_(setup) {
  const int n = timing ? static_cast<int>(setup.units) : 1;
  if (n == 1) {
    units_.push_back(std::make_unique<TextureUnit>(textures, materials, setup, tech, timing));
    return;
  }
  memory_ = std::make_unique<MemorySystem>(setup, n);
  for (int u = 0; u < n; ++u)
    units_.push_back(std::make_unique<TextureUnit>(textures, materials, setup, tech, *memory_, u));
  if (!setup.quad_merge && !whole_fragments) {
    for (auto& u : units_) {
      u->set_queued_timing(true);
      u->set_timing_out(&scratch_);
    }
    current_.resize(static_cast<size_t>(n));
    unpacked_.resize(static_cast<size_t>(n));
    stages_ = units_[0]->pipeline()->stage_count();
    front_ = std::min(units_[0]->front_stages(),
                      static_cast<int>(std::tuple_size_v<decltype(scratch_.front_latency)>));
    timed_ = std::make_unique<UnitScheduler<Waiting, TimedHooks>>(n, timed_hooks_, window);
    return;
  }
  lanes_.resize(static_cast<size_t>(n));
  sched_ = std::make_unique<UnitScheduler<Item, Hooks>>(n, hooks_, window);
}

UnitArray::~UnitArray() = default;

void UnitArray::set_surfaces(const std::vector<SurfaceFrame>& frames) {
  for (auto& u : units_) u->set_surfaces(frames);
}

UnitArray::Waiting UnitArray::pack(int u) {
  const TextureUnit::Timing& t = scratch_;
  bool fits = stages_ <= kPackedStages && t.misses <= 0xff && t.frame_end < 0;
  for (int s = 0; s < front_; ++s) fits = fits && t.front_latency[static_cast<size_t>(s)] == 0;
  uint64_t bits = uint64_t{t.misses} << kMissShift | (t.local ? kLocal : 0);
  for (int s = 0; s < stages_ && fits; ++s) {
    const uint32_t ii = t.ii[static_cast<size_t>(s)];
    fits = ii <= 0xff;
    bits |= uint64_t{ii} << (kIiShift + 8 * s);
  }
  if (fits) return {bits};
  unpacked_[static_cast<size_t>(u)].push_back(t);
  return {kEscaped};
}

TextureUnit::Timing& UnitArray::unpack(int u, Waiting w) {
  TextureUnit::Timing& t = current_[static_cast<size_t>(u)];
  if (w.bits & kEscaped) {
    std::deque<TextureUnit::Timing>& q = unpacked_[static_cast<size_t>(u)];
    t = q.front();
    q.pop_front();
    return t;
  }
  for (int s = 0; s < stages_; ++s)
    t.ii[static_cast<size_t>(s)] = static_cast<uint32_t>(w.bits >> (kIiShift + 8 * s)) & 0xff;
  for (int s = 0; s < front_; ++s) t.front_latency[static_cast<size_t>(s)] = 0;
  t.misses = static_cast<uint32_t>(w.bits >> kMissShift) & 0xff;
  t.frame_end = -1;
  t.local = (w.bits & kLocal) != 0;
  return t;
}

uint64_t UnitArray::Hooks::begin(int u, Item& it) {
  TextureUnit& unit = *a->units_[static_cast<size_t>(u)];
  Lane& lane = a->lanes_[static_cast<size_t>(u)];
  for (uint32_t k = 0; k < it.drops; ++k) {
    const Drop& d = lane.drops.front();
    unit.drop(d.material, d.front.data(), d.rejected);
    lane.drops.pop_front();
  }
  std::array<ItemCost, 2> front{};
  if (it.front) {
    front = lane.fronts.front();
    lane.fronts.pop_front();
  }
  // g is f itself unless the loaded texture's id differs (no copy then).
  Fragment own_g;
  const Fragment* g = &it.f;
  if (it.g_tex != it.f.tex) {
    own_g = it.f;
    own_g.tex = it.g_tex;
    g = &own_g;
  }
  Rgba c;
  if (it.own_u) {
    c = unit.process(lane.quads.front(), it.material, it.front ? front.data() : nullptr);
    lane.quads.pop_front();
  } else {
    c = unit.process(*g, it.material, it.front ? front.data() : nullptr);
  }
  a->record_(it.f, *g, it.material, &c, it.index);
  return unit.pending_start();
}

namespace {
// Whether a and b are the same fragment, bit for bit.
bool same_fragment(const Fragment& a, const Fragment& b) {
  auto bits = [](double d) { return std::bit_cast<uint64_t>(d); };
  auto fbits = [](float d) { return std::bit_cast<uint32_t>(d); };
  return a.frame == b.frame && a.prim == b.prim && a.x == b.x && a.y == b.y && a.tex == b.tex &&
         bits(a.u) == bits(b.u) && bits(a.v) == bits(b.v) && bits(a.dudx) == bits(b.dudx) &&
         bits(a.dvdx) == bits(b.dvdx) && bits(a.dudy) == bits(b.dudy) &&
         bits(a.dvdy) == bits(b.dvdy) && fbits(a.lod_bias) == fbits(b.lod_bias) &&
         fbits(a.view_x) == fbits(b.view_x) && fbits(a.view_y) == fbits(b.view_y) &&
         fbits(a.view_z) == fbits(b.view_z) && bits(a.w) == bits(b.w) &&
         bits(a.dwdx) == bits(b.dwdx) && bits(a.dwdy) == bits(b.dwdy) &&
         fbits(a.layer) == fbits(b.layer) && a.op == b.op &&
         a.gather_component == b.gather_component && a.sampler == b.sampler &&
         fbits(a.lod) == fbits(b.lod) && fbits(a.compare_ref) == fbits(b.compare_ref) &&
         a.offset_u == b.offset_u && a.offset_v == b.offset_v && a.offset_w == b.offset_w;
}
}  // namespace

void UnitArray::add(const Fragment& f, const Fragment& g, const Fragment& u, int material,
                    uint64_t index, const ItemCost* front) {
  const int unit = setup_.unit_of_pixel(f.x, f.y);
  if (timed_) {
    // Filtered now (u is g when it has no derivatives of its own), its timing written in
    // place into the scheduler's slot.
    TextureUnit& t = *units_[static_cast<size_t>(unit)];
    // (Every unit writes its timing to scratch_, packed before the next process().)
    // Its slot's line is fetched while the fragment is filtered.
    timed_->prefetch_slot(unit);
    if (timed_->idle(unit)) {
      // Nothing waits in the unit: a fragment whose look-ups all hit is timed as it is filtered.
      t.set_issue_now(true);
      const Rgba c = t.process(u, material, front);
      t.set_issue_now(false);
      record_(f, g, material, &c, index);
      if (t.timing_done()) {
        t.commit_timing(scratch_);
        timed_->count_local(unit);
      } else {
        const Waiting w = pack(unit);
        timed_->add_with(unit, [w](Waiting& slot) { slot = w; });
      }
      return;
    }
    const Rgba c = t.process(u, material, front);
    const Waiting w = pack(unit);
    timed_->add_with(unit, [w](Waiting& slot) { slot = w; });
    record_(f, g, material, &c, index);
    return;
  }
  Lane& lane = lanes_[static_cast<size_t>(unit)];
  // g differs from f in its texture id only (run.cc's loaded texture), never elsewhere.
  const bool own_u = &u != &g && !same_fragment(u, g);
  if (own_u) lane.quads.push_back(u);
  if (front) {
    std::array<ItemCost, 2>& c = lane.fronts.emplace_back();
    const int n = units_[0]->front_count(material);
    for (int s = 0; s < n; ++s) c[static_cast<size_t>(s)] = front[s];
  }
  const uint32_t drops = lane.new_drops;
  lane.new_drops = 0;
  auto fill = [&](Item& it) {
    it.f = f;
    it.index = index;
    it.g_tex = g.tex;
    it.material = material;
    it.drops = drops;
    it.own_u = own_u;
    it.front = front != nullptr;
  };
  if (!own_u && !front && drops == 0 && sched_->idle(unit)) {
    // The common case: nothing waits in the unit, so g begins now as Hooks::begin would begin
    // its item, without a copy; only a fragment that misses its L1 is handed over, begun.
    TextureUnit& t = *units_[static_cast<size_t>(unit)];
    const Rgba c = t.process(g, material, nullptr);
    record_(f, g, material, &c, index);
    if (hooks_.local(unit)) {  // (never with a commit observer)
      t.commit();
      sched_->count_local(unit);
    } else {
      sched_->add_begun(unit, fill, t.pending_start());
    }
    return;
  }
  sched_->add_with(unit, fill);
}

void UnitArray::drop(int material, const ItemCost* front, bool rejected, int32_t x, int32_t y) {
  const int unit =
      x < 0 ? 0 : setup_.unit_of_pixel(static_cast<uint32_t>(x), static_cast<uint32_t>(y));
  Drop d{material, {}, rejected};
  const int n = front ? units_[0]->front_count(material) : 0;
  for (int s = 0; s < n; ++s) d.front[static_cast<size_t>(s)] = front[s];
  if (timed_) {  // the unit's earlier fragments are all filtered: it takes the drop now
    units_[static_cast<size_t>(unit)]->drop(d.material, d.front.data(), d.rejected);
    return;
  }
  Lane& lane = lanes_[static_cast<size_t>(unit)];
  lane.drops.push_back(d);
  ++lane.new_drops;
}

const FrontEndStats& UnitArray::front_end_stats() const {
  front_stats_ = {};
  for (const auto& u : units_) {
    front_stats_.generated += u->front_end_stats().generated;
    front_stats_.occluded += u->front_end_stats().occluded;
    front_stats_.rejected += u->front_end_stats().rejected;
  }
  return front_stats_;
}

void UnitArray::finish() {
  if (sched_) sched_->finish();
  if (timed_) timed_->finish();
  // Drops after a unit's last fragment: counted; their cycles would go to a next fragment.
  for (size_t u = 0; u < lanes_.size(); ++u) {
    for (const Drop& d : lanes_[u].drops) units_[u]->drop(d.material, d.front.data(), d.rejected);
    lanes_[u] = {};
  }
}

uint64_t UnitArray::fragments() const {
  uint64_t n = 0;
  for (const auto& u : units_) n += u->fragments();
  return n;
}

uint64_t UnitArray::cycles() const {
  uint64_t c = 0;
  for (const auto& u : units_) c = std::max(c, u->cycles());
  return c;
}

namespace {
// Block uses of several units merged by name: operations, texels and areas add up (each unit
// is its own hardware), latency and materials are the first unit's.
std::vector<BlockUse> merge_uses(const std::vector<std::vector<BlockUse>>& per_unit) {
  std::vector<BlockUse> out = per_unit.front();
  for (size_t u = 1; u < per_unit.size(); ++u) {
    for (const BlockUse& b : per_unit[u]) {
      auto it =
          std::find_if(out.begin(), out.end(), [&](const BlockUse& o) { return o.name == b.name; });
      if (it == out.end()) {
        out.push_back(b);
        continue;
      }
      it->ops += b.ops;
      it->texels += b.texels;
      it->border_taps += b.border_taps;
      it->timing.area += b.timing.area;
    }
  }
  return out;
}
}  // namespace

std::vector<BlockUse> UnitArray::blocks() const {
  if (!several()) return units_[0]->blocks();
  std::vector<std::vector<BlockUse>> all;
  for (const auto& u : units_) all.push_back(u->blocks());
  return merge_uses(all);
}

std::vector<BlockUse> UnitArray::material_blocks(int m) const {
  if (!several()) return units_[0]->material_blocks(m);
  std::vector<std::vector<BlockUse>> all;
  for (const auto& u : units_) all.push_back(u->material_blocks(m));
  return merge_uses(all);
}

uint64_t UnitArray::material_fragments(int m) const {
  uint64_t n = 0;
  for (const auto& u : units_) n += u->material_fragments(m);
  return n;
}
TextureUnit::OpTallies UnitArray::material_op_tallies(int m) const {
  TextureUnit::OpTallies sum{};
  for (const auto& u : units_) {
    const TextureUnit::OpTallies& t = u->material_op_tallies(m);
    for (size_t k = 0; k < sum.size(); ++k) {
      sum[k].fragments += t[k].fragments;
      sum[k].taps += t[k].taps;
      sum[k].issue_cycles += t[k].issue_cycles;
      sum[k].ops += t[k].ops;
    }
  }
  return sum;
}
uint64_t UnitArray::quad_merged_lookups() const {
  uint64_t n = 0;
  for (const auto& u : units_) n += u->quad_merged_lookups();
  return n;
}
uint64_t UnitArray::material_relief_steps(int m) const {
  uint64_t n = 0;
  for (const auto& u : units_) n += u->material_relief_steps(m);
  return n;
}
uint64_t UnitArray::material_relief_fetches(int m) const {
  uint64_t n = 0;
  for (const auto& u : units_) n += u->material_relief_fetches(m);
  return n;
}

const std::vector<FrameStats>& UnitArray::frames() const {
  if (!several()) return units_[0]->frames();
  std::map<uint32_t, FrameStats> by;
  for (const auto& u : units_) {
    for (const FrameStats& f : u->frames()) {
      FrameStats& t = by[f.frame];
      t.frame = f.frame;
      t.fragments += f.fragments;
      t.cycles = std::max(t.cycles, f.cycles);
    }
  }
  frames_.clear();
  for (const auto& [k, v] : by) frames_.push_back(v);
  return frames_;
}

StageStats UnitArray::stage_totals(int s) const {
  StageStats t;
  for (const auto& u : units_) {
    const StageStats& st = u->pipeline()->stats(s);
    t.items += st.items;
    t.busy += st.busy;
    t.stall_starved += st.stall_starved;
    t.stall_blocked += st.stall_blocked;
    t.stall_full += st.stall_full;
    t.stall_extra += st.stall_extra;
    t.last_done = std::max(t.last_done, st.last_done);
  }
  return t;
}

double UnitArray::utilisation(int s) const {
  if (!several()) return units_[0]->pipeline()->utilisation(s);
  uint64_t end = 0;
  for (const auto& u : units_) end = std::max(end, u->pipeline()->run_end());
  if (end == 0) return 0.0;
  const double lanes = units_[0]->pipeline()->config(s).timing.lanes;
  return static_cast<double>(stage_totals(s).busy) /
         (static_cast<double>(end) * lanes * static_cast<double>(units_.size()));
}

void UnitArray::check_timing_invariants() const {
  for (const auto& u : units_) u->check_timing_invariants();
  if (!several()) return;
  uint64_t end = 0;
  for (const auto& u : units_) end = std::max(end, u->pipeline()->run_end());
  const uint64_t busy = memory().dram_totals().busy_cycles;
  if (end < busy)
    throw std::logic_error("timing invariant violated: the DRAM channel needs " +
                           std::to_string(busy) + " cycles but the run took " +
                           std::to_string(end));
}

}  // namespace texsim
