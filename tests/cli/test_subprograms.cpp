// Subprograms: --expand-subprograms writes each call
// inline so each pass gets its own compensation; without it, a subprogram
// that runs more than once stays as written and is named with its calls; one
// that runs once is compensated in place.
#include <doctest/doctest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "../support.hpp"

namespace fs = std::filesystem;
using namespace deflex;

namespace {

const char* kSample = "samples/programs/side_wall_sub.nc";

test::CliResult compensate(const std::string& in, const std::string& out, std::vector<std::string> more = {}) {
  std::vector<std::string> a = {"compensate", in, "-o", out, "--stock", "box:0,-40,-30,100,0,0"};
  a.insert(a.end(), more.begin(), more.end());
  return test::run_cli(a);
}

std::string replaced(std::string text, const std::vector<std::pair<std::string, std::string>>& edits) {
  for (const auto& e : edits) {
    REQUIRE_MESSAGE(text.find(e.first) != std::string::npos, e.first);
    text.replace(text.find(e.first), e.first.size(), e.second);
  }
  return text;
}

// From the first line of the summary on (the file name differs).
std::string summary(const std::string& err) { return err.substr(err.find(" points compensated") - 3); }

using test::TempDir;

}  // namespace

TEST_SUITE("cli") {
  TEST_CASE("subprogram sample: called at two depths, it stays as written and is named with its calls") {
    TempDir dir;
    const test::CliResult r = compensate(kSample, dir / "out.nc", {"--report", dir / "rep"});
    REQUIRE(r.rc == 0);
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
    CHECK(largest_mm == doctest::Approx(0.0923).epsilon(1e-3));
    test::check_deflection_physics(pts, 0.01);
    CHECK(r.err.find("side_wall_sub.nc:22:1: warning: 412 points outside +-0.0100 mm are left as programmed on moves in "
                     "subprograms that run more than once (the first here, in O5113, called at lines 12, 16); the "
                     "largest error left 0.0923 mm; --expand-subprograms writes each call inline and compensates each "
                     "pass [left_alone]") != std::string::npos);
    CHECK(r.err.find(" 0 points compensated") != std::string::npos);
    CHECK(test::read_file(dir / "out.nc") == test::read_file(kSample));
  }

  TEST_CASE("subprogram sample expanded: both passes compensated, as the program written out by hand") {
    TempDir dir;
    // The sample with O5113 written out at each call, by hand: the call
    // becomes the comment deflex writes, the pass follows.
    const std::string sub = "N100 G91 G01 X120. F2546.4\nN110 G90\n";
    const std::string by_hand =
        replaced(test::read_file(kSample),
                 {{"N22 M98 P5113\n", "(M98 P5113 AT LINE 12: O5113 WRITTEN INLINE BY DEFLEX)\n" + sub},
                  {"N30 M98 P5113\n", "(M98 P5113 AT LINE 16: O5113 WRITTEN INLINE BY DEFLEX)\n" + sub}});
    test::write_file(dir / "by_hand.nc", by_hand);
    // Expanding changes no motion.
    CHECK(test::run_cli({"path", kSample}).out == test::run_cli({"path", dir / "by_hand.nc"}).out);
    const test::CliResult e = compensate(kSample, dir / "expanded.nc", {"--expand-subprograms"});
    const test::CliResult h = compensate(dir / "by_hand.nc", dir / "by_hand_out.nc");
    REQUIRE_MESSAGE(e.rc == 0, e.err);
    REQUIRE(h.rc == 0);
    CHECK(e.err.find("[left_alone]") == std::string::npos);
    CHECK(e.err.find("side_wall_sub.nc (subprograms expanded):") != std::string::npos);
    CHECK(summary(e.err) == summary(h.err));
    // Byte for byte the compensation of the program written out by hand.
    const std::string out = test::read_file(dir / "expanded.nc");
    CHECK(out == test::read_file(dir / "by_hand_out.nc"));
    // Both passes moved into the wall (each its own blocks), the
    // subprogram's definition after M30 as it was.
    std::size_t passes = 0;
    for (std::size_t at = 0; (at = out.find("N100 G91 G01 X110. Y0.02 F2546.4\n", at)) != std::string::npos; ++at)
      ++passes;
    CHECK(passes == 2);
    CHECK(out.find("N38 M30\nO5113 (ONE PASS ALONG THE WALL, 120 MM IN +X)\nN100 G91 G01 X120. F2546.4\nN110 G90\n"
                   "N120 M99\n%\n") != std::string::npos);
  }

  TEST_CASE("a subprogram that runs once is compensated in place, as the same pass in the main program") {
    TempDir dir;
    // The second call replaced by the pass itself: O5113 now runs once.
    const std::string once =
        replaced(test::read_file(kSample), {{"N30 M98 P5113\n", "N30 G91 G01 X120. F2546.4\nN31 G90\n"}});
    const std::string inline_both = replaced(
        once, {{"N22 M98 P5113\n", "N22 G91 G01 X120. F2546.4\nN23 G90\n"}});
    test::write_file(dir / "once.nc", once);
    test::write_file(dir / "inline.nc", inline_both);
    const test::CliResult a = compensate(dir / "once.nc", dir / "once_out.nc");
    const test::CliResult b = compensate(dir / "inline.nc", dir / "inline_out.nc");
    REQUIRE(a.rc == 0);
    REQUIRE(b.rc == 0);
    CHECK(a.err.find("[left_alone]") == std::string::npos);
    CHECK(summary(a.err) == summary(b.err));
    // The subprogram's own block took the compensation (blocks inserted before it).
    const std::string out = test::read_file(dir / "once_out.nc");
    CHECK(out.find("G91 G1 X0.476 Y0.006 Z0. F2546.4\nN100 G91 G01 X110. Y0.02 F2546.4\nN110 G90\nN120 M99\n") !=
          std::string::npos);
    CHECK(test::run_cli({"path", dir / "once_out.nc"}).out == test::run_cli({"path", dir / "inline_out.nc"}).out);
    // `check` counts it compensable as compensate does: 2 plunges and 2 passes;
    // the sample's two calls leave only the plunges.
    CHECK(test::run_cli({"check", dir / "once.nc"}).out.find("12 motions (4 compensable)") != std::string::npos);
    CHECK(test::run_cli({"check", kSample}).out.find("12 motions (2 compensable)") != std::string::npos);
  }

  TEST_CASE("--expand-subprograms: nested calls and repeats, the path unchanged; a call it cannot write inline") {
    TempDir dir;
    const std::string nested =
        "%\nO1\nG21 G90 G17\nT6 M06\nG0 X0. Y0. Z5. S5000 M3\nG1 Z-1. F500.\nM98 P2 L2\nG0 Z5.\nM30\n"
        "O2 (TWO STEPS, THEN O3 TWICE)\nG91 G1 X10.\nM98 P3 L2\nG90\nM99\nO3\nG91 G1 Y5.\nY-5.\nG90\nM99\n%\n";
    test::write_file(dir / "n.nc", nested);
    // `compensate --gain 0` writes the expanded program with nothing moved.
    const test::CliResult e = compensate(dir / "n.nc", dir / "n_out.nc", {"--expand-subprograms", "--gain", "0"});
    REQUIRE_MESSAGE(e.rc == 0, e.err);
    const std::string out = test::read_file(dir / "n_out.nc");
    CHECK(test::run_cli({"path", dir / "n.nc"}).out == test::run_cli({"path", dir / "n_out.nc"}).out);
    std::size_t comments = 0;
    for (std::size_t at = 0; (at = out.find("WRITTEN INLINE BY DEFLEX)", at)) != std::string::npos; ++at) ++comments;
    CHECK(comments == 3);  // the call of O2 (two passes), the call of O3 in each pass of O2
    CHECK(out.find("(M98 P2 L2 AT LINE 7: O2 WRITTEN INLINE BY DEFLEX)\nG91 G1 X10.\n"
                   "(M98 P3 L2 AT LINE 12: O3 WRITTEN INLINE BY DEFLEX)\nG91 G1 Y5.\nY-5.\nG90\nG91 G1 Y5.\nY-5.\nG90\n"
                   "G90\nG91 G1 X10.\n") != std::string::npos);
    // A call sharing its block with a move cannot stand inline: an error at it, nothing written.
    test::write_file(dir / "bad.nc", replaced(nested, {{"M98 P2 L2\n", "G1 X1. M98 P2 L2\n"}}));
    const test::CliResult bad = compensate(dir / "bad.nc", dir / "bad_out.nc", {"--expand-subprograms"});
    CHECK(bad.rc == 1);
    CHECK(bad.err.find("bad.nc:7:1: error: M98 block with other words: it cannot be written inline") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "bad_out.nc"));
    // A block-delete call runs at the operator's switch; inline it would always run.
    test::write_file(dir / "bd.nc", replaced(nested, {{"M98 P2 L2\n", "/M98 P2 L2\n"}}));
    const test::CliResult bd = compensate(dir / "bd.nc", dir / "bd_out.nc", {"--expand-subprograms"});
    CHECK(bd.rc == 1);
    CHECK(bd.err.find("bd.nc:7:1: error: M98 in a block-delete '/' block cannot be written inline") != std::string::npos);
  }
}
