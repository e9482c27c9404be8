// The tool solids the solid model builds with OpenCASCADE, in deflex's
// OpenCASCADE plugin libdeflex_occt.so (src/plugin/load.cpp says why a
// plugin): the table of functions its entry point deflex_occt_stiffness
// returns (src/stiffness/occt/tool_solid.cpp). Private to src/stiffness/.
#pragma once
#include <string>

#include "deflex/stiffness/shape.hpp"

namespace deflex::stiffness::occt {

struct Api {
  // The revolved equivalent profile `s` as a .brep file.
  void (*write_shape_brep)(const ToolShape& s, const std::string& brep_path);
  // A tool's STEP model converted to a .brep file.
  void (*write_step_brep)(const std::string& step_path, const std::string& brep_path);
  // The revolved equivalent profile `s` as a STEP file.
  void (*write_shape_step)(const ToolShape& s, const std::string& step_path);
  // A part's STEP (`step`) or IGES file as its closed solid(s) in a .brep
  // file; Error(ErrorKind::config) when it bounds no volume.
  void (*write_part_brep)(const std::string& path, bool step, const std::string& brep_path);
};

// In the plugin: the part's solid (src/stiffness/occt/part_solid.cpp).
void write_part_brep(const std::string& path, bool step, const std::string& brep_path);


// The plugin's table, loaded on first use; throws Error(ErrorKind::config)
// when the plugin cannot be loaded (src/stiffness/solid_occt.cpp).
const Api& api();

}  // namespace deflex::stiffness::occt
