// PyObserver (observer.hpp).
#include "observer.hpp"

namespace deflex::python {

void PyObserver::progress(const std::string& stage, double fraction) {
  // The library ends with stage "" (job.hpp): not a stage, not passed on.
  if (stage.empty() || progress_.is_none()) return;
  py::gil_scoped_acquire gil;
  try {
    progress_(stage, fraction);
  } catch (py::error_already_set& e) {
    // Stops the run where the library expects a stop (between points);
    // job.cpp raises the callable's exception in its place.
    pending_.emplace(std::move(e));
    throw job::Cancelled();
  }
}

bool PyObserver::cancelled() {
  py::gil_scoped_acquire gil;
  if (PyErr_CheckSignals() == 0) return false;
  pending_.emplace();  // fetches KeyboardInterrupt (or whatever a handler raised)
  return true;
}

}  // namespace deflex::python
