// The .zmap file: read back, every cell's height is the Z-map's bit for bit
// (the invariant, on a scallop field where the STL cannot merge anything);
// the file is a small fraction of the STL and of the raw heights; a damaged
// file is an I/O error naming it; `deflex stock -o X.zmap` and `--stock X.zmap`
// round-trip through the command line.
#include <doctest/doctest.h>

#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "../support.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "deflex/stock/build.hpp"
#include "deflex/stock/mesh_out.hpp"
#include "deflex/stock/sweep.hpp"
#include "deflex/stock/zmap_file.hpp"

namespace fs = std::filesystem;
using namespace deflex;
using namespace deflex::stock;

namespace {

// A 40 x 30 mm box at 0.05 mm cells (800 x 600), a ball D6 raster 0.5 mm apart
// down a slope (scallops everywhere: no two neighbouring cells alike) and a flat
// D10 pocket through the base at one corner (cells without material).
ZMap scallop_field() {
  ZMap z = make_stock("box:0,0,-5,40,30,0", {0.05});
  for (double y = 0; y <= 30; y += 0.5) sweep_line(z, {EndShape::ball, 3, 3}, {-4, y, -1 - y / 20}, {44, y, -2.5 - y / 20});
  sweep_line(z, {EndShape::flat, 5, 0}, {36, 26, -6}, {36, 26, -6});
  return z;
}

fs::path temp_file(const std::string& name) {
  return fs::temp_directory_path() / ("deflex-zmap-" + std::to_string(::getpid()) + "-" + name);
}

std::string bytes_of(const ZMap& z) {
  std::ostringstream o;
  write_zmap(o, z);
  return o.str();
}

}  // namespace

TEST_SUITE("stock") {
  TEST_CASE("zmap file: every cell read back as it was, in a small fraction of the STL's bytes") {
    const ZMap z = scallop_field();
    const fs::path f = temp_file("field.zmap");
    test::write_file(f.string(), bytes_of(z));
    const ZMap back = read_zmap(f.string());
    const GridSpec &g = z.grid(), &h = back.grid();
    REQUIRE(h.nx == g.nx);
    REQUIRE(h.ny == g.ny);
    CHECK(h.x0_mm == g.x0_mm);
    CHECK(h.y0_mm == g.y0_mm);
    CHECK(h.cell_mm == g.cell_mm);
    CHECK(back.base_z_mm() == z.base_z_mm());
    int differ = 0, empty = 0;
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) {
        const float a = z.at(i, j), b = back.at(i, j);
        differ += std::memcmp(&a, &b, 4) != 0;
        empty += a == no_material;
      }
    CHECK(differ == 0);
    CHECK(empty > 0);  // the pocket's cells went through as "no material"
    // Through make_stock (what --stock FILE.zmap does) at the file's cell: the same.
    CHECK(bytes_of(make_stock(f.string(), {0.05})) == bytes_of(z));
    // The size: 480,000 cells are 1.9 MB of float32 and, even merged within
    // 0.001 mm, an STL of 46 MB (a scallop field does not merge); the file is
    // 26 kB, a small part of either.
    const double raw = 4.0 * g.nx * g.ny, stl = 84 + 50.0 * zmap_mesh(z, 0.001).size();
    const double size = static_cast<double>(fs::file_size(f));
    MESSAGE("zmap " << size << " bytes, raw heights " << raw << ", STL " << stl);
    CHECK(size < raw / 20);
    CHECK(size < stl / 200);
    fs::remove(f);
  }

  TEST_CASE("zmap file: an untouched box is a few bytes; another cell size interpolates between the file's centres") {
    const ZMap box = make_stock("box:0,0,-5,40,30,0", {0.05});
    CHECK(bytes_of(box).size() < 2000);
    const ZMap z = scallop_field();
    const fs::path f = temp_file("coarse.zmap");
    test::write_file(f.string(), bytes_of(z));
    const ZMap c = make_stock(f.string(), {0.1});
    CHECK(c.grid().nx == 400);
    CHECK(c.grid().ny == 300);
    for (int j = 0; j < 300; j += 7)
      for (int i = 0; i < 400; i += 7) REQUIRE(c.at(i, j) == static_cast<float>(z.height_smooth(c.cx(i), c.cy(j))));
    fs::remove(f);
  }

  TEST_CASE("zmap file: a plane read back at twice the cell is the plane, not shifted by half a cell") {
    // Each centre of the coarse grid lies on a boundary of the file's cells:
    // the cell on one side would put the plane 0.025 mm off in X and Y.
    ZMap z = make_stock("box:0,0,-5,20,10,0", {0.05});
    for (int j = 0; j < z.grid().ny; ++j)
      for (int i = 0; i < z.grid().nx; ++i) z.set(i, j, static_cast<float>(-1 - 0.2 * z.cx(i) - 0.1 * z.cy(j)));
    const fs::path f = temp_file("plane.zmap");
    test::write_file(f.string(), bytes_of(z));
    const ZMap c = make_stock(f.string(), {0.1});
    double worst = 0;
    for (int j = 1; j + 1 < c.grid().ny; ++j)
      for (int i = 1; i + 1 < c.grid().nx; ++i)
        worst = std::max(worst, std::fabs(c.at(i, j) - (-1 - 0.2 * c.cx(i) - 0.1 * c.cy(j))));
    CHECK(worst < 1e-5);  // float rounding; the cell beside the centre is 0.0075 mm off
    fs::remove(f);
  }

  TEST_CASE("zmap file: a damaged file is an I/O error that names it") {
    const std::string good = bytes_of(scallop_field());
    const fs::path f = temp_file("bad.zmap");
    auto fails = [&](const std::string& bytes, const char* why) {
      CAPTURE(why);
      test::write_file(f.string(), bytes);
      try {
        (void)read_zmap(f.string());
        FAIL("read");
      } catch (const Error& e) {
        CHECK(e.kind() == ErrorKind::io);
        CHECK(std::string(e.what()).find(f.string() + ": cannot read as a Z-map") == 0);
        CHECK(std::string(e.what()).find(why) != std::string::npos);
      }
    };
    fails("", "no DEFLEXZM header");
    fails("solid x\nendsolid x\n", "no DEFLEXZM header");
    fails(good.substr(0, good.size() / 2), "");
    fails(good + "x", "bytes after the tile data");
    std::string v2 = good;
    v2[8] = 2;
    fails(v2, "format version 2");
    std::string huge = good;
    const std::int32_t n = 1 << 30;
    std::memcpy(huge.data() + 16, &n, 4);
    fails(huge, "too many cells");
    std::string flipped = good;
    flipped[good.size() / 2] = static_cast<char>(flipped[good.size() / 2] ^ 0x55);
    fails(flipped, "");
    fs::remove(f);
  }
}

TEST_SUITE("cli") {
  TEST_CASE("deflex stock -o X.zmap: read back with --stock X.zmap, the same stock") {
    std::string t = (fs::temp_directory_path() / "deflex-zmapcli-XXXXXX").string();
    const fs::path dir = mkdtemp(t.data());
    const std::string a = (dir / "rest.zmap").string(), b = (dir / "again.zmap").string();
    const test::CliResult r = test::run_cli({"stock", "--stock", "box:0,0,-10,40,30,0", "--stock-from",
                                             "tests/engage/data/face_rough.nc", "-o", a});
    REQUIRE(r.rc == 0);
    CHECK(r.err.find("800 x 600 cells of 0.05 mm") != std::string::npos);
    CHECK(test::read_file(a).substr(0, 8) == "DEFLEXZM");
    REQUIRE(test::run_cli({"stock", "--stock", a, "-o", b}).rc == 0);
    CHECK(test::read_file(a) == test::read_file(b));
    fs::remove_all(dir);
  }
}
