// The holder and shank check on the command line: compensate stops on a
// holder in the material with exit code 1 (an input error), the error in
// compiler style with the source line, no output file and the input as it
// was; check --stock --stock-from gives the same error and exit code without
// simulating; with the longer stick-out both are clean (exit 0).
#include <doctest/doctest.h>

#include <filesystem>
#include <string>

#include "../support.hpp"

namespace fs = std::filesystem;
using namespace deflex;

namespace {

// As tests/job/test_collision.cpp: D10 flat ends at stick-outs 40 (T1) and
// 60 mm (T2), a pocket 55.5 mm deep roughed by T2, a floor pass at Z-55
// (tests/support.hpp).
struct Dir : test::TempDir {
  Dir() : TempDir("cli-collision") {
    test::write_file(*this / "tools.yaml", test::kPocketTools);
    test::write_file(*this / "rough.nc", test::pocket_roughing());
    for (int t : {1, 2}) test::write_file(*this / ("finish" + std::to_string(t) + ".nc"), test::pocket_floor_pass(t));
  }
  std::vector<std::string> args(const char* command, const std::string& program) const {
    return {command, *this / program, "--tool-file", *this / "tools.yaml", "--stock", "box:0,0,-80,100,100,0",
            "--stock-from", *this / "rough.nc"};
  }
};

}  // namespace

TEST_SUITE("cli") {

TEST_CASE("collision: compensate and check --stock exit 1 on the holder in the material, nothing written") {
  const Dir d;
  const std::string before = test::read_file(d / "finish1.nc");
  std::vector<std::string> a = d.args("compensate", "finish1.nc");
  a.insert(a.end(), {"--material", "Al6082-T4", "-o", d / "out.nc"});
  const test::CliResult c = test::run_cli(a);
  CHECK(c.rc == 1);
  const std::string where = d / "finish1.nc" + ":5:1: error: the holder of T1 runs 15.00 mm into the material";
  CHECK(c.err.find(where) != std::string::npos);
  CHECK(c.err.find("G1 Z-55. F300") != std::string::npos);
  CHECK(c.out.empty());
  CHECK_FALSE(fs::exists(d / "out.nc"));
  CHECK(test::read_file(d / "finish1.nc") == before);
  // The output is the input: refused before anything is read (the input is never overwritten).
  std::vector<std::string> same = d.args("compensate", "finish1.nc");
  same.insert(same.end(), {"--material", "Al6082-T4", "-o", d / "finish1.nc"});
  CHECK(test::run_cli(same).rc != 0);
  CHECK(test::read_file(d / "finish1.nc") == before);
  const test::CliResult k = test::run_cli(d.args("check", "finish1.nc"));
  CHECK(k.rc == 1);
  CHECK(k.err.find(where) != std::string::npos);
  CHECK(k.out.find("1 error") != std::string::npos);
}

TEST_CASE("collision: the longer stick-out is clean in compensate and check --stock") {
  const Dir d;
  std::vector<std::string> a = d.args("compensate", "finish2.nc");
  a.insert(a.end(), {"--material", "Al6082-T4", "-o", d / "out.nc"});
  const test::CliResult c = test::run_cli(a);
  CHECK(c.rc == 0);
  CHECK(fs::exists(d / "out.nc"));
  const test::CliResult k = test::run_cli(d.args("check", "finish2.nc"));
  CHECK(k.rc == 0);
  CHECK(k.err.find("error") == std::string::npos);
}

}  // TEST_SUITE
