// The pieces of the compiled module deflex._deflex, each registered by its own
// file (module.cpp calls them in turn). A thin layer over the library's job API
// (include/deflex/job/) and its physics calls: no computation of its own.
#pragma once
#include <pybind11/pybind11.h>

#include <exception>
#include <string>

namespace deflex::python {
namespace py = pybind11;

// job.cpp: _deflex.Job (settings from keywords or a job file; simulate, compensate).
void bind_job(py::module_& m);
// physics.cpp: compliance, forces, cusp_height.
void bind_physics(py::module_& m);
// errors.cpp: deflex::Error and job::Cancelled as the exceptions of deflex/errors.py.
void bind_errors(py::module_& m);

// Raises the Python exception of `failure` (a deflex::Error: the class of its
// exit code, with `messages`, what the run printed before it failed), by
// throwing py::error_already_set. Needs the GIL.
[[noreturn]] void raise_python(std::exception_ptr failure, const std::string& messages);

}  // namespace deflex::python
