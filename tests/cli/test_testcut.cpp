// deflex testcut and deflex probe on the command line: what they write and
// print, their help, and options refused before anything is written. What
// the calls compute is in tests/job/test_testcut.cpp.
#include <doctest/doctest.h>

#include <filesystem>
#include <string>

#include "../support.hpp"

namespace fs = std::filesystem;
using namespace deflex;

namespace {

std::vector<std::string> testcut_args(const test::TempDir& dir) {
  return {"testcut", "--machine", "samples/machines/mill3.yaml", "--tool", "T1", "--tool-file", "samples/tools.yaml",
          "--material", "Al7075-T6", "--stock", "box:0,0,-30,200,200,0", "-o", dir / "cut.nc"};
}

}  // namespace

TEST_SUITE("cli") {
  TEST_CASE("testcut then probe: the program and its plan, then the probing program on stdout or into -o") {
    test::TempDir dir("cli-testcut");
    const auto r = test::run_cli(testcut_args(dir));
    CAPTURE(r.err);
    REQUIRE(r.rc == 0);
    CHECK(r.out.empty());
    CHECK(r.err.find("cut.nc: 12 walls of T1 in Al7075-T6, S6000 F1200.0 (fz 0.0500 mm)") != std::string::npos);
    CHECK(r.err.find("plan " + dir / "cut.yaml") != std::string::npos);
    REQUIRE(fs::exists(dir / "cut.yaml"));
    const auto p = test::run_cli({"probe", dir / "cut.yaml", "--dialect", "linuxcnc", "--ball-diameter", "3", "--step", "0.25"});
    CAPTURE(p.err);
    REQUIRE(p.rc == 0);
    CHECK(p.out.find("G38.2 ") != std::string::npos);
    CHECK(p.out.find("BALL 1.500)\n") != std::string::npos);
    CHECK(p.err.find("points on 12 walls of " + dir / "cut.yaml" + ", ball D3.000") != std::string::npos);
    const auto f = test::run_cli({"probe", dir / "cut.yaml", "-o", dir / "probe.nc", "--probe-tool", "T20", "--probe-length", "40"});
    REQUIRE(f.rc == 0);
    const std::string fanuc = test::read_file(dir / "probe.nc");
    CHECK(fanuc.find("G31 ") != std::string::npos);  // the plan's dialect: mill3's fanuc
    CHECK(fanuc.find("DPRNT[PT1*X#5061[44]*Y#5062[44]*Z#5063[44]]\n") != std::string::npos);
    CHECK(fanuc.find("PROBE LENGTH 40.000 MM - PROBE T20") != std::string::npos);
    // --plan names the plan's file.
    std::vector<std::string> a = testcut_args(dir);
    a.insert(a.end(), {"--plan", dir / "other.yaml", "--spindle", "8000", "--feed", "1600"});
    const auto o = test::run_cli(a);
    CHECK(o.rc == 0);
    CHECK(test::read_file(dir / "other.yaml").find("fz_mm: 0.0500") != std::string::npos);
  }

  TEST_CASE("testcut and probe: --help teaches; bad options are refused before anything is written") {
    const auto h = test::run_cli({"testcut", "--help"});
    CHECK(h.rc == 0);
    CHECK(h.out.find("down\n(climb) milling") != std::string::npos);
    CHECK(h.out.find("deflex probe testcut.yaml") != std::string::npos);
    const auto ph = test::run_cli({"probe", "--help"});
    CHECK(ph.rc == 0);
    CHECK(ph.out.find("(DEFLEX PROBE 12 WX1 AT 10.000 5.000 -2.250 N 0.0000 1.0000 0.0000 BALL 1.000)") != std::string::npos);
    CHECK(ph.out.find("--ball-diameter") != std::string::npos);
    test::TempDir dir("cli-testcut");
    auto refused = [&](std::vector<std::string> args, const std::string& message) {
      const auto r = test::run_cli(args);
      CAPTURE(r.err);
      CHECK(r.rc == 2);
      CHECK(r.err.find(message) != std::string::npos);
      CHECK(r.out.empty());
      CHECK(fs::is_empty(dir.p));
    };
    std::vector<std::string> small = testcut_args(dir);
    small[10] = "box:0,0,-30,150,150,0";
    refused(small, "deflex: error: --stock: the block (150 x 150 x 30 mm) is too small");
    std::vector<std::string> both = testcut_args(dir);
    both.insert(both.end(), {"--feed", "1000", "--fz", "0.1"});
    refused(both, "give --feed or --fz, not both");
    refused({"testcut", "--tool", "T1", "--material", "Al7075-T6", "--stock", "box:0,0,-30,200,200,0"},
            "the program goes to a file (-o FILE.nc)");
    const auto t = test::run_cli(testcut_args(dir));
    REQUIRE(t.rc == 0);
    fs::remove(dir / "cut.nc");
    fs::remove(dir / "cut.yaml");
    test::write_file(dir / "bad.yaml", "features: []\n");
    const auto b = test::run_cli({"probe", dir / "bad.yaml", "-o", dir / "probe.nc"});
    CHECK(b.rc == 3);
    CHECK(b.err.find(dir / "bad.yaml" + ":1:1: error: missing key") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "probe.nc"));
    fs::remove(dir / "bad.yaml");
    const auto s = test::run_cli({"probe", "x.yaml", "--step", "1"});
    CHECK(s.rc == 2);
    CHECK(s.err == "deflex: error: --step must be in [0.25, 0.5] mm\n");  // before the plan is read
  }
}
