// The job file on the command line: --job reads it, an option given beside
// it wins, and its errors are configuration errors (exit 3) at line:col. The
// job file as settings (the same run as the command line's) is
// tests/job/test_job_file.cpp.
#include <doctest/doctest.h>

#include "../support.hpp"

using namespace deflex;

TEST_SUITE("cli") {
  TEST_CASE("compensate --job: the command line wins over the job; a bad key is exit 3 at its position") {
    // --gain 0 writes the input unchanged.
    const auto over = test::run_cli({"compensate", "--job", "tests/cli/data/wall_job.yaml", "--gain", "0"});
    REQUIRE(over.rc == 0);
    CHECK(over.out == test::read_file("tests/golden/wall.nc"));
    test::TempDir d("job");
    test::write_file(d / "bad.yaml", "program: x.nc\nstokc: box:0,0,0,1,1,1\n");
    const auto bad = test::run_cli({"compensate", "--job", d / "bad.yaml"});
    CHECK(bad.rc == 3);
    CHECK(bad.err.find(d / "bad.yaml" + ":2:1: error: unknown key 'stokc' in job") != std::string::npos);
  }
}
