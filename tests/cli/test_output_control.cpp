// Output control (issue 15 item 5): --quiet keeps errors and warnings only,
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
                          "forces", "stiffness", "calibrate"}) {
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
}
