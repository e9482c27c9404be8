// job::write_rest_stock(): the stock after an earlier program written as a
// .zmap (every height as computed) or a binary STL, and
// its refusals before anything is read.
#include <doctest/doctest.h>

#include <filesystem>

#include "support.hpp"
#include "deflex/job/stock.hpp"
#include "deflex/stock/zmap_file.hpp"

using namespace deflex;

namespace {

job::StockSettings pocket_on_box() {
  job::StockSettings s;
  s.stock = "box:-5,-5,-10,65,45,0";
  s.stock_from = {{"samples/programs/pocket_finish.nc", ""}};
  s.cell_mm = 0.5;
  return s;
}

}  // namespace

TEST_SUITE("job") {
  TEST_CASE("write_rest_stock: the .zmap holds rest_stock's heights exactly; an STL of the same stock") {
    test::TempDir t;
    test::Streams s;
    const stock::ZMap z = job::rest_stock(pocket_on_box(), s.io);
    const job::StockFile f = job::write_rest_stock(pocket_on_box(), t / "rest.zmap", 0.001, s.io);
    CHECK(f.zmap);
    CHECK(f.spec == "box:-5,-5,-10,65,45,0");
    const stock::ZMap back = stock::read_zmap(t / "rest.zmap");
    REQUIRE(back.grid().nx == z.grid().nx);
    REQUIRE(back.grid().ny == z.grid().ny);
    int cut = 0;
    for (int j = 0; j < z.grid().ny; ++j)
      for (int i = 0; i < z.grid().nx; ++i) {
        CHECK(back.at(i, j) == z.at(i, j));
        cut += z.at(i, j) < 0;
      }
    CHECK(cut > 0);  // the pocket is in it

    const job::StockFile stl = job::write_rest_stock(pocket_on_box(), t / "rest.stl", 0.001, s.io);
    CHECK(!stl.zmap);
    CHECK(stl.triangles > 0);
    // A binary STL: an 80-byte header naming the stock, the count, 50 bytes a
    // triangle (its accuracy against the heights: tests/stock/test_mesh_out.cpp).
    const std::string bytes = test::read_file(t / "rest.stl");
    CHECK(bytes.size() == 84 + 50 * stl.triangles);
    CHECK(bytes.rfind("deflex stock: box:-5,-5,-10,65,45,0", 0) == 0);
  }

  TEST_CASE("write_rest_stock refuses the output stream, an output onto nothing and a bad tolerance before reading") {
    test::TempDir t;
    test::Streams s;
    job::StockSettings missing = pocket_on_box();
    missing.stock_from = {{t / "no_such.nc", ""}};  // would be an I/O error if it were read
    for (const char* out : {"", "-"}) {
      try {
        (void)job::write_rest_stock(missing, out, 0.001, s.io);
        FAIL("wrote a stock to the output stream");
      } catch (const Error& e) {
        CHECK(e.kind() == ErrorKind::settings);
        CHECK(e.settings() == std::vector<std::string>{"output"});
      }
    }
    try {
      (void)job::write_rest_stock(missing, t / "rest.zmap", 11, s.io);
      FAIL("took a mesh tolerance of 11 mm");
    } catch (const Error& e) {
      CHECK(e.kind() == ErrorKind::settings);
      CHECK(e.settings() == std::vector<std::string>{"mesh_tolerance_mm"});
    }
    CHECK(!std::filesystem::exists(t / "rest.zmap"));
  }
}
