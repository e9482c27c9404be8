// The job file through job::apply_job_file: the same run as the settings it
// stands for, byte for byte; settings already given win over it; its errors
// at line:col. How the command line's --job and options combine is in
// tests/cli/test_job.cpp.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "support.hpp"

using namespace deflex;

namespace {

// `s` filled from the job file `file` (which names the program).
job::Settings from_job(const std::string& file, job::Settings s = {}) {
  std::vector<std::string> programs;
  job::apply_job_file(file, s, programs);
  REQUIRE(programs.size() == 1);
  if (s.program.empty()) s.program = programs[0];
  return s;
}

// The config Error apply_job_file throws on `file`: its message.
std::string job_error(const std::string& file) {
  job::Settings s;
  std::vector<std::string> programs;
  try {
    job::apply_job_file(file, s, programs);
  } catch (const Error& e) {
    CHECK(e.kind() == ErrorKind::config);
    return e.what();
  }
  FAIL("the job file was accepted");
  return "";
}

}  // namespace

TEST_SUITE("job") {
  TEST_CASE("job file: the job and the equivalent settings write the same program; given settings win") {
    job::Settings same;
    same.program = "tests/golden/wall.nc";
    same.stock = "box:0,0,-20,100,20,0";
    same.tool_file = "samples/tools.yaml";
    same.tolerance_mm = 0.002;
    same.threads = 1;
    job::Settings one_thread;
    one_thread.threads = 1;
    const auto cmd = test::compensate_job(same);
    const auto job = test::compensate_job(from_job("tests/cli/data/wall_job.yaml", one_thread));
    REQUIRE(cmd.ok());
    REQUIRE_MESSAGE(job.ok(), job.err);
    CHECK(job.out == cmd.out);
    CHECK(job.out != test::read_file("tests/golden/wall.nc"));  // something was compensated
    // A setting given before the job file is read wins: gain 0 writes the input unchanged.
    job::Settings no_gain;
    no_gain.gain = 0;
    const auto over = test::compensate_job(from_job("tests/cli/data/wall_job.yaml", no_gain));
    REQUIRE(over.ok());
    CHECK(over.out == test::read_file("tests/golden/wall.nc"));
  }

  TEST_CASE("job file: a key the format lacks is a config error named with its position") {
    test::TempDir d("job");
    test::write_file(d / "bad.yaml", "program: x.nc\nstokc: box:0,0,0,1,1,1\n");
    CHECK(job_error(d / "bad.yaml").find(d / "bad.yaml" + ":2:1: error: unknown key 'stokc' in job") != std::string::npos);
  }

  TEST_CASE("job file: fixture as one box or a list, and the workpiece's mesh and spacing; a negative size at its line") {
    test::TempDir d("job");
    test::write_file(d / "one.yaml", "program: x.nc\nfixture: box:0,0,0,1,1,1\n");
    CHECK(from_job(d / "one.yaml").workholding.fixtures == std::vector<std::string>{"box:0,0,0,1,1,1"});
    test::write_file(d / "two.yaml",
                     "program: x.nc\nfixture: ['box:0,0,0,1,1,1', 'box:2,2,2,3,3,3']\nworkpiece_mesh_mm: 2\nworkpiece_spacing_mm: 5\n");
    const job::Settings s = from_job(d / "two.yaml");
    CHECK(s.workholding.fixtures == std::vector<std::string>{"box:0,0,0,1,1,1", "box:2,2,2,3,3,3"});
    CHECK(s.workholding.mesh_mm == 2);
    CHECK(s.workholding.spacing_mm == 5);
    // Given before the job is read: the given fixtures win.
    job::Settings given;
    given.workholding.fixtures = {"box:9,9,9,10,10,10"};
    CHECK(from_job(d / "two.yaml", given).workholding.fixtures == given.workholding.fixtures);
    test::write_file(d / "bad.yaml", "program: x.nc\nfixture: box:0,0,0,1,1,1\nworkpiece_mesh_mm: -1\n");
    CHECK(job_error(d / "bad.yaml").find(d / "bad.yaml" + ":3:") != std::string::npos);
    // A box unquoted in a flow list falls apart at its commas: an error at the list.
    test::write_file(d / "flow.yaml", "program: x.nc\nfixture: [box:0,0,0,1,1,1]\n");
    const std::string e = job_error(d / "flow.yaml");
    CHECK(e.find(d / "flow.yaml" + ":2:") != std::string::npos);
    CHECK(e.find("quote a box") != std::string::npos);
  }
}
