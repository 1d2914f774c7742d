#include "pipeline/scene/scene.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "blocks/base/input_file.h"
#include "blocks/geometry/aviation_camera.h"
#include "pipeline/scene/compressed_loader.h"
#include "pipeline/scene/procedural_texture.h"
#include "pipeline/scene/scene_meshes.h"
#include "pipeline/scene/scene_models.h"
#include "pipeline/scene/scene_overrides.h"
#include "pipeline/scene/scene_values.h"

namespace texsim {

namespace {

std::string at(const std::string& src, const toml::node& n) { return source_at(src, n); }

void parse_output(const ConfigReader& top, Scene& s) {
  const ConfigReader out = top.sub("output");
  out.reject_unknown({"width", "height", "background", "frames"});
  s.frames = static_cast<int>(out.get_int("frames", 1, 1, 10000));
  s.width = static_cast<int>(out.get_int("width", s.width, 1, 16384));
  s.height = static_cast<int>(out.get_int("height", s.height, 1, 16384));
  s.background = read_vec<3>(out, "background", s.background);
}

// The camera's orientation from aviation angles (seed 003 §2.1): the view axis and the screen's
// up direction are columns u and v of A = Aψ·Aϑ·Aγ. `eye_offset` h (v frame) moves the eye off
// `position`, the vehicle's centre of gravity: r_h = r0 + A·h (eq. 2.16, 2.21).
void aviation_pose(const ConfigReader& cam, Camera& c) {
  for (const char* k : {"look_at", "up"}) {
    if (cam.table().contains(k)) cam.fail(k, "not together with yaw/pitch/roll");
  }
  const glm::dmat3 a = aviation_rotation(cam.get_double("yaw", 0), cam.get_double("pitch", 0),
                                         cam.get_double("roll", 0));
  if (cam.table().contains("eye_offset")) c.position += a * read_vec<3>(cam, "eye_offset", {});
  c.look_at = c.position + a[0];
  c.up = a[1];
}

// The camera, imaging the output's width × height.
void parse_camera(const ConfigReader& top, Scene& s, Camera& c) {
  const ConfigReader cam = top.sub("camera");
  cam.reject_unknown({"position", "look_at", "up", "yaw", "pitch", "roll", "eye_offset",
                      "projection", "fov_y", "height", "near", "path"});
  s.camera_path = read_camera_path(cam);
  if (!s.camera_path.empty()) {
    // Each key was checked on its own; frame 0 takes the first.
    for (const char* k : {"position", "look_at", "up", "yaw", "pitch", "roll", "eye_offset"}) {
      if (cam.table().contains(k)) cam.fail(k, "not together with path (each key has its pose)");
    }
    c.position = s.camera_path.front().position;
    c.look_at = s.camera_path.front().look_at;
    c.up = s.camera_path.front().up;
  } else if (s.frames > 1) {
    throw InputError(at(s.path, *top.table().get("output")),
                     "output.frames = " + std::to_string(s.frames) +
                         ": several frames need a [camera] path to move along");
  } else {
    c.position = read_vec<3>(cam, "position", c.position);
    if (cam.table().contains("yaw") || cam.table().contains("pitch") ||
        cam.table().contains("roll")) {
      aviation_pose(cam, c);
    } else {
      if (cam.table().contains("eye_offset"))
        cam.fail("eye_offset", "needs yaw/pitch/roll (h is given in the vehicle's frame)");
      c.look_at = read_vec<3>(cam, "look_at", c.look_at);
      c.up = read_vec<3>(cam, "up", c.up);
    }
  }
  c.orthographic = cam.get_choice("projection", 0, {"perspective", "orthographic"}) == 1;
  const double fov_y_deg = cam.get_double("fov_y", 60.0);
  const double view_height = cam.get_double("height", 2.0);
  if (c.orthographic && cam.table().contains("fov_y")) cam.fail("fov_y", "perspective only");
  if (!c.orthographic && cam.table().contains("height")) cam.fail("height", "orthographic only");
  c.near = cam.get_double("near", c.near);
  if (fov_y_deg <= 0 || fov_y_deg >= 179) cam.fail("fov_y", "must be in (0, 179) degrees");
  if (!(view_height > 0) || view_height > 1e9) cam.fail("height", "must be in (0, 1e9]");
  if (c.near <= 0) cam.fail("near", "must be > 0");
  c.tan_half_fov_y = std::tan(static_cast<long double>(fov_y_deg) *
                              3.14159265358979323846264338327950288L / 360.0L);
  c.ortho_half_height = view_height / 2.0L;
  c.width = s.width;
  c.height = s.height;
  const glm::dvec3 f = c.look_at - c.position;
  const glm::dvec3 x{f.y * c.up.z - f.z * c.up.y, f.z * c.up.x - f.x * c.up.z,
                     f.x * c.up.y - f.y * c.up.x};
  if (f.x * f.x + f.y * f.y + f.z * f.z == 0 || x.x * x.x + x.y * x.y + x.z * x.z == 0) {
    cam.fail("look_at", "camera direction is zero or parallel to 'up'");
  }
}

// `compress = { format, encoder, quality }`: the encoder defaults to the one Debian has for the
// format (squish for BC1-BC3, nvtt for BC4/BC5, astcenc for ASTC) or texsim's own (ETC2, EAC,
// BC7); formats no encoder makes (the SNORM ones) come only from files.
SceneTexture::Compress parse_compress(const ConfigReader& tr, const std::string& path,
                                      const std::string& name) {
  if (!tr.subtable("compress")) tr.fail("compress", "expected a table { format = \"…\", ... }");
  const ConfigReader c = tr.sub("compress");
  c.reject_unknown({"format", "encoder", "quality"});
  SceneTexture::Compress out;
  const std::string f = c.get_string("format", "");
  const auto fmt = compressed_format_from_name(f);
  if (!fmt)
    c.fail("format",
           "unknown compressed format '" + f + "' (one of " + compressed_format_names() + ")");
  out.format = *fmt;
  const std::string def = default_encoder(*fmt);
  out.encoder = c.get_string("encoder", def);
  if (!encoder_makes(out.encoder, *fmt)) {
    c.fail(def.empty() ? "format" : "encoder",
           def.empty() ? "no encoder makes '" + f + "' (load it from a .dds or .ktx file)"
                       : "encoder '" + out.encoder + "' cannot make '" + f +
                             "' (squish: bc1_rgb, bc1_rgba, bc2, bc3; nvtt: those and bc4, bc5; "
                             "astcenc: astc_*; texsim: bc7, etc2_rgb8, etc2_rgb8a1, etc2_rgba8, "
                             "eac_r11, eac_rg11)");
  }
  out.quality = c.get_string("quality", "");
  const std::vector<std::string> levels = encoder_qualities(out.encoder);
  if (!out.quality.empty() &&
      std::find(levels.begin(), levels.end(), out.quality) == levels.end()) {
    std::string list;
    for (const auto& l : levels) list += (list.empty() ? "" : ", ") + l;
    c.fail("quality",
           "unknown " + out.encoder + " quality '" + out.quality + "' (one of " + list + ")");
  }
  out.where = at(path, *tr.table().get("compress")) + ": textures." + name + ".compress";
  return out;
}

// A layered texture's `faces` (cube, cube_array) or `layers` (arrays): an array of sources,
// each checked where it stands, written as one "layered:…" source. Sets t.source, t.where.
void parse_layered_texture(const ConfigReader& tr, const Scene& s, SceneTexture& t) {
  const bool cube = t.type == SceneTextureType::Cube || t.type == SceneTextureType::CubeArray;
  const char* key = cube ? "faces" : "layers";
  const char* other = cube ? "layers" : "faces";
  const std::string type = to_string(t.type);
  if (tr.table().contains("source"))
    tr.fail("source", "a " + type + " texture takes its images from '" + key + "', not 'source'");
  if (tr.table().contains(other)) tr.fail(other, "a " + type + " texture has '" + key + "'");
  if (tr.table().contains("compress"))
    tr.fail("compress", "layered textures are not compressed (give 'format' instead)");
  const toml::node* n = tr.table().get(key);
  if (!n) {
    throw InputError(at(s.path, tr.table()), "textures." + t.name + ": a " + type +
                                                 " texture needs '" + key +
                                                 "' (an array of sources)");
  }
  const toml::array* a = n->as_array();
  if (!a) tr.fail(key, "expected an array of sources");
  LayeredSource ls;
  ls.type = t.type;
  for (const toml::node& e : *a) {
    const auto v = e.value_exact<std::string>();
    if (!v || v->empty()) throw InputError(at(s.path, e), std::string(key) + ": expected a source");
    if (v->find(';') != std::string::npos)
      throw InputError(at(s.path, e), std::string(key) + ": a source may not contain ';'");
    const std::string where = at(s.path, e) + ": textures." + t.name + "." + key;
    if (is_procedural_source(*v)) (void)parse_procedural_source(*v, where);
    ls.slices.push_back(*v);
  }
  t.where = at(s.path, *n) + ": textures." + t.name + "." + key;
  t.source = layered_source(ls);
  (void)parse_layered_source(t.source, t.where);  // the slice count the type allows
}

// Textures: [textures.NAME] source = "...", format = "..." (optional, storage_format.h);
// a layered texture: type = "...", faces or layers = [...].
void parse_textures(const ConfigReader& top, Scene& s) {
  const toml::table* t = top.subtable("textures");
  if (!t) return;
  for (const auto& [k, v] : *t) {
    const std::string name(k.str());
    if (!v.is_table()) throw InputError(at(s.path, v), "textures." + name + ": expected a table");
    const ConfigReader tr(*v.as_table(), s.path, "textures." + name);
    tr.reject_unknown({"source", "format", "compress", "type", "faces", "layers"});
    SceneTexture st;
    st.name = name;
    st.type = static_cast<SceneTextureType>(
        tr.get_choice("type", 0, {"2d", "cube", "cube_array", "1d_array", "2d_array", "3d"}));
    if (st.type != SceneTextureType::Tex2D) {
      parse_layered_texture(tr, s, st);
      if (tr.table().contains("format")) {
        const std::string f = tr.get_string("format", "");
        st.format = storage_format_from_name(f);
        if (!st.format)
          tr.fail("format",
                  "unknown texel format '" + f + "' (one of " + storage_format_names() + ")");
      }
      s.textures.push_back(std::move(st));
      continue;
    }
    for (const char* key : {"faces", "layers"})
      if (tr.table().contains(key)) tr.fail(key, "only for layered textures (give 'type')");
    const std::string src = tr.get_string("source", "");
    if (src.empty()) throw InputError(at(s.path, v), "textures." + name + ": missing 'source'");
    const std::string where =
        at(s.path, *v.as_table()->get("source")) + ": textures." + name + ".source";
    // A procedural spec is checked here, where its line:column is known; files are opened
    // only when the textures are loaded (a run with a trace uses the trace's instead).
    if (is_procedural_source(src)) (void)parse_procedural_source(src, where);
    // The one-string form a trace's texture table records is accepted as well.
    const SceneTextureType type =
        is_layered_source(src) ? parse_layered_source(src, where).type : SceneTextureType::Tex2D;
    std::optional<StorageFormat> format;
    if (tr.table().contains("format")) {
      const std::string f = tr.get_string("format", "");
      format = storage_format_from_name(f);
      if (!format)
        tr.fail("format",
                "unknown texel format '" + f + "' (one of " + storage_format_names() + ")");
    }
    std::optional<SceneTexture::Compress> compress;
    if (tr.table().contains("compress")) compress = parse_compress(tr, s.path, name);
    if (compress && format)
      tr.fail("compress", "a texture is either compressed or stored in a 'format', not both");
    if (compress && type != SceneTextureType::Tex2D)
      tr.fail("compress", "layered textures are not compressed (give 'format' instead)");
    s.textures.push_back({name, src, where, format, compress, type});
  }
}

int texture_index(const Scene& s, const std::string& name, const toml::node& where) {
  for (size_t i = 0; i < s.textures.size(); ++i)
    if (s.textures[i].name == name) return static_cast<int>(i);
  throw InputError(at(s.path, where), "unknown texture '" + name + "'");
}

// A material's `budget = { psnr = <dB> }` or `{ nmse = <positive> }`: one of the two.
MaterialBudget parse_material_budget(const ConfigReader& mr) {
  MaterialBudget b;
  if (!mr.table().contains("budget")) return b;
  if (!mr.subtable("budget"))
    mr.fail("budget", "expected a table: { psnr = <dB> } or { nmse = <x> }");
  const ConfigReader br = mr.sub("budget");
  br.reject_unknown({"psnr", "nmse"});
  if (br.table().size() != 1) br.fail("psnr", "expected one of psnr = <dB> or nmse = <x>");
  b.kind = br.table().contains("psnr") ? "psnr" : "nmse";
  b.value = br.get_double(b.kind, 0);
  if (!std::isfinite(b.value) || (b.kind == "nmse" && b.value <= 0))
    br.fail(b.kind, b.kind == "nmse" ? "expected a positive value" : "expected a finite value");
  return b;
}

// Samplers: [samplers.NAME], one table each (its keys are the texture unit's to check).
void parse_samplers(const ConfigReader& top, Scene& s) {
  const toml::table* t = top.subtable("samplers");
  if (!t) return;
  for (const auto& [k, v] : *t) {
    const std::string name(k.str());
    if (!v.is_table()) throw InputError(at(s.path, v), "samplers." + name + ": expected a table");
    s.samplers.push_back({name, v.as_table()});
  }
}

// A material's `lookup` against its texture's type: a cube needs a direction, an array may
// give a layer, a 2-D texture has no lookup (the table's own keys are the effect's to check).
void check_lookup(const ConfigReader& mr, const SceneTexture& t) {
  const toml::table* lk = mr.subtable("lookup");
  const bool cube = t.type == SceneTextureType::Cube || t.type == SceneTextureType::CubeArray;
  const toml::node* dir = lk ? lk->get("direction") : nullptr;
  const bool has_dir = dir && dir->value<std::string>().value_or("none") != "none";
  if (t.type == SceneTextureType::Tex2D && mr.table().contains("lookup"))
    mr.fail("lookup", "texture '" + t.name + "' is 2-D: lookup is for layered textures");
  if (cube && !has_dir) {
    mr.fail(lk ? "lookup" : "texture",
            "texture '" + t.name + "' is a " + to_string(t.type) +
                ": give lookup = { direction = \"reflect\" } or \"view\"");
  }
  if (!cube && has_dir)
    mr.sub("lookup").fail("direction", "texture '" + t.name + "' is not a cube");
  if (lk && lk->contains("r") && t.type != SceneTextureType::Volume3D)
    mr.sub("lookup").fail("r", "texture '" + t.name + "' is not 3-D: r is a 3-D texture's");
}

// Materials: [materials.NAME] texture = "...", and one table per effect. The effect tables are
// the texture unit's to check (its effect registry), but for `object_space`, which selects the
// object-space pipeline for the material and is read here.
void parse_materials(const ConfigReader& top, Scene& s) {
  const toml::table* t = top.subtable("materials");
  if (!t) return;
  for (const auto& [k, v] : *t) {
    const std::string name(k.str());
    if (!v.is_table()) throw InputError(at(s.path, v), "materials." + name + ": expected a table");
    const toml::table& mt = *v.as_table();
    const ConfigReader mr(mt, s.path, "materials." + name);
    SceneMaterial m;
    m.name = name;
    m.line = static_cast<int>(v.source().begin.line);
    m.column = static_cast<int>(v.source().begin.column);
    const toml::node* tn = mt.get("texture");
    if (!tn) throw InputError(at(s.path, v), "materials." + name + ": missing 'texture'");
    if (!tn->is_string()) mr.fail("texture", "expected a texture name");
    m.texture = texture_index(s, *tn->value<std::string>(), *tn);
    check_lookup(mr, s.textures[static_cast<size_t>(m.texture)]);
    m.budget = parse_material_budget(mr);
    m.effects = &mt;
    if (mt.contains("object_space"))
      m.object_space = ObjectSpaceConfig::from_toml(mr.sub("object_space"));
    s.materials.push_back(std::move(m));
  }
}

int material_index(const Scene& s, const std::string& name, const toml::node& where) {
  for (size_t i = 0; i < s.materials.size(); ++i)
    if (s.materials[i].name == name) return static_cast<int>(i);
  throw InputError(at(s.path, where), "unknown material '" + name + "'");
}

ScenePrimitive parse_plane(const toml::node& e, Scene& s) {
  if (!e.is_table()) throw InputError(at(s.path, e), "planes: each entry must be a table");
  const ConfigReader pr(*e.as_table(), s.path,
                        "planes[" + std::to_string(s.primitives.size()) + "]");
  pr.reject_unknown({"material", "origin", "edge_u", "edge_v", "uv_scale", "uv_offset"});
  ScenePrimitive p;
  glm::dvec2 uv_scale{1, 1};
  const toml::node* mn = e.as_table()->get("material");
  if (!mn || !mn->is_string()) pr.fail("material", "expected a material name");
  p.material = material_index(s, *mn->value<std::string>(), *mn);
  p.origin = read_vec<3>(pr, "origin", p.origin);
  p.edge_u = read_vec<3>(pr, "edge_u", p.edge_u);
  p.edge_v = read_vec<3>(pr, "edge_v", p.edge_v);
  uv_scale = read_vec<2>(pr, "uv_scale", uv_scale);
  p.uv_origin = read_vec<2>(pr, "uv_offset", p.uv_origin);
  p.uv_edge_u = {uv_scale.x, 0};
  p.uv_edge_v = {0, uv_scale.y};
  const glm::dvec3 a = p.edge_u, b = p.edge_v;
  const glm::dvec3 n{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  if (n.x * n.x + n.y * n.y + n.z * n.z == 0)
    pr.fail("edge_v", "plane edges are parallel or zero (degenerate plane)");
  return p;
}

// Planes: [[planes]]
void parse_planes(const toml::table& root, Scene& s) {
  const toml::node* pn = root.get("planes");
  if (!pn) return;
  const toml::array* arr = pn->as_array();
  if (!arr) throw InputError(at(s.path, *pn), "planes: expected an array of tables ([[planes]])");
  for (const toml::node& e : *arr) s.primitives.push_back(parse_plane(e, s));
}

// [reference] samples = "auto" | N (N×N fixed); supersamples = N is its older spelling.
void parse_reference_samples(const ConfigReader& ref, Scene& s) {
  const toml::node* n = ref.table().get("samples");
  if (n && ref.table().get("supersamples")) {
    ref.fail("samples", "give either samples or supersamples (its older name), not both");
  }
  if (n && n->is_string()) {
    (void)ref.get_choice("samples", 0, {"auto"});
    s.reference_samples = 0;
  } else if (n) {
    s.reference_samples = static_cast<int>(ref.get_int("samples", 8, 1, 64));
  } else if (ref.table().get("supersamples")) {
    s.reference_samples = static_cast<int>(ref.get_int("supersamples", 8, 1, 64));
  }
}

}  // namespace

Scene parse_scene(const std::string& text, const std::string& source_name,
                  const std::string& base_dir, const std::vector<std::string>& overrides) {
  Scene s;
  s.path = source_name;
  s.base_dir = base_dir;
  s.root = std::make_shared<toml::table>(parse_toml(text, source_name));
  apply_overrides(*s.root, overrides);
  const toml::table& root = *s.root;
  const ConfigReader top(root, source_name, "scene");
  top.reject_unknown({"output", "camera", "textures", "materials", "planes", "meshes", "models",
                      "pipeline", "tech", "reference", "raster", "samplers"});
  parse_output(top, s);
  parse_camera(top, s, s.camera);
  parse_textures(top, s);
  parse_samplers(top, s);
  parse_materials(top, s);
  parse_planes(root, s);
  parse_meshes(root, s);
  parse_models(root, s);
  const ConfigReader ref = top.sub("reference");
  ref.reject_unknown({"samples", "supersamples", "pixel", "relief"});
  parse_reference_samples(ref, s);
  s.reference_pixel = static_cast<TruthPixel>(ref.get_choice("pixel", 0, {"box", "gaussian"}));
  s.reference_relief_per_sample = ref.get_choice("relief", 0, {"pixel_centre", "per_sample"}) == 1;
  s.pipeline = top.subtable("pipeline");
  s.raster = RasterOrder::from_toml(top.sub("raster"));
  if (const toml::table* t = top.subtable("tech")) {
    s.tech = TechTable::from_toml(*t, source_name);
    s.energy = EnergyTable::from_toml(*t, source_name);
  }
  return s;
}

Camera frame_camera(const Scene& s, int k) {
  return camera_at(s.camera, s.camera_path, frame_time(s.camera_path, s.frames, k));
}

const char* to_string(TruthPixel p) { return p == TruthPixel::Box ? "box" : "gaussian"; }

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  const std::string text = read_input_file(path, "scene file", kMaxTextInput);
  const std::string dir = std::filesystem::path(path).parent_path().string();
  return parse_scene(text, path, dir, overrides);
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

# The ground truth takes the defaults: [reference] samples = "auto", pixel = "box".
)";
}

Scene default_scene(const std::vector<std::string>& overrides) {
  return parse_scene(default_scene_text(), "<built-in default scene>", "", overrides);
}

}  // namespace texsim
