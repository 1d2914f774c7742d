#include "pipeline/scene/procedural_texture.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <sstream>

#include "blocks/base/input_error.h"
#include "blocks/texture/layered/cube_face_select.h"

namespace texsim {

namespace {

constexpr const char* kPrefix = "procedural:";

uint32_t hash2(int x, int y, uint32_t seed) {
  uint32_t h = seed * 0x9E3779B1u ^ static_cast<uint32_t>(x) * 0x85EBCA77u ^
               static_cast<uint32_t>(y) * 0xC2B2AE3Du;
  h ^= h >> 15;
  h *= 0x2C1B3C6Du;
  h ^= h >> 12;
  h *= 0x297A2D39u;
  h ^= h >> 15;
  return h;
}

// Smooth value noise on a periodic lattice of `period` cells (tiles seamlessly).
float value_noise(double x, double y, int period, uint32_t seed) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const double fx = x - x0, fy = y - y0;
  auto lat = [&](int i, int j) {
    i = ((i % period) + period) % period;
    j = ((j % period) + period) % period;
    return static_cast<double>(hash2(i, j, seed) & 0xFFFF) / 65535.0;
  };
  auto s = [](double t) { return t * t * (3 - 2 * t); };
  const double a = lat(x0, y0), b = lat(x0 + 1, y0), c = lat(x0, y0 + 1), d = lat(x0 + 1, y0 + 1);
  const double sx = s(fx), sy = s(fy);
  return static_cast<float>((a * (1 - sx) + b * sx) * (1 - sy) + (c * (1 - sx) + d * sx) * sy);
}

// The sky's colour in direction d (unit vector, +Y up): above the horizon a gradient from a pale
// horizon to a deep zenith with a sun disc; below it a checker of `cells` longitude sectors
// and latitude bands, so that reflections show where they look.
void sky_colour(const double d[3], int cells, float out[3]) {
  constexpr double kPi = 3.14159265358979323846;
  const double sun[3] = {0.48, 0.6, -0.64};  // unit length
  const double cos_sun = d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2];
  if (d[1] >= 0) {
    const double k = std::sqrt(d[1]);
    out[0] = static_cast<float>(0.80 - 0.62 * k);
    out[1] = static_cast<float>(0.87 - 0.45 * k);
    out[2] = static_cast<float>(0.97 - 0.22 * k);
    if (cos_sun > 0.995) out[0] = out[1] = out[2] = 1.0f;
    return;
  }
  const double lon = std::atan2(d[2], d[0]) / (2 * kPi) + 0.5;      // [0, 1]
  const double lat = -std::asin(std::max(-1.0, d[1])) / (kPi / 2);  // (0, 1]
  const auto a = static_cast<int>(std::floor(lon * cells));
  const auto b = static_cast<int>(std::floor(lat * cells / 2));
  const bool on = (a + b) % 2 == 0;
  out[0] = on ? 0.55f : 0.20f;
  out[1] = on ? 0.42f : 0.32f;
  out[2] = on ? 0.25f : 0.12f;
}

}  // namespace

bool is_procedural_source(const std::string& source) { return source.rfind(kPrefix, 0) == 0; }

ProceduralSpec parse_procedural_source(const std::string& source, const std::string& where) {
  if (!is_procedural_source(source)) throw InputError(where, "not a procedural texture: " + source);
  const std::string rest = source.substr(std::string(kPrefix).size());
  const auto q = rest.find('?');
  ProceduralSpec spec;
  spec.kind = rest.substr(0, q);
  std::map<std::string, std::string> kv;
  if (q != std::string::npos) {
    std::stringstream ss(rest.substr(q + 1));
    std::string item;
    while (std::getline(ss, item, '&')) {
      const auto eq = item.find('=');
      if (eq == std::string::npos || eq == 0) {
        throw InputError(where, std::string("procedural texture '")
                                    .append(source)
                                    .append("': expected key=value, got '")
                                    .append(item)
                                    .append("'"));
      }
      kv[item.substr(0, eq)] = item.substr(eq + 1);
    }
  }
  auto get_int = [&](const std::string& key, int def, int lo, int hi) {
    auto it = kv.find(key);
    if (it == kv.end()) return def;
    char* end = nullptr;
    const long v = std::strtol(it->second.c_str(), &end, 10);
    if (end == it->second.c_str() || *end != '\0' || v < lo || v > hi) {
      throw InputError(where, "procedural texture '" + source + "': " + key +
                                  " must be an integer in [" + std::to_string(lo) + ", " +
                                  std::to_string(hi) + "]");
    }
    kv.erase(it);
    return static_cast<int>(v);
  };
  // As for texture files: at most 8192 × 8192 texels (an rgba32f pyramid of that is 1.4 GB).
  spec.size = get_int("size", spec.size, 1, 8192);
  spec.rows = get_int("rows", spec.size, 1, spec.size);
  if (auto it = kv.find("format"); it != kv.end()) {
    if (it->second == "rgba32f")
      spec.format = TexelFormat::Rgba32f;
    else if (it->second != "rgba8")
      throw InputError(where,
                       "procedural texture '" + source + "': format must be rgba8 or rgba32f");
    kv.erase(it);
  }
  if (spec.kind == "checker") {
    spec.cells = get_int("cells", spec.cells, 1, spec.size);
  } else if (spec.kind == "grid") {
    spec.cells = get_int("cells", spec.cells, 1, spec.size);
    spec.line = get_int("line", spec.line, 1, spec.size);
  } else if (spec.kind == "noise") {
    spec.seed = get_int("seed", spec.seed, 0, 1 << 30);
    spec.octaves = get_int("octaves", spec.octaves, 1, 12);
    spec.cells = get_int("cells", spec.cells, 1, spec.size);
  } else if (spec.kind == "sky") {
    spec.face = get_int("face", spec.face, 0, 5);
    spec.cells = get_int("cells", spec.cells, 1, 256);
  } else {
    throw InputError(where, "procedural texture '" + source + "': unknown kind '" + spec.kind +
                                "' (known: checker, grid, noise, sky)");
  }
  if (!kv.empty()) {
    throw InputError(
        where, "procedural texture '" + source + "': unknown key '" + kv.begin()->first + "'");
  }
  return spec;
}

Texture make_procedural_texture(const std::string& source, const std::string& where) {
  const ProceduralSpec spec = parse_procedural_source(source, where);
  const int size = spec.size, cells = spec.cells;
  std::vector<float> rgba(static_cast<size_t>(size) * size * 4, 1.0f);
  // Built square, then cut to its first `rows` rows (a 1-D array's layers are one row).
  auto put = [&](int x, int y, float r, float g, float b) {
    float* p = &rgba[(static_cast<size_t>(y) * size + x) * 4];
    p[0] = r;
    p[1] = g;
    p[2] = b;
    p[3] = 1.0f;
  };
  if (spec.kind == "checker") {
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const bool on = ((x * cells / size) + (y * cells / size)) % 2 == 0;
        if (on)
          put(x, y, 0.95f, 0.92f, 0.85f);
        else
          put(x, y, 0.08f, 0.12f, 0.30f);
      }
  } else if (spec.kind == "grid") {
    const int line = spec.line;
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const bool on = (x * cells % size) < line * cells || (y * cells % size) < line * cells;
        if (on)
          put(x, y, 0.9f, 0.9f, 0.2f);
        else
          put(x, y, 0.1f, 0.3f, 0.1f);
      }
  } else if (spec.kind == "sky") {
    // Face `face` of a sky cube: texel (x, y)'s centre is the direction m + (2s − 1)·S +
    // (2t − 1)·T of the face's axes (s = ½·sc/|rc| + ½ inverted).
    const CubeFaceAxes& ax = cube_face_axes(spec.face);
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const double s = 2 * (x + 0.5) / size - 1, t = 2 * (y + 0.5) / size - 1;
        double d[3];
        double len2 = 0;
        for (int k = 0; k < 3; ++k) {
          d[k] = ax.m[static_cast<size_t>(k)] + s * ax.s[static_cast<size_t>(k)] +
                 t * ax.t[static_cast<size_t>(k)];
          len2 += d[k] * d[k];
        }
        for (double& c : d) c /= std::sqrt(len2);
        float c[3];
        sky_colour(d, cells, c);
        put(x, y, c[0], c[1], c[2]);
      }
  } else {  // noise
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        double sum = 0, amp = 0.5, norm = 0;
        for (int o = 0; o < spec.octaves; ++o) {
          const int period = cells << o;
          const double s = static_cast<double>(period) / size;
          sum += amp * value_noise((x + 0.5) * s, (y + 0.5) * s, period,
                                   static_cast<uint32_t>(spec.seed + o));
          norm += amp;
          amp *= 0.5;
        }
        const auto v = static_cast<float>(sum / norm);
        put(x, y, v, 0.6f * v + 0.2f, 1.0f - v);
      }
  }
  rgba.resize(static_cast<size_t>(size) * static_cast<size_t>(spec.rows) * 4);
  return Texture::from_rgba(source, size, spec.rows, rgba, spec.format, true);
}

}  // namespace texsim
