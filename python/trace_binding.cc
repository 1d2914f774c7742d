// texsim.read_trace and texsim.write_trace: trace files (traces/FORMAT.md, or the CSV form) as
// numpy structured arrays of texsim.fragment_dtype, one record per fragment.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <string>
#include <vector>

#include "blocks/base/fragment.h"
#include "python/texsim_module.h"
#include "traces/trace_file.h"

namespace py = pybind11;

namespace texsim_py {
namespace {

using texsim::Fragment;

py::list texture_list(const std::vector<texsim::TraceTexture>& textures) {
  py::list out;
  for (const texsim::TraceTexture& t : textures) {
    py::dict d;
    d["id"] = t.id;
    d["name"] = t.name;
    d["source"] = t.source;
    d["width"] = t.width;
    d["height"] = t.height;
    d["storage"] = t.storage;
    out.append(d);
  }
  return out;
}

std::vector<texsim::TraceTexture> texture_table(const py::iterable& textures) {
  std::vector<texsim::TraceTexture> out;
  for (const py::handle& h : textures) {
    const py::dict d = py::reinterpret_borrow<py::dict>(h);
    texsim::TraceTexture t{};
    t.id = d["id"].cast<uint32_t>();
    t.name = d["name"].cast<std::string>();
    t.source = d["source"].cast<std::string>();
    t.width = d["width"].cast<uint32_t>();
    t.height = d["height"].cast<uint32_t>();
    if (d.contains("storage")) t.storage = d["storage"].cast<std::string>();
    out.push_back(std::move(t));
  }
  return out;
}

// The sampler table (version 5) as dicts with the CSV directive's keys and value names.
py::list sampler_list(const std::vector<texsim::TraceSampler>& samplers) {
  py::list out;
  for (const texsim::TraceSampler& s : samplers) {
    py::dict d;
    d["name"] = s.name;
    d["mode"] = std::string(texsim::kTraceFilterNames[s.mode]);
    d["address_u"] = std::string(texsim::kTraceAddressNames[s.address_u]);
    d["address_v"] = std::string(texsim::kTraceAddressNames[s.address_v]);
    d["address_w"] = std::string(texsim::kTraceAddressNames[s.address_w]);
    d["border"] = py::make_tuple(s.border[0], s.border[1], s.border[2], s.border[3]);
    d["compare"] = std::string(texsim::kTraceCompareNames[s.compare]);
    d["reduction"] = std::string(texsim::kTraceReductionNames[s.reduction]);
    d["aniso"] = std::string(texsim::kTraceAnisoNames[s.aniso]);
    d["max_aniso"] = int{s.max_aniso};
    d["lod_bias"] = s.lod_bias;
    d["min_lod"] = s.min_lod;
    d["max_lod"] = s.max_lod;
    d["unnormalized"] = s.unnormalized != 0;
    d["seamless"] = s.seamless != 0;
    d["sub_texel_bits"] = int{s.sub_texel_bits};
    d["mipmap_bits"] = int{s.mipmap_bits};
    out.append(d);
  }
  return out;
}

template <size_t N>
uint8_t sampler_code(const py::handle& v, const char* key, const std::string_view (&names)[N]) {
  const auto name = v.cast<std::string>();
  for (size_t k = 0; k < N; ++k)
    if (names[k] == name) return static_cast<uint8_t>(k);
  throw py::value_error(std::string("texsim.write_trace: sampler ") + key + " '" + name +
                        "' is not known");
}

// Dicts as sampler_list gives them; a key left out keeps the scene's default. The writer checks
// the values (texsim.InputError naming the entry).
std::vector<texsim::TraceSampler> sampler_table(const py::iterable& samplers) {
  std::vector<texsim::TraceSampler> out;
  for (const py::handle& h : samplers) {
    const py::dict d = py::reinterpret_borrow<py::dict>(h);
    texsim::TraceSampler s;
    for (const auto& item : d) {
      const py::handle k = item.first, v = item.second;
      const auto key = k.cast<std::string>();
      const auto small = [&](int hi) {
        const int x = v.cast<int>();
        if (x < 0 || x > hi)
          throw py::value_error("texsim.write_trace: sampler " + key + " " + std::to_string(x) +
                                " is outside 0.." + std::to_string(hi));
        return static_cast<uint8_t>(x);
      };
      if (key == "name")
        s.name = v.cast<std::string>();
      else if (key == "mode")
        s.mode = sampler_code(v, "mode", texsim::kTraceFilterNames);
      else if (key == "address_u")
        s.address_u = sampler_code(v, "address_u", texsim::kTraceAddressNames);
      else if (key == "address_v")
        s.address_v = sampler_code(v, "address_v", texsim::kTraceAddressNames);
      else if (key == "address_w")
        s.address_w = sampler_code(v, "address_w", texsim::kTraceAddressNames);
      else if (key == "compare")
        s.compare = sampler_code(v, "compare", texsim::kTraceCompareNames);
      else if (key == "reduction")
        s.reduction = sampler_code(v, "reduction", texsim::kTraceReductionNames);
      else if (key == "aniso")
        s.aniso = sampler_code(v, "aniso", texsim::kTraceAnisoNames);
      else if (key == "border") {
        const auto c = v.cast<std::vector<float>>();
        if (c.size() != 4)
          throw py::value_error("texsim.write_trace: sampler border needs 4 numbers");
        std::copy(c.begin(), c.end(), s.border);
      } else if (key == "max_aniso")
        s.max_aniso = small(255);
      else if (key == "lod_bias")
        s.lod_bias = v.cast<float>();
      else if (key == "min_lod")
        s.min_lod = v.cast<float>();
      else if (key == "max_lod")
        s.max_lod = v.cast<float>();
      else if (key == "unnormalized")
        s.unnormalized = v.cast<bool>() ? 1 : 0;
      else if (key == "seamless")
        s.seamless = v.cast<bool>() ? 1 : 0;
      else if (key == "sub_texel_bits")
        s.sub_texel_bits = small(255);
      else if (key == "mipmap_bits")
        s.mipmap_bits = small(255);
      else
        throw py::value_error("texsim.write_trace: unknown sampler key '" + key + "'");
    }
    out.push_back(std::move(s));
  }
  return out;
}

// The whole trace; the records' array owns the vector they were read into (no copy).
py::object read_trace(const std::string& path, bool textures, bool samplers) {
  auto* records = new std::vector<Fragment>();
  py::capsule base(records, [](void* p) { delete static_cast<std::vector<Fragment>*>(p); });
  texsim::TraceHeader header;
  {
    const py::gil_scoped_release release;
    *records = texsim::read_trace(path, &header);
  }
  py::array_t<Fragment> array(static_cast<py::ssize_t>(records->size()), records->data(), base);
  if (samplers)
    return py::make_tuple(array, texture_list(header.textures), sampler_list(header.samplers));
  if (!textures) return array;
  return py::make_tuple(array, texture_list(header.textures));
}

// Any structured array: the fields of fragment_dtype it has are copied by name, the others
// are 0 (frame, prim, x, y, tex, u, v and the four derivatives are required).
py::array_t<Fragment> as_fragments(const py::array& records) {
  const py::dtype want = py::dtype::of<Fragment>();
  if (records.dtype().is(want) || records.dtype().equal(want))
    return py::array_t<Fragment, py::array::c_style>::ensure(records);
  py::array_t<Fragment> out(records.size());
  std::fill(out.mutable_data(), out.mutable_data() + out.size(), Fragment{});
  const py::dict have = records.dtype().attr("fields");
  for (const char* need :
       {"frame", "prim", "x", "y", "tex", "u", "v", "dudx", "dvdx", "dudy", "dvdy"}) {
    if (!have.contains(need))
      throw py::value_error(std::string("texsim.write_trace: the records have no field '") + need +
                            "'");
  }
  for (const auto& [name, spec] : want.attr("fields").cast<py::dict>()) {
    if (have.contains(name)) out[name] = records[name];
  }
  return out;
}

// Writes records (binary, or CSV for a .csv path); the flags of the optional fields are set
// when some record has a non-zero value in them.
void write_trace(const std::string& path, const py::array& records, const py::iterable& textures,
                 const py::object& samplers) {
  const py::array_t<Fragment> frags = as_fragments(records);
  texsim::TraceHeader header;
  header.textures = texture_table(textures);
  if (!samplers.is_none()) header.samplers = sampler_table(samplers);
  std::vector<Fragment> v(frags.data(), frags.data() + frags.size());
  const py::gil_scoped_release release;
  for (const Fragment& f : v) {
    header.has_lod_bias = header.has_lod_bias || f.lod_bias != 0;
    header.has_view = header.has_view || f.has_view();
    header.has_ops = header.has_ops || f.w != 0 || f.dwdx != 0 || f.dwdy != 0 || f.layer != 0 ||
                     f.lod != 0 || f.compare_ref != 0 || f.sampler != 0 || f.op != 0 ||
                     f.gather_component != 0 || f.offset_u != 0 || f.offset_v != 0 ||
                     f.offset_w != 0;
  }
  texsim::write_trace(path, header, v);
}

}  // namespace

void bind_traces(py::module_& m) {
  // The record layout of the arrays: Fragment itself, fields named as in the trace format.
  PYBIND11_NUMPY_DTYPE_EX(texsim::Fragment, frame, "frame", prim, "prim", x, "x", y, "y", tex,
                          "tex", u, "u", v, "v", dudx, "dudx", dvdx, "dvdx", dudy, "dudy", dvdy,
                          "dvdy", lod_bias, "lod_bias", view_x, "view_x", view_y, "view_y", view_z,
                          "view_z", w, "w", dwdx, "dwdx", dwdy, "dwdy", layer, "layer", lod, "lod",
                          compare_ref, "compare_ref", sampler, "sampler", op, "op",
                          gather_component, "gather_comp", offset_u, "offset_u", offset_v,
                          "offset_v", offset_w, "offset_w");
  m.attr("fragment_dtype") = py::dtype::of<Fragment>();
  m.def("read_trace", &read_trace, py::arg("path"), py::arg("textures") = false,
        py::arg("samplers") = false,
        "Reads a trace (binary or .csv) into an array of fragment_dtype; with textures=True "
        "returns (array, [texture dicts]); with samplers=True (array, [texture dicts], [sampler "
        "dicts]).");
  m.def("write_trace", &write_trace, py::arg("path"), py::arg("records"), py::arg("textures"),
        py::arg("samplers") = py::none(),
        "Writes records (a structured array) with the texture table [{id, name, source, width, "
        "height[, storage]}] and the sampler table [{name, mode, ...}] (optional; version 5); "
        ".csv paths get the CSV form.");
}

}  // namespace texsim_py
