// Stock from solids: a hand-written STL pyramid (exact), and a sphere of radius
// 10 written by OpenCASCADE as STEP and IGES (within the mesh deflection).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>

#include "../support.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "deflex/stock/build.hpp"

using namespace deflex;
using namespace deflex::stock;

namespace {

const std::string data_dir = std::string(DEFLEX_SOURCE_DIR) + "/tests/stock/data/";

// Square pyramid on [0, 20]^2, apex (10, 10, 8), closed by its base at z = 0.
std::string write_pyramid_stl() {
  const auto path = std::filesystem::temp_directory_path() / "deflex_pyramid_test.stl";
  std::ofstream f(path);
  const double c[4][2] = {{0, 0}, {20, 0}, {20, 20}, {0, 20}};
  f << "solid pyramid\n";
  auto facet = [&](const double* a, double az, const double* b, double bz, const double* d, double dz) {
    f << " facet normal 0 0 0\n  outer loop\n";
    f << "   vertex " << a[0] << " " << a[1] << " " << az << "\n";
    f << "   vertex " << b[0] << " " << b[1] << " " << bz << "\n";
    f << "   vertex " << d[0] << " " << d[1] << " " << dz << "\n";
    f << "  endloop\n endfacet\n";
  };
  const double apex[2] = {10, 10};
  for (int k = 0; k < 4; ++k) facet(c[k], 0, c[(k + 1) % 4], 0, apex, 8);
  facet(c[0], 0, c[2], 0, c[1], 0);
  facet(c[0], 0, c[3], 0, c[2], 0);
  f << "endsolid pyramid\n";
  return path.string();
}

void check_sphere(const ZMap& z, double deflection) {
  CHECK(z.base_z_mm() == deflex::test::within(-10, 1e-3));
  int inside = 0;
  for (int j = 0; j < z.grid().ny; j += 7)
    for (int i = 0; i < z.grid().nx; i += 7) {
      const double x = z.cx(i), y = z.cy(j), rr = x * x + y * y;
      if (rr > 10.2 * 10.2) CHECK(z.at(i, j) == no_material);
      if (rr > 9 * 9) continue;
      const double h = std::sqrt(100 - rr), slope = std::sqrt(rr) / h;
      // The mesh lies within `deflection` of the sphere, measured along the normal.
      CHECK(std::fabs(z.at(i, j) - h) <= deflection * std::sqrt(1 + slope * slope) + 1e-4);
      ++inside;
    }
  CHECK(inside > 100);
}

}  // namespace

TEST_SUITE("stock") {

TEST_CASE("triangle soup: the upper envelope equals every triangle tested at every cell centre, bit for bit") {
  // A closed height-field solid (top of random heights, flat bottom, sides)
  // plus loose triangles above and below it, in shuffled order: the skip of
  // triangles that cannot raise a cell must not change a single cell.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> h(-3.0, 3.0);
  std::vector<Triangle> tris;
  const int n = 12;
  const double step = 2.5;
  std::vector<double> top((n + 1) * (n + 1));
  for (double& t : top) t = h(rng);
  auto at = [&](int i, int j) { return std::array<double, 3>{i * step, j * step, top[j * (n + 1) + i]}; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      tris.push_back({{at(i, j), at(i + 1, j), at(i + 1, j + 1)}});
      tris.push_back({{at(i, j), at(i + 1, j + 1), at(i, j + 1)}});
    }
  const double L = n * step;
  tris.push_back({{{{0, 0, -10}, {L, 0, -10}, {L, L, -10}}}});  // bottom
  tris.push_back({{{{0, 0, -10}, {L, L, -10}, {0, L, -10}}}});
  tris.push_back({{{{0, 0, -10}, {L, 0, -10}, {L, 0, 3}}}});      // a side (vertical: no area)
  std::uniform_real_distribution<double> u(-2.0, L + 2.0), v(-12.0, 6.0);
  for (int k = 0; k < 60; ++k)
    tris.push_back({{{{u(rng), u(rng), v(rng)}, {u(rng), u(rng), v(rng)}, {u(rng), u(rng), v(rng)}}}});
  std::shuffle(tris.begin(), tris.end(), rng);
  const double cell = 0.05;
  const ZMap z = zmap_from_triangles(tris, cell);
  // The plain rule: each cell centre takes the highest triangle over it.
  const GridSpec& g = z.grid();
  std::size_t raised = 0;
  for (int j = 0; j < g.ny; j += 3)
    for (int i = 0; i < g.nx; i += 3) {
      const double x = z.cx(i), y = z.cy(j);
      float want = no_material;
      for (const Triangle& t : tris) {
        const auto& p = t.p;
        const double d = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
        if (std::fabs(d) < 1e-18) continue;
        const double l1 = ((x - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (y - p[0][1])) / d;
        const double l2 = ((p[1][0] - p[0][0]) * (y - p[0][1]) - (x - p[0][0]) * (p[1][1] - p[0][1])) / d;
        const double l0 = 1 - l1 - l2;
        if (l0 < -1e-12 || l1 < -1e-12 || l2 < -1e-12) continue;
        want = std::max(want, static_cast<float>(l0 * p[0][2] + l1 * p[1][2] + l2 * p[2][2]));
      }
      REQUIRE(z.at(i, j) == want);
      raised += want != no_material;
    }
  CHECK(raised > 10000);
}

TEST_CASE("STL pyramid: the upper envelope is exact at the cell centres") {
  const std::string path = write_pyramid_stl();
  const ZMap z = zmap_from_solid_file(path, {0.1, 0.005});
  std::filesystem::remove(path);
  CHECK(z.grid().nx == 200);
  CHECK(z.base_z_mm() == 0);
  for (int j = 0; j < z.grid().ny; ++j)
    for (int i = 0; i < z.grid().nx; ++i) {
      const double x = z.cx(i), y = z.cy(j);
      const double expect = 8 * (1 - std::max(std::fabs(x - 10), std::fabs(y - 10)) / 10);
      if (std::fabs(z.at(i, j) - expect) > 1e-5) REQUIRE(z.at(i, j) == doctest::Approx(expect));
    }
}

TEST_CASE("STEP and IGES sphere: top surface within the mesh deflection") {
  for (const char* name : {"sphere_r10.step", "sphere_r10.igs"}) {
    CAPTURE(name);
    SolidOptions o;
    o.cell_mm = 0.05;
    o.mesh_deflection_mm = 0.005;
    const ZMap z = make_stock(data_dir + name, o);
    check_sphere(z, o.mesh_deflection_mm);
  }
}

TEST_CASE("stock spec errors") {
  CHECK_THROWS_AS(make_stock(data_dir + "missing.step"), Error);
  try {
    make_stock(data_dir + "missing.step");
  } catch (const Error& e) {
    CHECK(e.kind() == ErrorKind::io);
  }
  const auto txt = std::filesystem::temp_directory_path() / "deflex_stock_test.txt";
  std::ofstream(txt) << "not a solid\n";
  try {
    make_stock(txt.string());
    FAIL("expected an error");
  } catch (const Error& e) {
    CHECK(e.kind() == ErrorKind::settings);
  }
  std::filesystem::remove(txt);
  CHECK(make_stock("box:0,0,0,10,10,5").height_at(5, 5) == 5);
}

}  // TEST_SUITE
