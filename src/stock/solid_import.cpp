// Reading a stock solid: STL by our own reader (stl.cpp: a triangulation as
// is), STEP and IGES through OpenCASCADE in deflex's plugin libdeflex_occt.so
// (src/stock/occt/read_brep.cpp), loaded on the first such file.
#include <algorithm>
#include <cctype>
#include <filesystem>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/stock/build.hpp"
#include "deflex_plugin.hpp"
#include "stock_occt_api.hpp"

namespace deflex::stock {

namespace {

std::string lower_extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e;
}

}  // namespace

const occt::Api& occt::api() {
  static const Api& a = plugin::api<Api>("deflex_occt", "deflex_occt_stock", "OpenCASCADE: STEP and IGES files");
  return a;
}

void route_occt_messages() { occt::api().route_messages(); }

std::vector<Triangle> read_solid_triangles(const std::string& path, double mesh_deflection_mm) {
  if (!std::filesystem::is_regular_file(path)) throw Error(ErrorKind::io, path + ": no such file");
  const std::string ext = lower_extension(path);
  if (ext == ".stl") {
    std::vector<Triangle> out = read_stl(path);
    if (out.empty()) throw Error(ErrorKind::io, path + ": cannot read as STL (or it has no triangles)");
    return out;
  }
  if (ext != ".step" && ext != ".stp" && ext != ".iges" && ext != ".igs")
    throw Error(ErrorKind::settings, path + ": stock file must be .stl, .step/.stp or .iges/.igs (or box:X0,Y0,Z0,X1,Y1,Z1)");
  if (!(mesh_deflection_mm > 0)) throw Error(ErrorKind::config, "stock: mesh deflection must be > 0");
  return occt::api().read_brep_triangles(path, ext == ".step" || ext == ".stp", mesh_deflection_mm);
}

}  // namespace deflex::stock
