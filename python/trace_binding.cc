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

// The whole trace; the records' array owns the vector they were read into (no copy).
py::object read_trace(const std::string& path, bool textures) {
  auto* records = new std::vector<Fragment>();
  py::capsule base(records, [](void* p) { delete static_cast<std::vector<Fragment>*>(p); });
  texsim::TraceHeader header;
  {
    const py::gil_scoped_release release;
    *records = texsim::read_trace(path, &header);
  }
  py::array_t<Fragment> array(static_cast<py::ssize_t>(records->size()), records->data(), base);
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
void write_trace(const std::string& path, const py::array& records, const py::iterable& textures) {
  const py::array_t<Fragment> frags = as_fragments(records);
  texsim::TraceHeader header;
  header.textures = texture_table(textures);
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
        "Reads a trace (binary or .csv) into an array of fragment_dtype; with textures=True "
        "returns (array, [texture dicts]).");
  m.def("write_trace", &write_trace, py::arg("path"), py::arg("records"), py::arg("textures"),
        "Writes records (a structured array) with the texture table [{id, name, source, width, "
        "height[, storage]}]; .csv paths get the CSV form.");
}

}  // namespace texsim_py
