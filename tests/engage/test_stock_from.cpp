// --stock-from: earlier operations swept into the stock before the program
// (issue 13 item 1). A flat D20 faces the box at Z-2; a ball D10 then runs at
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
}
