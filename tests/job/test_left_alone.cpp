// What a run leaves as written, through the job API: the moves per reason
// that open() counts (Run::left_moves, the same read whole or in pieces), and
// the points outside the tolerance on them that compensate() finds
// (RunFigures::left_alone), each named at its first line in the messages
// and in the summary, never silently missing from the points compensated.
#include <doctest/doctest.h>

#include <cstdlib>
#include <sstream>

#include "support.hpp"

using namespace deflex;

TEST_SUITE("job") {
  TEST_CASE("left as written: the pocket's drilling cycle, counted once per block, whole or in pieces") {
    job::Settings s;
    s.program = "samples/programs/pocket_finish.nc";
    s.stock = "box:-5,-5,-20,105,85,0";
    s.stock_from = test::pocket_predrilled();
    test::Streams streams;
    job::Io& io = streams.io;
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
    test::Streams streams;
    job::Io& io = streams.io;
    job::Run run = job::open(s, job::Purpose::compensate, io);
    CHECK(run.left_moves.empty());
    const job::CompensateResult r = job::compensate(run, streams.out, io);
    CHECK(r.figures.left_alone.empty());
    CHECK(r.summary["left_alone"].empty());
    CHECK(r.result.compensated_points > 0);
    // In C35 the wall deflects 0.17 mm, over mill3's cap of 0.1 mm: compensated
    // up to the cap (an [offset_cap] warning), the error less by that much.
    CHECK(!r.result.capped_lines.empty());
    CHECK(r.figures.error.max_abs < r.figures.error_as_written.max_abs - 0.05);
  }

  TEST_CASE("left as written: one note per reason with the block count and the first line, in pieces too") {
    job::Settings s;
    s.program = "samples/programs/pocket_finish.nc";
    s.stock = "box:-5,-5,-20,105,85,0";
    s.stock_from = test::pocket_predrilled();
    const auto r = test::compensate_job(s);
    REQUIRE(r.ok());
    const std::string note =
        "samples/programs/pocket_finish.nc: note: 2 executed blocks stay as written: canned-cycle moves (drilling is not a "
        "surface); the first at line 21\n";
    CHECK(r.err.find(note) != std::string::npos);
    CHECK(r.err.find("canned-cycle") == r.err.rfind("canned-cycle"));  // once, not per block
    {
      test::PieceLines p("5");
      CHECK(test::compensate_job(s).err == r.err);
    }
    // The plain side wall has no such move: no note.
    s.program = "samples/programs/side_wall.nc";
    s.stock = "box:0,-40,-30,100,0,0";
    const auto plain = test::compensate_job(s);
    REQUIRE(plain.ok());
    CHECK(plain.err.find("stay as written") == std::string::npos);
  }

  TEST_CASE("left alone: a compensable pass whose end starts a block deflex cannot move is named, not silent") {
    test::TempDir dir("held");
    // The first pass ends where a drilling cycle starts: its end stays, and
    // so does the pass (nothing to ramp to).
    const std::string in = test::side_wall_with(
        dir, "held.nc", "N22 X110. F2546.4\nN23 G99 G81 X110. Y3.5 Z-12.5 R-11. F200.\nN23 G80\n");
    const auto r = test::compensate_side_wall(in, dir / "out.nc");
    REQUIRE(r.ok());
    CHECK(r.err.find("held.nc:16:1: warning: 207 points outside +-0.0100 mm are left as programmed on moves ending where "
                     "a block deflex cannot re-target starts") != std::string::npos);
  }

  TEST_CASE("left alone: a pass deflex does not move is named with its count, in the messages and the summary") {
    test::TempDir dir("left");
    // The first pass as a block-delete block (run or not at the operator's switch).
    const std::string prog = test::side_wall_with(dir, "wall_bd.nc", "/N22 X110. F2546.4\n");
    const auto bd = test::compensate_side_wall(prog, dir / "out.nc");
    const auto plain = test::compensate_side_wall("samples/programs/side_wall.nc", dir / "out.nc");
    REQUIRE(bd.ok());
    REQUIRE(plain.ok());
    const std::string want = prog + ":16:1: warning: ";
    const std::size_t at = bd.err.find(want);
    REQUIRE(at != std::string::npos);
    const std::string line = bd.err.substr(at, bd.err.find('\n', at) - at);
    CHECK(line.find("points outside +-0.0100 mm are left as programmed on block-delete '/' moves") != std::string::npos);
    CHECK(line.find("[left_alone]") != std::string::npos);
    const report::Json& s = bd.result->summary;
    REQUIRE(s["left_alone"].size() == 1);
    CHECK(s["left_alone"][0]["reason"] == "block delete '/'");
    CHECK(s["left_alone"][0]["first_line"] == 16);
    // The count is the first pass's points outside the tolerance: on the plain
    // program the same pass is compensated, and nothing is left alone.
    const std::size_t n = s["left_alone"][0]["points"];
    CHECK(n > 150);
    CHECK(n <= s["cl_points"].get<std::size_t>());
    CHECK(plain.err.find("[left_alone]") == std::string::npos);
    CHECK(plain.result->summary["left_alone"].empty());
  }
}
