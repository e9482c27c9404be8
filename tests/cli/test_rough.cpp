// deflex rough: a roughing program generated from a finishing
// program, swept with --stock-from before it. The plan itself is checked in
// tests/plan; here the command: its checks, its output, and what the
// finishing program meets afterwards.
#include <doctest/doctest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "../support.hpp"

namespace fs = std::filesystem;
using namespace deflex;

namespace {

// The largest material removal rate (mm^3/s) of the points.csv rows strictly
// inside the box along X. Not a_p: a thin layer over the whole groove engages
// the ball over the groove's full depth as well.
double max_mrr(const std::string& csv) {
  std::istringstream in(csv);
  std::string row;
  std::getline(in, row);
  double m = 0;
  while (std::getline(in, row)) {
    std::vector<std::string> f;
    std::stringstream ss(row);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    if (std::stod(f[1]) > 10 && std::stod(f[1]) < 30) m = std::max(m, std::stod(f[9]));
  }
  return m;
}

}  // namespace

TEST_SUITE("cli") {
  TEST_CASE("rough: a roughing program before the ball finish; the finish then meets less than the box") {
    std::string t = (fs::temp_directory_path() / "deflex-rough-XXXXXX").string();
    const fs::path dir = mkdtemp(t.data());
    const std::string finish = "tests/engage/data/ball_finish.nc", box = "box:0,0,-10,40,30,0";
    const std::string rough = (dir / "rough.nc").string();
    // A ball D6 follows the D10 groove 0.3 mm off, lines 1 mm apart, one level.
    const std::vector<std::string> args = {"rough", finish, "--stock", box, "--rough-tool", "T3", "--allowance", "0.3",
                                           "--stepdown", "0", "--stepover", "1"};
    std::vector<std::string> to_file = args;
    to_file.insert(to_file.end(), {"-o", rough});
    const auto r = test::run_cli(to_file);
    REQUIRE(r.rc == 0);
    CHECK(r.err.find("rough.nc: 1 level from Z0.000 to the floor") != std::string::npos);
    CHECK(r.err.find("31 lines 1.000 mm apart") != std::string::npos);
    CHECK(r.err.find("T3 leaves 0.300 mm over the surface of " + finish) != std::string::npos);
    // The program reads back clean, like any program.
    CHECK(test::run_cli({"check", rough}).rc == 0);
    // Standard output when no -o, the same bytes.
    const auto o = test::run_cli(args);
    CHECK(o.rc == 0);
    CHECK(o.out == test::read_file(rough));
    auto sim = [&](std::vector<std::string> extra, const std::string& rep) {
      std::vector<std::string> a = {"simulate", finish, "--stock", box, "--material", "Al7075-T6", "--report", (dir / rep).string()};
      a.insert(a.end(), extra.begin(), extra.end());
      REQUIRE(test::run_cli(a).rc == 0);
      return max_mrr(test::read_file((dir / rep / "points.csv").string()));
    };
    // The ball D10 at Z-3 in the box removes the groove's whole section (a
    // segment of 3 mm of a circle R5: 19.0 mm^2) at 20 mm/s; after the rough
    // a layer of about 0.3 mm over an arc of 11.6 mm (3.5 mm^2), plus scallops.
    const double on_box = sim({}, "box"), on_rough = sim({"--stock-from", rough}, "rough");
    const double segment = 25 * std::acos(2.0 / 5) - 2 * std::sqrt(25.0 - 4);
    CHECK(on_box == doctest::Approx(segment * 20).epsilon(0.02));
    CHECK(on_rough < 0.3 * on_box);
    CHECK(on_rough > 0.15 * on_box);
    fs::remove_all(dir);
  }

  TEST_CASE("rough: the header names the spacing the lines have, the stepover spread evenly") {
    // 30 mm of stock at a stepover of at most 4 mm: 8 gaps of 3.75 mm.
    const auto r = test::run_cli({"rough", "tests/engage/data/ball_finish.nc", "--stock", "box:0,0,-10,40,30,0",
                                  "--rough-tool", "T3", "--stepdown", "0", "--stepover", "4"});
    REQUIRE(r.rc == 0);
    CHECK(r.err.find("9 lines 3.750 mm apart") != std::string::npos);
    CHECK(r.out.find("ALONG X, ONE LEVEL, LINES 3.750 MM APART - THE STEPOVER 4.000 SPREAD EVENLY OVER THE STOCK") !=
          std::string::npos);
    CHECK(r.out.find("STEPOVER 4.000 MM") == std::string::npos);
  }

  TEST_CASE("rough: refused before anything is computed") {
    const std::string finish = "tests/engage/data/ball_finish.nc", box = "box:0,0,-10,40,30,0";
    auto rc = [&](std::vector<std::string> extra, const std::string& says) {
      std::vector<std::string> a = {"rough", finish, "--stock", box};
      a.insert(a.end(), extra.begin(), extra.end());
      const auto r = test::run_cli(a);
      CAPTURE(r.err);
      CHECK(r.err.find(says) != std::string::npos);
      CHECK(r.out.empty());
      return r.rc;
    };
    CHECK(rc({}, "--rough-tool T<n> is required") == 2);
    CHECK(test::run_cli({"rough", "-", "--stock", box, "--rough-tool", "T1"}).rc == 2);
    CHECK(rc({"--rough-tool", "T99"}, "T99") == 2);
    CHECK(rc({"--rough-tool", "T1", "--stepover", "11"}, "the stepover must be") == 2);
    CHECK(rc({"--rough-tool", "T1", "--stepover", "0.0001", "--sample", "0.01"}, "floor samples") == 2);
    CHECK(rc({"--rough-tool", "T1", "-o", finish}, "") == 2);  // never over the input
    // The allowance above the stock top: nothing to rough.
    CHECK(rc({"--rough-tool", "T1", "--allowance", "5"}, "nothing to rough") == 2);
  }
}
