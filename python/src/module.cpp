// The compiled half of `import deflex`: deflex/__init__.py imports it as
// deflex._deflex and wraps its results (python/deflex/).
#include "bindings.hpp"

PYBIND11_MODULE(_deflex, m) {
  m.doc() = "deflex's job API and physics calls (use the package `deflex`, which wraps these)";
  deflex::python::bind_errors(m);
  deflex::python::bind_job(m);
  deflex::python::bind_physics(m);
}
