// STL stock import: OpenCASCADE's reader through a file, then the Z-map of the
// triangles. Huge but legal extents are skipped: their cost is time, not a bug
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
    if (!tris.empty() && (hi[0] - lo[0]) / cell * ((hi[1] - lo[1]) / cell) > 1e6) return;
    stock::zmap_from_triangles(tris, cell);
  });
}
