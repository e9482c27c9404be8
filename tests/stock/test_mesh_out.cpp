// The stock as a closed STL: every edge shared by two triangles with opposite
// orientations, the enclosed volume that of the Z-map, every cell's height
// within the tolerance when read back, flat regions merged; and the issue's
// check: a finish simulated on the written STL engages exactly as on the stock
// swept from the same roughing program. And the stock as boxes (a solid for
// OpenCASCADE): disjoint, every cell with material once, at its rounded height.
#include <doctest/doctest.h>

#include <unistd.h>

#include <Eigen/Dense>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <tuple>

#include "../support.hpp"
#include "deflex/stock/build.hpp"
#include "deflex/stock/mesh_out.hpp"
#include "deflex/stock/sweep.hpp"

namespace fs = std::filesystem;
using namespace deflex;
using namespace deflex::stock;
using doctest::Approx;

namespace {

// A 20 x 10 mm box, top Z0 base Z-5, cell 0.1 mm, with a ball D6 slot 1 mm deep
// along X and a flat D4 pocket 2 mm deep: flat, curved and vertical.
ZMap cut_box() {
  ZMap z = make_stock("box:0,0,-5,20,10,0", {0.1});
  sweep_line(z, {EndShape::ball, 3, 3}, {2, 5, -1}, {18, 5, -1});
  sweep_line(z, {EndShape::flat, 2, 0}, {15, 2.5, -2}, {15, 2.5, -2});
  return z;
}

using Key = std::tuple<float, float, float>;
Key key(const std::array<double, 3>& p) { return {float(p[0]), float(p[1]), float(p[2])}; }

// Read back through deflex's STL reader at the same cell: the same grid, and
// the largest difference of a cell's height from the Z-map's.
double worst_read_back(const ZMap& z, const std::vector<Triangle>& tris) {
  const fs::path f = fs::temp_directory_path() / ("deflex-mesh-" + std::to_string(::getpid()) + ".stl");
  {
    std::ofstream o(f, std::ios::binary);
    write_binary_stl(o, tris, "test");
  }
  const ZMap back = zmap_from_triangles(read_stl(f.string()), z.grid().cell_mm);
  fs::remove(f);
  REQUIRE(back.grid().nx == z.grid().nx);
  REQUIRE(back.grid().ny == z.grid().ny);
  CHECK(back.grid().x0_mm == Approx(z.grid().x0_mm).epsilon(1e-6));
  double worst = 0;
  for (int j = 0; j < z.grid().ny; ++j)
    for (int i = 0; i < z.grid().nx; ++i) worst = std::max(worst, std::fabs(double(back.at(i, j)) - z.at(i, j)));
  return worst;
}

}  // namespace

TEST_SUITE("stock") {
  TEST_CASE("stock mesh: closed and oriented, the Z-map's volume, every cell within the tolerance") {
    const ZMap z = cut_box();
    for (double tol : {0.0, 0.01}) {
      CAPTURE(tol);
      const std::vector<Triangle> tris = zmap_mesh(z, tol);
      // Each directed edge once, and its reverse once: closed, manifold, consistently oriented.
      std::map<std::pair<Key, Key>, int> edges;
      for (const Triangle& t : tris)
        for (int k = 0; k < 3; ++k) ++edges[{key(t.p[k]), key(t.p[(k + 1) % 3])}];
      int bad = 0;
      for (const auto& [e, n] : edges) bad += n != 1 || edges.count({e.second, e.first}) != 1 || edges.at({e.second, e.first}) != 1;
      CHECK(bad == 0);
      // Outward normals: the signed volume is positive and is the stock's (cells x
      // height over the bottom 0.01 mm under the base), but for the interpolation
      // across the cut's edges.
      double vol = 0;
      for (const Triangle& t : tris) {
        const Eigen::Vector3d a(t.p[0].data()), b(t.p[1].data()), c(t.p[2].data());
        vol += a.dot(b.cross(c)) / 6;
      }
      double cells = 0;
      for (int j = 0; j < z.grid().ny; ++j)
        for (int i = 0; i < z.grid().nx; ++i) cells += (z.at(i, j) - (-5.01)) * 0.01;
      CHECK(vol == Approx(cells).epsilon(0.002));
      CHECK(worst_read_back(z, tris) <= tol + 2e-5);  // + float rounding of the STL
    }
    // Flat regions merge. The full grid is 2 x 201 x 101 triangles on top; the
    // untouched box needs under a tenth of that (the quadtree's leaves stay small
    // only along the borders the power-of-two squares cut), the box with its
    // slot (curved over most of its width) and pocket still fewer than the grid.
    const double full = 2.0 * 201 * 101;
    CHECK(zmap_mesh(make_stock("box:0,0,-5,20,10,0", {0.1}), 0.001).size() < full / 10);
    CHECK(zmap_mesh(z, 0.001).size() < 0.6 * full);
  }

  TEST_CASE("stock mesh: sloped and curved surfaces merge too, every cell still within the tolerance") {
    // A 20 x 10 mm ramp rising 0.1 mm per mm along X and 0.05 along Y (0.01 mm
    // from cell to cell: no two neighbours within 0.001 mm of each other), with
    // a ball D16 dimple 1 mm deep in it.
    auto make_ramp = [] {
      ZMap r = make_stock("box:0,0,-5,20,10,0", {0.1});
      for (int j = 0; j < r.grid().ny; ++j)
        for (int i = 0; i < r.grid().nx; ++i) r.set(i, j, static_cast<float>(-3 + 0.1 * r.cx(i) + 0.05 * r.cy(j)));
      return r;
    };
    const ZMap ramp = make_ramp();
    ZMap z = make_ramp();
    sweep_line(z, {EndShape::ball, 8, 8}, {6, 5, -2.15 - 1}, {6, 5, -2.15 - 1});
    const double full = 2.0 * 201 * 101;
    const std::vector<Triangle> plane = zmap_mesh(ramp, 0.001);
    CHECK(plane.size() < full / 5);  // the strip along the outline stays fine: its ring of vertices is level
    CHECK(worst_read_back(ramp, plane) <= 0.001 + 2e-5);
    for (double tol : {0.001, 0.01}) {
      CAPTURE(tol);
      const std::vector<Triangle> tris = zmap_mesh(z, tol);
      CHECK(tris.size() < full / 2);
      CHECK(worst_read_back(z, tris) <= tol + 2e-5);
    }
  }

  TEST_CASE("deflex stock: the finish on the written STL engages as on the stock swept from the same roughing") {
    std::string t = (fs::temp_directory_path() / "deflex-stockout-XXXXXX").string();
    const fs::path dir = mkdtemp(t.data());
    const std::string rest = (dir / "rest.stl").string();
    REQUIRE(test::run_cli({"stock", "--stock", "box:0,0,-10,40,30,0", "--stock-from", "tests/engage/data/face_rough.nc",
                           "--mesh-tolerance", "0", "-o", rest})
                .rc == 0);
    auto engagement = [&](std::vector<std::string> stock, const std::string& rep) {
      std::vector<std::string> a = {"simulate", "tests/engage/data/ball_finish.nc", "--material", "Al7075-T6",
                                    "--report", (dir / rep).string()};
      a.insert(a.end(), stock.begin(), stock.end());
      REQUIRE(test::run_cli(a).rc == 0);
      std::string ae;  // line, x, y, z, path, a_p, a_e of every point
      std::istringstream in(test::read_file((dir / rep / "points.csv").string()));
      for (std::string row; std::getline(in, row);) {
        std::size_t at = 0;
        for (int k = 0; k < 7; ++k) at = row.find(',', at) + 1;
        ae += row.substr(0, at) + "\n";
      }
      return ae;
    };
    const std::string swept = engagement({"--stock", "box:0,0,-10,40,30,0", "--stock-from", "tests/engage/data/face_rough.nc"}, "a");
    const std::string read = engagement({"--stock", rest}, "b");
    const std::string box = engagement({"--stock", "box:0,0,-10,40,30,0"}, "c");
    CHECK(swept == read);
    CHECK(swept != box);
    CHECK(test::run_cli({"stock", "--stock", "box:0,0,-10,40,30,0"}).rc == 2);  // -o is required
    fs::remove_all(dir);
  }

  TEST_CASE("zmap_boxes: disjoint boxes that cover every cell with material, each at its cell's rounded height") {
    // The cut box: a ball slot (every cell its own height) and a flat pocket.
    const ZMap z = cut_box();
    const GridSpec& g = z.grid();
    const double step = 0.25;
    const std::vector<BoxSpec> boxes = zmap_boxes(z, step);
    std::vector<int> covered(static_cast<std::size_t>(g.nx) * static_cast<std::size_t>(g.ny), 0);
    double volume = 0;
    for (const BoxSpec& b : boxes) {
      const int i0 = static_cast<int>(std::lround((b.x0_mm - g.x0_mm) / g.cell_mm));
      const int i1 = static_cast<int>(std::lround((b.x1_mm - g.x0_mm) / g.cell_mm));
      const int j0 = static_cast<int>(std::lround((b.y0_mm - g.y0_mm) / g.cell_mm));
      const int j1 = static_cast<int>(std::lround((b.y1_mm - g.y0_mm) / g.cell_mm));
      REQUIRE(i0 < i1);
      REQUIRE(j0 < j1);
      CHECK(b.z0_mm == z.base_z_mm());
      for (int j = j0; j < j1; ++j)
        for (int i = i0; i < i1; ++i) {
          ++covered[static_cast<std::size_t>(j) * static_cast<std::size_t>(g.nx) + static_cast<std::size_t>(i)];
          // Its top is the cell's height rounded to the step.
          CHECK(std::fabs(b.z1_mm - z.at(i, j)) <= 0.5 * step + 1e-9);
        }
      volume += (b.x1_mm - b.x0_mm) * (b.y1_mm - b.y0_mm) * (b.z1_mm - b.z0_mm);
    }
    double cells_volume = 0;
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) {
        const int c = covered[static_cast<std::size_t>(j) * static_cast<std::size_t>(g.nx) + static_cast<std::size_t>(i)];
        CHECK(c == (z.at(i, j) > z.base_z_mm() ? 1 : 0));  // once each, and only material
        cells_volume += g.cell_mm * g.cell_mm * (z.at(i, j) - z.base_z_mm());
      }
    // The volume within half a step over the footprint; merged far below a box per cell.
    CHECK(std::fabs(volume - cells_volume) <= 0.5 * step * 20 * 10);
    MESSAGE(boxes.size(), " boxes for ", g.nx * g.ny, " cells");
    CHECK(boxes.size() < static_cast<std::size_t>(g.nx * g.ny) / 20);
  }
}
