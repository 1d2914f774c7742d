#include "pipeline/scene/scene_models.h"

#include <filesystem>
#include <map>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "pipeline/scene/model_loader.h"
#include "pipeline/scene/scene_meshes.h"
#include "pipeline/scene/scene_values.h"

namespace texsim {

namespace {

std::string at(const std::string& src, const toml::node& n) { return source_at(src, n); }

bool material_named(const Scene& s, const std::string& name) {
  for (const SceneMaterial& m : s.materials)
    if (m.name == name) return true;
  return false;
}

// The file's materials used by the model's faces, each a texsim texture and material; returns
// the texsim material of every face.
std::vector<int> file_materials(const Model& model, const ConfigReader& r, const toml::node& e,
                                const std::string& stem, Scene& s) {
  auto effects = std::make_shared<toml::table>();
  if (r.table().contains("effects")) {
    const toml::table* fx = r.subtable("effects");
    if (!fx) r.fail("effects", "expected a table of effects, as a material has");
    *effects = *fx;
    for (const char* k : {"texture", "object_space", "budget"}) {
      if (fx->contains(k)) r.fail("effects", std::string("'") + k + "' is not allowed here");
    }
  }
  s.model_effects.push_back(effects);
  std::map<int, int> made;  // file material -> texsim material
  std::vector<int> faces(model.triangle_material.size());
  for (size_t i = 0; i < faces.size(); ++i) {
    const int fm = model.triangle_material[i];
    auto it = made.find(fm);
    if (it == made.end()) {
      const ModelMaterial& mm = model.materials[static_cast<size_t>(fm)];
      const std::string label = mm.name.empty() ? std::to_string(fm) : mm.name;
      if (mm.texture.empty()) {
        std::string what = stem;
        what.append(": the file's material '").append(label);
        what.append("' has no diffuse texture file: give the entry a 'material'");
        throw InputError(at(s.path, e), what);
      }
      std::string base = stem;
      base.append(".").append(label);
      std::string name = base;
      for (int n = 2; material_named(s, name); ++n) name = base + "#" + std::to_string(n);
      SceneTexture t;
      t.name = name;
      t.source = std::filesystem::absolute(mm.texture).lexically_normal().string();
      t.where = at(s.path, e);
      t.where.append(": texture '").append(mm.texture);
      t.where.append("' of the model's material '").append(label).append("'");
      s.textures.push_back(std::move(t));
      SceneMaterial m;
      m.name = name;
      m.texture = static_cast<int>(s.textures.size() - 1);
      m.effects = effects.get();
      m.line = static_cast<int>(e.source().begin.line);
      m.column = static_cast<int>(e.source().begin.column);
      s.materials.push_back(std::move(m));
      it = made.emplace(fm, static_cast<int>(s.materials.size() - 1)).first;
    }
    faces[i] = it->second;
  }
  return faces;
}

void parse_model(const toml::node& e, int index, Scene& s) {
  if (!e.is_table()) throw InputError(at(s.path, e), "models: each entry must be a table");
  const ConfigReader r(*e.as_table(), s.path, "models[" + std::to_string(index) + "]");
  r.reject_unknown(
      {"path", "material", "effects", "uv", "position", "rotation", "scale", "uv_scale", "cull"});
  SceneMesh sm;
  sm.model = true;
  sm.source = r.get_string("path", "");
  if (sm.source.empty()) r.fail("path", "expected a model file (glTF, 3DS, OBJ, MD3, ...)");
  const bool own = r.table().contains("material");
  if (own) sm.material = read_material(s, r);
  if (own && r.table().contains("effects"))
    r.fail("effects", "for the file's materials only (without 'material')");
  static const std::vector<std::string_view> kUv = {"file", "planar", "box", "spherical"};
  const int uv = r.get_choice("uv", 0, kUv);
  sm.uv = std::string(kUv[static_cast<size_t>(uv)]);
  const UvProjection proj = uv == 0   ? UvProjection::None
                            : uv == 1 ? UvProjection::Planar
                            : uv == 2 ? UvProjection::Box
                                      : UvProjection::Spherical;
  const MeshPlacement pl = read_placement(r);
  Model model;
  try {
    model = load_model(sm.source, s.base_dir, scene_mesh_budget(s));
  } catch (const InputError& err) {
    throw InputError(at(s.path, e),
                     std::string("models[") + std::to_string(index) + "].path: " + err.what());
  }
  if (proj == UvProjection::None && !model.mesh.has_uvs) {
    r.fail("uv",
           "the model has no texture coordinates (or not on every mesh): give a "
           "projection (\"planar\", \"box\" or \"spherical\")");
  }
  project_uvs(model.mesh, proj);
  const std::string stem = std::filesystem::path(sm.source).stem().string();
  std::vector<int> faces;
  if (!own) {
    faces = file_materials(model, r, e, stem, s);
    sm.material = faces.front();
  }
  append_mesh(model.mesh, pl, own ? nullptr : &faces, std::move(sm), e, s);
}

}  // namespace

void parse_models(const toml::table& root, Scene& s) {
  const toml::node* mn = root.get("models");
  if (!mn) return;
  const toml::array* arr = mn->as_array();
  if (!arr) throw InputError(at(s.path, *mn), "models: expected an array of tables ([[models]])");
  int i = 0;
  for (const toml::node& e : *arr) parse_model(e, i++, s);
}

}  // namespace texsim
