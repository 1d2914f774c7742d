#include "pipeline/texture/unit_array.h"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>

namespace texsim {

UnitArray::UnitArray(TextureSet& textures, const std::vector<MaterialSetup>& materials,
                     const PipelineSetup& setup, const TechTable& tech, bool timing, size_t window)
    : setup_(setup) {
  const int n = timing ? static_cast<int>(setup.units) : 1;
  if (n == 1) {
    units_.push_back(std::make_unique<TextureUnit>(textures, materials, setup, tech, timing));
    return;
  }
  memory_ = std::make_unique<MemorySystem>(setup, n);
  for (int u = 0; u < n; ++u)
    units_.push_back(std::make_unique<TextureUnit>(textures, materials, setup, tech, *memory_, u));
  if (units_[0]->front_stages() > 0)
    throw std::invalid_argument(
        "[pipeline] units > 1: a material with a coordinate unit (`coords`) runs on one texture "
        "unit only; set units = 1");
  sched_ = std::make_unique<UnitScheduler<Item, Hooks>>(n, hooks_, window);
}

UnitArray::~UnitArray() = default;

void UnitArray::set_surfaces(const std::vector<SurfaceFrame>& frames) {
  for (auto& u : units_) u->set_surfaces(frames);
}

uint64_t UnitArray::Hooks::begin(int u, Item& it) {
  TextureUnit& unit = *a->units_[static_cast<size_t>(u)];
  const Rgba c = unit.process(it.u, it.material);
  Fragment g = it.f;
  g.tex = it.g_tex;
  (*a->record_)(it.f, g, it.material, &c, it.index);
  return unit.pending_start();
}

void UnitArray::Hooks::commit(int u, Item& /*it*/) {
  TextureUnit& unit = *a->units_[static_cast<size_t>(u)];
  unit.commit();
  if (a->observer_) a->observer_(u, *unit.pipeline());
}

void UnitArray::add(const Fragment& f, const Fragment& g, const Fragment& u, int material,
                    uint64_t index, const Record& record) {
  record_ = &record;
  // g differs from f in its texture id only (run.cc's loaded texture), never elsewhere.
  sched_->add(setup_.unit_of_pixel(f.x, f.y), Item{f, u, g.tex, material, index});
}

void UnitArray::finish() {
  if (sched_) sched_->finish();
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
