// Earlier operations with tool libraries of their own on the command line:
// `--stock-from P --stock-from-tools LIB` (a job's stock_from entries and
// the call itself: tests/job/test_earlier.cpp). A roughing whose T21 (a flat D20) is only in its own
// library faces the box at Z-2 before the ball finish at Z-3 (a_p 1 mm, not
// 3: tests/engage/test_stock_from.cpp); a tool that library lacks is an error
// at the roughing's line naming that library.
#include <doctest/doctest.h>

#include <unistd.h>

#include <filesystem>
#include <set>
#include <string>

#include "../support.hpp"

namespace fs = std::filesystem;
using namespace deflex;

namespace {

// The facing pass of tests/engage/data/face_rough.nc with tool `t`.
std::string facing(const std::string& t) {
  std::string s = test::read_file("tests/engage/data/face_rough.nc");
  s.replace(s.find("T4 M06"), 6, t + " M06");
  return s;
}

// The flat D20 of samples/tools.yaml (T4) as T21, alone in a library.
std::string roughing_library() {
  const std::string all = test::read_file("samples/tools.yaml");
  const std::size_t a = all.find("\n  T4:"), b = all.find("\n  T5:");
  return "tools:\n  T21:" + all.substr(a + 6, b - a - 6) + "\n";
}

struct Dir {
  fs::path p;
  Dir() {
    std::string t = (fs::temp_directory_path() / "deflex-earlier-XXXXXX").string();
    p = mkdtemp(t.data());
    test::write_file((p / "rough21.nc").string(), facing("T21"));
    test::write_file((p / "rough22.nc").string(), facing("T22"));
    test::write_file((p / "rough_tools.yaml").string(), roughing_library());
  }
  ~Dir() { fs::remove_all(p); }
  std::string operator/(const char* f) const { return (p / f).string(); }
};

// The a_p column of points.csv for the points inside the box along X.
std::set<std::string> depths(const std::string& csv) {
  std::set<std::string> ap;
  const test::Csv c = test::read_csv(csv);
  for (std::size_t i = 0; i < c.rows.size(); ++i)
    if (c.num(i, "x_mm") > 10 && c.num(i, "x_mm") < 30) ap.insert(c.rows[i][5]);
  return ap;
}

test::CliResult simulate(const Dir& d, std::vector<std::string> extra, const char* report) {
  std::vector<std::string> a = {"simulate", "tests/engage/data/ball_finish.nc", "--material", "Al7075-T6",
                                "--report", d / report};
  a.insert(a.end(), extra.begin(), extra.end());
  return test::run_cli(a);
}

}  // namespace

TEST_SUITE("cli") {
  TEST_CASE("--stock-from-tools: the earlier program's tools come from its own library") {
    const Dir d;
    const std::vector<std::string> box = {"--stock", "box:0,0,-10,40,30,0"};
    auto with = [&](std::vector<std::string> more) {
      more.insert(more.begin(), box.begin(), box.end());
      return more;
    };
    const auto own = simulate(d, with({"--stock-from", d / "rough21.nc", "--stock-from-tools", d / "rough_tools.yaml"}), "own");
    REQUIRE(own.rc == 0);
    CHECK(depths(d / "own/points.csv") == std::set<std::string>{"1.0000"});
    CHECK(test::read_file(d / "own/report.html").find("rough21.nc (tools: " + d / "rough_tools.yaml" + ")") != std::string::npos);
    // A tool its own library lacks: exit 3, the error naming that library
    // (without --stock-from-tools, the run's: tests/job/test_earlier.cpp).
    const auto missing = simulate(d, with({"--stock-from", d / "rough22.nc", "--stock-from-tools", d / "rough_tools.yaml"}), "m");
    CHECK(missing.rc == 3);
    CHECK(missing.err.find(d / "rough22.nc" + ":7:1: error: tool T22 is not in the tool library " + d / "rough_tools.yaml") !=
          std::string::npos);
    // The library goes after its program: before any, or twice, is a usage error.
    CHECK(simulate(d, with({"--stock-from-tools", d / "rough_tools.yaml", "--stock-from", d / "rough21.nc"}), "u").rc == 2);
    CHECK(simulate(d, with({"--stock-from", d / "rough21.nc", "--stock-from-tools", d / "rough_tools.yaml",
                            "--stock-from-tools", d / "rough_tools.yaml"}), "u").rc == 2);
    // Only the program before it: the second one, T4 of the run's library, faces as well.
    const auto two = simulate(d, with({"--stock-from", d / "rough21.nc", "--stock-from-tools", d / "rough_tools.yaml",
                                       "--stock-from", "tests/engage/data/face_rough.nc"}), "two");
    CHECK(two.rc == 0);
    // deflex stock takes it too.
    CHECK(test::run_cli({"stock", "--stock", "box:0,0,-10,40,30,0", "--stock-from", d / "rough21.nc",
                         "--stock-from-tools", d / "rough_tools.yaml", "-o", d / "rest.zmap"}).rc == 0);
  }
}
