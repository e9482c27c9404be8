// Plausibility warnings (compensate/plausibility.hpp): one small program per
// warning, the default force limit by hand, and the sane samples give none.
#include <doctest/doctest.h>

#include <unistd.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "../support.hpp"
#include "deflex/compensate/compensate.hpp"
#include "deflex/compensate/plausibility.hpp"
#include "deflex/force/material.hpp"
#include "deflex/profile/yaml.hpp"
#include "deflex/stock/build.hpp"

using namespace deflex;

namespace {

// T1: D10 flat, flutes 5 mm long; T2: the same, not centre-cutting; T3: the
// sample library's D6 necked ball; T4: D10 flat with max_force_N 50.
const char* kTools = R"(tools:
  T1: {type: flat, diameter_mm: 10, flutes: 4, flute_length_mm: 5, stickout_mm: 40, material: carbide}
  T2: {type: flat, diameter_mm: 10, flutes: 4, flute_length_mm: 22, stickout_mm: 40, material: carbide,
       centre_cutting: false}
  T3: {type: ball, diameter_mm: 6, flutes: 2, flute_length_mm: 9, stickout_mm: 42, shank_diameter_mm: 6,
       flute_diameter_ratio: 0.78, neck: {diameter_mm: 5.6, length_mm: 15}, material: carbide}
  T4: {type: flat, diameter_mm: 10, flutes: 4, flute_length_mm: 22, stickout_mm: 40, material: carbide,
       max_force_N: 50}
)";

struct Run {
  compensate::Physics ph;
  compensate::Settings s;
  std::vector<compensate::Point> points;
  compensate::Plausibility pl;
  Run(const std::string& program, const std::string& stock_spec, const std::string& material = "Al6082-T4",
      const std::string& tools = kTools, std::size_t max_motions = 0) {
    test::Interpreted in = test::interpret_text(program);
    REQUIRE(in.errors == 0);
    if (max_motions && in.motions.size() > max_motions) in.motions.resize(max_motions);
    ph.tools = tools.empty() ? stiffness::load_tool_library("samples/tools.yaml")
                             : stiffness::parse_tool_library(tools, "lib.yaml");
    ph.machine = stiffness::load_machine_stiffness("samples/machines/mill3.yaml");
    ph.k = force::find_material(force::load_material_library("samples/materials.yaml"), material).k;
    stock::ZMap z = stock::make_stock(stock_spec, {});
    ph.stock = &z;
    s.threads = 0;
    points = compensate::simulate(in.motions, {}, ph, s);
    pl = compensate::plausibility(points, ph.tools, s);
  }
};

std::string slot(int tool, double z, double feed = 300) {
  return "G21 G90 G17\nT" + std::to_string(tool) + " M6\nS8000 M3\nG0 X-10. Y0. Z5.\nG1 Z" + std::to_string(z) +
         " F" + std::to_string(feed) + "\nX30.\nG0 Z5.\nM30\n";
}

}  // namespace

TEST_SUITE("compensate") {

TEST_CASE("plausibility: a slot deeper than the flute length") {
  Run r(slot(1, -8), "box:0,-20,-20,50,20,0");
  const compensate::Finding* f = r.pl.find("flute_length");
  REQUIRE(f);
  CHECK(f->worst == deflex::test::within(8.0, 0.02));
  CHECK(f->limit == 5.0);
  CHECK(f->line == 6);
  CHECK(f->tool == "T1");
  CHECK(f->count > 10);
  CHECK(f->lines == std::vector<std::uint32_t>{6});
  CHECK(f->message.find("flutes are 5.00 mm long") != std::string::npos);
  // The same slot 4 mm deep: inside the flutes.
  Run ok(slot(1, -4), "box:0,-20,-20,50,20,0");
  CHECK_FALSE(ok.pl.find("flute_length"));
}

TEST_CASE("plausibility: the default force limit from the bending strength, and max_force_N") {
  const auto lib = stiffness::parse_tool_library(kTools, "lib.yaml");
  const double pi = std::numbers::pi;
  // T3: the shank at the holder face (d 6, L 42) is weaker than the neck root
  // (d 5.6, L 24) and the flute root (d 0.78 * 6, L 9); carbide 1000 MPa.
  const compensate::ForceLimit t3 = compensate::default_force_limit(lib.tools.at("T3"));
  CHECK(t3.N == doctest::Approx(1000.0 * pi * 216.0 / 32.0 / 42.0));
  CHECK(t3.where == "the holder face");
  // T1: flutes 0.8 * 10 over 5 mm vs the shank 10 over 40 mm.
  CHECK(compensate::default_force_limit(lib.tools.at("T1")).N == doctest::Approx(1000.0 * pi * 1000.0 / 32.0 / 40.0));
  CHECK(compensate::force_limit(lib.tools.at("T4")).N == 50.0);
  // HSS allows more than carbide.
  CHECK(stiffness::material_preset("hss")->allowable_bending_MPa > stiffness::material_preset("carbide")->allowable_bending_MPa);
  Run r(slot(4, -3, 3000), "box:0,-20,-20,50,20,0");
  const compensate::Finding* f = r.pl.find("peak_force");
  REQUIRE(f);
  CHECK(f->limit == 50.0);
  CHECK(f->worst > 50.0);
  CHECK(f->line == 6);
  // The same cut with T2 (same tool, default limit ~2300 N at the flute root): no warning.
  Run ok(slot(2, -3, 3000), "box:0,-20,-20,50,20,0");
  CHECK_FALSE(ok.pl.find("peak_force"));
}

TEST_CASE("plausibility: the deflection over the offset cap") {
  Run r(slot(2, -3), "box:0,-20,-20,50,20,0");
  REQUIRE_FALSE(r.pl.find("offset_cap"));  // default cap 0.1 mm
  r.s.max_offset_mm = 1e-4;
  test::Interpreted in = test::interpret_text(slot(2, -3));
  const compensate::Plausibility pl = compensate::plausibility(r.points, r.ph.tools, r.s);
  const compensate::Finding* f = pl.find("offset_cap");
  REQUIRE(f);
  CHECK(f->worst > 1e-4);
  CHECK(f->limit == 1e-4);
  CHECK(f->line == 6);
}

TEST_CASE("plausibility: a plunge with an end mill that does not cut at its centre") {
  const std::string plunge = "G21 G90 G17\nT2 M6\nS8000 M3\nG0 X20. Y0. Z5.\nG1 Z-3. F100\nX30. F300\nG0 Z5.\nM30\n";
  Run r(plunge, "box:0,-20,-20,50,20,0");
  const compensate::Finding* f = r.pl.find("centre_cutting");
  REQUIRE(f);
  CHECK(f->line == 5);
  CHECK(f->lines == std::vector<std::uint32_t>{5});
  CHECK(f->tool == "T2");
  // T4: the same tool, centre-cutting by default.
  std::string t4 = plunge;
  t4.replace(t4.find("T2"), 2, "T4");
  Run ok(t4, "box:0,-20,-20,50,20,0");
  CHECK_FALSE(ok.pl.find("centre_cutting"));
  // Plunging outside the stock: nothing engaged.
  Run air(plunge, "box:40,-20,-20,50,20,0");
  CHECK_FALSE(air.pl.find("centre_cutting"));
}

TEST_CASE("plausibility: a raw box under a finishing ball end") {
  // T3 (ball R 3) 5 mm into a raw box: roughing needed first.
  const std::string ball = "G21 G90 G17\nT3 M6\nS10000 M3\nG0 X-10. Y0. Z5.\nG1 Z-5. F300\nX30.\nG0 Z5.\nM30\n";
  Run r(ball, "box:0,-20,-20,50,20,0");
  const compensate::Finding* f = r.pl.find("roughing");
  REQUIRE(f);
  CHECK(f->worst > 3.0);
  CHECK(f->limit == 3.0);
  CHECK(f->line == 6);
  // 0.5 mm allowance: a finishing cut.
  Run ok(ball, "box:0,-20,-20,50,20,-4.5");
  CHECK_FALSE(ok.pl.find("roughing"));
  // A flat end in a full-width slot deeper than D/2.
  Run flat(slot(2, -7), "box:0,-20,-20,50,20,0");
  REQUIRE(flat.pl.find("roughing"));
  CHECK(flat.pl.find("roughing")->line == 6);
}

// An offset pocket 60 x 60 mm in three 3 mm levels with T1 of the sample
// library (D10 flat): at each level the outer loop first (a full-width slot
// along the walls the level above left), then inner loops 4 mm apart.
std::string offset_pocket() {
  std::string g = "G21 G90 G17\nT1 M6\nS10000 M3\n";
  for (int z : {-3, -6, -9}) {
    g += "G0 X-25. Y-25. Z5.\nG1 Z" + std::to_string(z) + ". F300\n";
    for (int h : {25, 21, 17, 13, 9, 5, 1}) {
      const std::string p = std::to_string(h) + ".", m = "-" + p;
      g += "G1 X" + m + " Y" + m + " F1000\nX" + p + "\nY" + p + "\nX" + m + "\nY" + m + "\n";
    }
    g += "G0 Z5.\n";
  }
  return g + "M30\n";
}

TEST_CASE("plausibility: a_p of an offset pocket is the level's depth, not the walls the tool grazes") {
  // The outer loops are lines 6-10, 44-48 and 82-86. Below the first level
  // the flank passes along the walls of the levels above, which it cut
  // itself: a_p read 5.7 and 8.1 mm there (the envelope's top) and the
  // full-width slot under it looked like a raw blank.
  Run r(offset_pocket(), "box:-40,-40,-20,40,40,0", "C35", "");
  const double cell_mm = stock::default_cell_mm;
  for (const std::uint32_t first : {6u, 44u, 82u}) {
    std::size_t n = 0;
    for (const compensate::Point& p : r.points) {
      if (p.air || p.line < first || p.line > first + 4) continue;
      // Closing on its own plunge (the loop's last 1.5 mm) the tool meets a
      // crescent it left, then only its own cut: no height cut deeper than a
      // cell at the end, where the envelope's top stands.
      if (p.line == first + 4 && p.tip_mm.y() < -23.4) continue;
      ++n;
      CHECK_MESSAGE(std::fabs(p.ap_mm - 3.0) <= cell_mm, "line ", p.line, " a_p ", p.ap_mm);
    }
    CHECK(n > 300);
  }
  CHECK_FALSE(r.pl.find("roughing"));
  // The graze adds next to nothing to the force: mid-way along the first side
  // each level is cut as the first.
  auto force_at = [&](std::uint32_t line) {
    for (const compensate::Point& p : r.points)
      if (p.line == line && std::fabs(p.tip_mm.x()) < 0.3) return p.force_N.norm();
    return 0.0;
  };
  REQUIRE(force_at(7) > 0);
  CHECK(force_at(45) == deflex::test::within(force_at(7), 0.01));
  CHECK(force_at(83) == deflex::test::within(force_at(7), 0.01));
  // A real full-width slot 12 mm deep in one pass still looks like a raw blank.
  Run deep(slot(1, -12), "box:0,-20,-20,50,20,0", "C35", "");
  const compensate::Finding* f = deep.pl.find("roughing");
  REQUIRE(f);
  CHECK(f->worst == deflex::test::within(12.0, 0.02));
  CHECK(f->line == 6);
}

// The sample library's T7 (ball D10) rasters along X at Z-0.5 over a box
// (1 mm steps, passes 2 mm apart); on the pass at Y10 one sample drops to
// Z-11.5 at X20 (line 341), as a drop-cutter sample off a rim would.
std::string rim_raster() {
  std::string g = "G21 G90 G17\nT7 M6\nS10000 M3\nG0 X-10. Y0. Z5.\nG1 Z-0.5 F1000\n";
  for (int k = 0, y = 0; y <= 20; ++k, y += 2) {
    g += "G1 Y" + std::to_string(y) + ".\n";
    for (int i = 1; i <= 60; ++i) {
      const int x = k % 2 ? 50 - i : -10 + i;
      g += "X" + std::to_string(x) + ". Z" + (x == 20 && y == 10 ? "-11.5" : "-0.5") + "\n";
    }
  }
  return g + "G0 Z5.\nM30\n";
}

TEST_CASE("plausibility: a ball end dropped deep into the stock and back in two short steps is a gouge, not a raw blank") {
  const std::string g = rim_raster();
  Run r(g, "box:0,0,-20,40,20,0", "C35", "");
  REQUIRE(test::interpret_text(g).motions.size() > 300);
  const compensate::Finding* f = r.pl.find("gouge");
  REQUIRE(f);
  CHECK(f->line == 341);
  CHECK(f->lines == std::vector<std::uint32_t>{341, 342});  // down and back up
  CHECK(f->worst == doctest::Approx(11.0));
  CHECK(f->message.find("the program plunges 11.00 mm in one 1.00 mm step at line 341") != std::string::npos);
  CHECK(f->message.find("a gouge in the CAM program?") != std::string::npos);
  CHECK_FALSE(r.pl.find("roughing"));
  // The ball at Z-11.5 reached by a gentle ramp (11 mm over 40 mm): a raw blank.
  Run ramp("G21 G90 G17\nT7 M6\nS10000 M3\nG0 X-10. Y10. Z5.\nG1 Z-0.5 F1000\nX0.\nX40. Z-11.5\nG0 Z5.\nM30\n",
           "box:0,0,-20,40,20,0", "C35", "");
  CHECK(ramp.pl.find("roughing"));
  CHECK_FALSE(ramp.pl.find("gouge"));
  // A step down that stays down (a wall in a raster): the ball may go there;
  // on a raw box it is roughing.
  Run wall("G21 G90 G17\nT7 M6\nS10000 M3\nG0 X-10. Y10. Z5.\nG1 Z-0.5 F1000\nX20.\nX21. Z-11.5\nX40.\nG0 Z5.\nM30\n",
           "box:0,0,-20,40,20,0", "C35", "");
  CHECK(wall.pl.find("roughing"));
  CHECK_FALSE(wall.pl.find("gouge"));
}

TEST_CASE("plausibility: with a part model the moves the gouge check flags stay as written and are no raw blank") {
  std::string t = (std::filesystem::temp_directory_path() / "deflex-gouge-XXXXXX").string();
  const std::filesystem::path dir = mkdtemp(t.data());
  const std::string prog = (dir / "rim.nc").string(), part = (dir / "part.stl").string(), out = (dir / "out.nc").string();
  const std::string g = rim_raster();
  test::write_file(prog, g);
  // The part: the box 0..40 x 0..20 with its top at Z-0.5, the raster's surface.
  const double x[2] = {0, 40}, y[2] = {0, 20}, z[2] = {-20, -0.5};
  auto v = [&](int i, int j, int k) {
    return std::to_string(x[i]) + " " + std::to_string(y[j]) + " " + std::to_string(z[k]);
  };
  std::string stl = "solid part\n";
  auto quad = [&](const std::string& a, const std::string& b, const std::string& c, const std::string& d) {
    for (const auto& tri : {std::array<std::string, 3>{a, b, c}, std::array<std::string, 3>{a, c, d}})
      stl += "facet normal 0 0 0\nouter loop\nvertex " + tri[0] + "\nvertex " + tri[1] + "\nvertex " + tri[2] +
             "\nendloop\nendfacet\n";
  };
  quad(v(0, 0, 0), v(0, 1, 0), v(1, 1, 0), v(1, 0, 0));  // bottom, outward -Z
  quad(v(0, 0, 1), v(1, 0, 1), v(1, 1, 1), v(0, 1, 1));  // top
  quad(v(0, 0, 0), v(1, 0, 0), v(1, 0, 1), v(0, 0, 1));  // y = 0
  quad(v(0, 1, 0), v(0, 1, 1), v(1, 1, 1), v(1, 1, 0));  // y = 20
  quad(v(0, 0, 0), v(0, 0, 1), v(0, 1, 1), v(0, 1, 0));  // x = 0
  quad(v(1, 0, 0), v(1, 1, 0), v(1, 1, 1), v(1, 0, 1));  // x = 40
  test::write_file(part, stl + "endsolid part\n");
  const auto r = test::run_cli({"compensate", prog, "--stock", "box:0,0,-20,40,20,0", "--part", part, "-o", out});
  REQUIRE_MESSAGE(r.rc == 0, r.err);
  CHECK(r.err.find("[roughing]") == std::string::npos);
  CHECK(r.err.find("stay as written: moves the gouge check finds cutting into the part") != std::string::npos);
  // Line 341 (the drop) and its neighbours on the gouge are written as they were.
  const std::string written = test::read_file(out);
  auto line_of = [](const std::string& text, int n) {
    std::size_t at = 0;
    for (int i = 1; i < n; ++i) at = text.find('\n', at) + 1;
    return text.substr(at, text.find('\n', at) - at);
  };
  for (int n : {340, 341, 342}) CHECK(line_of(written, n) == line_of(g, n));
  std::filesystem::remove_all(dir);
}

TEST_CASE("plausibility: the side-wall and six-surface samples are sane") {
  {
    Run r(test::read_file("samples/programs/side_wall.nc"), "box:0,-40,-30,100,0,0", "Al6082-T4", "");
    for (const char* k : {"flute_length", "peak_force", "centre_cutting", "roughing"}) CHECK_MESSAGE(!r.pl.find(k), k);
  }
  {
    // The first passes of the six surfaces (T5, ball R 8) on their stock.
    Run r(test::read_file("samples/programs/six_surfaces.nc"), "samples/stock/six_surfaces_stock.stl", "C35", "", 3000);
    REQUIRE(r.points.size() > 1000);
    for (const char* k : {"flute_length", "peak_force", "centre_cutting", "roughing"}) CHECK_MESSAGE(!r.pl.find(k), k);
  }
}

}  // TEST_SUITE

TEST_SUITE("compensate") {
  TEST_CASE("offset cap: the capped lines handed over as the mirror pass finds them give what all at the end give") {
    // Points on lines 1..60 whose |e| rises and falls; capped lines in program
    // order, some twice, and a tie of the worst on two of them.
    compensate::Settings s;
    stiffness::ToolLibrary lib = stiffness::parse_tool_library(kTools, "lib.yaml");
    std::vector<compensate::Point> pts;
    for (std::uint32_t l = 1; l <= 60; ++l)
      for (int k = 0; k < 3; ++k) {
        compensate::Point p;
        p.line = l;
        p.tool = 3;
        p.air = false;
        p.error_mm = (l == 17 || l == 44 ? 0.3 : 0.01 * std::fabs(30.0 - l)) + 0.001 * k;
        pts.push_back(p);
      }
    const std::vector<std::uint32_t> capped = {5, 5, 17, 20, 21, 33, 44, 44, 50, 51, 52, 53, 54, 55, 56, 57, 58, 59};
    const compensate::Plausibility all = compensate::plausibility(pts, lib, s, &capped);
    const compensate::Finding* want = all.find("offset_cap");
    REQUIRE(want);
    CHECK(want->line == 17);  // the earlier of the two worst lines
    CHECK(want->count == capped.size());
    CHECK(want->line_count == 16);
    CHECK(want->lines.size() == 12);
    // In pieces: the points of a piece, then its capped lines (a late point of
    // the piece before may follow, as the as-written simulation's batch does).
    compensate::PlausibilityScan scan(lib, s);
    std::size_t next = 0;
    for (std::uint32_t end : {12u, 30u, 45u, 61u}) {
      while (next < pts.size() && pts[next].line < end) scan.add(pts[next++]);
      std::vector<std::uint32_t> piece;
      for (std::uint32_t l : capped)
        if (l < end && l >= (end == 12 ? 0u : end == 30 ? 12u : end == 45 ? 30u : 45u)) piece.push_back(l);
      scan.capped(piece);
    }
    const compensate::Plausibility got = scan.finish(true);
    const compensate::Finding* f = got.find("offset_cap");
    REQUIRE(f);
    CHECK(f->line == want->line);
    CHECK(f->worst == want->worst);
    CHECK(f->count == want->count);
    CHECK(f->line_count == want->line_count);
    CHECK(f->lines == want->lines);
    CHECK(f->message == want->message);
  }
}
