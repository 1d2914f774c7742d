#include "pipeline/texture/texture_unit.h"

#include <algorithm>
#include <bit>
#include <glm/geometric.hpp>
#include <stdexcept>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "blocks/texture/decode/block_decoder.h"
#include "blocks/texture/layered/cube_face_select.h"
#include "blocks/texture/memory/storage_format.h"
#include "blocks/texture/sampler/gather_unit.h"
#include "blocks/texture/sampler/texel_reduce.h"
#include "blocks/texture/sampler/unnormalized_taps.h"
#include "blocks/texture/volume/volume_address_gen.h"
#include "pipeline/texture/stages/relief_stage.h"

namespace texsim {

namespace {
// The sampler slots after the front end, as the fixed kernels see them.
enum Stage { kLod, kAddress, kCache, kBlend, kStages };
constexpr int kMaxFront = 2;  // coordinate and derivative slots (a constant bound for the compiler)
// The kernels' kFront for a timed unit with other slots or timed in two steps: slots by index.
constexpr int kAnyStages = 1000;
// The kernels' kFront for a unit of several with the fixed slots: kTwoStep + its front slots.
constexpr int kTwoStep = 100;
}  // namespace

TextureUnit::TextureUnit(TextureSet& textures, std::vector<MaterialSetup> materials,
                         const PipelineSetup& setup, const TechTable& tech, bool timing)
    : TextureUnit(textures, std::move(materials), setup, tech, timing,
                  std::make_unique<MemorySystem>(setup, 1), nullptr, 0) {}

TextureUnit::TextureUnit(TextureSet& textures, std::vector<MaterialSetup> materials,
                         const PipelineSetup& setup, const TechTable& tech, MemorySystem& memory,
                         int unit)
    : TextureUnit(textures, std::move(materials), setup, tech, true, nullptr, &memory, unit) {}

TextureUnit::~TextureUnit() = default;

uint64_t TextureUnit::srgb_fragments() const {
  uint64_t n = 0;
  for (const Path& p : paths_) n += p.srgb_fragments;
  return n;
}

uint64_t TextureUnit::srgb_texels() const {
  uint64_t n = 0;
  for (const Path& p : paths_) n += p.srgb_texels;
  return n;
}

PerCompressedFormat TextureUnit::decoded_blocks() const {
  PerCompressedFormat n = fetch_.decoded_by_format();
  if (const BlockDecompressor* d = mem_->decompressor(); d && unit_ == 0) {
    for (size_t f = 0; f < n.size(); ++f) n[f] += d->stats().blocks_by_format[f];
  }
  return n;
}

void TextureUnit::attach_decoders() {
  const TechTable tech = tech_;
  mem_->attach_textures(textures_, [tech](CompressedFormat f) {
    const TimingSpec t = decoder_timing(f, tech);
    return BlockDecompressor::Timing{t.latency, t.ii};
  });
  if (setup_.decompress == PipelineSetup::Decompress::AfterL1)
    fetch_.set_blocks_in_l1([tech](CompressedFormat f) { return decoder_timing(f, tech).latency; });
}

TextureUnit::TextureUnit(TextureSet& textures, std::vector<MaterialSetup> materials,
                         const PipelineSetup& setup, const TechTable& tech, bool timing,
                         std::unique_ptr<MemorySystem> own, MemorySystem* shared, int unit)
    : textures_(textures),
      mats_(std::move(materials)),
      setup_(setup),
      tech_(tech),
      timing_(timing),
      own_memory_(std::move(own)),
      mem_(shared ? shared : own_memory_.get()),
      fetch_(mem_->l1(unit), mem_->behind_l1(), unit, setup.cache, setup.quad_merge),
      defer_(shared != nullptr),
      unit_(unit),
      srgb_(setup.srgb_decode, setup.blend.taps_per_cycle) {
  if (mats_.empty()) throw std::invalid_argument("texture unit: no materials");
  textures_.set_srgb_after_filter(setup.srgb_decode == SrgbDecode::AfterFilter);
  textures_.place(setup.layout);
  if (textures_.any_compressed()) attach_decoders();
  int reliefs = 0;
  for (const auto& m : mats_) {
    Path p;
    p.stages = assemble_stages(m, textures_, setup_, tech_, reliefs);
    paths_.push_back(std::move(p));
  }
  plan_pipeline();
  cube_select_ = CubeFaceSelect::timing(tech_);
  for (size_t m = 0; m < paths_.size(); ++m) {
    paths_[m].kernel = choose_kernel(paths_[m]);
    paths_[m].layered_kernel = choose_kernel(paths_[m], true);
    // A min/max reduction or a depth comparison replaces the blend: its own kernel, no batch.
    // An unnormalised sampler reads level 0 at texel coordinates: process_op, no batch.
    paths_[m].unnormalized = paths_[m].stages.address && mats_[m].filter.unnormalized;
    if (paths_[m].unnormalized) continue;
    if (paths_[m].stages.address && mats_[m].filter.reduces()) {
      paths_[m].kernel = &TextureUnit::process_reduced;
      continue;
    }
    if (mats_[m].filter.fixed_arithmetic) {
      // material_from_toml checked the sampler's settings; the texture is known only here.
      std::string why;
      if (!FixedSampler::covers_texture(textures_[mats_[m].texture], &why)) {
        throw InputError(mats_[m].arithmetic_where,
                         "materials." + mats_[m].name +
                             ".filter.arithmetic: \"fixed\" does not cover texture '" +
                             textures_[mats_[m].texture].name() + "': " + why);
      }
      paths_[m].fixed = std::make_shared<const FixedSampler>(
          FixedSampler::config_of(mats_[m].filter, mats_[m].lod));
      continue;  // one by one: no batched datapath
    }
    choose_batch(paths_[m], mats_[m]);
  }
}

void TextureUnit::plan_pipeline() {
  // One pipeline stage per slot some material occupies; a slot serving several materials is
  // sized for the slowest (the stages' bind() takes each material's own throughput back).
  SlotPlan plan(setup_.fifo_depth);
  for (const Path& p : paths_) {
    for (const auto& s : p.stages.all) s->declare(plan, tech_);
  }
  fetch_.declare(plan);
  plan.finish();
  for (Path& p : paths_) {
    for (const auto& s : p.stages.all) s->bind(plan, tech_);
  }
  front_ = plan.front_slots();
  address_ = plan.index(Slot::Address);
  cache_slot_ = plan.index(Slot::Cache);
  blend_ = plan.index(Slot::Blend);
  sampler_only_ = plan.sampler_only();
  if (!timing_) return;
  pipe_ = std::make_unique<ClockedPipeline>(plan.stages());
  defer_costs_.resize(static_cast<size_t>(pipe_->stage_count()));
  two_step_fixed_ = defer_ && sampler_only_ && pipe_->stage_count() == front_ + kStages &&
                    cache_slot_ == front_ + kCache;
}

void TextureUnit::choose_batch(Path& p, const MaterialSetup& m) {
  // The batched datapath: a plain bilinear or trilinear material (LOD, address and blend
  // stages only), on a unit without other slots.
  const MaterialStages& st = p.stages;
  if (!st.address || st.front || !st.surface.empty()) return;
  const FilterMode filter = st.address->filter();
  const bool plain = filter != FilterMode::Nearest &&
                     st.blend->blend().quads_in_one_group(filter == FilterMode::Trilinear ? 2 : 1);
  if (!plain || front_ != 0 || !sampler_only_ || defer_) return;
  p.batch = std::make_shared<LinearBatchSampler>(m.lod, m.filter);
  p.batch_kernel = pipe_ ? pick_batch_kernel<0>(filter, textures_.layout())
                         : pick_batch_kernel<-1>(filter, textures_.layout());
  if (!batch_out_) {
    batch_out_ = std::make_unique<LinearBatch>();
    batch_missed_.resize(8 * LinearBatch::kMax);
    batch_missed_end_.resize(LinearBatch::kMax + 1);
  }
}

void TextureUnit::new_frame(const Fragment& f) {
  // Queued timing: the frame's cycles once the fragments before this one have been issued.
  if (!frames_.empty() && pipe_) {
    if (queued_) {
      frame_end_ = static_cast<int32_t>(frames_.size() - 1);
    } else {
      frames_.back().cycles = pipe_->cycles();
    }
  }
  frames_.push_back({f.frame, 0, 0});
}

void TextureUnit::generate_coords(int material, const CoordTriangle& tri,
                                  std::vector<CoordUnitFragment>& out,
                                  std::vector<ItemCost>& costs) {
  FrontEndStage* fe = paths_[static_cast<size_t>(material)].stages.front;
  if (!fe) throw std::logic_error("generate_coords: material has no coordinate unit");
  fe->generate(tri, tech_, out, costs);
}

void TextureUnit::drop(int material, const ItemCost* front, bool rejected) {
  FrontEndStage* fe = paths_[static_cast<size_t>(material)].stages.front;
  if (!fe) throw std::logic_error("drop: material has no coordinate unit");
  fe->drop(pipe_ ? front : nullptr, rejected, owed_);
}

const FrontEndStats& TextureUnit::front_end_stats() const {
  front_stats_ = {};
  for (const Path& p : paths_) {
    if (!p.stages.front) continue;
    const FrontEndStats& s = p.stages.front->stats();
    front_stats_.generated += s.generated;
    front_stats_.occluded += s.occluded;
    front_stats_.rejected += s.rejected;
  }
  return front_stats_;
}

uint64_t TextureUnit::material_relief_steps(int m) const {
  const ReliefStage* r = find_stage<ReliefStage>(m);
  return r ? r->steps() : 0;
}

uint64_t TextureUnit::material_relief_fetches(int m) const {
  const ReliefStage* r = find_stage<ReliefStage>(m);
  return r ? r->fetches() : 0;
}

bool TextureUnit::material_has_relief(int m) const { return find_stage<ReliefStage>(m) != nullptr; }

Rgba TextureUnit::process(const Fragment& f, int material, const ItemCost* front) {
  Path& p = paths_[static_cast<size_t>(material)];
  if (!p.stages.surface.empty()) return process_surface(f, p, material, front);
  return filter_fragment(f, p, front);
}

void TextureUnit::process_batch(const Fragment* f, size_t n, int material, Rgba* out) {
  Path& p = paths_[static_cast<size_t>(material)];
  if (p.fixed && fixed_board_ && n > 1) {
    // The board's results for the whole batch in one call (few round trips), then each
    // fragment on its way as one by one.
    fixed_ahead_in_.resize(n);
    fixed_ahead_.resize(n);
    for (size_t i = 0; i < n; ++i) fixed_ahead_in_[i] = FixedSampler::to_input(f[i]);
    fixed_board_->sample_batch(material, fixed_ahead_in_, fixed_ahead_);
    fixed_ahead_at_ = 0;
    try {
      for (size_t i = 0; i < n; ++i) out[i] = process(f[i], material);
    } catch (...) {
      fixed_ahead_.clear();
      throw;
    }
    fixed_ahead_.clear();
    return;
  }
  if (!p.batch_kernel) {
    for (size_t i = 0; i < n; ++i) out[i] = process(f[i], material);
    return;
  }
  // Batches of at most LinearBatch::kMax on the texture of their first fragment; a fragment
  // on another texture goes through the scalar kernel with its own.
  for (size_t i = 0; i < n; i += LinearBatch::kMax) {
    const size_t m = std::min(LinearBatch::kMax, n - i);
    const uint32_t t = f[i].tex;
    if (t >= static_cast<uint32_t>(textures_.size()))
      filter_fragment(f[i], p, nullptr);  // throws, naming the texture
    if (textures_[static_cast<int>(t)].srgb_after_filter()) {
      for (size_t k = i; k < i + m; ++k) out[k] = process(f[k], material);  // decodes after
      continue;
    }
    (this->*p.batch_kernel)(f + i, m, p, textures_[static_cast<int>(t)], out + i);
  }
}

Rgba TextureUnit::process_surface(const Fragment& f, Path& p, int material, const ItemCost* front) {
  if (f.prim >= surfaces_.size()) {
    throw std::invalid_argument(
        "texture unit: material '" + mats_[static_cast<size_t>(material)].name +
        "' has relief or lighting, which needs the plane of its primitive (a scene run); "
        "primitive " +
        std::to_string(f.prim) + " is not known");
  }
  const SurfaceFrame& sf = surfaces_[f.prim];
  // The eye direction in the primitive's tangent frame: the fragment's own (a version-2 trace
  // carries it), else through the pixel's centre from the scene's camera.
  const glm::dvec3 view_ts = f.has_view() ? glm::normalize(glm::dvec3(f.view_x, f.view_y, f.view_z))
                                          : sf.to_tangent(sf.view(f.x + 0.5, f.y + 0.5));
  SurfaceItem it{f, sf, view_ts, pipe_ != nullptr, item_extra_};
  for (SurfaceStage* s : p.stages.surface) s->enter(it, fetch_);
  surface_ = &it;
  Rgba c = filter_fragment(it.g, p, front);
  surface_ = nullptr;
  std::fill(std::begin(item_extra_), std::end(item_extra_), 0u);
  fetch_.clear_staged();
  for (SurfaceStage* s : p.stages.surface) c = s->leave(it, c);
  return c;
}

Rgba TextureUnit::process_filter(const Fragment& f, Path& p, const Texture& tex,
                                 const ItemCost* front) {
  const FilterStage::Result r = p.stages.filter->filter(f, tex, surface_, pipe_ != nullptr, fetch_);
  filter_texels_ += r.texels;
  ++p.fragments;
  count_frame(f);
  if (pipe_) {
    issue_general(p, front, r.address_cycles - 1, fetch_.extra_ii(r.texels), 0,
                  [&](uint64_t start) {
                    return fetch_.access_lines(r.lines->data(), static_cast<int>(r.lines->size()),
                                               r.texels, start);
                  });
  }
  return r.colour;
}

Rgba TextureUnit::filter_fragment(const Fragment& f, Path& p, const ItemCost* front) {
  // The fragment's own texture: a trace may texture a material's primitive with any texture of
  // its table, and the reference filters the same one.
  if (f.tex >= static_cast<uint32_t>(textures_.size()))
    throw std::out_of_range("texture unit: fragment texture " + std::to_string(f.tex) +
                            " is not loaded");
  const Texture& tex = textures_[static_cast<int>(f.tex)];
  if (tex.layered()) {
    if (!p.layered_kernel)
      throw std::invalid_argument("texture unit: texture '" + tex.name() + "' is a " +
                                  to_string(tex.shape().type) +
                                  " texture, which footprint filters do not sample");
    return (this->*p.layered_kernel)(f, p, tex, front);
  }
  if (p.fixed) [[unlikely]]
    return filter_fixed(f, p, tex, front);
  if ((f.op | f.sampler | f.offset_u | f.offset_v) != 0 || p.unnormalized) [[unlikely]]
    return process_op(f, p, tex, front);
  if (tex.storage() == StorageFormat::Srgb8A8) return filter_srgb(f, p, tex, front);
  return (this->*p.kernel)(f, p, tex, front);
}

const TextureUnit::FixedTexture& TextureUnit::fixed_texture(uint32_t t) {
  auto it = fixed_textures_.find(t);
  if (it == fixed_textures_.end()) {
    const Texture& tex = textures_[static_cast<int>(t)];
    it = fixed_textures_
             .emplace(t, FixedTexture{FixedSampler::describe(tex), FixedSampler::memory_image(tex)})
             .first;
  }
  return it->second;
}

namespace {
bool same_input(const FixedSampler::Input& a, const FixedSampler::Input& b) {
  return a.u == b.u && a.v == b.v && a.dudx == b.dudx && a.dvdx == b.dvdx && a.dudy == b.dudy &&
         a.dvdy == b.dvdy;
}
}  // namespace

Rgba TextureUnit::filter_fixed(const Fragment& f, Path& p, const Texture& tex,
                               const ItemCost* front) {
  // The fragment's own texture, operation and bias: what a trace may give beyond the material.
  std::string why;
  if (f.op != 0) why = "an explicit sample operation";
  if (f.lod_bias != 0.0f) why = "a fragment's own LOD bias";
  if (f.offset_u != 0 || f.offset_v != 0) why = "a fragment's own texel offset";
  if (f.sampler != 0) why = "a fragment's own sampler";
  const size_t m = static_cast<size_t>(&p - paths_.data());
  if (fixed_board_ && f.tex != static_cast<uint32_t>(mats_[m].texture))
    why = "on the board, a texture other than the material's";
  if (why.empty()) FixedSampler::covers_texture(tex, &why);
  if (!why.empty()) {
    throw InputError(mats_[m].arithmetic_where, "materials." + mats_[m].name +
                                                    ".filter.arithmetic: \"fixed\" does not "
                                                    "cover " +
                                                    why + " (texture '" + tex.name() + "')");
  }
  (void)(this->*p.kernel)(f, p, tex, front);
  if (fixed_board_) {
    const FixedSampler::Input in = FixedSampler::to_input(f);
    if (fixed_ahead_at_ < fixed_ahead_.size() && same_input(fixed_ahead_in_[fixed_ahead_at_], in)) {
      fixed_last_ = fixed_ahead_[fixed_ahead_at_++];
    } else {
      fixed_last_ = fixed_board_->sample(static_cast<int>(m), in);
    }
  } else {
    const FixedTexture& t = fixed_texture(f.tex);
    fixed_last_ = p.fixed->sample(FixedSampler::to_input(f), t.desc, t.image);
  }
  const FixedSampler::Result& r = fixed_last_;
  const auto channel = [&](int c) {
    return static_cast<float>((r.rgba >> (8 * c)) & 255) / 255.0f;
  };
  return Rgba(channel(0), channel(1), channel(2), channel(3));
}

Rgba TextureUnit::filter_srgb(const Fragment& f, Path& p, const Texture& tex,
                              const ItemCost* front) {
  const AddressStage* a = p.stages.address;
  const uint64_t probes = a ? a->probes() : 0, border = a ? a->border_taps() : 0;
  const uint64_t texels = filter_texels_;
  const Rgba c = (this->*p.kernel)(f, p, tex, front);
  ++p.srgb_fragments;
  // The texels read (a border tap reads none, and its colour is linear already).
  p.srgb_texels += a ? (a->probes() - probes) * a->taps_per_probe() - (a->border_taps() - border)
                     : filter_texels_ - texels;
  return tex.srgb_after_filter() ? SrgbDecoder::decode_filtered(c) : c;
}

Rgba TextureUnit::process_op(const Fragment& f, Path& p, const Texture& tex,
                             const ItemCost* front) {
  if (!valid_sample_op(f.op))
    throw std::invalid_argument("texture unit: fragment operation " + std::to_string(f.op) +
                                " is not known");
  const std::string_view op_name = kSampleOpNames[f.op];
  if (!p.stages.address)
    throw std::invalid_argument("texture unit: material '" +
                                mats_[static_cast<size_t>(&p - paths_.data())].name +
                                "' has a footprint filter, which serves implicit-LOD samples "
                                "only; operation '" +
                                std::string(op_name) + "' needs nearest, bilinear or trilinear");
  // The fragment's sampler: its own pick, or its material's; offsets of its own (gather takes
  // them itself) or an unnormalised sampler need sampler state the material's path lacks.
  const MaterialSetup& m = mats_[static_cast<size_t>(&p - paths_.data())];
  const auto sampler = static_cast<uint16_t>(f.sampler == 0 ? m.sampler : f.sampler);
  const bool gather = f.op == static_cast<uint8_t>(SampleOp::kGather);
  if (sampler != m.sampler || p.unnormalized || (!gather && (f.offset_u | f.offset_v) != 0))
    return process_alt(f, p, tex, front, alt_sampler(f, p, sampler, gather));
  if (f.op == 0) {  // the material's own sampler, picked by its id
    return tex.storage() == StorageFormat::Srgb8A8 ? filter_srgb(f, p, tex, front)
                                                   : (this->*p.kernel)(f, p, tex, front);
  }
  OpTally& t = p.op_tallies[f.op];
  ++t.fragments;
  if (gather) {
    t.taps += 4;
    t.issue_cycles += 1;
    t.ops += GatherUnit::ops_per_item(p.stages.address->gen().config());
    return process_gather(f, p, tex, front, p.stages.address->gen().config());
  }
  // Explicit LOD or gradients: the material's datapath with the operation's λ.
  const SampleOp op = static_cast<SampleOp>(f.op);
  const LodResult lod = p.stages.lod->eval(f, tex);
  const uint32_t probes = TexelAddressGen::issue_cycles(lod);
  const TexelAddressGen& addr = p.stages.address->gen();
  const uint64_t taps = uint64_t{probes} * p.stages.address->taps_per_probe();
  t.taps += taps;
  t.issue_cycles += probes;
  const OpCounts per_tap =
      addr.config().reduces()
          ? TexelReduce::ops_per_tap(addr.config().reduction, addr.config().compare)
          : TexelBlend::ops_per_item();
  t.ops += p.stages.lod->ops_for(op) + addr.ops_setup(probes > 1) +
           addr.ops_per_item(probes > 1) * probes + per_tap * taps;
  return (this->*p.kernel)(f, p, tex, front);
}

Rgba TextureUnit::process_reduced(const Fragment& f, Path& p, const Texture& tex,
                                  const ItemCost* front) {
  const LodResult lod = p.stages.lod->eval(f, tex);
  const TexelAddressGen& addr = p.stages.address->gen();
  addr.taps(tex, f.u, f.v, lod, taps_);
  const TexelAddressGen::Config& c = addr.config();
  const Rgba colour = c.compare != CompareOp::None
                          ? TexelReduce::compare(taps_, tex, c.compare, f.compare_ref)
                          : TexelReduce::minmax(taps_, tex, c.reduction);
  if (taps_.border_taps > 0) p.stages.address->count_border(taps_.border_taps);
  const uint32_t probes = TexelAddressGen::issue_cycles(lod);
  count_fragment(f, p, probes);
  if (pipe_) {
    issue_general(p, front, probes - 1,
                  fetch_.extra_ii(uint64_t{probes} * p.stages.address->taps_per_probe()),
                  p.stages.blend->extra_ii(probes),
                  [&](uint64_t start) { return fetch_.lookup_taps(taps_, tex, start); });
  }
  return colour;
}

const TextureUnit::AltSampler& TextureUnit::alt_sampler(const Fragment& f, Path& p,
                                                        uint16_t sampler, bool gather) {
  // Gather adds the fragment's offsets itself; the other operations take them folded in.
  const int ou = gather ? 0 : f.offset_u, ov = gather ? 0 : f.offset_v;
  const uint32_t key =
      sampler | static_cast<uint32_t>(ou + 128) << 16 | static_cast<uint32_t>(ov + 128) << 24;
  auto& slot = p.alt[key];
  if (slot) return *slot;
  const MaterialSetup& m = mats_[static_cast<size_t>(&p - paths_.data())];
  const size_t n = m.samplers ? m.samplers->size() : 0;
  if (sampler > n) {
    throw std::invalid_argument("texture unit: sampler " + std::to_string(sampler) +
                                " is not in the sampler table (" + std::to_string(n) +
                                " samplers)");
  }
  TexelAddressGen::Config c = sampler == 0 ? m.filter : (*m.samplers)[sampler - 1u].filter;
  const LodUnit::Config l = sampler == 0 ? m.lod : (*m.samplers)[sampler - 1u].lod;
  c.offset_u += ou;
  c.offset_v += ov;
  slot = std::make_unique<const AltSampler>(AltSampler{LodUnit(l), TexelAddressGen(c)});
  return *slot;
}

Rgba TextureUnit::process_alt(const Fragment& f, Path& p, const Texture& tex, const ItemCost* front,
                              const AltSampler& s) {
  const TexelAddressGen::Config& c = s.gen.config();
  if (c.unnormalized) {
    if (const std::string why = unnormalized_refusal(f); !why.empty())
      throw std::invalid_argument("texture unit: " + why);
  }
  OpTally& t = p.op_tallies[f.op];
  if (f.op == static_cast<uint8_t>(SampleOp::kGather)) {
    ++t.fragments;
    t.taps += 4;
    t.issue_cycles += 1;
    t.ops += GatherUnit::ops_per_item(c);
    return process_gather(f, p, tex, front, c);
  }
  LodResult lod;  // unnormalised: level 0, one probe, no LOD unit
  OpCounts ops;
  if (c.unnormalized) {
    UnnormalizedTaps::taps(c, tex, f.u, f.v, taps_);
    ops = UnnormalizedTaps::ops_per_item(c);
  } else {
    lod = s.lod.eval(f, tex.width(0), tex.height(0));
    s.gen.taps(tex, f.u, f.v, lod, taps_, ops);
    ops += s.lod.ops_for(static_cast<SampleOp>(f.op));
  }
  const Rgba colour =
      c.compare != CompareOp::None ? TexelReduce::compare(taps_, tex, c.compare, f.compare_ref)
      : c.reduction != Reduction::WeightedAverage ? TexelReduce::minmax(taps_, tex, c.reduction)
                                                  : p.stages.blend->blend().blend(taps_, tex);
  const uint32_t probes = TexelAddressGen::issue_cycles(lod);
  const auto taps = static_cast<uint64_t>(taps_.count);
  if (f.op != 0) {  // an implicit-LOD sample is counted in the material's rows only
    ++t.fragments;
    t.taps += taps;
    t.issue_cycles += probes;
    t.ops += ops + (c.reduces() ? TexelReduce::ops_per_tap(c.reduction, c.compare)
                                : TexelBlend::ops_per_item()) *
                       taps;
  }
  if (taps_.border_taps > 0) p.stages.address->count_border(taps_.border_taps);
  count_fragment(f, p, probes);
  if (pipe_) {
    issue_general(p, front, probes - 1, fetch_.extra_ii(taps), p.stages.blend->extra_ii(probes),
                  [&](uint64_t start) { return fetch_.lookup_taps(taps_, tex, start); });
  }
  return colour;
}

Rgba TextureUnit::process_gather(const Fragment& f, Path& p, const Texture& tex,
                                 const ItemCost* front, const TexelAddressGen::Config& c) {
  const TexelQuad q = GatherUnit::quad(c, tex, f.u, f.v, f.offset_u, f.offset_v);
  int border = 0;
  Rgba out = GatherUnit::gather(
      q, tex, f.gather_component,
      c.uses_border() ? border_texel(tex.storage(), c.border) : Rgba(0.0f), &border);
  if (c.compare != CompareOp::None) {
    // textureGatherCompare: each of the four texels compared with the reference.
    const float ref = TexelReduce::reference(tex, f.compare_ref);
    for (int k = 0; k < 4; ++k) out[k] = compare_passes(c.compare, ref, out[k]) ? 1.0f : 0.0f;
  }
  if (border > 0) p.stages.address->count_border(border);
  count_fragment(f, p, 1);
  if (pipe_) {
    taps_.tap[0] = {0, q.x0, q.y0, 1.0f};
    taps_.tap[1] = {0, q.x1, q.y0, 1.0f};
    taps_.tap[2] = {0, q.x0, q.y1, 1.0f};
    taps_.tap[3] = {0, q.x1, q.y1, 1.0f};
    taps_.count = 4;
    taps_.border_taps = border;
    issue_general(p, front, 0, fetch_.extra_ii(4), 0,
                  [&](uint64_t start) { return fetch_.lookup_taps(taps_, tex, start); });
  }
  return out;
}

template <class CostFn>
void TextureUnit::issue_any(CostFn&& cost_at) {
  if (!defer_) {
    pipe_->issue_with(0, cost_at);
    return;
  }
  // Every stage's cost now (only the cache slot's wait depends on the cycle, and its
  // look-ups are recorded, not made); the stages in front of the cache now, the rest at commit.
  ItemCost* c = queued_ ? scratch_.data() : defer_costs_.data();
  fetch_.begin_recording();
  for (int s = 0; s < pipe_->stage_count(); ++s) c[s] = cost_at(s, 0);
  fetch_.end_recording();
  if (queued_) {
    keep_timing(c, pipe_->stage_count());
    return;
  }
  const int k = cache_slot_;
  defer_arrival_ = pipe_->issue_head(
      0, k, [&](int s, uint64_t) { return defer_costs_[static_cast<size_t>(s)]; });
  defer_start_ = pipe_->start_at(k, defer_arrival_);
}

void TextureUnit::commit_deferred() {
  defer_costs_[static_cast<size_t>(cache_slot_)].extra_latency =
      fetch_.commit_lookups(defer_start_);
  issue_deferred_tail();
}

void TextureUnit::set_queued_timing(bool on) {
  if (on && (!defer_ || fetch_.quad_merge()))
    throw std::logic_error("queued timing: a unit of several without quad merging only");
  queued_ = on;
  fetch_.set_keep_misses(on);
}

void TextureUnit::keep_timing(const ItemCost* c, int n) {
  // Only the front-end slots and the cache slot have an extra latency; the cache slot's is
  // its misses' wait, known at commit.
  Timing& t = *timing_out_;
  for (int s = 0; s < n; ++s) t.ii[static_cast<size_t>(s)] = c[s].extra_ii;
  for (int s = 0; s < front_ && s < kMaxFront; ++s)
    t.front_latency[static_cast<size_t>(s)] = c[s].extra_latency;
  t.misses = fetch_.kept_misses();
  t.local = fetch_.recorded_local();
  t.frame_end = frame_end_;
  frame_end_ = -1;
}

template <int kN>
uint64_t TextureUnit::begin_fixed(const Timing& t, bool whole) {
  constexpr int k = kN - kStages + kCache;
  auto cost = [&t](auto s, uint64_t) __attribute__((always_inline)) {
    constexpr int i = decltype(s)::value;
    if constexpr (i < kN - kStages) return ItemCost{t.front_latency[i], t.ii[i]};
    return ItemCost{0, t.ii[i]};
  };
  if (whole) {
    pipe_->issue_fixed<kN>(0, cost);
    return 0;
  }
  defer_arrival_ = pipe_->issue_head_fixed<k>(0, cost);
  defer_start_ = pipe_->start_at(k, defer_arrival_);
  return defer_start_;
}

template <int kN>
void TextureUnit::commit_fixed(const Timing& t, uint64_t wait) {
  constexpr int k = kN - kStages + kCache;
  pipe_->issue_tail_fixed<k, kN>(defer_arrival_, [&t, wait](auto s, uint64_t) {
    constexpr int i = decltype(s)::value;
    return ItemCost{i == k ? wait : 0, t.ii[i]};
  });
}

uint64_t TextureUnit::begin_timing(const Timing& t) {
  // The unit's earlier fragments have all left: the frame before this one ends here.
  if (t.frame_end >= 0) frames_[static_cast<size_t>(t.frame_end)].cycles = pipe_->cycles();
  // Its look-ups all hit as they came (the cache slot waits for nothing): the whole way now.
  const bool whole = early_ && t.local;
  done_ = whole;
  if (two_step_fixed_) {
    switch (front_) {
      case 0:
        return begin_fixed<kStages>(t, whole);
      case 1:
        return begin_fixed<1 + kStages>(t, whole);
      default:
        return begin_fixed<kMaxFront + kStages>(t, whole);
    }
  }
  const int n = pipe_->stage_count();
  for (int s = 0; s < n; ++s) {
    const auto i = static_cast<size_t>(s);
    defer_costs_[i] = {s < front_ && s < kMaxFront ? t.front_latency[i] : 0, t.ii[i]};
  }
  const ItemCost* c = defer_costs_.data();
  auto cost = [c](int s, uint64_t) { return c[s]; };
  if (whole) {
    pipe_->issue_with(0, cost);
    return 0;
  }
  defer_arrival_ = pipe_->issue_head(0, cache_slot_, cost);
  defer_start_ = pipe_->start_at(cache_slot_, defer_arrival_);
  return defer_start_;
}

void TextureUnit::commit_timing(const Timing& t) {
  if (done_) {  // begin_timing() took the whole way
    done_ = false;
    return;
  }
  const uint64_t wait = fetch_.commit_misses(t.misses, defer_start_);
  if (two_step_fixed_) {
    switch (front_) {
      case 0:
        return commit_fixed<kStages>(t, wait);
      case 1:
        return commit_fixed<1 + kStages>(t, wait);
      default:
        return commit_fixed<kMaxFront + kStages>(t, wait);
    }
  }
  defer_costs_[static_cast<size_t>(cache_slot_)].extra_latency = wait;
  issue_deferred_tail();
}

void TextureUnit::issue_deferred_tail() {
  const int k = cache_slot_;
  if (!two_step_fixed_) {
    pipe_->issue_tail(k, defer_arrival_,
                      [&](int s, uint64_t) { return defer_costs_[static_cast<size_t>(s)]; });
    return;
  }
  // The same steps unrolled for the fixed slot sequences.
  const ItemCost* c = defer_costs_.data();
  auto cost = [c](auto s, uint64_t) { return c[decltype(s)::value]; };
  switch (front_) {
    case 0:
      pipe_->issue_tail_fixed<kCache, kStages>(defer_arrival_, cost);
      break;
    case 1:
      pipe_->issue_tail_fixed<1 + kCache, 1 + kStages>(defer_arrival_, cost);
      break;
    default:
      pipe_->issue_tail_fixed<kMaxFront + kCache, kMaxFront + kStages>(defer_arrival_, cost);
      break;
  }
}

template <int kFront, class Lookups>
void TextureUnit::issue_two_step(Path& p, const ItemCost* front, uint32_t probes, uint64_t texels,
                                 Lookups& lookups) {
  // issue_any's first step for the fixed slots: every stage's cost now, the look-ups
  // recorded, the stages in front of the cache slot issued (queued timing: kept for later).
  ItemCost* c = queued_ ? scratch_.data() : defer_costs_.data();
  for (int s = 0; s < kFront; ++s) c[s] = front_cost(p, front, s);
  c[kFront + kLod] = {};
  c[kFront + kAddress] = {0, probes - 1};
  c[kFront + kCache] = {0, fetch_.extra_ii(texels)};
  c[kFront + kBlend] = {0, p.stages.blend->extra_ii(probes)};
  fetch_.begin_recording();
  lookups(0);
  fetch_.end_recording();
  if (queued_) {
    if (issue_now_ && early_ && fetch_.recorded_local()) {
      if (frame_end_ >= 0) frames_[static_cast<size_t>(frame_end_)].cycles = pipe_->cycles();
      frame_end_ = -1;
      pipe_->issue_fixed<kFront + kStages>(
          0, [c](auto s, uint64_t)
                 __attribute__((always_inline)) { return c[decltype(s)::value]; });
      done_ = true;
      return;
    }
    keep_timing(c, kFront + kStages);
    return;
  }
  if (early_ && !fetch_.quad_merge() && fetch_.recorded_local()) {
    // Every look-up hit (the cache slot waits for nothing) and nothing behind the L1 is
    // asked: the whole way now, as the unit would take it at commit (done_: commit() has
    // nothing left to do).
    pipe_->issue_fixed<kFront + kStages>(
        0, [c](auto s, uint64_t) __attribute__((always_inline)) { return c[decltype(s)::value]; });
    done_ = true;
    return;
  }
  constexpr int k = kFront + kCache;
  defer_arrival_ = pipe_->issue_head_fixed<k>(
      0, [c](auto s, uint64_t) __attribute__((always_inline)) { return c[decltype(s)::value]; });
  defer_start_ = pipe_->start_at(k, defer_arrival_);
}

template <class Lookups>
void TextureUnit::issue_general(Path& p, const ItemCost* front, uint32_t address_ii,
                                uint32_t cache_ii, uint32_t blend_ii, Lookups&& lookups,
                                uint64_t address_latency) {
  const int addr = address_, cache = cache_slot_, blend = blend_;
  issue_any([&](int s, uint64_t start) {
    if (s < kMaxFront && s < front_) return front_cost(p, front, s);
    ItemCost c;
    c.extra_ii = item_extra_[s];
    if (s == addr) {
      c.extra_ii += address_ii;
      c.extra_latency = address_latency;
    }
    if (s == cache) {
      c.extra_ii += cache_ii;
      // The reads earlier stages made (relief) first: the cache sees requests in time order.
      const uint64_t staged = fetch_.staged_lookups(start);
      c.extra_latency = std::max(staged, lookups(start));
    }
    if (s == blend) c.extra_ii += blend_ii;
    return c;
  });
}

template <int kFront, class Lookups>
void TextureUnit::issue_timed(Path& p, const ItemCost* front, uint32_t probes, uint64_t texels,
                              Lookups&& lookups) {
  // Per-slot costs: the address slot issues one probe per cycle, cache and blend take
  // their texels in groups, and a miss in the cache slot waits for the memory behind it.
  if constexpr (kFront == kAnyStages) {
    issue_general(p, front, probes - 1, fetch_.extra_ii(texels), p.stages.blend->extra_ii(probes),
                  lookups);
  } else if constexpr (kFront >= kTwoStep) {
    issue_two_step<kFront - kTwoStep>(p, front, probes, texels, lookups);
  } else {
    issue_fixed_stages<kFront>(p, front, probes, texels, lookups);
  }
}

template <int kFront, class Lookups>
void TextureUnit::issue_fixed_stages(Path& p, const ItemCost* front, uint32_t probes,
                                     uint64_t texels, Lookups& lookups) {
  const MaterialStages& st = p.stages;
  pipe_->issue_fixed<kFront + kStages>(
      0, [&](auto stage, uint64_t start) __attribute__((always_inline)) {
        constexpr int s = decltype(stage)::value;
        ItemCost c;
        if constexpr (s < kFront) {
          c = front_cost(p, front, s);
        } else if constexpr (s == kFront + kAddress) {
          c.extra_ii = probes - 1;
        } else if constexpr (s == kFront + kCache) {
          c.extra_ii = fetch_.extra_ii(texels);
          c.extra_latency = lookups(start);
        } else if constexpr (s == kFront + kBlend) {
          c.extra_ii = st.blend->extra_ii(probes);
        }
        return c;
      });
}

template <int kFront>
Rgba TextureUnit::process_taps(const Fragment& f, Path& p, const Texture& tex,
                               const ItemCost* front, const LodResult& lod) {
  const MaterialStages& st = p.stages;
  st.address->gen().taps(tex, f.u, f.v, lod, taps_);
  const Rgba colour = st.blend->blend().blend(taps_, tex);
  if (taps_.border_taps > 0) p.stages.address->count_border(taps_.border_taps);
  const uint32_t probes = TexelAddressGen::issue_cycles(lod);
  count_fragment(f, p, probes);
  if constexpr (kFront >= 0) {
    issue_timed<kFront>(p, front, probes, probes * st.address->taps_per_probe(),
                        [&](uint64_t start) { return fetch_.lookup_taps(taps_, tex, start); });
  }
  return colour;
}

template <int kFront>
Rgba TextureUnit::process_any(const Fragment& f, Path& p, const Texture& tex,
                              const ItemCost* front) {
  return process_taps<kFront>(f, p, tex, front, p.stages.lod->eval(f, tex));
}

const TextureUnit::AltSampler* TextureUnit::layered_sampler(const Fragment& f, Path& p,
                                                            const Texture& tex) {
  const MaterialSetup& m = mats_[static_cast<size_t>(&p - paths_.data())];
  const auto sampler = static_cast<uint16_t>(f.sampler == 0 ? m.sampler : f.sampler);
  // The layered paths take no constant offsets of a record (as with the material's sampler).
  const AltSampler* s = sampler != m.sampler ? &alt_sampler(f, p, sampler, true) : nullptr;
  if ((s ? s->gen.config() : m.filter).unnormalized)
    throw std::invalid_argument("texture unit: " + unnormalized_refusal(tex.shape().type));
  return s;
}

template <int kFront>
Rgba TextureUnit::process_layered(const Fragment& f, Path& p, const Texture& tex,
                                  const ItemCost* front) {
  // The record's sampler when it names one other than its material's.
  const AltSampler* alt = f.sampler != 0 || p.unnormalized ? layered_sampler(f, p, tex) : nullptr;
  if (tex.volume()) return process_volume<kFront>(f, p, tex, front, alt);
  const MaterialStages& st = p.stages;
  const LayeredAddressGen gen =
      alt ? LayeredAddressGen(alt->gen, alt->gen.config().seamless_cube) : st.address->layered();
  const auto eval_lod = [&](const Fragment& g) {
    return alt ? alt->lod.eval(g, tex.width(0), tex.height(0)) : st.lod->eval(g, tex);
  };
  LodResult lod;
  uint32_t probes = 1;
  if (tex.shape().type == TextureType::Cube) {
    // The direction (u, v, w) to a face and its coordinates; the LOD unit then works on the
    // face (level 0 of slice 0 has the face's size).
    const CubeFaceCoord c = CubeFaceSelect::select(static_cast<float>(f.u), static_cast<float>(f.v),
                                                   static_cast<float>(f.w));
    const float dx[3] = {static_cast<float>(f.dudx), static_cast<float>(f.dvdx),
                         static_cast<float>(f.dwdx)};
    const float dy[3] = {static_cast<float>(f.dudy), static_cast<float>(f.dvdy),
                         static_cast<float>(f.dwdy)};
    const CubeFaceDerivs d = CubeFaceSelect::derivatives(c, dx, dy);
    Fragment g = f;
    g.u = c.s;
    g.v = c.t;
    g.dudx = d.dsdx;
    g.dvdx = d.dtdx;
    g.dudy = d.dsdy;
    g.dvdy = d.dtdy;
    lod = eval_lod(g);
    const int cube = LayeredAddressGen::select_layer(f.layer, tex.shape().slices / kCubeFaces);
    const int edge = gen.cube_taps(tex, c, cube, lod, taps_);
    st.address->count_cube(edge);
    probes = static_cast<uint32_t>(LayeredAddressGen::cube_probes(lod));
  } else {
    lod = eval_lod(f);
    const int layer = LayeredAddressGen::select_layer(f.layer, tex.shape().slices);
    gen.array_taps(tex, f.u, f.v, layer, lod, taps_);
    st.address->count_array();
    probes = TexelAddressGen::issue_cycles(lod);
  }
  const Rgba colour = st.blend->blend().blend(taps_, tex);
  if (taps_.border_taps > 0) p.stages.address->count_border(taps_.border_taps);
  count_fragment(f, p, probes);
  const auto lookups = [&](uint64_t start) { return fetch_.lookup_taps(taps_, tex, start); };
  if (kFront >= 0 && tex.shape().type == TextureType::Cube) {
    // The face selector issues in the address slot ahead of the probes (its ii, one cycle)
    // and its result reaches the address generator after its latency.
    issue_general(p, front, probes - 1 + cube_select_.ii,
                  fetch_.extra_ii(static_cast<uint64_t>(taps_.count)), st.blend->extra_ii(probes),
                  lookups, cube_select_.latency);
  } else if constexpr (kFront >= 0) {
    issue_timed<kFront>(p, front, probes, static_cast<uint64_t>(taps_.count), lookups);
  }
  return colour;
}

template <int kFront>
Rgba TextureUnit::process_volume(const Fragment& f, Path& p, const Texture& tex,
                                 const ItemCost* front, const AltSampler* alt) {
  const MaterialStages& st = p.stages;
  // The record's sampler's filter, address modes and border (null: the material's).
  const TexelAddressGen::Config& c = alt ? alt->gen.config() : st.address->gen().config();
  const VolumeAddressGen gen({c.filter, c.address_u, c.address_v, c.address_w});
  const VolumeSize base{tex.width(0), tex.height(0), tex.shape().slices};
  // The LOD unit's λ on the 3-D footprint (its float32 arithmetic; the operation's λ_base, the
  // bias and the clamp as on a 2-D λ), then the address generator's level selection: the
  // level and its fraction in fixed point (mipmap_bits), as a 2-D sample's.
  const auto op = static_cast<SampleOp>(f.op);
  if (op == SampleOp::kGather)
    throw std::invalid_argument("texture unit: gather on the 3-D texture '" + tex.name() +
                                "' (a gather reads 2-D and cube images only)");
  const TexelAddressGen::LevelSelect sel = st.address->gen().select_levels(
      st.lod->eval_volume(f, tex).lambda, VolumeAddressGen::level_count(base));
  const float lambda = static_cast<float>(sel.d_hi) + sel.delta;  // exact: delta is k·2^-m
  VolumeAddressGen::Taps vt;
  const int n = gen.taps(base, f.u, f.v, f.w, lambda, vt);
  // The taps as the blend takes them: level = the z-slice's level, border taps marked.
  taps_.count = n;
  taps_.border_taps = 0;
  uint64_t lines[VolumeAddressGen::kMaxTaps];
  int distinct = 0;
  const uint32_t shift = fetch_.line_shift();
  for (int k = 0; k < n; ++k) {
    const VolumeTap& v = vt[static_cast<size_t>(k)];
    TexelTap& t = taps_.tap[static_cast<size_t>(k)];
    if (v.x < 0) {
      t = {0, kBorderTexel, kBorderTexel, v.weight};
      ++taps_.border_taps;
      continue;
    }
    t = {tex.volume_level(v.level, v.z), v.x, v.y, v.weight};
    const uint64_t line = tex.volume_address(v.level, v.x, v.y, v.z) >> shift;
    if (std::find(lines, lines + distinct, line) == lines + distinct) lines[distinct++] = line;
  }
  if (taps_.border_taps > 0) {
    taps_.border = border_texel(tex.storage(), c.border);
    st.address->count_border(taps_.border_taps);
  }
  const Rgba colour = st.blend->blend().blend(taps_, tex);
  const uint32_t per_probe = std::max(st.address->taps_per_probe(), 1u);
  const uint32_t probes = std::max(1u, (static_cast<uint32_t>(n) + per_probe - 1) / per_probe);
  st.address->count_volume();
  if (op == SampleOp::kSampleLod || op == SampleOp::kSampleGrad) {
    // The operation's own row, as a 2-D one's (process_op): its LOD datapath, the address
    // generator's per probe (the r axis's operations stay in the volume.r_axis row), the blend.
    const TexelAddressGen& addr = st.address->gen();
    OpTally& t = p.op_tallies[f.op];
    ++t.fragments;
    t.taps += static_cast<uint64_t>(n);
    t.issue_cycles += probes;
    t.ops += st.lod->ops_for(op) + addr.ops_setup(false) + addr.ops_per_item(false) * probes +
             TexelBlend::ops_per_item() * static_cast<uint64_t>(n);
  }
  count_fragment(f, p, probes);
  if constexpr (kFront >= 0) {
    issue_timed<kFront>(p, front, probes, static_cast<uint64_t>(n), [&](uint64_t start) {
      return fetch_.access_lines(lines, distinct, static_cast<uint64_t>(n - taps_.border_taps),
                                 start);
    });
  }
  return colour;
}

template <FilterMode kFilter, TexelLayout L, int kFront>
Rgba TextureUnit::process_linear(const Fragment& f, Path& p, const Texture& tex,
                                 const ItemCost* front) {
  const MaterialStages& st = p.stages;
  const LodResult lod = st.lod->eval(f, tex);
  if (TexelAddressGen::issue_cycles(lod) != 1 || tex.layout() != L)
    return process_taps<kFront>(f, p, tex, front, lod);
  // One probe at (u, v): the taps TexelAddressGen::taps() gives, as quads.
  using texel_address_detail::finite_or_zero;
  const TexelAddressGen& addr = st.address->gen();
  const TexelAddressGen::LevelSelect sel = addr.select_levels(lod.lambda, tex.levels());
  const float uf = finite_or_zero(static_cast<float>(f.u));
  const float vf = finite_or_zero(static_cast<float>(f.v));
  TexelQuad q[2];
  constexpr int n = kFilter == FilterMode::Trilinear ? 2 : 1;
  if constexpr (n == 1) {
    q[0] = addr.linear_quad(tex, sel.d_hi, uf, vf, 1.0f);
  } else {
    q[0] = addr.linear_quad(tex, sel.d_hi, uf, vf, 1.0f - sel.delta);
    q[1] = addr.linear_quad(tex, sel.d_lo, uf, vf, sel.delta);
  }
  const Rgba colour = st.blend->blend().blend_quads(q, n, tex);
  count_fragment(f, p, 1);
  if constexpr (kFront >= 0) {
    issue_timed<kFront>(p, front, 1, 4 * n,
                        [&](uint64_t start) { return fetch_.lookup_quads<L>(q, n, tex, start); });
  }
  return colour;
}

template <FilterMode kFilter, TexelLayout L, int kFront>
void TextureUnit::batch_linear(const Fragment* f, size_t n, Path& p, const Texture& tex,
                               Rgba* out) {
  if (tex.layout() != L || tex.layered() || !p.batch->serves(tex)) {
    for (size_t i = 0; i < n; ++i) out[i] = filter_fragment(f[i], p, nullptr);
    return;
  }
  LinearBatch& b = *batch_out_;
  // The colours straight into out; the undone fragments' are the scalar kernel's.
  p.batch->filter(f, n, tex, b, kFront >= 0 ? fetch_.line_shift() : 0, out);
  if constexpr (kFront < 0) {
    finish_functional_batch(f, n, p, b, out);
  } else {
    finish_timed_batch<kFilter, L, kFront>(f, n, p, tex, b, out);
  }
}

template <FilterMode kFilter, TexelLayout L, int kFront>
void TextureUnit::finish_timed_batch(const Fragment* f, size_t n, Path& p, const Texture& tex,
                                     const LinearBatch& b, Rgba* out) {
  constexpr int nq = kFilter == FilterMode::Trilinear ? 2 : 1;
  // timed_run clocks the fixed slots without a front end (the batch's only timed kernel).
  static_assert(kFront == 0);
  if (b.has_lines && fetch_.looks_up_ahead()) {
    // Runs of done fragments looked up ahead of the clock; an undone one in between takes the
    // scalar kernel in its place in the order.
    for (size_t i = 0; i < n;) {
      size_t e = i;
      while (e < n && b.done[e]) ++e;
      if (e > i) timed_run<nq>(f, i, e, p, b);
      if (e < n) out[e] = filter_fragment(f[e], p, nullptr);
      i = e + 1;
    }
    return;
  }
  for (size_t i = 0; i < n; ++i) {
    if (!b.done[i]) {
      out[i] = filter_fragment(f[i], p, nullptr);  // its own texture, the scalar kernel
      continue;
    }
    count_fragment(f[i], p, 1);
    if (b.has_lines) {
      // The batch's distinct lines, in order of first use (as lookup_quads<L> finds them).
      issue_timed<kFront>(p, nullptr, 1, 4 * nq, [&](uint64_t start) {
        uint64_t lines[4 * nq];
        int k = 0;
        for (int t = 0; t < 4 * nq; ++t) {
          if (b.first_use[i] & (1 << t)) lines[k++] = static_cast<uint64_t>(b.line[t][i]);
        }
        return fetch_.access_lines(lines, k, 4 * nq, start);
      });
      continue;
    }
    TexelQuad q[nq];
    for (int j = 0; j < nq; ++j) {
      q[j].level = b.level[j][i];
      q[j].x0 = b.x0[j][i];
      q[j].x1 = b.x1[j][i];
      q[j].y0 = b.y0[j][i];
      q[j].y1 = b.y1[j][i];
    }
    issue_timed<kFront>(p, nullptr, 1, 4 * nq,
                        [&](uint64_t start) { return fetch_.lookup_quads<L>(q, nq, tex, start); });
  }
}

template <int kQuads>
void TextureUnit::timed_run(const Fragment* f, size_t first, size_t end, Path& p,
                            const LinearBatch& b) {
  // The look-ups of fragments [first, end) in order (each fragment's distinct lines in order
  // of first use), the lines that missed listed per fragment: missed_[missed_end_[i − 1] ..
  // missed_end_[i]) for fragment i (missed_end_[first − 1] read as 0).
  constexpr int kTaps = 4 * kQuads;
  uint64_t* const missed = batch_missed_.data();
  uint32_t* const missed_end = batch_missed_end_.data() + 1;
  missed_end[static_cast<ptrdiff_t>(first) - 1] = 0;
  {
    TextureCache::Run run(fetch_.l1());
    uint32_t m = 0;
    for (size_t i = first; i < end; ++i) {
      for (auto bits = static_cast<uint32_t>(b.first_use[i]); bits != 0; bits &= bits - 1) {
        const auto line = static_cast<uint64_t>(b.line[std::countr_zero(bits)][i]);
        if (!run.access(line)) missed[m++] = line;
      }
      missed_end[i] = m;
    }
  }
  fetch_.count_texels(kTaps * static_cast<uint64_t>(end - first));
  // Then the clocked pipeline, in runs of one frame (a new frame takes the cycles of the
  // fragments before it), counted as count_fragment would.
  const uint32_t cache_ii = fetch_.extra_ii(kTaps);
  const uint32_t blend_ii = p.stages.blend->extra_ii(1);
  for (size_t i = first; i < end;) {
    if (frames_.empty() || frames_.back().frame != f[i].frame) new_frame(f[i]);
    const uint32_t frame = f[i].frame;
    size_t e = i + 1;
    while (e < end && f[e].frame == frame) ++e;
    frames_.back().fragments += e - i;
    pipe_->issue_run<kStages>(
        e - i, [&](size_t k, auto stage, uint64_t start) __attribute__((always_inline)) {
          constexpr int s = decltype(stage)::value;
          ItemCost c;
          if constexpr (s == kCache) {
            c.extra_ii = cache_ii;
            const size_t j = i + k;
            const uint32_t m0 = missed_end[static_cast<ptrdiff_t>(j) - 1], m1 = missed_end[j];
            if (m1 != m0) c.extra_latency = fetch_.read_misses(missed + m0, m1 - m0, start);
          } else if constexpr (s == kBlend) {
            c.extra_ii = blend_ii;
          }
          return c;
        });
    i = e;
  }
  const uint64_t done = end - first;
  p.fragments += done;
  fragments_ += done;
  p.stages.address->count_single_probes(done);
}

void TextureUnit::finish_functional_batch(const Fragment* f, size_t n, Path& p,
                                          const LinearBatch& b, Rgba* out) {
  const bool quad_merge = fetch_.quad_merge();
  if (b.all_done && b.one_frame && !quad_merge && n > 0) {  // the common case, counted at once
    if (frames_.empty() || frames_.back().frame != f[0].frame) new_frame(f[0]);
    frames_.back().fragments += n;
    p.fragments += n;
    fragments_ += n;
    p.stages.address->count_single_probes(n);
    return;
  }
  // count_fragment per done fragment, with the sums kept in locals: the frame's count is
  // added when the frame changes or an undone fragment (counted by its own kernel) comes.
  uint64_t done = 0, pending = 0;
  bool have_frame = !frames_.empty();
  uint32_t frame = have_frame ? frames_.back().frame : 0;
  for (size_t i = 0; i < n; ++i) {
    if (!b.done[i]) {
      if (pending) frames_.back().fragments += pending;
      pending = 0;
      out[i] = filter_fragment(f[i], p, nullptr);  // its own texture, the scalar kernel
      frame = frames_.back().frame;
      have_frame = true;
      continue;
    }
    ++done;
    if (quad_merge) fetch_.note_quad(f[i]);
    if (!have_frame || frame != f[i].frame) {
      if (pending) frames_.back().fragments += pending;
      pending = 0;
      new_frame(f[i]);
      frame = f[i].frame;
      have_frame = true;
    }
    ++pending;
  }
  if (pending) frames_.back().fragments += pending;
  p.fragments += done;
  fragments_ += done;
  p.stages.address->count_single_probes(done);
}

template <int kFront>
TextureUnit::BatchKernel TextureUnit::pick_batch_kernel(FilterMode filter, TexelLayout layout) {
  constexpr FilterMode kBi = FilterMode::Bilinear, kTri = FilterMode::Trilinear;
  const bool tri = filter == kTri;
  switch (layout) {
    case TexelLayout::Linear:
      return tri ? &TextureUnit::batch_linear<kTri, TexelLayout::Linear, kFront>
                 : &TextureUnit::batch_linear<kBi, TexelLayout::Linear, kFront>;
    case TexelLayout::Tiled4x4:
      return tri ? &TextureUnit::batch_linear<kTri, TexelLayout::Tiled4x4, kFront>
                 : &TextureUnit::batch_linear<kBi, TexelLayout::Tiled4x4, kFront>;
    case TexelLayout::Morton:
      return tri ? &TextureUnit::batch_linear<kTri, TexelLayout::Morton, kFront>
                 : &TextureUnit::batch_linear<kBi, TexelLayout::Morton, kFront>;
  }
  return nullptr;
}

template <int kFront>
TextureUnit::Kernel TextureUnit::pick_kernel(FilterMode filter, TexelLayout layout, bool quads,
                                             bool layered) {
  if (layered) return &TextureUnit::process_layered<kFront>;
  if (!quads) return &TextureUnit::process_any<kFront>;
  constexpr FilterMode kBi = FilterMode::Bilinear, kTri = FilterMode::Trilinear;
  const bool tri = filter == kTri;
  switch (layout) {
    case TexelLayout::Linear:
      return tri ? &TextureUnit::process_linear<kTri, TexelLayout::Linear, kFront>
                 : &TextureUnit::process_linear<kBi, TexelLayout::Linear, kFront>;
    case TexelLayout::Tiled4x4:
      return tri ? &TextureUnit::process_linear<kTri, TexelLayout::Tiled4x4, kFront>
                 : &TextureUnit::process_linear<kBi, TexelLayout::Tiled4x4, kFront>;
    case TexelLayout::Morton:
      return tri ? &TextureUnit::process_linear<kTri, TexelLayout::Morton, kFront>
                 : &TextureUnit::process_linear<kBi, TexelLayout::Morton, kFront>;
  }
  return &TextureUnit::process_any<kFront>;
}

TextureUnit::Kernel TextureUnit::choose_kernel(const Path& p, bool layered) const {
  const MaterialStages& st = p.stages;
  if (st.filter) return layered ? nullptr : &TextureUnit::process_filter;
  const FilterMode filter = st.address->filter();
  const bool linear = filter != FilterMode::Nearest;
  // Border taps read no texel: the quad kernels, which read four, leave them to the taps path.
  const bool quads = linear && !st.address->gen().config().uses_border() &&
                     st.blend->blend().quads_in_one_group(filter == FilterMode::Trilinear ? 2 : 1);
  const TexelLayout layout = textures_.layout();
  if (!pipe_) return pick_kernel<-1>(filter, layout, quads, layered);
  if (two_step_fixed_) {
    switch (front_) {
      case 0:
        return pick_kernel<kTwoStep>(filter, layout, quads, layered);
      case 1:
        return pick_kernel<kTwoStep + 1>(filter, layout, quads, layered);
      default:
        return pick_kernel<kTwoStep + kMaxFront>(filter, layout, quads, layered);
    }
  }
  if (!sampler_only_ || defer_) return pick_kernel<kAnyStages>(filter, layout, quads, layered);
  switch (front_) {
    case 0:
      return pick_kernel<0>(filter, layout, quads, layered);
    case 1:
      return pick_kernel<1>(filter, layout, quads, layered);
    default:
      return pick_kernel<kMaxFront>(filter, layout, quads, layered);
  }
}

void TextureUnit::check_timing_invariants() const {
  if (!pipe_) return;
  // The run ends at the last exit or at a stage's last issue slot, whichever is later (the
  // last items' slots can outlast the run: a triangle's or row's set-up, and the front-end
  // cycles of dropped fragments, are charged as extra issue cycles after a fragment).
  const uint64_t cycles = pipe_->run_end();
  auto fail = [&](const std::string& what, uint64_t need) {
    throw std::logic_error("timing invariant violated: " + what + " needs " + std::to_string(need) +
                           " cycles but the run took " + std::to_string(cycles));
  };
  for (int s = 0; s < pipe_->stage_count(); ++s) {
    const uint64_t lanes = std::max<uint32_t>(1, pipe_->config(s).timing.lanes);
    const uint64_t busy = pipe_->stats(s).busy;
    if (cycles < busy / lanes) fail("stage '" + pipe_->config(s).name + "'", busy / lanes);
  }
  // A unit of several shares its DRAM: UnitArray checks it against the last unit's cycles.
  const uint64_t dram_busy = own_memory_ ? mem_->dram_totals().busy_cycles : 0;
  if (cycles < dram_busy) fail("the DRAM channel", dram_busy);
}

std::vector<BlockUse> TextureUnit::material_blocks(int material) const {
  const Path& p = paths_[static_cast<size_t>(material)];
  StageReport r{mats_[static_cast<size_t>(material)].name, tech_, p.fragments};
  std::vector<BlockUse> out;
  for (const auto& s : p.stages.all) s->rows(r, out);
  // The sRGB decoder: per texel read before the filter, per fragment after it.
  if (p.srgb_fragments > 0)
    r.add(out, srgb_.name(), srgb_.arithmetic(), srgb_.timing(tech_),
          srgb_.ops(p.srgb_fragments, p.srgb_texels));
  return out;
}

std::vector<BlockUse> TextureUnit::blocks() const {
  // One entry per hardware unit: materials share a unit when they use the same block with the
  // same arithmetic. A block used with two configurations is two units, told apart by their
  // materials ("filter.ewa[floor]").
  std::map<std::pair<std::string, std::string>, BlockUse> by;
  std::map<std::string, int> configs;
  uint64_t texels = 0;
  for (int i = 0; i < material_count(); ++i) {
    for (const BlockUse& u : material_blocks(i)) {
      auto [it, fresh] = by.try_emplace({u.name, u.arithmetic}, u);
      BlockUse& b = it->second;
      if (fresh) {
        ++configs[u.name];
      } else {
        if (u.timing.latency >= b.timing.latency) b.timing = u.timing;
        b.ops += u.ops;
        b.texels += u.texels;
        b.materials.push_back(u.materials.front());
      }
      texels += u.texels;
    }
  }
  std::vector<BlockUse> out;
  for (auto& [k, v] : by) {
    if (configs[v.name] > 1) {
      std::string mats;
      for (const auto& m : v.materials) mats += (mats.empty() ? "" : ",") + m;
      v.name += "[" + mats + "]";
    }
    out.push_back(v);
  }
  std::vector<std::string> all;
  for (const auto& m : mats_) all.push_back(m.name);
  out.push_back(fetch_.row(texels, all));
  // The texel decoders: one block per compressed format decoded, its operations per block.
  const PerCompressedFormat decoded = decoded_blocks();
  for (int f = 0; f < kCompressedFormats; ++f) {
    const uint64_t n = decoded[static_cast<size_t>(f)];
    if (n == 0) continue;
    const auto cf = static_cast<CompressedFormat>(f);
    BlockUse b;
    b.name = decoder_name(cf);
    b.arithmetic = decoder_arithmetic(cf);
    b.timing = decoder_timing(cf, tech_);
    b.ops = decoder_ops(cf) * n;
    b.materials = all;
    out.push_back(std::move(b));
  }
  // Measured areas (e.g. LUTs of the real RTL) replace derived ones, by the reported name.
  for (BlockUse& b : out) b.timing.area = tech_.block_area_or(b.name, b.timing.area);
  return out;
}

}  // namespace texsim
