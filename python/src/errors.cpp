// Library failures as Python exceptions: deflex::Error by its kind
// (diag/diagnostics.hpp) as the classes of deflex/errors.py, with the errors
// it carries (their file:line:col) and the settings it names; job::Cancelled
// as KeyboardInterrupt (only Ctrl-C cancels a run from Python: a progress
// callback that raises keeps its own exception, job.cpp).
#include <Python.h>

#include "bindings.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "deflex/job/job.hpp"

namespace deflex::python {
namespace {

// Each class carries the command line's exit code of its kind (deflex/errors.py).
const char* class_of(ErrorKind kind) {
  switch (kind) {
    case ErrorKind::input:
      return "InputError";
    case ErrorKind::settings:
      return "UsageError";
    case ErrorKind::config:
      return "ConfigError";
    case ErrorKind::io:
      return "FileError";
    default:
      return "InternalError";
  }
}

// The exception set as Python's current error, from the translator or for
// raise_python.
void set_python_error(const Error& e, const std::string& messages) {
  // Imported when first needed: deflex/__init__.py imports this module first.
  const py::object cls = py::module_::import("deflex.errors").attr(class_of(e.kind()));
  py::list errors;  // the program's errors behind the failure, where they are
  for (const Diagnostic& d : e.diagnostics())
    errors.append(py::make_tuple(d.file, d.line ? py::object(py::int_(d.line)) : py::object(py::none()),
                                 d.col ? py::object(py::int_(d.col)) : py::object(py::none()), format(d)));
  py::list settings;
  for (const std::string& k : e.settings()) settings.append(py::str(k));
  const py::object inst = cls(py::str(e.what()), py::str(messages), py::arg("errors") = errors,
                              py::arg("settings") = settings);
  PyErr_SetObject(cls.ptr(), inst.ptr());
}

}  // namespace

void raise_python(std::exception_ptr failure, const std::string& messages) {
  try {
    std::rethrow_exception(failure);
  } catch (const Error& e) {
    set_python_error(e, messages);
    throw py::error_already_set();
  } catch (const job::Cancelled&) {
    PyErr_SetNone(PyExc_KeyboardInterrupt);
    throw py::error_already_set();
  }
  // Anything else (py::error_already_set, std::bad_alloc, a bug) leaves
  // through pybind11's own translation.
}

void bind_errors(py::module_& m) {
  py::register_exception_translator([](std::exception_ptr p) {
    if (!p) return;
    try {
      std::rethrow_exception(p);
    } catch (const Error& e) {
      set_python_error(e, "");
    } catch (const job::Cancelled&) {
      PyErr_SetNone(PyExc_KeyboardInterrupt);
    }
  });
}

}  // namespace deflex::python
