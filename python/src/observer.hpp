// The job's Observer (job/job.hpp) for a run from Python: the optional
// progress callable, Ctrl-C, and the points.csv rows kept in C++.
#pragma once
#include <pybind11/pybind11.h>

#include <optional>

#include "columns.hpp"
#include "deflex/job/job.hpp"

namespace deflex::python {
namespace py = pybind11;

// The run goes with the GIL released; progress() and cancelled() come from
// the thread that called the run (job.hpp) and take the GIL for Python;
// row() may come from a worker thread and touches nothing of Python.
// Destroy it with the GIL held (it owns a reference to the callable).
class PyObserver : public job::Observer {
 public:
  // `progress`: None or callable(stage: str, fraction: float).
  PyObserver(py::object progress, bool rows) : progress_(std::move(progress)), rows_(rows) {}
  void progress(const std::string& stage, double fraction) override;
  // Python's signal handlers run here (PyErr_CheckSignals): Ctrl-C raises
  // KeyboardInterrupt there, which cancels the run and is raised again after it.
  bool cancelled() override;
  bool wants_rows() const override { return rows_; }
  void row(const report::PointRow& r) override { columns_.add(r); }

  // The Python exception that stopped the run (a signal handler's, the
  // progress callable's), if one did. Needs the GIL.
  std::optional<py::error_already_set>& pending() { return pending_; }
  const Columns& columns() const { return columns_; }

 private:
  py::object progress_;
  bool rows_;
  Columns columns_;
  std::optional<py::error_already_set> pending_;
};

}  // namespace deflex::python
