// What stock reads through OpenCASCADE, in deflex's OpenCASCADE plugin
// libdeflex_occt.so (src/plugin/load.cpp says why a plugin): the table of
// functions its entry point deflex_occt_stock returns. The plugin and the
// module are built together: plain C++ types cross, and deflex::Error
// reaches the caller as thrown.
#pragma once
#include <string>
#include <vector>

#include "deflex/stock/build.hpp"

class TopoDS_Shape;

namespace deflex::stock::occt {

struct Api {
  // A STEP (`step`) or IGES file meshed within mesh_deflection_mm, as
  // read_solid_triangles() documents (src/stock/occt/read_brep.cpp).
  std::vector<Triangle> (*read_brep_triangles)(const std::string& path, bool step, double mesh_deflection_mm);
  // route_occt_messages() (deflex/stock/build.hpp).
  void (*route_messages)();
};

// The plugin's table, loaded on first use; throws Error(ErrorKind::config)
// when the plugin cannot be loaded (src/stock/solid_import.cpp).
const Api& api();

// In the plugin, for its other readers (src/stiffness/occt/).
void route_messages();
// A STEP (`step`) or IGES file's shape; Error(ErrorKind::io) when unreadable.
TopoDS_Shape read_shape(const std::string& path, bool step);

}  // namespace deflex::stock::occt
