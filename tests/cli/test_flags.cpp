// The library names settings by keyword; the command line names each by the
// option that gives it (cli/flags.cpp). Every keyword has one, and it is an
// option some command takes.
#include <doctest/doctest.h>

#include <string>

#include "../support.hpp"
#include "deflex/cli/command.hpp"
#include "deflex/diag/settings.hpp"

using namespace deflex;

TEST_SUITE("cli") {
  TEST_CASE("every setting the library's messages may name has its flag, taken by a command") {
    std::string helps;
    for (const char* c : {"compensate", "simulate", "rough", "diff", "check", "path", "stock", "testcut", "probe"})
      helps += test::run_cli({c, "--help"}).out;
    for (std::string_view k : setting_keywords()) {
      CAPTURE(k);
      const std::string flag = cli::flag_of(k);
      CHECK(flag != k);
      if (flag.starts_with("-")) CHECK(helps.find("  " + flag + " ") != std::string::npos);
    }
  }

  TEST_CASE("a library message names the flag on the command line, the keyword through the API") {
    const test::CliResult r = test::run_cli({"compensate", "missing.nc", "--tolerance", "-1"});
    CHECK(r.rc == 2);
    CHECK(r.err == "deflex: error: --tolerance must be > 0 mm\n");
    const test::CliResult k = test::run_cli({"simulate", "samples/programs/side_wall.nc", "--kt", "800", "--stock", "box:0,0,-20,40,10,0"});
    CHECK(k.rc == 2);
    CHECK(k.err.find("--kt, --kr and --ka go together") != std::string::npos);
  }
}
