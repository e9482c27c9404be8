// The thread count is a matter of speed only: one thread and more threads than
// the machine has cores write the same bytes (program, points.csv,
// summary.json), as the simulator promises (engage/simulator.hpp).
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "../support.hpp"

using namespace deflex;

namespace {

// A ball end over the wave of the corpus (2,300 blocks, 9,400 CL points: many
// batches of the simulator, and points the mirror moves) on its bare blank.
std::vector<std::string> wave(const std::string& command, const std::string& threads, const std::string& dir) {
  return {command,  "tests/data/corpus/wave.gcode", "--stock", "box:0,0,-5,92,92,0", "--tool", "T3", "--dialect",
          "linuxcnc", "--threads", threads, "--report", dir};
}

}  // namespace

TEST_SUITE("cli") {
  TEST_CASE("--threads 1 and --threads 16 write the same bytes (simulate and compensate)") {
    test::TempDir t;
    for (const char* command : {"simulate", "compensate"}) {
      CAPTURE(command);
      const test::CliResult one = test::run_cli(wave(command, "1", t / (std::string(command) + "1")));
      const test::CliResult many = test::run_cli(wave(command, "16", t / (std::string(command) + "16")));
      REQUIRE(one.rc == 0);
      REQUIRE(many.rc == 0);
      CHECK(one.out == many.out);  // compensate: the program
      CHECK(one.err == many.err);  // the figures
      for (const char* f : {"points.csv", "summary.json"}) {
        CAPTURE(f);
        const std::string a = test::read_file(t / (std::string(command) + "1/" + f));
        CHECK(a.size() > 1000);
        CHECK(a == test::read_file(t / (std::string(command) + "16/" + f)));
      }
    }
  }
}
