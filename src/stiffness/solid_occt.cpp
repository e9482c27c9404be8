// The tool solid of the solid model, built by deflex's OpenCASCADE plugin
// (occt_api.hpp), loaded when the first solid is built.
#include "deflex/stiffness/solid.hpp"
#include "deflex_plugin.hpp"
#include "occt_api.hpp"
#include "solid_internal.hpp"

namespace deflex::stiffness {

const occt::Api& occt::api() {
  static const Api& a = plugin::api<Api>("deflex_occt", "deflex_occt_stiffness", "OpenCASCADE: solid tool models");
  return a;
}

void solid::write_tool_brep(const Tool& t, const std::string& brep_path) {
  if (t.step_file.empty()) occt::api().write_shape_brep(tool_shape(t), brep_path);
  else occt::api().write_step_brep(t.step_file, brep_path);
}

void write_tool_step(const Tool& t, const std::string& step_path) {
  occt::api().write_shape_step(tool_shape(t), step_path);
}

}  // namespace deflex::stiffness
