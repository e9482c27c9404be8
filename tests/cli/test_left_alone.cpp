// Every move left alone says why (issue 16 item 5): points outside the
// tolerance on moves deflex does not move are counted per reason and named at
// the first line, never silently missing from "N points compensated".
#include <doctest/doctest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "../support.hpp"
#include "deflex/report/json.hpp"

namespace fs = std::filesystem;
using namespace deflex;

TEST_SUITE("cli") {
  TEST_CASE("left alone: the first pass of the side wall in G91 is named, with its count, on stderr and in summary.json") {
    const fs::path dir = fs::temp_directory_path() / ("deflex-left-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    // The sample's first pass (line 16) as an incremental move of the same end.
    std::string text = test::read_file("samples/programs/side_wall.nc");
    const std::string pass = "N22 X110. F2546.4\n";
    REQUIRE(text.find(pass) != std::string::npos);
    text.replace(text.find(pass), pass.size(), "N22 G91 X120. F2546.4\nN23 G90\n");
    const std::string prog = (dir / "wall91.nc").string();
    test::write_file(prog, text);
    const std::vector<std::string> stock = {"--stock", "box:0,-40,-30,100,0,0"};
    auto run = [&](const std::string& p, const fs::path& report) {
      std::vector<std::string> a = {"compensate", p, "-o", (dir / "out.nc").string(), "--report", report.string()};
      a.insert(a.end(), stock.begin(), stock.end());
      return test::run_cli(a);
    };
    const test::CliResult g91 = run(prog, dir / "r91"), g90 = run("samples/programs/side_wall.nc", dir / "r90");
    REQUIRE(g91.rc == 0);
    REQUIRE(g90.rc == 0);
    const std::string want = prog + ":16:1: warning: ";
    const std::size_t at = g91.err.find(want);
    REQUIRE(at != std::string::npos);
    const std::string line = g91.err.substr(at, g91.err.find('\n', at) - at);
    CHECK(line.find("points outside +-0.0100 mm are left as programmed on incremental (G91) moves") != std::string::npos);
    CHECK(line.find("[left_alone]") != std::string::npos);
    const report::Json s = report::Json::parse(test::read_file((dir / "r91/summary.json").string()));
    REQUIRE(s["left_alone"].size() == 1);
    CHECK(s["left_alone"][0]["reason"] == "incremental (G91)");
    CHECK(s["left_alone"][0]["first_line"] == 16);
    // The count is the first pass's points outside the tolerance: on the
    // program in G90 the same pass is compensated, and nothing is left alone.
    const std::size_t n = s["left_alone"][0]["points"];
    CHECK(n > 150);
    CHECK(n <= s["cl_points"].get<std::size_t>());
    CHECK(g90.err.find("[left_alone]") == std::string::npos);
    CHECK(report::Json::parse(test::read_file((dir / "r90/summary.json").string()))["left_alone"].empty());
    fs::remove_all(dir);
  }
}

TEST_SUITE("cli") {
  TEST_CASE("left as written: one note per reason with the block count and the first line, in pieces too") {
    const std::vector<std::string> a = {"compensate", "samples/programs/pocket_finish.nc", "--stock",
                                        "box:-5,-5,-20,105,85,0", "-o", "/tmp/deflex-left-pf.nc"};
    const test::CliResult r = test::run_cli(a);
    REQUIRE(r.rc == 0);
    const std::string note =
        "samples/programs/pocket_finish.nc: note: 2 executed blocks stay as written: canned-cycle moves (drilling is not a "
        "surface); the first at line 21\n";
    CHECK(r.err.find(note) != std::string::npos);
    CHECK(r.err.find("canned-cycle") == r.err.rfind("canned-cycle"));  // once, not per block
    ::setenv("DEFLEX_CHUNK_LINES", "5", 1);
    const test::CliResult p = test::run_cli(a);
    ::unsetenv("DEFLEX_CHUNK_LINES");
    CHECK(p.err == r.err);
    // The plain side wall has no such move: no note.
    CHECK(test::run_cli({"compensate", "samples/programs/side_wall.nc", "--stock", "box:0,-40,-30,100,0,0", "-o",
                         "/tmp/deflex-left-sw.nc"})
              .err.find("stay as written") == std::string::npos);
  }
}
