// --stock-from: earlier operations swept into the stock before the program.
// A flat D20 faces the box at Z-2; a ball D10 then runs at
// Z-3: a_p is 3 mm on the box and 3 - 2 = 1 mm on the faced stock.
#include <doctest/doctest.h>

#include <unistd.h>

#include <filesystem>
#include <map>
#include <sstream>

#include "../support.hpp"

namespace fs = std::filesystem;
using namespace deflex;

namespace {

// a_p of the points.csv rows strictly inside the box along X (not the entry or exit).
std::map<std::string, int> depths(const std::string& csv) {
  std::map<std::string, int> n;
  std::istringstream in(csv);
  std::string row;
  std::getline(in, row);
  while (std::getline(in, row)) {
    std::vector<std::string> f;
    std::stringstream ss(row);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    if (std::stod(f[1]) > 10 && std::stod(f[1]) < 30) ++n[f[5]];
  }
  return n;
}

}  // namespace

TEST_SUITE("engage") {
  TEST_CASE("--stock-from: a facing pass before a ball finish leaves a_p = 3 - 2 mm; bad earlier programs are named") {
    std::string t = (fs::temp_directory_path() / "deflex-stockfrom-XXXXXX").string();
    const fs::path dir = mkdtemp(t.data());
    const std::vector<std::string> base = {"simulate", "tests/engage/data/ball_finish.nc", "--stock",
                                           "box:0,0,-10,40,30,0", "--material", "Al7075-T6"};
    auto run = [&](std::vector<std::string> extra, const std::string& rep) {
      std::vector<std::string> a = base;
      a.insert(a.end(), extra.begin(), extra.end());
      a.push_back("--report");
      a.push_back((dir / rep).string());
      return test::run_cli(a);
    };
    REQUIRE(run({}, "box").rc == 0);
    REQUIRE(run({"--stock-from", "tests/engage/data/face_rough.nc"}, "faced").rc == 0);
    const auto box = depths(test::read_file((dir / "box" / "points.csv").string()));
    const auto faced = depths(test::read_file((dir / "faced" / "points.csv").string()));
    CHECK(box.size() == 1);
    CHECK(box.count("3.0000") == 1);
    CHECK(faced.size() == 1);
    CHECK(faced.count("1.0000") == 1);
    // The earlier program's diagnostics name its own file; a tool the library
    // lacks is the library's error (exit 3), before anything is built.
    test::write_file((dir / "bad.nc").string(), "G21 G90\nT99 M6\nG0 X0 Y0 Z5 S1000 M3\nG1 Z-1 F100\nM30\n");
    const auto bad = run({"--stock-from", (dir / "bad.nc").string()}, "bad");
    CHECK(bad.rc == 3);
    CHECK(bad.err.find((dir / "bad.nc").string() + ":4:1: error: tool T99 is not in the tool library") != std::string::npos);
    CHECK(run({"--stock-from", "-"}, "stdin").rc == 2);
    fs::remove_all(dir);
  }

  TEST_CASE("--stock-from: a finish in air over an earlier cut below its surface is named, with share, line and depth") {
    std::string t = (fs::temp_directory_path() / "deflex-earliercut-XXXXXX").string();
    const fs::path dir = mkdtemp(t.data());
    // T7 (ball D10) at Z-3 along X, passes 2 mm apart from Y0 to Y30, on a
    // 40 x 30 box; lines 7, 9, ... 35 are the passes.
    std::string finish = "G21 G90 G17\nT7 M6\nS10000 M3\nG0 X-10. Y0. Z5.\nG1 Z-3. F1200\n";
    for (int y = 0; y <= 30; y += 2) finish += "G1 Y" + std::to_string(y) + ".\nX" + (y % 4 ? "-10.\n" : "50.\n");
    finish += "G0 Z5.\nM30\n";
    test::write_file((dir / "finish.nc").string(), finish);
    // T4 (flat D20) faces Y -10..15 at Z-3.5 (0.5 mm below the finish) or Z-2.8 (0.2 mm above it).
    auto earlier = [&](const std::string& z) {
      const std::string f = (dir / ("face" + z + ".nc")).string();
      test::write_file(f, "G21 G90 G17\nT4 M6\nS6000 M3\nG0 X-15. Y-5. Z5.\nG1 Z" + z +
                              " F800\nX55.\nY5.\nX-15.\nG0 Z5.\nM30\n");
      return test::run_cli({"simulate", (dir / "finish.nc").string(), "--stock", "box:0,0,-10,40,30,0",
                            "--stock-from", f});
    };
    const auto below = earlier("-3.5");
    REQUIRE(below.rc == 0);
    const std::string name = (dir / "finish.nc").string();
    const std::size_t at = below.err.find(name + ":7:1: warning: ");
    REQUIRE_MESSAGE(at != std::string::npos, below.err);
    const std::string w = below.err.substr(at, below.err.find('\n', at) - at);
    CHECK(w.find("[earlier_cut]") != std::string::npos);
    CHECK(w.find("up to 0.500 mm below the tool") != std::string::npos);
    // The passes up to Y10 lie in air (the ball's leading half reaches 4.75 mm
    // to the side: Y12 meets the box), of 16 passes and the steps between.
    const std::size_t pct = w.find("% of the cutting points");
    REQUIRE(pct != std::string::npos);
    const int share = std::stoi(w.substr(w.rfind(' ', pct - 1) + 1));
    CHECK(share >= 25);
    CHECK(share <= 40);
    CHECK(w.find("lines (7, 9, 11, 13, 15, 17)") != std::string::npos);
    CHECK(below.err.find("[no_material]") == std::string::npos);
    // Left 0.2 mm above the finish: the finish cuts everywhere, nothing to say.
    const auto above = earlier("-2.8");
    REQUIRE(above.rc == 0);
    CHECK(above.err.find("[earlier_cut]") == std::string::npos);
    // The same finish on the box alone: no earlier program, no such warning.
    const auto box = test::run_cli({"simulate", name, "--stock", "box:0,0,-10,40,30,0"});
    CHECK(box.err.find("[earlier_cut]") == std::string::npos);
    fs::remove_all(dir);
  }
}
