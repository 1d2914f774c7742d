// The Python module `texsim`: scenes run in process, reports as Python objects, images and
// traces as numpy arrays (docs/python.md).
#include "python/texsim_module.h"

#include <exception>
#include <string>

#include "blocks/base/input_error.h"
#include "python/oiio_plugin_path.h"

namespace py = pybind11;

namespace {

// texsim.InputError (a ValueError): the CLI's message; `location` is the part before the
// first ": " (file, file:line:column or the option), `message` the whole text.
void bind_input_error(py::module_& m) {
  // Held for the life of the process: the translator below raises it.
  static py::handle input_error =
      py::exception<texsim::InputError>(m, "InputError", PyExc_ValueError).release();
  // pybind11 takes translators as void (*)(std::exception_ptr): by value.
  py::register_exception_translator(
      [](std::exception_ptr p) {  // NOLINT(performance-unnecessary-value-param)
        try {
          if (p) std::rethrow_exception(p);
        } catch (const texsim::InputError& e) {
          const std::string text = e.what();
          const size_t colon = text.find(": ");
          py::object err = py::reinterpret_borrow<py::object>(input_error)(text);
          err.attr("message") = text;
          err.attr("location") = colon == std::string::npos ? std::string() : text.substr(0, colon);
          PyErr_SetObject(input_error.ptr(), err.ptr());
        }
      });
}

}  // namespace

PYBIND11_MODULE(texsim, m) {
  m.doc() = "texsim: a cycle-approximate texture-unit simulator (docs/python.md)";
  m.attr("__version__") = TEXSIM_VERSION;
  texsim_py::point_at_oiio_plugin();
  bind_input_error(m);
  texsim_py::bind_runs(m);
  texsim_py::bind_traces(m);
}
