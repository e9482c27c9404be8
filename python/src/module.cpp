// The compiled half of `import deflex`: deflex/__init__.py imports it as
// deflex._deflex and wraps its results (python/deflex/).
#include "bindings.hpp"
#include "deflex/profile/search.hpp"

PYBIND11_MODULE(_deflex, m) {
  m.doc() = "deflex's job API and physics calls (use the package `deflex`, which wraps these)";
  deflex::python::bind_errors(m);
  deflex::python::bind_job(m);
  deflex::python::bind_physics(m);
  m.def("data_dir", &deflex::profile::data_dir,
        "The folder of deflex's own files (config.yaml, samples/): $DEFLEX_DATA_DIR, else the installed prefix's "
        "share/deflex");
}
