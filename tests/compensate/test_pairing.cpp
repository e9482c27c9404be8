// Pairing a compensated program with its original by structure
// (compensate/pairing.hpp): what the safety check, simulate --reference and
// diff all go through.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>
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

namespace {

// A raster as a CAM post writes it without N numbers (bear.nc's style): no
// blanks, modal axis words, fixed 3 decimals (1 for F), a plunge of up to
// 18 mm with a D10 flat end (the offset cap bites), long passes that deflex
// splits, a short first piece, step-overs of 0.125, 0.375 or 0.05-0.6 mm,
// some no longer than the offsets. In inch (G20, 4 decimals) when asked.
struct Raster {
  std::string text, stock;
};
Raster cam_raster(std::mt19937& rng, bool inch) {
  std::uniform_real_distribution<double> u(0, 1);
  auto pick = [&](double a, double b) { return u(rng) < 0.5 ? a : b; };
  const double scale = inch ? 1 / 25.4 : 1;
  const char* xyz = inch ? "%s%c%.4f\n" : "%s%c%.3f\n";
  char buf[96];
  auto word = [&](const char* lead, char letter, double mm) {
    std::snprintf(buf, sizeof buf, xyz, lead, letter, mm * scale);
    return std::string(buf);
  };
  const double depth = pick(17.368, 2 + 16 * u(rng)), width = pick(80, 20 + 60 * u(rng));
  std::string p = std::string("T1M6\n") + (inch ? "G20" : "G21") + "\nG17\n" + word("G0", 'Z', 20);
  const char* start = inch ? "G0X0.0000Y0.0000S15000M3\nG0X0.0000Y0.0000Z%.4f\nG1Z%.4fF%.1f\n"
                           : "G0X0.000Y0.000S15000M3\nG0X0.001Y0.001Z%.3f\nG1Z%.3fF%.1f\n";
  std::snprintf(buf, sizeof buf, start, 10 * scale, -depth * scale, pick(6000, 2000 + 4000 * u(rng)) * scale);
  p += buf;
  double x = 0.001, y = 0.001;
  const char* g1 = "G1";
  for (int pass = 0, passes = 3 + static_cast<int>(5 * u(rng)); pass < passes; ++pass) {
    const double x_end = pass % 2 ? 0.001 : width - 0.001;
    if (u(rng) < 0.5) {  // a short first piece, as G1X0.161
      p += word(g1, 'X', x + (x_end - x) * (0.001 + 0.05 * u(rng)));
      g1 = "";
    }
    p += word(g1, 'X', x_end);
    g1 = "";
    x = x_end;
    for (int s = 0, n = 1 + (u(rng) < 0.5); s < n; ++s) {
      const double r = u(rng);
      y += r < 1.0 / 3 ? 0.125 : r < 2.0 / 3 ? 0.375 : 0.05 + 0.55 * u(rng);
      p += word("", 'Y', y);
    }
  }
  p += word("G0", 'Z', 20) + "M30\n";
  std::snprintf(buf, sizeof buf, "box:0,0,-25,%.3f,%.3f,0", width, pick(80, y + 10));
  return {p, buf};
}

// Whether each line of `out` that is not a line of `in` writes its numbers as
// `in` does: no blanks, and X Y Z with `decimals` decimals.
std::string style_break(const std::string& in, const std::string& out, int decimals) {
  std::set<std::string> original;
  std::istringstream a(in), b(out);
  for (std::string l; std::getline(a, l);) original.insert(l);
  for (std::string l; std::getline(b, l);) {
    if (original.count(l)) continue;
    if (l.find(' ') != std::string::npos) return l;
    for (std::size_t k = 0; k < l.size(); ++k) {
      if (l[k] != 'X' && l[k] != 'Y' && l[k] != 'Z') continue;
      const std::size_t dot = l.find('.', k), next = l.find_first_of("XYZFGM", k + 1);
      const std::size_t end = next == std::string::npos ? l.size() : next;
      if (dot == std::string::npos || dot > end || end - dot - 1 != static_cast<std::size_t>(decimals)) return l;
    }
  }
  return "";
}

}  // namespace

TEST_CASE("pairing property: generated CAM rasters compensate, within the cap as written, in the program's style") {
  // Every one must compensate: the written program pairs with the original
  // block by block, or deflex stops with exit 70. The offset cap holds on
  // the coordinates as written (diff measures them), and what deflex changes
  // or inserts is written as the rest of the program is.
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("deflex-raster-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string in = (dir / "raster.nc").string();
  std::mt19937 rng(20261126);
  int split = 0, capped = 0;
  for (int k = 0; k < 32; ++k) {
    const bool inch = k % 4 == 3;
    const Raster r = cam_raster(rng, inch);
    std::ofstream(in) << r.text;
    const auto c = test::run_cli({"compensate", in, "--stock", r.stock, "--threads", "1"});
    INFO("program " << k << " (stock " << r.stock << "):\n" << r.text << c.err);
    CHECK(c.rc == 0);
    if (c.rc != 0) continue;
    split += c.err.find("blocks inserted to split moves") != std::string::npos;
    capped += c.err.find("[offset_cap]") != std::string::npos;
    const auto d = test::run_cli({"diff", in, "-", "--format", "json"}, c.out);
    REQUIRE(d.rc == 0);
    const double moved_mm = nlohmann::json::parse(d.out).at("max_displacement_mm").get<double>();
    CHECK(moved_mm <= 0.1);  // mill3's max_offset_mm
    CHECK(style_break(r.text, c.out, inch ? 4 : 3) == "");
  }
  CHECK(split > 16);   // most programs had moves split (blocks inserted)
  CHECK(capped > 8);   // and the cap bit in many
  fs::remove_all(dir);
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

TEST_SUITE("compensate") {

TEST_CASE("the offset cap holds on the coordinates as written, and its warning says what bit") {
  // A D6 ball end down a 27 deg slope, 3 to 6 mm deep, in inch; the dialect
  // writes 3 inch decimals (0.0254 mm steps), so rounding alone moves a
  // written point 0.022 mm in 3D. The cap (mill3: 0.1 mm) must hold on the
  // written numbers, which diff measures.
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("deflex-capw-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::string prog = "T3M6\nG20\nG17\nG0Z0.8000\nG0X0.0000Y0.0000S12000M3\n";
  char buf[80];
  for (int k = 0; k < 12; ++k) {
    const double y = 0.02 * k, z = -0.12 - 0.5 * y;
    for (int i = 0; i <= 20; ++i) {
      const double x = 0.1 * (k % 2 ? 20 - i : i);
      if (k == 0 && i == 0) std::snprintf(buf, sizeof buf, "G0X%.4fY%.4f\nG1Z%.4fF40.0\n", x, y, z);
      else if (i == 0) std::snprintf(buf, sizeof buf, "G1X%.4fY%.4fZ%.4f\n", x, y, z);
      else std::snprintf(buf, sizeof buf, "X%.4f\n", x);
      prog += buf;
    }
  }
  prog += "G0Z0.8000\nM30\n";
  std::string dialect = test::read_file(std::string(DEFLEX_SOURCE_DIR) + "/postproc/fanuc.yaml");
  dialect.replace(dialect.find("decimals_inch: 4"), 16, "decimals_inch: 3");
  const std::string in = (dir / "slope.nc").string(), dia = (dir / "fanuc3.yaml").string();
  std::ofstream(in) << prog;
  std::ofstream(dia) << dialect;
  const auto c = test::run_cli({"compensate", in, "--stock", "box:-5,-5,-20,60,15,0", "--dialect", dia, "--threads", "1"});
  INFO(c.err);
  REQUIRE(c.rc == 0);
  REQUIRE(c.err.find("[offset_cap]") != std::string::npos);
  const auto d = test::run_cli({"diff", in, "-", "--format", "json"}, c.out);
  REQUIRE(d.rc == 0);
  const double moved_mm = nlohmann::json::parse(d.out).at("max_displacement_mm").get<double>();
  CHECK(moved_mm <= 0.1);
  CHECK(moved_mm > 0.05);  // the cap still lets the points move
  // The warning's figure and its words agree: over the cap it says so; under
  // it, that the offset needed (not the error as programmed) is over it.
  const std::size_t at = c.err.find("[offset_cap]");
  const std::string line = c.err.substr(c.err.rfind('\n', at) + 1, at - c.err.rfind('\n', at));
  const bool over = line.find("reaches") != std::string::npos;
  CHECK((over || line.find("the offset these points need exceeds") != std::string::npos));
  if (over) CHECK(std::stod(line.substr(line.find("reaches") + 8)) > 0.1);
  // simulate compensates nothing, and says so of the cap.
  const auto s = test::run_cli({"simulate", in, "--stock", "box:-5,-5,-20,60,15,0", "--threads", "1"});
  CHECK(s.err.find("compensate would correct these points only up to the cap") != std::string::npos);
  CHECK(s.err.find("these points are compensated") == std::string::npos);
  fs::remove_all(dir);
}

}  // TEST_SUITE
