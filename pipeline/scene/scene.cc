#include "pipeline/scene/scene.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"

namespace texsim {

namespace {

std::string at(const std::string& src, const toml::node& n) {
  const auto& b = n.source().begin;
  return src + ":" + std::to_string(b.line) + ":" + std::to_string(b.column);
}

template <int N>
glm::vec<N, double> read_vec(const ConfigReader& r, std::string_view key, glm::vec<N, double> def) {
  const toml::node* n = r.table().get(key);
  if (!n) return def;
  const toml::array* a = n->as_array();
  if (!a || a->size() != N) r.fail(key, "expected an array of " + std::to_string(N) + " numbers");
  glm::vec<N, double> v;
  for (int i = 0; i < N; ++i) {
    const toml::node& e = *a->get(static_cast<size_t>(i));
    if (auto f = e.value_exact<double>())
      v[i] = *f;
    else if (auto k = e.value_exact<int64_t>())
      v[i] = static_cast<double>(*k);
    else
      r.fail_at(e, std::string(key) + ": element " + std::to_string(i) + " is not a number");
    if (!std::isfinite(v[i])) r.fail_at(e, std::string(key) + ": element must be finite");
  }
  return v;
}

}  // namespace

Scene parse_scene(const std::string& text, const std::string& source_name,
                  const std::string& base_dir) {
  Scene s;
  s.path = source_name;
  s.base_dir = base_dir;
  toml::table doc;
  try {
    doc = toml::parse(text, source_name);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw InputError(source_name + ":" + std::to_string(b.line) + ":" + std::to_string(b.column),
                     std::string(e.description()));
  }
  s.root = std::make_shared<toml::table>(std::move(doc));
  const toml::table& root = *s.root;
  ConfigReader top(root, source_name, "scene");
  top.reject_unknown(
      {"output", "camera", "textures", "materials", "planes", "pipeline", "tech", "reference"});

  ConfigReader out = top.sub("output");
  out.reject_unknown({"width", "height", "background"});
  s.width = static_cast<int>(out.get_int("width", s.width, 1, 16384));
  s.height = static_cast<int>(out.get_int("height", s.height, 1, 16384));
  s.background = read_vec<3>(out, "background", s.background);

  ConfigReader cam = top.sub("camera");
  cam.reject_unknown({"position", "look_at", "up", "fov_y", "near"});
  s.camera.position = read_vec<3>(cam, "position", s.camera.position);
  s.camera.look_at = read_vec<3>(cam, "look_at", s.camera.look_at);
  s.camera.up = read_vec<3>(cam, "up", s.camera.up);
  s.camera.fov_y_deg = cam.get_double("fov_y", s.camera.fov_y_deg);
  s.camera.near = cam.get_double("near", s.camera.near);
  if (s.camera.fov_y_deg <= 0 || s.camera.fov_y_deg >= 179)
    cam.fail("fov_y", "must be in (0, 179) degrees");
  if (s.camera.near <= 0) cam.fail("near", "must be > 0");
  {
    const glm::dvec3 f = s.camera.look_at - s.camera.position;
    const glm::dvec3 c{f.y * s.camera.up.z - f.z * s.camera.up.y,
                       f.z * s.camera.up.x - f.x * s.camera.up.z,
                       f.x * s.camera.up.y - f.y * s.camera.up.x};
    if (f.x * f.x + f.y * f.y + f.z * f.z == 0 || c.x * c.x + c.y * c.y + c.z * c.z == 0) {
      cam.fail("look_at", "camera direction is zero or parallel to 'up'");
    }
  }

  // Textures: [textures.NAME] source = "..."
  std::vector<std::string> tex_names;
  if (const toml::table* t = top.subtable("textures")) {
    for (const auto& [k, v] : *t) {
      if (!v.is_table())
        throw InputError(at(source_name, v),
                         "textures." + std::string(k.str()) + ": expected a table");
      ConfigReader tr(*v.as_table(), source_name, "textures." + std::string(k.str()));
      tr.reject_unknown({"source"});
      const std::string src = tr.get_string("source", "");
      if (src.empty())
        throw InputError(at(source_name, v),
                         "textures." + std::string(k.str()) + ": missing 'source'");
      s.textures.push_back({std::string(k.str()), src});
    }
  }
  auto texture_index = [&](const std::string& name, const toml::node& where) {
    for (size_t i = 0; i < s.textures.size(); ++i)
      if (s.textures[i].name == name) return static_cast<int>(i);
    throw InputError(at(source_name, where), "unknown texture '" + name + "'");
  };

  // Materials: [materials.NAME] texture = "...", and one table per effect.
  if (const toml::table* t = top.subtable("materials")) {
    for (const auto& [k, v] : *t) {
      const std::string name(k.str());
      if (!v.is_table())
        throw InputError(at(source_name, v), "materials." + name + ": expected a table");
      const toml::table& mt = *v.as_table();
      // The effect tables are the texture unit's to check (its effect registry).
      ConfigReader mr(mt, source_name, "materials." + name);
      SceneMaterial m;
      m.name = name;
      m.line = static_cast<int>(v.source().begin.line);
      m.column = static_cast<int>(v.source().begin.column);
      const toml::node* tn = mt.get("texture");
      if (!tn) throw InputError(at(source_name, v), "materials." + name + ": missing 'texture'");
      if (!tn->is_string()) mr.fail("texture", "expected a texture name");
      m.texture = texture_index(*tn->value<std::string>(), *tn);
      m.effects = &mt;
      s.materials.push_back(std::move(m));
    }
  }
  auto material_index = [&](const std::string& name, const toml::node& where) {
    for (size_t i = 0; i < s.materials.size(); ++i)
      if (s.materials[i].name == name) return static_cast<int>(i);
    throw InputError(at(source_name, where), "unknown material '" + name + "'");
  };

  // Planes: [[planes]]
  if (const toml::node* pn = root.get("planes")) {
    const toml::array* arr = pn->as_array();
    if (!arr)
      throw InputError(at(source_name, *pn), "planes: expected an array of tables ([[planes]])");
    for (const toml::node& e : *arr) {
      if (!e.is_table()) throw InputError(at(source_name, e), "planes: each entry must be a table");
      ConfigReader pr(*e.as_table(), source_name,
                      "planes[" + std::to_string(s.planes.size()) + "]");
      pr.reject_unknown({"material", "origin", "edge_u", "edge_v", "uv_scale", "uv_offset"});
      ScenePlane p;
      const toml::node* mn = e.as_table()->get("material");
      if (!mn || !mn->is_string()) pr.fail("material", "expected a material name");
      p.material = material_index(*mn->value<std::string>(), *mn);
      p.origin = read_vec<3>(pr, "origin", p.origin);
      p.edge_u = read_vec<3>(pr, "edge_u", p.edge_u);
      p.edge_v = read_vec<3>(pr, "edge_v", p.edge_v);
      p.uv_scale = read_vec<2>(pr, "uv_scale", p.uv_scale);
      p.uv_offset = read_vec<2>(pr, "uv_offset", p.uv_offset);
      const glm::dvec3 a = p.edge_u, b = p.edge_v;
      const glm::dvec3 n{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
      if (n.x * n.x + n.y * n.y + n.z * n.z == 0)
        pr.fail("edge_v", "plane edges are parallel or zero (degenerate plane)");
      s.planes.push_back(p);
    }
  }

  ConfigReader ref = top.sub("reference");
  ref.reject_unknown({"supersamples"});
  s.reference_supersamples =
      static_cast<int>(ref.get_int("supersamples", s.reference_supersamples, 1, 64));
  s.pipeline = top.subtable("pipeline");
  if (const toml::table* t = top.subtable("tech")) s.tech = TechTable::from_toml(*t, source_name);
  return s;
}

Scene load_scene(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open scene file");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string dir = std::filesystem::path(path).parent_path().string();
  return parse_scene(ss.str(), path, dir);
}

const char* default_scene_text() {
  return R"(# Built-in default scene: a long checkerboard floor seen at a grazing angle (minification
# and anisotropy), a noise-textured wall and a grid on a tilted panel.
[output]
width = 320
height = 240
background = [0.02, 0.02, 0.05]

[camera]
position = [0.0, 1.2, 0.0]
look_at = [0.0, 0.6, -10.0]
fov_y = 60.0

[textures.checker]
source = "procedural:checker?size=512&cells=16"
[textures.noise]
source = "procedural:noise?size=256&cells=8"
[textures.grid]
source = "procedural:grid?size=256&cells=8&line=3"

[materials.floor]
texture = "checker"
filter = { mode = "trilinear", address = "wrap" }
[materials.wall]
texture = "noise"
filter = { mode = "trilinear", address = "mirror" }
[materials.panel]
texture = "grid"
filter = { mode = "bilinear", address = "clamp" }

[[planes]]
material = "floor"
origin = [-40.0, 0.0, -0.5]
edge_u = [80.0, 0.0, 0.0]
edge_v = [0.0, 0.0, -80.0]
uv_scale = [20.0, 20.0]

[[planes]]
material = "wall"
origin = [-12.0, 0.0, -30.0]
edge_u = [24.0, 0.0, 0.0]
edge_v = [0.0, 8.0, 0.0]
uv_scale = [3.0, 1.0]

[[planes]]
material = "panel"
origin = [1.0, 0.3, -4.0]
edge_u = [1.6, 0.0, -1.2]
edge_v = [0.0, 1.4, 0.0]

[reference]
supersamples = 8
)";
}

Scene default_scene() { return parse_scene(default_scene_text(), "<built-in default scene>", ""); }

}  // namespace texsim
