// The compiled half of `import deflex`: deflex/__init__.py imports it as
// deflex._deflex and wraps its results (python/deflex/).
#include <filesystem>
#include <string>

#include "bindings.hpp"
#include "deflex/profile/search.hpp"

PYBIND11_MODULE(_deflex, m) {
  m.doc() = "deflex's job API and physics calls (use the package `deflex`, which wraps these)";
  deflex::python::bind_errors(m);
  deflex::python::bind_job(m);
  deflex::python::bind_physics(m);
  // None where there is none (a build used from its tree): never a folder
  // that does not exist, as `deflex --version` says "none found".
  m.def(
      "data_dir",
      []() -> pybind11::object {
        const std::string d = deflex::profile::data_dir();
        std::error_code ec;
        if (!std::filesystem::is_directory(d, ec)) return pybind11::none();
        return pybind11::str(d);
      },
      "The folder of deflex's own files (config.yaml, samples/): $DEFLEX_DATA_DIR, else the installed prefix's "
      "share/deflex; None where there is none");
}
