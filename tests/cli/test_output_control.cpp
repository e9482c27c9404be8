// Output control: --quiet keeps errors and warnings only,
// --verbose adds the setup and each stage's time, --progress forces the
// progress line on or off; every --help lists them and shows its defaults as
// a user would type them.
#include <doctest/doctest.h>

#include <cstdlib>
#include <regex>

#include "../support.hpp"

using namespace deflex;

namespace {

const std::vector<std::string> kWall = {"compensate", "samples/programs/side_wall.nc", "--stock", "box:0,-40,-30,100,0,0",
                                        "-o", "/tmp/deflex-output-control.nc"};

test::CliResult with(std::vector<std::string> more) {
  std::vector<std::string> a = kWall;
  a.insert(a.end(), more.begin(), more.end());
  return test::run_cli(a);
}

}  // namespace

TEST_SUITE("cli") {
  TEST_CASE("--quiet: the warnings stay, notes and the summary go; --verbose: the setup and stage times") {
    const test::CliResult normal = with({}), quiet = with({"--quiet"}), verbose = with({"-v"});
    REQUIRE(normal.rc == 0);
    CHECK(quiet.rc == 0);
    CHECK(verbose.rc == 0);
    // The side wall deflects past the offset cap: a warning a machinist must see.
    CHECK(normal.err.find("warning: the deflection along the surface normal") != std::string::npos);
    CHECK(quiet.err.find("warning: the deflection along the surface normal") != std::string::npos);
    CHECK(normal.err.find("points compensated") != std::string::npos);
    CHECK(quiet.err.find("points compensated") == std::string::npos);
    CHECK(quiet.err.find("machining time") == std::string::npos);
    // Every line of the quiet output is a line of the normal one.
    CHECK(normal.err.find(quiet.err) != std::string::npos);
    CHECK(verbose.err.find("deflex: config config.yaml; machine mill3") != std::string::npos);
    CHECK(verbose.err.find("deflex: compensating done in ") != std::string::npos);
    CHECK(verbose.err.find(normal.err) != std::string::npos);  // and all the rest
  }

  TEST_CASE("--progress: always on a log (a line per tenth, with the elapsed time), never, and bad values") {
    const test::CliResult always = with({"--progress=always"}), never = with({"--progress", "never"});
    CHECK(always.rc == 0);
    CHECK(always.err.find("deflex: compensating   0%, 0:00 elapsed") != std::string::npos);
    CHECK(always.err.find('\033') == std::string::npos);  // not a terminal: no redraw codes
    CHECK(never.err.find("compensating") == std::string::npos);
    CHECK(with({"--progress=sometimes"}).rc == 2);
    CHECK(with({"--progress"}).rc == 2);
    CHECK(with({"-q", "--verbose"}).rc == 2);
  }

  TEST_CASE("--help of every command: the output options, and defaults as typed (no 0.050000000000000003)") {
    const std::regex noisy(R"(\(=[0-9]*\.[0-9]{7,}\))");
    for (std::string c : {"compensate", "simulate", "compare", "path", "check", "diff", "rewrite", "stock", "rough",
                          "testcut", "probe", "forces", "stiffness", "calibrate", "stability"}) {
      CAPTURE(c);
      const test::CliResult h = test::run_cli({c, "--help"});
      CHECK(h.rc == 0);
      CHECK_FALSE(std::regex_search(h.out, noisy));
      CHECK(h.out.find("--progress arg (=auto)") != std::string::npos);
    }
    CHECK(test::run_cli({"compensate", "--help"}).out.find("--cell-mm arg (=0.05)") != std::string::npos);
  }
}

TEST_SUITE("cli") {
  TEST_CASE("--verbose in pieces: one stage per simulation, closed at the end") {
    ::setenv("DEFLEX_CHUNK_LINES", "40", 1);
    const test::CliResult s = test::run_cli({"simulate", "samples/programs/side_wall.nc", "--stock",
                                             "box:0,-40,-30,100,0,0", "-v", "--threads", "1"});
    const test::CliResult c = with({"-v", "--threads", "1"});
    ::unsetenv("DEFLEX_CHUNK_LINES");
    CHECK(s.rc == 0);
    CHECK(s.err.find("deflex: simulating done in ") != std::string::npos);
    // With one thread the program as written is simulated beside the mirror
    // pass: the stage stays "compensating", once.
    CHECK(c.rc == 0);
    const std::size_t at = c.err.find("deflex: compensating done in ");
    CHECK(at != std::string::npos);
    CHECK(c.err.find("done in ", at + 30) == std::string::npos);
    CHECK(c.err.find("simulating") == std::string::npos);
  }
  TEST_CASE("machining time: over an hour every time of the line is h:mm:ss, and the label says so") {
    // 120 mm at 1 mm/min: two hours of cutting, seconds of rapids.
    const std::string slow = "%\nO0001\nN1 G21 G90 G17 G40 G49 G80 G54\nN2 T1 M06\nN3 S8000 M03\nN4 G00 X-10. Y-3. Z5.\n"
                             "N5 G01 Z-10. F800.\nN6 X110. F1.\nN7 G00 Z5.\nN8 M30\n%\n";
    const test::CliResult r = test::run_cli({"simulate", "-", "--stock", "box:0,0,-20,100,20,0"}, slow);
    REQUIRE(r.rc == 0);
    CHECK(std::regex_search(r.out + r.err, std::regex(R"(machining time: +2:00:\d\d \(cutting 2:00:\d\d, rapids )"
                                                       R"(0:00:\d\d\) \[h:mm:ss, axis limits)")));
    // Under an hour, m:ss.
    const test::CliResult w = with({});
    CHECK(w.err.find(" [m:ss, axis limits") != std::string::npos);
  }
  TEST_CASE("compensate --help names the normal's sources as compensate/normals.hpp orders them") {
    const test::CliResult h = test::run_cli({"compensate", "--help"});
    REQUIRE(h.rc == 0);
    const std::size_t part = h.out.find("comes, best first, from the part\nmodel (--part)");
    const std::size_t path = h.out.find("fitted through the CL points of the same and the adjacent passes");
    const std::size_t travel = h.out.find("for flat and bull-nose ends from the\ntool and the travel");
    CHECK(part < path);
    CHECK(path < travel);
    CHECK(travel != std::string::npos);
  }
}
