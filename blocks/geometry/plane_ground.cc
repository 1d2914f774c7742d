#include "blocks/geometry/plane_ground.h"

#include <glm/geometric.hpp>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<PlaneGround>);

namespace {

// `key = [a, b, ...]` of `n` finite numbers into `out`; absent: `out` is kept.
void read_numbers(const ConfigReader& r, std::string_view key, double* out, size_t n) {
  const toml::node* node = r.table().get(key);
  if (!node) return;
  const toml::array* a = node->as_array();
  if (!a || a->size() != n) r.fail(key, "expected an array of " + std::to_string(n) + " numbers");
  for (size_t i = 0; i < n; ++i) {
    const toml::node& e = *a->get(i);
    const auto v = e.value<double>();
    if (!e.is_number() || !v || !std::isfinite(*v))
      r.fail_at(e, std::string(key) + ": each must be a finite number");
    out[i] = *v;
  }
}

PlaneGround::Element read_element(const ConfigReader& r) {
  r.reject_unknown({"normal", "d", "x", "z"});
  PlaneGround::Element e;
  double n[3] = {0, 1, 0}, x[2] = {e.x0, e.x1}, z[2] = {e.z0, e.z1};
  read_numbers(r, "normal", n, 3);
  read_numbers(r, "x", x, 2);
  read_numbers(r, "z", z, 2);
  e.d = r.get_double("d", 0);
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(len > 0) || !std::isfinite(len)) r.fail("normal", "must be a non-zero vector");
  if (!std::isfinite(e.d)) r.fail("d", "must be finite");
  if (!(x[0] <= x[1])) r.fail("x", "needs x0 <= x1");
  if (!(z[0] <= z[1])) r.fail("z", "needs z0 <= z1");
  e.n = glm::dvec3(n[0], n[1], n[2]) / len;
  e.x0 = x[0];
  e.x1 = x[1];
  e.z0 = z[0];
  e.z1 = z[1];
  return e;
}

}  // namespace

PlaneGround::Config PlaneGround::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"elements", "datapath"});
  Config c;
  c.datapath = parse_datapath(r, c.datapath);
  const toml::node* node = r.table().get("elements");
  if (!node) return c;
  const toml::array* a = node->as_array();
  if (!a || a->empty() || a->size() > 4096)
    r.fail("elements", "expected an array of 1 to 4096 tables { normal, d, x, z }");
  c.elements.clear();
  for (size_t i = 0; i < a->size(); ++i) {
    const toml::node& e = *a->get(i);
    if (!e.is_table()) r.fail_at(e, "elements: each must be a table { normal, d, x, z }");
    c.elements.push_back(
        read_element(ConfigReader(*e.as_table(), r.source(), r.block() + ".elements")));
  }
  return c;
}

OpCounts PlaneGround::ops_per_item() const {
  OpCounts o;
  o.mul = 3 + 2;      // G = n·V; λ·V_x, λ·V_z
  o.add = 2 + 2;      // G's sums; X_h + λV_x, Z_h + λV_z
  o.div = 1;          // λ = F/G
  o.cmp = 2 + 4 + 1;  // λ > 0 and < the nearest so far; the rectangle; the select
  return o;
}

OpCounts PlaneGround::critical_path() const {
  OpCounts p;
  p.mul = 2;  // n·V products, λ·V
  p.add = 3;  // n·V sums, the point
  p.div = 1;
  p.cmp = 2;  // the rectangle, the select
  return p;
}

OpCounts PlaneGround::setup_ops() const {
  OpCounts o;  // F = d - n·r_h
  o.mul = 3;
  o.add = 3;
  return o;
}

TimingSpec PlaneGround::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), critical_path(), cfg_.datapath, 1, setup_ops());
}

}  // namespace texsim
