#pragma once
// The Python module `texsim` (docs/python.md): declarations shared by its binding files.
#include <pybind11/pybind11.h>

namespace texsim_py {

// texsim.run, texsim.sweep and the Result class (run_binding.cc).
void bind_runs(pybind11::module_& m);
// texsim.read_trace, texsim.write_trace and texsim.fragment_dtype (trace_binding.cc).
void bind_traces(pybind11::module_& m);

}  // namespace texsim_py
