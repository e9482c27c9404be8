// Interpreter tests: one or more per trap of docs/physics.md, 'G-code traps', plus cycles,
// subprograms and frames. Expected positions are worked out by hand from the
// Fanuc/ISO rules, never read back from deflex's own output.
#include <doctest/doctest.h>

#include <cmath>

#include "../support.hpp"

using namespace deflex;
using namespace deflex::interp;
using deflex::test::interpret_text;

namespace {
bool near(const Vec3& a, const Vec3& b, double tol = 1e-9) {
  for (int i = 0; i < 3; ++i)
    if (std::fabs(a[i] - b[i]) > tol) return false;
  return true;
}
bool has(const std::string& s, const std::string& sub) { return s.find(sub) != std::string::npos; }
}  // namespace

TEST_SUITE("interp") {

TEST_CASE("trap 1: decimal point omitted follows the dialect") {
  auto f = interpret_text("G21 G90 G0 X1000 Y2.5 Z-2\n", "fanuc");
  REQUIRE(f.motions.size() == 1);
  CHECK(near(f.motions[0].end_mm, {1.0, 2.5, -0.002}));
  auto l = interpret_text("G21 G90 G0 X1000 Y2.5 Z-2\n", "linuxcnc");
  CHECK(near(l.motions[0].end_mm, {1000.0, 2.5, -2.0}));
  // Fanuc in inch: X1000 is 0.1000 in.
  auto i = interpret_text("G20 G90 G0 X1000\n", "fanuc");
  CHECK(near(i.motions[0].end_mm, {2.54, i.motions[0].end_mm[1], i.motions[0].end_mm[2]}));
}

TEST_CASE("trap 2: one code per modal group; axis words repeat the motion mode") {
  auto e = interpret_text("G21 G0 G1 X1\n");
  CHECK(e.errors == 1);
  CHECK(has(e.diagnostics, "t.nc:1:8: error: G1 and G0 are in the same modal group"));
  auto m = interpret_text("G21 G90 G1 X1. Y0 Z0 F100\nX2.\nY3.\n");
  REQUIRE(m.motions.size() == 3);
  CHECK(m.motions[1].kind == MotionKind::linear);
  CHECK(near(m.motions[2].end_mm, {2, 3, 0}));
  // G80 and G0 are in different groups (Fanuc groups 09 and 01).
  CHECK(interpret_text("G00 G17 G21 G40 G49 G80 G90\n").errors == 0);
}

TEST_CASE("trap 3: arcs follow the plane; I/J/K incremental even in G90; helix") {
  // G17 quarter circle, centre from I/J relative to the start.
  auto a = interpret_text("G21 G90 G0 X10. Y0 Z0\nG3 X0 Y10. I-10. J0 F100\n");
  REQUIRE(a.motions.size() == 2);
  CHECK(a.motions[1].kind == MotionKind::arc_ccw);
  CHECK(near(a.motions[1].center_mm, {0, 0, 0}));
  // G18: I and K; centre in X and Z.
  auto b = interpret_text("G21 G90 G18 G0 X0 Y0 Z0\nG2 X10. Z0 I5. K0 F100\n");
  REQUIRE(b.errors == 0);
  CHECK(near(b.motions[1].center_mm, {5, 0, 0}));
  // G19 with an I word (off plane) is an error.
  auto c = interpret_text("G21 G90 G19 G0 X0 Y0 Z0\nG2 Y10. Z0 I5. F100\n");
  CHECK(has(c.diagnostics, "I is not in the G19 plane"));
  // A helix: Z moves while the arc is in XY.
  auto h = interpret_text("G21 G90 G0 X10. Y0 Z0\nG3 X-10. Y0 Z-2. I-10. J0 F100\n");
  CHECK(near(h.motions[1].end_mm, {-10, 0, -2}));
  CHECK(near(h.motions[1].center_mm, {0, 0, 0}));
  // G91: the end is incremental, I/J are incremental as always.
  auto g = interpret_text("G21 G90 G0 X10. Y0 Z0\nG91 G3 X-10. Y10. I-10. J0 F100\n");
  CHECK(near(g.motions[1].end_mm, {0, 10, 0}));
  CHECK(near(g.motions[1].center_mm, {0, 0, 0}));
}

TEST_CASE("trap 4: R arcs; negative R is the long way; R full circle refused; radius mismatch") {
  // From (10,0) to (0,10), R10 CCW: the short arc has its centre at (0,0)...
  auto s = interpret_text("G21 G90 G0 X10. Y0 Z0\nG3 X0 Y10. R10. F100\n");
  CHECK(near(s.motions[1].center_mm, {0, 0, 0}, 1e-9));
  // ...R-10 (more than 180°) puts it at (10,10).
  auto l = interpret_text("G21 G90 G0 X10. Y0 Z0\nG3 X0 Y10. R-10. F100\n");
  CHECK(near(l.motions[1].center_mm, {10, 10, 0}, 1e-9));
  // CW short arc from (10,0) to (0,10): centre (10,10).
  auto c = interpret_text("G21 G90 G0 X10. Y0 Z0\nG2 X0 Y10. R10. F100\n");
  CHECK(near(c.motions[1].center_mm, {10, 10, 0}, 1e-9));
  auto full = interpret_text("G21 G90 G0 X10. Y0 Z0\nG2 X10. Y0 R5. F100\n");
  CHECK(has(full.diagnostics, "a full circle cannot be written with R"));
  // Full circle with I/J is fine.
  auto fij = interpret_text("G21 G90 G0 X10. Y0 Z0\nG2 I-5. F100\n");
  CHECK(fij.errors == 0);
  CHECK(fij.motions.size() == 2);
  CHECK(near(fij.motions[1].end_mm, {10, 0, 0}));
  auto bad = interpret_text("G21 G90 G0 X10. Y0 Z0\nG3 X0 Y10.1 I-10. J0 F100\n");
  CHECK(has(bad.diagnostics, "t.nc:2:13: error: arc end off the radius by 0.1"));
  auto tiny = interpret_text("G21 G90 G0 X0 Y0 Z0\nG2 X10. Y0 R4. F100\n");
  CHECK(has(tiny.diagnostics, "too small"));
}

TEST_CASE("trap 5: G91 and G20/G21 switching mid-program (position converts)") {
  auto r = interpret_text("G21 G90 G0 X10. Y0 Z0\nG91 X5.\nG20 X1.\nG21 G90 X0\n");
  REQUIRE(r.motions.size() == 4);
  CHECK(near(r.motions[1].end_mm, {15, 0, 0}));
  CHECK(near(r.motions[2].end_mm, {15 + 25.4, 0, 0}, 1e-12));
  CHECK(near(r.motions[3].end_mm, {0, 0, 0}));
  auto unknown = interpret_text("G21 G91 G0 X5.\n");
  CHECK(has(unknown.diagnostics, "incremental X move before the X position is known"));
}

TEST_CASE("trap 6: G43 H before or after Z; H is an offset number") {
  auto a = interpret_text("G21 G90 G0 X0 Y0\nG43 H5 Z10.\n");
  auto b = interpret_text("G21 G90 G0 X0 Y0\nG43 Z10. H5\n");
  CHECK(a.errors == 0);
  CHECK(b.errors == 0);
  // The programmed point is the tool tip: Z10 either way.
  CHECK(near(a.motions[1].end_mm, {0, 0, 10}));
  CHECK(near(b.motions[1].end_mm, a.motions[1].end_mm));
}

TEST_CASE("trap 7: cutter compensation gives the centre path; G68, G51, G52, G92, macro B, G65/G66 refused") {
  // D1 of radius 5 (test::interpret_text): the start-up move stays as
  // written, the contour after it is compensable, the tool runs offset.
  auto c = interpret_text("G21 G90 G0 X0 Y0 Z0\nG41 D1 G1 X10. F100\nX20.\nG40 X30.\n");
  REQUIRE(c.motions.size() == 4);
  CHECK(c.motions[1].fixed == Fixed::cutter_comp);
  CHECK(c.motions[2].fixed == Fixed::no);
  CHECK(c.motions[2].comp == 1);
  CHECK(near(c.motions[2].end_mm, {20, 5, 0}));
  CHECK(near(c.motions[2].contour_end_mm, {20, 0, 0}));
  CHECK(c.motions[3].fixed == Fixed::no);
  CHECK(near(c.motions[3].start_mm, {20, 5, 0}));
  CHECK(c.stats.cutter_comp_motions == 2);
  for (const char* code : {"G68 X0 Y0 R30.", "G51 X0 Y0 P2000", "G52 X10.", "G92 X0 Y0", "G65 P9010 A1.", "G66 P9010"}) {
    auto r = interpret_text(std::string("G21 G90 G0 X0 Y0 Z0\n") + code + "\nG1 X5. F100\n");
    CHECK_MESSAGE(r.errors == 1, code);
    CHECK_MESSAGE(r.stats.stopped, code);
    CHECK_MESSAGE(r.motions.size() == 1, code);  // nothing after the refusal
    CHECK_MESSAGE(has(r.diagnostics, "block refused"), code);
  }
  auto m = interpret_text("G21 G90 G0 X0 Y0 Z0\n#1=2.\nG1 X#1 F100\n");
  CHECK(m.stats.stopped);
  CHECK(has(m.diagnostics, "t.nc:2:1: error: macro B"));
  auto w = interpret_text("G21 G90 G0 X0 Y0 Z0\nWHILE [#1 LT 3] DO1\n");
  CHECK(has(w.diagnostics, "macro B"));
}

TEST_CASE("trap 7: canned cycles expand into their moves, G98/G99, K repeats, G80") {
  // G81 from Z25, R2, Z-12, G98: back to the initial level 25.
  auto r = interpret_text("G21 G90 G0 X0 Y0 Z25.\nG98 G81 X10. Y0 Z-12. R2. F100\nX20.\nG80\nG0 X0\n");
  REQUIRE(r.errors == 0);
  REQUIRE(r.motions.size() == 1 + 4 + 4 + 1);
  CHECK(r.motions[1].kind == MotionKind::rapid);
  CHECK(near(r.motions[1].end_mm, {10, 0, 25}));
  CHECK(near(r.motions[2].end_mm, {10, 0, 2}));
  CHECK(r.motions[3].kind == MotionKind::linear);
  CHECK(near(r.motions[3].end_mm, {10, 0, -12}));
  CHECK(near(r.motions[4].end_mm, {10, 0, 25}));
  CHECK(near(r.motions[8].end_mm, {20, 0, 25}));
  for (int i = 1; i <= 8; ++i) CHECK(r.motions[i].fixed != Fixed::no);
  // G99 retracts to R.
  auto q = interpret_text("G21 G90 G0 X0 Y0 Z25.\nG99 G81 X10. Z-12. R2. F100\n");
  CHECK(near(q.motions.back().end_mm, {10, 0, 2}));
  // G91 with K3 (Fanuc repeat word): three holes 5 mm apart.
  auto k = interpret_text("G21 G90 G0 X0 Y0 Z10.\nG91 G99 G81 X5. Z-3. R-8. K3 F100\n");
  REQUIRE(k.errors == 0);
  std::vector<Vec3> bottoms;
  for (const Motion& m : k.motions)
    if (m.kind == MotionKind::linear) bottoms.push_back(m.end_mm);
  REQUIRE(bottoms.size() == 3);
  CHECK(near(bottoms[0], {5, 0, -1}));  // R = 10-8 = 2, Z = 2-3 = -1
  CHECK(near(bottoms[2], {15, 0, -1}));
  // G83 pecks of Q4 to Z-10 from R1: feeds to -3, -7, -10.
  auto p = interpret_text("G21 G90 G0 X0 Y0 Z10.\nG98 G83 Z-10. R1. Q4. F100\n");
  std::vector<double> depths;
  for (const Motion& m : p.motions)
    if (m.kind == MotionKind::linear) depths.push_back(m.end_mm[2]);
  REQUIRE(depths.size() == 3);
  CHECK(depths[0] == doctest::Approx(-3));
  CHECK(depths[1] == doctest::Approx(-7));
  CHECK(depths[2] == doctest::Approx(-10));
}

TEST_CASE("trap 7: M98/M99 subprograms in the file, with L repeats") {
  std::string prog =
      "O1000\nG21 G90 G0 X0 Y0 Z0\nM98 P2000 L2\nG0 X50.\nM30\n"
      "O2000\nG91 G1 X10. F100\nG90\nM99\n";
  auto r = interpret_text(prog);
  REQUIRE(r.errors == 0);
  REQUIRE(r.motions.size() == 4);
  CHECK(near(r.motions[1].end_mm, {10, 0, 0}));
  CHECK(near(r.motions[2].end_mm, {20, 0, 0}));
  CHECK(r.motions[1].fixed == Fixed::subprogram);
  CHECK(near(r.motions[3].end_mm, {50, 0, 0}));
  CHECK(r.stats.ended);
  // Fanuc's 8-digit form P rrrr nnnn: 3 repeats of O2000.
  auto e = interpret_text("G21 G90 G0 X0 Y0 Z0\nM98 P00032000\nM30\nO2000\nG91 G1 X1. F100\nG90\nM99\n");
  CHECK(e.motions.size() == 4);
  auto huge = interpret_text("G21 G90 G0 X0 Y0 Z0\nM98 P2000 L999999999\nM30\nO2000\nM99\n");
  CHECK(has(huge.diagnostics, "repeat count over 9999"));
  auto missing = interpret_text("G21 G90 G0 X0 Y0 Z0\nM98 P7777\n");
  CHECK(has(missing.diagnostics, "subprogram O7777 is not in this file"));
}

TEST_CASE("trap 8: block delete, comments, N, O and percent") {
  std::string prog = "%\nO0001 (TEST)\nN10 G21 G90 G0 X0 Y0 Z0 ; start\n/N20 G1 X5. F100\nN30 G1 X10. F100 (cut)\n%\nafter the end\n";
  auto on = interpret_text(prog, "fanuc", nullptr, false);
  REQUIRE(on.errors == 0);
  REQUIRE(on.motions.size() == 3);
  CHECK(on.motions[1].fixed == Fixed::block_delete);
  auto off = interpret_text(prog, "fanuc", nullptr, true);
  CHECK(off.motions.size() == 2);
}

TEST_CASE("work offsets, G54.1 P, G53, G28 via the machine profile") {
  profile::MachineProfile m;
  m.work_offsets_mm["G54"] = {100, 0, -300};
  m.work_offsets_mm["G55"] = {200, 0, -300};
  m.work_offsets_mm["G54.1P2"] = {0, 50, 0};
  m.reference_points_mm[1] = {0, 0, 0};
  auto r = interpret_text("G21 G90 G54 G0 X0 Y0 Z0\nG55\nG1 X0 F100\nG54.1 P2\nG53 G0 Z0\nG54 G91 G28 Z0\n", "fanuc", &m);
  REQUIRE(r.errors == 0);
  // G55: the tool has not moved, its X in the G55 frame is 100 - 200 = -100.
  CHECK(near(r.motions[1].start_mm, {-100, 0, 0}));
  CHECK(near(r.motions[1].end_mm, {0, 0, 0}));
  // G53 Z0: machine Z 0 is work Z 0 - 0 in the G54.1 P2 frame.
  CHECK(r.motions[2].fixed == Fixed::machine_frame);
  CHECK(r.motions[2].end_mm[2] == doctest::Approx(0.0));
  // G91 G28 Z0 in G54: up to machine Z0 = work Z 300.
  CHECK(r.motions.back().end_mm[2] == doctest::Approx(300.0));
  auto bad = interpret_text("G21 G54.1 P49\n");
  CHECK(has(bad.diagnostics, "out of range"));
}

TEST_CASE("refusals name what is not interpreted and where") {
  auto a = interpret_text("G21 G90 G0 X0 Y0 Z0 A10.\n");
  CHECK(has(a.diagnostics, "t.nc:1:21: error: axis A: deflex reads 3-axis programs"));
  auto b = interpret_text("G21 G90 G0 X0 X1.\n");
  CHECK(has(b.diagnostics, "two X words"));
  auto c = interpret_text("G21 G90 G1 X1.\n");
  CHECK(has(c.diagnostics, "no feed rate"));
  auto d = interpret_text("G21 G7 X1.\n");
  CHECK(has(d.diagnostics, "unknown G code G7"));
}

}  // TEST_SUITE
