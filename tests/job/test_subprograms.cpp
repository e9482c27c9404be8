// Subprograms through the job API: Settings::expand_subprograms writes each
// call inline so each pass gets its own compensation; without it, a
// subprogram that runs more than once stays as written and is named with its
// calls; one that runs once is compensated in place.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "deflex/job/check.hpp"
#include "support.hpp"

namespace fs = std::filesystem;
using namespace deflex;

namespace {

const char* kSample = "samples/programs/side_wall_sub.nc";

job::Settings wall(const std::string& program) {
  job::Settings s;
  s.program = program;
  s.stock = "box:0,-40,-30,100,0,0";
  return s;
}

std::string replaced(std::string text, const std::vector<std::pair<std::string, std::string>>& edits) {
  for (const auto& e : edits) {
    REQUIRE_MESSAGE(text.find(e.first) != std::string::npos, e.first);
    text.replace(text.find(e.first), e.first.size(), e.second);
  }
  return text;
}

// job::check's count of a program's motions: all, and those deflex may move.
std::pair<std::uint64_t, std::uint64_t> motions(const std::string& program) {
  job::CheckSettings cs;
  cs.program = program;
  test::Streams st;
  const job::CheckResult r = job::check(cs, st.io);
  CHECK(r.errors == 0);
  return {r.stats.motions, r.stats.compensable};
}

}  // namespace

TEST_SUITE("job") {
  TEST_CASE("subprogram sample: called at two depths, it stays as written and is named with its calls") {
    test::TempDir dir("sub");
    job::Settings s = wall(kSample);
    s.report_dir = dir / "rep";
    const auto r = test::compensate_job(s);
    REQUIRE_MESSAGE(r.ok(), r.err);
    // The figures of the message are a regression snapshot of deflex's output;
    // they must be the per-point predictions of the run's points.csv (all its
    // cutting points are in O5113), and those must show the physics.
    const test::Csv pts = test::read_csv(dir / "rep/points.csv");
    int outside = 0;
    double largest_mm = 0;
    for (std::size_t i = 0; i < pts.rows.size(); ++i) {
      outside += std::fabs(pts.num(i, "surface_error_mm")) > 0.01;
      largest_mm = std::max(largest_mm, std::fabs(pts.num(i, "surface_error_mm")));
    }
    CHECK(outside == 412);
    CHECK(largest_mm == deflex::test::within(0.0923, 1e-3));
    test::check_deflection_physics(pts, 0.01);
    CHECK(r.err.find("side_wall_sub.nc:22:1: warning: 412 points outside +-0.0100 mm are left as programmed on moves in "
                     "subprograms that run more than once (the first here, in O5113, called at lines 12, 16); the "
                     "largest error left 0.0923 mm; ") != std::string::npos);
    CHECK(r.err.find("writes each call inline and compensates each pass [left_alone]") != std::string::npos);
    CHECK(r.result->result.compensated_points == 0);
    CHECK(r.out == test::read_file(kSample));
  }

  TEST_CASE("subprogram sample expanded: both passes compensated, as the program written out by hand") {
    test::TempDir dir("sub");
    // The sample with O5113 written out at each call, by hand: the call
    // becomes the comment deflex writes, the pass follows.
    const std::string sub = "N100 G91 G01 X120. F2546.4\nN110 G90\n";
    const std::string by_hand =
        replaced(test::read_file(kSample),
                 {{"N22 M98 P5113\n", "(M98 P5113 AT LINE 12: O5113 WRITTEN INLINE BY DEFLEX)\n" + sub},
                  {"N30 M98 P5113\n", "(M98 P5113 AT LINE 16: O5113 WRITTEN INLINE BY DEFLEX)\n" + sub}});
    test::write_file(dir / "by_hand.nc", by_hand);
    // Expanding changes no motion.
    CHECK(test::path_text(kSample) == test::path_text(dir / "by_hand.nc"));
    job::Settings expand = wall(kSample);
    expand.expand_subprograms = true;
    const auto e = test::compensate_job(expand), h = test::compensate_job(wall(dir / "by_hand.nc"));
    REQUIRE_MESSAGE(e.ok(), e.err);
    REQUIRE(h.ok());
    CHECK(e.err.find("[left_alone]") == std::string::npos);
    CHECK(e.err.find("side_wall_sub.nc (subprograms expanded):") != std::string::npos);
    CHECK(test::summary_but_lines(*e.result) == test::summary_but_lines(*h.result));
    // Byte for byte the compensation of the program written out by hand.
    CHECK(e.out == h.out);
    // Both passes moved into the wall (each its own blocks), the
    // subprogram's definition after M30 as it was.
    std::size_t passes = 0;
    for (std::size_t at = 0; (at = e.out.find("G91 G1 X0.498 Y0. Z0. F2546.4\nN100 G91 G01 X10.452 F2546.4\n", at)) != std::string::npos; ++at)
      ++passes;
    CHECK(passes == 2);
    CHECK(e.out.find("N38 M30\nO5113 (ONE PASS ALONG THE WALL, 120 MM IN +X)\nN100 G91 G01 X120. F2546.4\nN110 G90\n"
                     "N120 M99\n%\n") != std::string::npos);
  }

  TEST_CASE("a subprogram that runs once is compensated in place, as the same pass in the main program") {
    test::TempDir dir("sub");
    // The second call replaced by the pass itself: O5113 now runs once.
    const std::string once =
        replaced(test::read_file(kSample), {{"N30 M98 P5113\n", "N30 G91 G01 X120. F2546.4\nN31 G90\n"}});
    const std::string inline_both = replaced(once, {{"N22 M98 P5113\n", "N22 G91 G01 X120. F2546.4\nN23 G90\n"}});
    test::write_file(dir / "once.nc", once);
    test::write_file(dir / "inline.nc", inline_both);
    job::Settings a_in = wall(dir / "once.nc"), b_in = wall(dir / "inline.nc");
    a_in.output = dir / "once_out.nc";
    b_in.output = dir / "inline_out.nc";
    const auto a = test::compensate_job(a_in), b = test::compensate_job(b_in);
    REQUIRE(a.ok());
    REQUIRE(b.ok());
    CHECK(a.err.find("[left_alone]") == std::string::npos);
    CHECK(test::summary_but_lines(*a.result) == test::summary_but_lines(*b.result));
    // The subprogram's own block took the compensation (blocks inserted before it).
    CHECK(test::read_file(a_in.output)
              .find("G91 G1 X0.498 Y0. Z0. F2546.4\nN100 G91 G01 X10.452 F2546.4\nN110 G90\nN120 M99\n") !=
          std::string::npos);
    CHECK(test::path_text(a_in.output) == test::path_text(b_in.output));
    // job::check counts it compensable as compensate does: 2 plunges and 2
    // passes; the sample's two calls leave only the plunges.
    CHECK(motions(dir / "once.nc") == std::pair<std::uint64_t, std::uint64_t>{12, 4});
    CHECK(motions(kSample) == std::pair<std::uint64_t, std::uint64_t>{12, 2});
  }

  TEST_CASE("expand_subprograms: nested calls and repeats, the path unchanged; a call it cannot write inline") {
    test::TempDir dir("sub");
    const std::string nested =
        "%\nO1\nG21 G90 G17\nT6 M06\nG0 X0. Y0. Z5. S5000 M3\nG1 Z-1. F500.\nM98 P2 L2\nG0 Z5.\nM30\n"
        "O2 (TWO STEPS, THEN O3 TWICE)\nG91 G1 X10.\nM98 P3 L2\nG90\nM99\nO3\nG91 G1 Y5.\nY-5.\nG90\nM99\n%\n";
    test::write_file(dir / "n.nc", nested);
    // With gain 0 the expanded program is written with nothing moved.
    job::Settings n = wall(dir / "n.nc");
    n.expand_subprograms = true;
    n.gain = 0;
    n.output = dir / "n_out.nc";
    const auto e = test::compensate_job(n);
    REQUIRE_MESSAGE(e.ok(), e.err);
    const std::string out = test::read_file(n.output);
    CHECK(test::path_text(dir / "n.nc") == test::path_text(n.output));
    std::size_t comments = 0;
    for (std::size_t at = 0; (at = out.find("WRITTEN INLINE BY DEFLEX)", at)) != std::string::npos; ++at) ++comments;
    CHECK(comments == 3);  // the call of O2 (two passes), the call of O3 in each pass of O2
    CHECK(out.find("(M98 P2 L2 AT LINE 7: O2 WRITTEN INLINE BY DEFLEX)\nG91 G1 X10.\n"
                   "(M98 P3 L2 AT LINE 12: O3 WRITTEN INLINE BY DEFLEX)\nG91 G1 Y5.\nY-5.\nG90\nG91 G1 Y5.\nY-5.\nG90\n"
                   "G90\nG91 G1 X10.\n") != std::string::npos);
    // A call sharing its block with a move cannot stand inline; a block-delete
    // call runs at the operator's switch, inline it would always run. Each an
    // input error at the call, nothing written.
    for (const auto& [name, call, message] :
         {std::tuple{"bad.nc", "G1 X1. M98 P2 L2\n", "bad.nc:7:1: error: M98 block with other words: it cannot be written inline"},
          std::tuple{"bd.nc", "/M98 P2 L2\n", "bd.nc:7:1: error: M98 in a block-delete '/' block cannot be written inline"}}) {
      const std::string file = name;  // CAPTURE's lambda cannot take a structured binding (clang 14)
      CAPTURE(file);
      test::write_file(dir / name, replaced(nested, {{"M98 P2 L2\n", call}}));
      job::Settings bad = wall(dir / name);
      bad.expand_subprograms = true;
      bad.output = dir / (std::string(name) + ".out");
      const auto r = test::compensate_job(bad);
      CHECK(r.error == ErrorKind::input);
      CHECK(r.err.find(message) != std::string::npos);
      CHECK_FALSE(fs::exists(bad.output));
    }
  }
}
