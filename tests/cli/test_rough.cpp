// deflex rough on the command line: what it prints (the plan on stderr, the
// program on stdout or into -o) and its own option check. What the call
// computes and refuses is in tests/job/test_rough.cpp.
#include <doctest/doctest.h>

#include <string>

#include "../support.hpp"

using namespace deflex;

TEST_SUITE("cli") {
  TEST_CASE("rough: the plan on stderr, the program on stdout or into -o; --rough-tool is required") {
    test::TempDir dir("rough");
    const std::string finish = "tests/engage/data/ball_finish.nc", rough = dir / "rough.nc";
    const std::vector<std::string> args = {"rough", finish, "--stock", "box:0,0,-10,40,30,0", "--rough-tool", "T3",
                                           "--stepdown", "0", "--stepover", "4"};
    std::vector<std::string> to_file = args;
    to_file.insert(to_file.end(), {"-o", rough});
    const auto r = test::run_cli(to_file);
    REQUIRE(r.rc == 0);
    CHECK(r.out.empty());
    CHECK(r.err.find("rough.nc: 1 level from Z0.000 to the floor") != std::string::npos);
    CHECK(r.err.find("9 lines 3.750 mm apart") != std::string::npos);
    CHECK(r.err.find("T3 leaves 0.500 mm over the surface of " + finish) != std::string::npos);
    // Standard output when no -o, the same bytes.
    const auto o = test::run_cli(args);
    CHECK(o.rc == 0);
    CHECK(o.out == test::read_file(rough));
    const auto none = test::run_cli({"rough", finish, "--stock", "box:0,0,-10,40,30,0"});
    CHECK(none.rc == 2);
    CHECK(none.err.find("--rough-tool T<n> is required") != std::string::npos);
    CHECK(none.out.empty());
  }
}
