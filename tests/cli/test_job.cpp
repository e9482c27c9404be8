// The job file: the same run as the command line, byte for byte; the command
// line overrides it; its errors at line:col.
#include <doctest/doctest.h>

#include "../support.hpp"

using namespace deflex;

TEST_SUITE("cli") {
  TEST_CASE("compensate --job: the job and the equivalent command line write the same program") {
    const auto cmd = test::run_cli({"compensate", "tests/golden/wall.nc", "--stock", "box:0,0,-20,100,20,0",
                                    "--tool-file", "samples/tools.yaml", "--tolerance", "0.002", "--threads", "1"});
    const auto job = test::run_cli({"compensate", "--job", "tests/cli/data/wall_job.yaml", "--threads", "1"});
    REQUIRE(cmd.rc == 0);
    REQUIRE(job.rc == 0);
    CHECK(job.out == cmd.out);
    CHECK(job.out != test::read_file("tests/golden/wall.nc"));  // something was compensated
    // The command line wins: --gain 0 writes the input unchanged.
    const auto over = test::run_cli({"compensate", "--job", "tests/cli/data/wall_job.yaml", "--gain", "0"});
    REQUIRE(over.rc == 0);
    CHECK(over.out == test::read_file("tests/golden/wall.nc"));
    // A key the job format lacks is named with its position.
    test::write_file("/tmp/deflex-badjob.yaml", "program: x.nc\nstokc: box:0,0,0,1,1,1\n");
    const auto bad = test::run_cli({"compensate", "--job", "/tmp/deflex-badjob.yaml"});
    CHECK(bad.rc == 3);
    CHECK(bad.err.find("/tmp/deflex-badjob.yaml:2:1: error: unknown key 'stokc' in job") != std::string::npos);
  }
}
