// What a run leaves as written, through the job API: the moves per reason
// that open() counts (Run::left_moves, the same read whole or in pieces), and
// the points outside the tolerance on them that compensate() finds
// (RunFigures::left_alone). The command line's notes and warnings on them are
// in tests/cli/test_left_alone.cpp.
#include <doctest/doctest.h>

#include <cstdlib>
#include <sstream>

#include "../support.hpp"
#include "deflex/job/job.hpp"

using namespace deflex;

TEST_SUITE("job") {
  TEST_CASE("left as written: the pocket's drilling cycle, counted once per block, whole or in pieces") {
    job::Settings s;
    s.program = "samples/programs/pocket_finish.nc";
    s.stock = "box:-5,-5,-20,105,85,0";
    std::istringstream in;
    std::ostringstream out, err;
    job::Io io{in, out, err};
    for (const char* lines : {"0", "5"}) {
      CAPTURE(lines);
      ::setenv("DEFLEX_CHUNK_LINES", lines, 1);
      const job::Run run = job::open(s, job::Purpose::compensate, io);
      ::unsetenv("DEFLEX_CHUNK_LINES");
      CHECK((run.pieces != nullptr) == (lines[0] != '0'));
      REQUIRE(run.left_moves.size() == 1);
      const auto& [why, moves] = *run.left_moves.begin();
      CHECK(why == interp::Fixed::canned_cycle);
      CHECK(moves.blocks == 2);
      CHECK(moves.first_line == 21);
    }
  }

  TEST_CASE("left alone: nothing on the plain side wall; its points past the offset cap are capped, not left") {
    job::Settings s;
    s.program = "samples/programs/side_wall.nc";
    s.stock = "box:0,-40,-30,100,0,0";
    std::istringstream in;
    std::ostringstream out, err;
    job::Io io{in, out, err};
    job::Run run = job::open(s, job::Purpose::compensate, io);
    CHECK(run.left_moves.empty());
    const job::CompensateResult r = job::compensate(run, out, io);
    CHECK(r.figures.left_alone.empty());
    CHECK(r.summary["left_alone"].empty());
    CHECK(r.result.compensated_points > 0);
    // In C35 the wall deflects 0.17 mm, over mill3's cap of 0.1 mm: compensated
    // up to the cap (an [offset_cap] warning), the error less by that much.
    CHECK(!r.result.capped_lines.empty());
    CHECK(r.figures.error.max_abs < r.figures.error_as_written.max_abs - 0.05);
  }
}
