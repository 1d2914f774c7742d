#include "pipeline/texture/effect_registry.h"

#include <map>

#include "blocks/base/sample_op.h"
#include "blocks/texture/footprint/feline_filter.h"
#include "blocks/texture/footprint/multi_probe_filter.h"
#include "blocks/texture/footprint/spaf_filter.h"
#include "blocks/texture/sampler/fixed_sampler.h"
#include "pipeline/scene/scene.h"

namespace texsim {

namespace {

constexpr std::string_view kFootprint = "footprint filter";

void build_filter(const ConfigReader& r, std::string_view key, MaterialSetup& m) {
  m.filter = TexelAddressGen::Config::from_toml(r.sub(key));
}

// `filter.arithmetic = "fixed"`: the material must be one FixedSampler covers, with the sampler
// alone in the unit (no footprint filter, coordinate unit, relief or lighting).
void check_fixed_arithmetic(const ConfigReader& r, MaterialSetup& m) {
  const ConfigReader f = r.sub("filter");
  m.arithmetic_where = f.where(f.table().get("arithmetic"));
  std::string why;
  if (m.footprint) why = std::string("a footprint filter (") + m.footprint->name() + ")";
  if (m.coords) why = "a coordinate unit";
  if (m.relief) why = "relief";
  if (m.lighting) why = "lighting";
  if (why.empty() && FixedSampler::covers(m.filter, m.lod, &why)) return;
  f.fail("arithmetic", "\"fixed\" (FixedSampler, the RTL sampler's arithmetic) does not cover " +
                           why + "; use \"float\"");
}

void build_lod(const ConfigReader& r, std::string_view key, MaterialSetup& m) {
  m.lod = LodUnit::Config::from_toml(r.sub(key));
}

void build_coords(const ConfigReader& r, std::string_view key, MaterialSetup& m) {
  m.coords = std::make_shared<const CoordUnit>(CoordUnitConfig::from_toml(r.sub(key)));
}

void build_ewa(const ConfigReader& r, std::string_view key, MaterialSetup& m) {
  m.footprint = make_ewa_filter(r.sub(key));
}

template <class Block>
void build_footprint(const ConfigReader& r, std::string_view key, MaterialSetup& m) {
  m.footprint = make_footprint_filter<Block>(r.sub(key));
}

void build_relief(const ConfigReader& r, std::string_view key, MaterialSetup& m) {
  m.relief = ReliefSetup::from_toml(r.sub(key));
}

void build_lighting(const ConfigReader& r, std::string_view key, MaterialSetup& m) {
  m.lighting = LightingSetup::from_toml(r.sub(key));
}

// The id of texture `name` that effect `key` names in its `field`.
int bind_texture(const ConfigReader& r, std::string_view key, std::string_view field,
                 const std::string& name, const std::map<std::string, int>& textures) {
  const auto it = textures.find(name);
  if (it != textures.end()) return it->second;
  std::string have;
  for (const auto& [n, id] : textures) have += (have.empty() ? "'" : ", '") + n + "'";
  r.sub(key).fail(field, "no texture named '" + name +
                             "' (textures: " + (have.empty() ? std::string("none") : have) + ")");
}

// `object_space` selects a pipeline variant, not a block of the texture unit: the scene reads
// its table (pipeline/scene/object_space_config.h).
void build_object_space(const ConfigReader& /*r*/, std::string_view /*key*/, MaterialSetup& /*m*/) {
}

void build_operation(const ConfigReader& r, std::string_view key, MaterialSetup& m) {
  m.operation = OperationSetup::from_toml(r.sub(key));
}

// `sampler = "NAME"`: the material's lod and filter state from the scene's sampler NAME.
void bind_sampler(const ConfigReader& r, MaterialSetup& m) {
  const toml::node* n = r.table().get("sampler");
  if (!n) return;
  if (!n->is_string()) r.fail("sampler", "expected the name of a [samplers.NAME] table");
  const std::string name = *n->value<std::string>();
  for (std::string_view k : {"filter", "lod"}) {
    if (r.table().contains(k)) {
      r.fail(k, "the material takes its filter and LOD state from sampler '" + name +
                    "'; give these keys there");
    }
  }
  std::string have;
  for (size_t i = 0; m.samplers && i < m.samplers->size(); ++i) {
    const SamplerSetup& s = (*m.samplers)[i];
    if (s.name == name) {
      m.sampler = static_cast<int>(i) + 1;
      m.filter = s.filter;
      m.lod = s.lod;
      return;
    }
    have += (have.empty() ? "'" : ", '") + s.name + "'";
  }
  r.fail("sampler", "no sampler named '" + name +
                        "' (samplers: " + (have.empty() ? std::string("none") : have) + ")");
}

// The material's operation against its sampler and filter.
void check_operation(const ConfigReader& r, const MaterialSetup& m) {
  if (!m.operation) {
    // The material's fragments ask the implicit-LOD sample, which Vulkan refuses there.
    if (m.filter.unnormalized) {
      r.fail("sampler",
             "the sampler is unnormalised, which serves explicit LOD 0 only; the material "
             "asks the implicit-LOD sample (give operation = { op = \"lod\", "
             "lod = 0.0 })");
    }
    return;
  }
  if (m.footprint && m.operation->op != SampleOp::kSample) {
    r.sub("operation")
        .fail("op", std::string("a footprint filter (") + m.footprint->name() +
                        ") serves implicit-LOD samples only");
  }
  if (m.filter.unnormalized) {
    Fragment f;
    m.operation->apply(f);
    if (const std::string why = unnormalized_refusal(f); !why.empty())
      r.fail("operation", why + " (the material's sampler is unnormalised)");
  }
}

void build_raster(const ConfigReader& r, std::string_view key, MaterialSetup& m) {
  m.raster = RasterSetup::from_toml(r.sub(key));
}

void build_lookup(const ConfigReader& r, std::string_view key, MaterialSetup& m) {
  m.lookup = LayeredLookup::from_toml(r.sub(key));
}

}  // namespace

RasterSetup RasterSetup::from_toml(const ConfigReader& r) {
  RasterSetup s;
  s.method = static_cast<Method>(r.get_choice("method", 0, {"edge", "rect_scan"}));
  if (s.method == Method::Edge) {
    s.edge = EdgeRasterizer::Config::from_toml(r.for_block("raster.edge", {"method"}));
  } else {
    s.coords = static_cast<Coords>(r.get_choice("coords", 0, {"constant_depth", "exact"}));
    s.rect_scan = RectScanRasterizer::Config::from_toml(
        r.for_block("raster.rect_scan", {"method", "coords"}));
  }
  return s;
}

const std::vector<Effect>& effect_registry() {
  static const std::vector<Effect> effects = {
      {"filter", "", build_filter},
      {"lod", "", build_lod},
      {"coords", "", build_coords},
      {"raster", "", build_raster},
      {"relief", "", build_relief},
      {"lighting", "", build_lighting},
      {"object_space", "", build_object_space},
      {"lookup", "", build_lookup},
      {"operation", "", build_operation},
      {"ewa", kFootprint, build_ewa},
      {"multi_probe", kFootprint, build_footprint<MultiProbeFilter>},
      {"feline", kFootprint, build_footprint<FelineFilter>},
      {"spaf", kFootprint, build_footprint<SpafFilter>},
  };
  return effects;
}

MaterialSetup material_from_toml(const std::string& name, int texture, const toml::table& effects,
                                 const std::string& source,
                                 const std::map<std::string, int>* textures,
                                 const std::shared_ptr<const SamplerTable>& samplers) {
  const ConfigReader r(effects, source, "materials." + name);
  // budget: the tuner's; sampler: a scene sampler's name.
  std::vector<std::string_view> keys = {"texture", "budget", "sampler"};
  for (const Effect& e : effect_registry()) keys.push_back(e.key);
  r.reject_unknown(keys);
  for (const auto& [k, v] : effects) {
    if (k.str() != "texture" && k.str() != "budget" && k.str() != "sampler" && !v.is_table())
      r.fail(k.str(), "expected a table of effect settings");
  }
  MaterialSetup m;
  m.name = name;
  m.texture = texture;
  m.samplers = samplers;
  std::map<std::string_view, std::string_view> chosen;  // group -> the effect that took it
  for (const Effect& e : effect_registry()) {
    if (!effects.contains(e.key)) continue;
    if (!e.group.empty()) {
      const auto [it, fresh] = chosen.try_emplace(e.group, e.key);
      if (!fresh) {
        r.fail(e.key, "a material takes one " + std::string(e.group) + "; it already has '" +
                          std::string(it->second) + "'");
      }
    }
    e.build(r, e.key, m);
  }
  bind_sampler(r, m);
  check_operation(r, m);
  if (m.coords && !m.coords->has_derivs() &&
      (m.footprint || m.filter.filter == FilterMode::Trilinear)) {
    r.sub("coords").fail("derivs", std::string("'none' leaves the ") +
                                       (m.footprint ? m.footprint->name() : "filter.trilinear") +
                                       " of this material without the derivatives it needs");
  }
  if (m.filter.fixed_arithmetic) check_fixed_arithmetic(r, m);
  if (m.lighting) m.lighting->bind_terrain(r.sub("lighting"), m.relief ? &*m.relief : nullptr);
  if (textures && m.relief) {
    m.relief->height_tex =
        bind_texture(r, "relief", "height_texture", m.relief->height_texture, *textures);
  }
  if (textures && m.lighting && m.lighting->normal != LightingSetup::Normal::Flat) {
    m.lighting->normal_tex =
        bind_texture(r, "lighting", "normal_texture", m.lighting->normal_texture, *textures);
  }
  if (m.lookup && (m.coords || m.relief || effects.contains("object_space"))) {
    r.fail("lookup",
           "a layered texture's lookup is not combined with coords, relief or "
           "object_space (they compute a 2-D texture's coordinates)");
  }
  if (m.coords && m.raster.method != RasterSetup::Method::Edge) {
    r.sub("raster").fail("method",
                         "a coordinate unit walks the edge-function rasteriser's rows; "
                         "rect_scan drives its own constant-depth coordinates (raster.coords) "
                         "and is for materials without `coords`");
  }
  return m;
}

std::shared_ptr<const SamplerTable> build_samplers(const Scene& scene) {
  if (scene.samplers.empty()) return nullptr;
  auto table = std::make_shared<SamplerTable>();
  table->reserve(scene.samplers.size());
  for (const SceneSampler& s : scene.samplers) {
    table->push_back(
        SamplerSetup::from_toml(s.name, ConfigReader(*s.table, scene.path, "samplers." + s.name)));
  }
  return table;
}

void check_sampler_texture(const Scene& scene, const SceneMaterial& sm, const MaterialSetup& m) {
  const SceneTextureType type = scene.textures[static_cast<size_t>(sm.texture)].type;
  if (type == SceneTextureType::Tex2D) return;
  const ConfigReader r(*sm.effects, scene.path, "materials." + sm.name);
  const std::string tex = "texture '" + scene.textures[static_cast<size_t>(sm.texture)].name +
                          "' is a " + to_string(type) + " texture";
  if (m.footprint) {
    r.fail("texture", std::string("a footprint filter (") + m.footprint->name() +
                          ") samples 2-D textures only, and " + tex);
  }
  if (type == SceneTextureType::Volume3D && m.operation && m.operation->op == SampleOp::kGather)
    r.fail("operation", "a gather reads 2-D and cube images only, and " + tex);
  if (!m.filter.unnormalized && !m.filter.reduces()) return;
  const std::string_view key = sm.effects->contains("sampler") ? "sampler" : "filter";
  if (m.filter.unnormalized) {
    r.fail(key, "the sampler is unnormalised, and " + tex +
                    " (Vulkan: unnormalised coordinates read 1-D or 2-D image views of one "
                    "layer only)");
  }
  r.fail(key, "the sampler compares or reduces (compare/reduction), and " + tex +
                  ": the cube, array and 3-D paths blend their taps and have no texel reducer");
}

std::vector<MaterialSetup> build_materials(const Scene& scene) {
  std::map<std::string, int> textures;
  for (size_t i = 0; i < scene.textures.size(); ++i)
    textures[scene.textures[i].name] = static_cast<int>(i);
  const std::shared_ptr<const SamplerTable> samplers = build_samplers(scene);
  std::vector<MaterialSetup> mats;
  mats.reserve(scene.materials.size());
  for (const SceneMaterial& m : scene.materials) {
    mats.push_back(
        material_from_toml(m.name, m.texture, *m.effects, scene.path, &textures, samplers));
    check_sampler_texture(scene, m, mats.back());
  }
  return mats;
}

}  // namespace texsim
