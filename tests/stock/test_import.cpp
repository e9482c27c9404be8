// Stock from solids: a hand-written STL pyramid (exact), and a sphere of radius
// 10 written by OpenCASCADE as STEP and IGES (within the mesh deflection).
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

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
  CHECK(z.base_z_mm() == doctest::Approx(-10).epsilon(1e-3));
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
    CHECK(e.code() == Exit::io);
  }
  const auto txt = std::filesystem::temp_directory_path() / "deflex_stock_test.txt";
  std::ofstream(txt) << "not a solid\n";
  try {
    make_stock(txt.string());
    FAIL("expected an error");
  } catch (const Error& e) {
    CHECK(e.code() == Exit::usage);
  }
  std::filesystem::remove(txt);
  CHECK(make_stock("box:0,0,0,10,10,5").height_at(5, 5) == 5);
}

}  // TEST_SUITE
