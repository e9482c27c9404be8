// Earlier operations with tool libraries of their own, through the job API
// (Settings::stock_from): a roughing whose T21 (a flat D20) is only in its own
// library faces the box at Z-2 before the ball finish at Z-3, so the finish
// cuts a_p 1 mm, not 3 (tests/engage/test_stock_from.cpp); a tool that
// library lacks is a config error at the roughing's line naming the library.
// The command line's forms of the same are in tests/cli/test_earlier.cpp.
#include <doctest/doctest.h>

#include <cmath>
#include <set>
#include <sstream>

#include "../support.hpp"
#include "deflex/job/job.hpp"

using namespace deflex;

namespace {

// The facing pass of tests/engage/data/face_rough.nc with tool `t`, and the
// flat D20 of samples/tools.yaml (T4) as T21 alone in a library.
struct Roughing : test::TempDir {
  Roughing() : TempDir("job-earlier") {
    for (const char* t : {"T21", "T22"}) {
      std::string s = test::read_file("tests/engage/data/face_rough.nc");
      s.replace(s.find("T4 M06"), 6, std::string(t) + " M06");
      test::write_file(*this / (std::string("rough") + (t + 1) + ".nc"), s);
    }
    const std::string all = test::read_file("samples/tools.yaml");
    const std::size_t a = all.find("\n  T4:"), b = all.find("\n  T5:");
    test::write_file(*this / "rough_tools.yaml", "tools:\n  T21:" + all.substr(a + 6, b - a - 6) + "\n");
  }
};

// The a_p of the finish's points inside the box along X, mm, to 1 um.
struct Depths : job::Observer {
  std::set<long> ap_um;
  bool wants_rows() const override { return true; }
  void row(const report::PointRow& r) override {
    if (r.tip_mm.x() > 10 && r.tip_mm.x() < 30) ap_um.insert(std::lround(1000 * r.ap_mm));
  }
};

job::Settings finish_on_box() {
  job::Settings s;
  s.program = "tests/engage/data/ball_finish.nc";
  s.material.material = "Al7075-T6";
  s.stock = "box:0,0,-10,40,30,0";
  return s;
}

}  // namespace

TEST_SUITE("job") {
  TEST_CASE("stock_from: the earlier program's tools come from its own library") {
    const Roughing d;
    job::Settings s = finish_on_box();
    s.stock_from = {{d / "rough21.nc", d / "rough_tools.yaml"}};
    std::istringstream in;
    std::ostringstream out, err;
    job::Io io{in, out, err};
    Depths depths;
    job::Run run = job::open(s, job::Purpose::simulate, io);
    (void)job::simulate(run, io, &depths);
    CHECK(depths.ap_um == std::set<long>{1000});
    bool named = false;
    for (const auto& [key, value] : job::provenance(run, ""))
      named |= key == "stock from" && value == d / "rough21.nc" + " (tools: " + d / "rough_tools.yaml" + ")";
    CHECK(named);
    // Without its library T21 is looked up in the run's, which lacks it; a
    // tool its own library lacks names that library. Both before any stock.
    for (const auto& [program, library, named_lib] :
         {std::tuple{d / "rough21.nc", std::string(), std::string("samples/tools.yaml")},
          std::tuple{d / "rough22.nc", d / "rough_tools.yaml", d / "rough_tools.yaml"}}) {
      s.stock_from = {{program, library}};
      std::ostringstream e;
      job::Io quiet{in, out, e};
      CAPTURE(program);
      try {
        (void)job::open(s, job::Purpose::simulate, quiet);
        FAIL("a tool missing from the library was accepted");
      } catch (const Error& x) {
        CHECK(x.kind() == ErrorKind::config);
      }
      const std::string tool = program.ends_with("21.nc") ? "T21" : "T22";
      CHECK(e.str().find(program + ":7:1: error: tool " + tool + " is not in the tool library " + named_lib) !=
            std::string::npos);
    }
  }
}
