// STL stock import: deflex's own STL reader (src/stock/stl.cpp) through a file,
// then the Z-map of the triangles. Huge but legal extents are skipped: their cost is time, not a bug
// (the cell limit itself is tested in tests/stock).
#include <algorithm>
#include <cmath>

#include "deflex/stock/build.hpp"
#include "fuzz_support.hpp"

using namespace deflex;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fuzz::temp_file(".stl", data, size);
  return fuzz::guarded([&] {
    const std::vector<stock::Triangle> tris = stock::read_solid_triangles(path, 0.005);
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (const stock::Triangle& t : tris)
      for (const auto& p : t.p)
        for (int a = 0; a < 2; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
    const double cell = 0.5;
    // Cells per axis as the Z-map counts them: at least one. (The product of
    // the extents alone let a 3e-43 x 1.3e8 mm stock through as "0 cells": a
    // legal 2.7e8-cell raster whose cost is time, found as a timeout.)
    const double nx = std::max(1.0, std::ceil((hi[0] - lo[0]) / cell)), ny = std::max(1.0, std::ceil((hi[1] - lo[1]) / cell));
    if (!tris.empty() && !(nx * ny <= 1e6)) return;
    stock::zmap_from_triangles(tris, cell);
  });
}
