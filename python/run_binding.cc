// texsim.run and texsim.sweep: a scene run in process through run_simulation, with the GIL
// released while it runs; the report read back as Python objects, the images as numpy arrays.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <stdlib.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "pipeline/app/run.h"
#include "pipeline/kernel/parallel_range.h"
#include "python/texsim_module.h"

namespace py = pybind11;
namespace fs = std::filesystem;

namespace texsim_py {
namespace {

using texsim::ImageRgb;

// What one run leaves for Python: built without the GIL, converted with it.
struct RawRun {
  std::string report_json;
  std::unique_ptr<ImageRgb> image, reference;
  bool has_reference = false;
};

// The result of texsim.run: report (dict), image / reference / error (numpy, H × W × 3
// float32, linear 0..1), ledger (the report's per-block ledger, or None).
struct Result {
  py::object report, image, reference, error, ledger;
};

// A directory of its own under the temporary directory, removed when this goes away.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "texsim-py-XXXXXX").string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("texsim: cannot create " + pattern);
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// The run's settings from Python's arguments (taken while the GIL is held).
struct RunArgs {
  std::string scene, scene_text, trace, out, reference = "scene";
  std::vector<std::string> overrides;
  bool functional = false, ledger = false;
  int threads = 0;
};

// "KEY=VALUE" from a dict (values as TOML: bools, numbers, strings quoted, lists, dicts as inline
// tables) or a list of "KEY=VALUE" strings.
std::string toml_value(const py::handle& v) {
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(v)) return py::str(v).cast<std::string>();
  if (py::isinstance<py::float_>(v)) {
    const double d = v.cast<double>();
    std::ostringstream s;
    s.precision(17);
    s << d;
    std::string t = s.str();
    if (std::isfinite(d) && t.find_first_of(".eE") == std::string::npos) t += ".0";
    return t;
  }
  if (py::isinstance<py::str>(v)) {
    return py::module_::import("json").attr("dumps")(v).cast<std::string>();
  }
  if (py::isinstance<py::dict>(v)) {  // an inline table: {"mode": "ewa"} -> { mode = "ewa" }
    std::string t = "{";
    for (const auto& [k, e] : v.cast<py::dict>()) {
      t += (t.size() > 1 ? ", " : " ") + py::str(k).cast<std::string>() + " = " + toml_value(e);
    }
    return t + " }";
  }
  if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    std::string t = "[";
    for (const py::handle& e : v) t += (t.size() > 1 ? ", " : "") + toml_value(e);
    return t + "]";
  }
  throw py::type_error("texsim: an override's value must be a bool, number, string, list or dict");
}

std::vector<std::string> override_list(const py::object& overrides) {
  std::vector<std::string> out;
  if (overrides.is_none()) return out;
  if (py::isinstance<py::dict>(overrides)) {
    for (const auto& [k, v] : overrides.cast<py::dict>())
      out.push_back(py::str(k).cast<std::string>() + "=" + toml_value(v));
    return out;
  }
  for (const py::handle& s : overrides) out.push_back(s.cast<std::string>());
  return out;
}

// A scene argument: TOML text when it holds a line break, else a file ("default" or None: the
// built-in default scene).
void set_scene(RunArgs& a, const py::object& scene) {
  if (scene.is_none()) return;
  const std::string s = py::str(scene).cast<std::string>();
  if (s.find('\n') != std::string::npos) {
    a.scene_text = s;
  } else {
    a.scene = s;
  }
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// One run, without the GIL: into args.out, or a temporary directory removed afterwards.
RawRun run_raw(const RunArgs& a) {
  std::unique_ptr<TempDir> tmp = a.out.empty() ? std::make_unique<TempDir>() : nullptr;
  texsim::RunOptions opt;
  opt.scene = a.scene;
  opt.scene_text = a.scene_text;
  opt.trace = a.trace;
  opt.out = tmp ? tmp->path() : a.out;
  opt.functional = a.functional;
  opt.overrides = a.overrides;
  opt.threads = a.threads;
  opt.reference = a.reference;
  opt.ledger = a.ledger;
  opt.command = "texsim.run (Python)";
  texsim::RunCapture capture;
  capture.write_outputs = true;
  opt.capture = &capture;
  std::ostringstream log;
  texsim::run_simulation(opt, log);
  RawRun r;
  r.report_json = read_text(opt.out + "/report.json");
  r.image = std::move(capture.image);
  r.reference = std::move(capture.reference);
  r.has_reference = a.reference != "none";
  return r;
}

// The canvas of an image as H × W × 3 float32. A buffer that is the whole canvas is handed to
// numpy without a copy (a capsule owns it); else the buffer is placed on the background.
py::array canvas_array(std::unique_ptr<ImageRgb> img) {
  const auto h = static_cast<py::ssize_t>(img->canvas_height);
  const auto w = static_cast<py::ssize_t>(img->canvas_width);
  const std::vector<py::ssize_t> shape{h, w, 3};
  if (img->x0 == 0 && img->y0 == 0 && img->width == img->canvas_width &&
      img->height == img->canvas_height) {
    ImageRgb* owned = img.release();
    py::capsule base(owned, [](void* p) { delete static_cast<ImageRgb*>(p); });
    return py::array_t<float>(shape, owned->rgb.data(), base);
  }
  py::array_t<float> out(shape);
  float* dst = out.mutable_data();
  for (py::ssize_t i = 0; i < h * w; ++i) {
    dst[3 * i] = img->background.r;
    dst[3 * i + 1] = img->background.g;
    dst[3 * i + 2] = img->background.b;
  }
  for (int y = 0; y < img->height; ++y) {
    const int cy = img->y0 + y;
    if (cy < 0 || cy >= img->canvas_height) continue;
    for (int x = 0; x < img->width; ++x) {
      const int cx = img->x0 + x;
      if (cx < 0 || cx >= img->canvas_width) continue;
      const size_t from =
          3 * (static_cast<size_t>(y) * static_cast<size_t>(img->width) + static_cast<size_t>(x));
      const size_t to =
          3 * (static_cast<size_t>(cy) * static_cast<size_t>(w) + static_cast<size_t>(cx));
      for (size_t c = 0; c < 3; ++c) dst[to + c] = img->rgb[from + c];
    }
  }
  return out;
}

// |image − reference| per channel.
py::array error_array(const py::array_t<float>& image, const py::array_t<float>& reference) {
  py::array_t<float> out(std::vector<py::ssize_t>(image.shape(), image.shape() + image.ndim()));
  const float* a = image.data();
  const float* b = reference.data();
  float* d = out.mutable_data();
  for (py::ssize_t i = 0; i < image.size(); ++i) d[i] = std::fabs(a[i] - b[i]);
  return out;
}

Result to_python(RawRun r) {
  Result out;
  out.report = py::module_::import("json").attr("loads")(r.report_json);
  out.image = canvas_array(std::move(r.image));
  out.ledger = py::none();
  const py::dict report = out.report.cast<py::dict>();
  if (report.contains("ledger")) out.ledger = report["ledger"];
  if (r.has_reference) {
    out.reference = canvas_array(std::move(r.reference));
    out.error = error_array(out.image, out.reference);
  } else {
    out.reference = py::none();
    out.error = py::none();
  }
  return out;
}

RunArgs run_args(const py::object& scene, const py::object& overrides, bool functional, bool ledger,
                 const std::string& reference, int threads, const py::object& trace,
                 const py::object& out) {
  RunArgs a;
  set_scene(a, scene);
  a.overrides = override_list(overrides);
  a.functional = functional;
  a.ledger = ledger;
  a.reference = reference;
  a.threads = threads;
  if (!trace.is_none()) a.trace = py::str(trace).cast<std::string>();
  if (!out.is_none()) a.out = py::str(out).cast<std::string>();
  if (reference != "scene" && reference != "none")
    throw texsim::InputError("reference", "\"" + reference + "\": expected \"scene\" or \"none\"");
  return a;
}

Result run(const py::object& scene, const py::object& overrides, bool functional, bool ledger,
           const std::string& reference, int threads, const py::object& trace,
           const py::object& out) {
  const RunArgs a = run_args(scene, overrides, functional, ledger, reference, threads, trace, out);
  RawRun raw;
  {
    const py::gil_scoped_release release;
    raw = run_raw(a);
  }
  return to_python(std::move(raw));
}

// Several override sets on one scene, the runs spread over `jobs` threads (one thread each).
std::vector<Result> sweep(const py::object& scene, const py::iterable& override_sets,
                          bool functional, const std::string& reference, int jobs) {
  std::vector<RunArgs> args;
  for (const py::handle& set : override_sets) {
    RunArgs a = run_args(scene, py::reinterpret_borrow<py::object>(set), functional, false,
                         reference, 1, py::none(), py::none());
    args.push_back(std::move(a));
  }
  std::vector<RawRun> raw(args.size());
  {
    const py::gil_scoped_release release;
    texsim::parallel_tasks(args.size(), jobs, [&](size_t i) { raw[i] = run_raw(args[i]); });
  }
  std::vector<Result> out;
  out.reserve(raw.size());
  for (RawRun& r : raw) out.push_back(to_python(std::move(r)));
  return out;
}

}  // namespace

void bind_runs(py::module_& m) {
  py::class_<Result>(m, "Result", "One run: report, image, reference, error, ledger")
      .def_readonly("report", &Result::report, "report.json's content (dict)")
      .def_readonly("image", &Result::image, "the imaged frame, H x W x 3 float32")
      .def_readonly("reference", &Result::reference, "the ground truth (None without one)")
      .def_readonly("error", &Result::error, "|image - reference| per channel (or None)")
      .def_readonly("ledger", &Result::ledger, "the per-block error ledger (ledger=True)");
  m.def("run", &run, py::arg("scene") = py::none(), py::arg("overrides") = py::none(),
        py::arg("functional") = false, py::arg("ledger") = false, py::arg("reference") = "scene",
        py::arg("threads") = 0, py::arg("trace") = py::none(), py::arg("out") = py::none(),
        "Runs a scene (file, TOML text or None for the built-in one) with overrides "
        "({key: value} as --set); raises texsim.InputError on bad input.");
  m.def("sweep", &sweep, py::arg("scene"), py::arg("override_sets"), py::arg("functional") = false,
        py::arg("reference") = "scene", py::arg("jobs") = 0,
        "Runs the scene once per override set on `jobs` threads (0: one per hardware thread); "
        "returns the results in the sets' order.");
}

}  // namespace texsim_py
