// Pairing a compensated program with its original by structure
// (compensate/pairing.hpp): what the safety check, simulate --reference and
// diff all go through.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <unistd.h>

#include "../support.hpp"
#include "deflex/compensate/pairing.hpp"

using namespace deflex;
using compensate::V3;

namespace {

struct Paired {
  test::Interpreted a, b;
  compensate::LinePairing lines;
  std::vector<V3> intent;
};

Paired pair_texts(const std::string& a, const std::string& b, bool ignore_feed = false) {
  Paired p{test::interpret_text(a), test::interpret_text(b), {}, {}};
  REQUIRE(p.a.errors == 0);
  REQUIRE(p.b.errors == 0);
  gcode::Program pa(SourceText("a.nc", a)), pb(SourceText("b.nc", b));
  p.lines = compensate::pair_lines(compensate::line_facts(pa, p.a.motions, ignore_feed),
                                   compensate::line_facts(pb, p.b.motions, ignore_feed));
  p.intent = compensate::intent_offsets(p.lines, p.a.motions, p.b.motions, "b.nc");
  return p;
}

// Motions of B on the given lines of B.
bool on_line(const interp::Motion& m, std::initializer_list<std::uint32_t> lines) {
  for (std::uint32_t l : lines)
    if (m.line == l) return true;
  return false;
}

}  // namespace

TEST_SUITE("compensate") {

TEST_CASE("pairing: a split move followed by unchanged moves; every unchanged motion has intent offset exactly 0") {
  // A raster of `G1` lines without N numbers, the skeleton of the inserted
  // block too: only the order and the geometry place it. B moves line 5 by
  // 0.02 mm in Y and splits its move with a point 0.05 mm before its end,
  // nearer that end than the next move is long.
  const std::string a =
      "G21 G90 G17\nG0 X0 Y0 Z0\nG1 X10. F500.\nG1 Y0.1\nG1 X0.\nG1 Y0.2\nG1 X10.\nG1 Y0.3\nG1 X0.\nM30\n";
  const std::string b = "G21 G90 G17\nG0 X0 Y0 Z0\nG1 X10. F500.\nG1 Y0.1\nG1 X0.05 Y0.119 Z0.\nG1 X0. Y0.12\n"
                        "G1 Y0.2\nG1 X10.\nG1 Y0.3\nG1 X0.\nM30\n";
  Paired p = pair_texts(a, b);
  CHECK(p.lines.inserted(5));
  CHECK(p.lines.parent_of_b[5] == 5);
  CHECK(p.lines.a_of_b[6] == 5);
  for (std::uint32_t l = 1; l <= 4; ++l) CHECK(p.lines.a_of_b[l] == l);
  for (std::uint32_t l = 7; l <= 11; ++l) CHECK(p.lines.a_of_b[l] == l - 1);
  REQUIRE(p.intent.size() == p.b.motions.size());
  for (std::size_t i = 0; i < p.b.motions.size(); ++i) {
    const interp::Motion& m = p.b.motions[i];
    if (on_line(m, {5})) {
      CHECK(p.intent[i].norm() == doctest::Approx(0.019));  // off the move X10 -> X0 at Y0.1
    } else if (on_line(m, {6})) {
      CHECK(p.intent[i].y() == doctest::Approx(0.02));
    } else {
      INFO("line " << m.line);
      CHECK(p.intent[i] == V3::Zero());  // exactly: the judge sees the as-written move
    }
  }
}

TEST_CASE("pairing: the chords of a linearised arc are inserted blocks of the arc, on its circle") {
  // A quarter circle of radius 10 about (0,0) from (10,0) to (0,10), G3 by
  // I/J; B writes its first part as G1 chords on the circle and keeps the last
  // piece as an arc re-aimed from the last chord's end.
  const std::string a = "N1 G21 G90 G17\nN2 G0 X10. Y-5. Z0\nN3 G1 Y0 F300.\nN4 G3 X0. Y10. I-10. J0.\nN5 G1 X-5.\nN6 M30\n";
  std::string b = "N1 G21 G90 G17\nN2 G0 X10. Y-5. Z0\nN3 G1 Y0 F300.\n";
  double last[2] = {10, 0};
  for (int k = 1; k <= 4; ++k) {
    const double t = k * (M_PI / 2) / 5;
    char buf[80];
    std::snprintf(buf, sizeof buf, "G1 X%.6f Y%.6f Z0.\n", 10 * std::cos(t), 10 * std::sin(t));
    b += buf;
    last[0] = 10 * std::cos(t);
    last[1] = 10 * std::sin(t);
  }
  char arc[80];
  std::snprintf(arc, sizeof arc, "N4 G3 X0. Y10. I%.6f J%.6f\n", -last[0], -last[1]);
  b += std::string(arc) + "N5 G1 X-5.\nN6 M30\n";
  Paired p = pair_texts(a, b);
  for (std::uint32_t l = 4; l <= 7; ++l) {
    CHECK(p.lines.inserted(l));
    CHECK(p.lines.parent_of_b[l] == 4);
  }
  CHECK(p.lines.a_of_b[8] == 4);
  CHECK(p.lines.a_of_b[9] == 5);
  for (std::size_t i = 0; i < p.b.motions.size(); ++i) {
    INFO("line " << p.b.motions[i].line);
    if (p.lines.inserted(p.b.motions[i].line)) CHECK(p.intent[i].norm() < 1e-6);  // on the circle, to the written digits
    else CHECK(p.intent[i] == V3::Zero());
  }
}

TEST_CASE("pairing: a --feed-limit output (F words changed and added) still pairs block by block") {
  const std::string a = "N1 G21 G90\nN2 G0 X0 Y0 Z0\nN3 G1 X10. F800.\nN4 X20.\nN5 X30.\nN6 M30\n";
  const std::string b = "N1 G21 G90\nN2 G0 X0 Y0 Z0\nN3 G1 X10. F612.5\nN4 X20.01 F800.\nN5 X30.\nN6 M30\n";
  Paired p = pair_texts(a, b, true);
  for (std::uint32_t l = 1; l <= 6; ++l) CHECK(p.lines.a_of_b[l] == l);
  for (std::size_t i = 0; i < p.b.motions.size(); ++i) {
    if (p.b.motions[i].line == 4) CHECK(p.intent[i].x() == doctest::Approx(0.01));
    else CHECK(p.intent[i] == V3::Zero());
  }
  // With F in the skeleton the changed blocks do not pair.
  gcode::Program pa(SourceText("a.nc", a)), pb(SourceText("b.nc", b));
  auto strict = compensate::pair_lines(compensate::line_facts(pa, p.a.motions, false),
                                       compensate::line_facts(pb, p.b.motions, false));
  CHECK(strict.a_of_b[3] == 0);
}

TEST_CASE("pairing: two 200,000-line programs align in memory linear in their size, every split found") {
  // A raster of `G1 X Y` lines without N numbers (every skeleton equal, the
  // inserted blocks' too); B moves every 50th
  // point by 0.01 mm and splits its move, 100 inserted blocks per 5,000 lines.
  std::string a = "G21 G90 G17\nG0 X0 Y0 Z0\nG1 F1000.\n", b = a;
  const int rows = 200000;
  std::vector<std::uint32_t> split_lines;  // lines of B that are inserted
  std::uint32_t line_b = 3;
  char buf[96];
  for (int r = 0; r < rows; ++r) {
    const double x = (r % 2) ? 0.0 : 50.0, y = 0.05 * r;
    const bool moved = r % 50 == 25;
    if (moved) {
      // The move goes from the previous point (the other end, 0.05 mm lower) to (x, y).
      const double x0 = (r % 2) ? 50.0 : 0.0;
      std::snprintf(buf, sizeof buf, "G1 X%.4f Y%.4f Z0.\n", 0.5 * (x0 + x), y - 0.025);
      b += buf;
      split_lines.push_back(++line_b);
    }
    std::snprintf(buf, sizeof buf, "G1 X%.3f Y%.3f\n", x, y);
    a += buf;
    std::snprintf(buf, sizeof buf, "G1 X%.3f Y%.3f\n", x, moved ? y + 0.01 : y);
    b += buf;
    ++line_b;
  }
  a += "M30\n";
  b += "M30\n";
  const test::Interpreted ia = test::interpret_text(a), ib = test::interpret_text(b);
  REQUIRE(ia.errors == 0);
  REQUIRE(ib.errors == 0);
  gcode::Program pa(SourceText("a.nc", a)), pb(SourceText("b.nc", b));
  const auto fa = compensate::line_facts(pa, ia.motions, false), fb = compensate::line_facts(pb, ib.motions, false);
  const compensate::LinePairing lp = compensate::pair_lines(fa, fb);
  const std::size_t n = fa.size() + fb.size();
  MESSAGE("alignment work entries: " << lp.work_entries << " for " << n << " lines");
  CHECK(lp.work_entries <= 6 * n);  // Myers' trace would hold D x (2D+2) ints
  std::size_t found = 0;
  for (std::uint32_t l = 1; l < fb.size(); ++l) found += lp.inserted(l);
  CHECK(found == split_lines.size());
  for (std::uint32_t l : split_lines) CHECK(lp.inserted(l));
  const std::vector<V3> off = compensate::intent_offsets(lp, ia.motions, ib.motions, "b.nc");
  double worst = 0;
  for (const V3& o : off) worst = std::max(worst, o.norm());
  CHECK(worst == doctest::Approx(0.01));
}

}  // TEST_SUITE

TEST_SUITE("compensate") {

TEST_CASE("pairing: a full-width slot of a raster without blanks, whose step-over is shorter than the offsets") {
  // The first lines of a CAM raster (CAMotics' bear.nc): no blanks, modal
  // axis words, a 17 mm plunge with a D10 flat end, so the cap bites; the
  // Y steps (0.125 and 0.375 mm) are about as long as the offsets, and the
  // compensated end of `X79.999` lies nearer the end of `Y0.126` than its own.
  const std::string prog =
      "T1M6\nG21\nG17\nG0Z20.000\nG0X0.000Y0.000S15000M3\nG0X0.001Y0.001Z10.000\nG1Z-17.368F6000.0\n"
      "G1X0.161\nX79.999\nY0.126\nY0.501\nX79.839\nX0.001\nY0.626\nM30\n";
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("deflex-slot-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string in = (dir / "bear15.nc").string(), out = (dir / "comp.nc").string();
  std::ofstream(in) << prog;
  const auto r = test::run_cli({"compensate", in, "--stock", "box:0,0,-25,80,80,0", "--threads", "1", "-o", out});
  INFO(r.err);
  REQUIRE(r.rc == 0);
  // The cap bites and moves are split, so the case is the one meant.
  CHECK(r.err.find("[offset_cap]") != std::string::npos);
  CHECK(r.err.find("blocks inserted to split moves") != std::string::npos);
  // diff and the judge read the written program as the safety check did.
  const auto d = test::run_cli({"diff", in, out});
  INFO(d.out << d.err);
  CHECK(d.rc == 0);
  const auto j = test::run_cli({"simulate", out, "--reference", in, "--stock", "box:0,0,-25,80,80,0", "--threads", "1"});
  INFO(j.err);
  CHECK(j.rc == 0);
  fs::remove_all(dir);
}

TEST_CASE("pairing property: generated rasters in the style of CAM output never fail the safety check") {
  // Programs as a CAM post writes them without N numbers (bear.nc's style):
  // no blanks, modal axis words, plunges to 18 mm with a D10 flat end (the
  // offset cap bites), long passes that deflex splits, a short first piece,
  // step-overs of 0.125, 0.375 or 0.05-0.6 mm, some no longer than the
  // offsets. Every one must compensate: the written program pairs with the
  // original block by block, or deflex stops with exit 70.
  std::mt19937 rng(20261126);
  std::uniform_real_distribution<double> u(0, 1);
  auto pick = [&](double a, double b) { return u(rng) < 0.5 ? a : b; };
  int split = 0;
  for (int k = 0; k < 32; ++k) {
    const double depth = pick(17.368, 2 + 16 * u(rng)), width = pick(80, 20 + 60 * u(rng));
    std::string p = "T1M6\nG21\nG17\nG0Z20.000\nG0X0.000Y0.000S15000M3\nG0X0.001Y0.001Z10.000\n";
    char buf[96];
    std::snprintf(buf, sizeof buf, "G1Z%.3fF%.1f\n", -depth, pick(6000, 2000 + 4000 * u(rng)));
    p += buf;
    double x = 0.001, y = 0.001;
    const char* g1 = "G1";
    for (int pass = 0, passes = 3 + static_cast<int>(5 * u(rng)); pass < passes; ++pass) {
      const double x_end = pass % 2 ? 0.001 : width - 0.001;
      if (u(rng) < 0.5) {  // a short first piece, as G1X0.161
        std::snprintf(buf, sizeof buf, "%sX%.3f\n", g1, x + (x_end - x) * (0.001 + 0.05 * u(rng)));
        p += buf;
        g1 = "";
      }
      std::snprintf(buf, sizeof buf, "%sX%.3f\n", g1, x_end);
      p += buf;
      g1 = "";
      x = x_end;
      for (int s = 0, n = 1 + (u(rng) < 0.5); s < n; ++s) {
        const double r = u(rng);
        y += r < 1.0 / 3 ? 0.125 : r < 2.0 / 3 ? 0.375 : 0.05 + 0.55 * u(rng);
        std::snprintf(buf, sizeof buf, "Y%.3f\n", y);
        p += buf;
      }
    }
    p += "G0Z20.000\nM30\n";
    std::snprintf(buf, sizeof buf, "box:0,0,-25,%.3f,%.3f,0", width, pick(80, y + 10));
    const auto r = test::run_cli({"compensate", "-", "--stock", buf, "--threads", "1", "--quiet"}, p);
    INFO("program " << k << " (stock " << buf << "):\n" << p << r.err);
    CHECK(r.rc == 0);
    split += r.out.find("G1 X") != std::string::npos;
  }
  CHECK(split > 16);  // most programs had moves split (blocks inserted)
}

TEST_CASE("simulate --reference: a program judged against itself gives exactly its as-written error") {
  // Every intent offset is zero, so the judge runs the same simulation.
  const std::vector<std::string> common = {"--stock", "box:0,0,-20,100,20,0", "--tolerance", "0.002", "--threads", "1"};
  std::vector<std::string> plain = {"simulate", "tests/golden/wall.nc"}, judged = plain;
  plain.insert(plain.end(), common.begin(), common.end());
  judged.insert(judged.end(), {"--reference", "tests/golden/wall.nc"});
  judged.insert(judged.end(), common.begin(), common.end());
  auto p = test::run_cli(plain), j = test::run_cli(judged);
  REQUIRE(p.rc == 0);
  REQUIRE(j.rc == 0);
  std::string want = p.out;
  want.replace(want.find(" CL points:"), 11, " CL points against the reference:");
  CHECK(j.out == want);
}

}  // TEST_SUITE
