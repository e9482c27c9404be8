// Compensation: which points may move, how the program text changes, the
// read-back safety check, and the physics of the mirror loop checked against
// the force and stiffness modules used directly (an independent path through
// the textbook engagement instead of the Z-map).
#include <doctest/doctest.h>

#include <cmath>

#include "../support.hpp"
#include "deflex/compensate/apply.hpp"
#include "deflex/compensate/compensate.hpp"
#include "deflex/force/engagement.hpp"
#include "deflex/force/flank.hpp"
#include "deflex/force/tool.hpp"
#include "deflex/force/material.hpp"
#include "deflex/force/mechanistic.hpp"
#include "deflex/stiffness/beam.hpp"
#include "deflex/stock/build.hpp"

using namespace deflex;
using compensate::V3;

namespace {

// Side milling of a wall along +X with the D10 flat end T1 of the sample
// library: tool centre at Y = -3, stock from Y = 0: a_e = 2 mm, a_p = 10 mm,
// material on the +Y side (up-milling with M3).
const char* kWall =
    "%\nO0001\nN1 G21 G90 G17 G40 G49 G80 G54\nN2 T1 M06\nN3 S8000 M03\nN4 G00 X-10. Y-3. Z5.\n"
    "N5 G01 Z-10. F800.\nN6 X20.\nN7 X50.\nN8 X80.\nN9 X110.\nN10 G00 Z5.\nN11 M30\n%\n";
const char* kWallStock = "box:0,0,-20,100,20,0";

struct Fixture {
  gcode::Program prog{SourceText("wall.nc", kWall)};
  std::vector<interp::Motion> motions;
  stock::ZMap stock = stock::make_stock(kWallStock, {});
  compensate::Physics ph;
  compensate::Settings s;
  interp::Options opt;
  Fixture() {
    opt.dialect = profile::load_dialect("fanuc");
    Diagnostics d(nullptr, 0);
    test::Collect c;
    c.out = &motions;
    interp::interpret(prog, opt, d, c);
    REQUIRE(d.errors() == 0);
    ph.tools = stiffness::load_tool_library("samples/tools.yaml");
    ph.machine = stiffness::load_machine_stiffness("samples/machines/mill3.yaml");
    ph.k = force::find_material(force::load_material_library("samples/materials.yaml"), "C35").k;
    ph.stock = &stock;
    s.tolerance_mm = 0.002;
    s.threads = 1;
  }
};

}  // namespace

TEST_SUITE("compensate") {

TEST_CASE("movable: cutting points only, and never before a block that cannot be re-targeted") {
  auto r = test::interpret_text(
      "G21 G90 G0 X0 Y0 Z5.\nG1 Z-1. F100 S1000\nX10.\nX20.\nG81 X30. Z-5. R1.\nG80\nG1 X40.\nG0 Z5.\n");
  REQUIRE(r.errors == 0);
  auto can = compensate::movable(r.motions);
  REQUIRE(can.size() == r.motions.size());
  CHECK_FALSE(can[0]);  // rapid
  CHECK(can[1]);        // plunge end, followed by a plain G1
  CHECK(can[2]);
  CHECK_FALSE(can[3]);  // followed by a canned cycle: its XY and initial level would move
  for (std::size_t i = 4; i < r.motions.size(); ++i)
    if (r.motions[i].fixed == interp::Fixed::canned_cycle) CHECK_FALSE(can[i]);
  CHECK(can[r.motions.size() - 2]);  // G1 X40 before a plain G0
  // Not before a change of work frame.
  profile::MachineProfile mp;
  mp.work_offsets_mm["G55"] = {100, 0, 0};
  auto w = test::interpret_text("G21 G90 G0 X0 Y0 Z5.\nG1 Z-1. F100 S1000\nX10.\nG55\nG1 X20.\nX30.\n", "fanuc", &mp);
  REQUIRE(w.errors == 0);
  auto cw = compensate::movable(w.motions);
  CHECK_FALSE(cw[2]);  // X10 in G54, then G55
  CHECK(cw[3]);
}

TEST_CASE("apply_offsets: zero offsets give the input; a modal axis carries no offset into the next block") {
  Fixture f;
  std::vector<V3> zero(f.motions.size(), V3::Zero());
  CHECK(compensate::apply_offsets(f.prog, f.opt.dialect, f.motions, zero) == kWall);
  // Move the end of N6 (motion index 2) by +0.0123 in Y: N6 gets a Y word, and
  // N7, which relies on the modal Y, gets its programmed Y back.
  std::vector<V3> off = zero;
  std::size_t i6 = 0;
  while (f.motions[i6].line != 8) ++i6;
  off[i6] = V3(0, 0.012, 0);
  compensate::WriteStats ws;
  std::string out = compensate::apply_offsets(f.prog, f.opt.dialect, f.motions, off, &ws);
  CHECK(out.find("N6 X20. Y-2.988\n") != std::string::npos);
  CHECK(out.find("N7 X50. Y-3.\n") != std::string::npos);
  CHECK(ws.words_inserted == 2);
  std::vector<bool> can(f.motions.size(), false);
  can[i6] = true;
  CHECK_NOTHROW(compensate::safety_check(f.prog, f.motions, out, f.opt, can, 0.1));
  // The same text fails when that motion was not allowed to move, or beyond the cap.
  std::vector<bool> none(f.motions.size(), false);
  CHECK_THROWS_AS(compensate::safety_check(f.prog, f.motions, out, f.opt, none, 0.1), Error);
  CHECK_THROWS_AS(compensate::safety_check(f.prog, f.motions, out, f.opt, can, 0.01), Error);
}

TEST_CASE("safety check: a change in anything but coordinates aborts") {
  Fixture f;
  std::vector<bool> can = compensate::movable(f.motions);
  std::string t = kWall;
  t.replace(t.find("F800."), 5, "F900.");
  CHECK_THROWS_WITH_AS(compensate::safety_check(f.prog, f.motions, t, f.opt, can, 0.1),
                       doctest::Contains("changed in more than its coordinate words"), Error);
  std::string r = kWall;
  r.replace(r.find("N10 G00 Z5."), 11, "N10 G00 Z6.");  // a rapid moved
  CHECK_THROWS_AS(compensate::safety_check(f.prog, f.motions, r, f.opt, can, 0.1), Error);
}

TEST_CASE("MRR per point is a_e a_p v_f at the motion's own feed; D_eff and CWE area are carried") {
  Fixture f;
  // N7 at F800 as written, N8 at F1600: the simulator's Process keeps the first feed.
  std::string text = kWall;
  text.replace(text.find("N8 X80."), 7, "N8 X80. F1600.");
  gcode::Program prog{SourceText("wall2.nc", text)};
  std::vector<interp::Motion> motions;
  Diagnostics d(nullptr, 0);
  test::Collect c;
  c.out = &motions;
  interp::interpret(prog, f.opt, d, c);
  REQUIRE(d.errors() == 0);
  const auto pts = compensate::simulate(motions, {}, f.ph, f.s);
  int seen = 0;
  for (const auto& q : pts) {
    if (q.index != q.count / 2 || (q.line != 9 && q.line != 10)) continue;
    const double vf_mm_per_s = (q.line == 9 ? 800.0 : 1600.0) / 60;
    CHECK(q.mrr_mm3_per_s == deflex::test::within(2.0 * 10.0 * vf_mm_per_s, 0.02));
    CHECK(q.d_eff_mm == doctest::Approx(10.0));  // a flat end cuts with its full diameter
    // The engaged flank: a_p 10 times the arc of a_e 2 on a D10 (acos(1 - 2/5) 5 mm).
    CHECK(q.cwe_area_mm2 == deflex::test::within(10.0 * 5 * std::acos(1 - 2.0 / 5), 0.03));
    ++seen;
  }
  CHECK(seen == 2);
}

TEST_CASE("the deflection at a steady wall point equals C(h) F from the force and stiffness modules") {
  Fixture f;
  auto pts = compensate::simulate(f.motions, {}, f.ph, f.s);
  // A point well inside the wall, on N7.
  const compensate::Point* p = nullptr;
  for (const auto& q : pts)
    if (q.line == 9 && q.index == q.count / 2) p = &q;
  REQUIRE(p != nullptr);
  CHECK(p->ap_mm == deflex::test::within(10.0, 0.01));
  CHECK(p->ae_mm == deflex::test::within(2.0, 0.01));
  // Independent: the textbook engagement (a_e 2 on the +Y side, up-milling),
  // the same slices and coefficients, f_z = 800 / (8000 * 4).
  const auto& tool = stiffness::find_tool(f.ph.tools, "T1");
  force::Cutter c;
  c.type = stock::EndShape::flat;
  c.diameter_mm = tool.diameter_mm;
  c.flutes = tool.flutes;
  c.helix_deg = tool.helix_deg;
  c.flute_length_mm = tool.flute_length_mm;
  auto cs = force::make_slices(c, f.s.slice_mm, tool.flute_length_mm);
  force::Engagement e;
  force::simple_engagement(cs, 2.0, 10.0, force::MillingMode::up, e);
  auto rev = force::revolution_forces(cs, f.ph.k, 800.0 / (8000.0 * 4), e, 360);
  force::Vec3 F = force::summarize(rev).mean_N;
  CHECK(p->force_N.x() == deflex::test::within(F.x(), 0.02));
  CHECK(p->force_N.y() == deflex::test::within(F.y(), 0.02));
  CHECK(p->force_N.z() == deflex::test::within(F.z(), 0.05));
  // The force acts at mid depth of the engaged flank.
  CHECK(p->height_mm == deflex::test::within(5.0, 0.02));
  auto C = stiffness::beam_compliance(tool, f.ph.machine, false);
  V3 delta = C.at(5.0) * V3(F.x(), F.y(), F.z());
  CHECK((p->delta_mm - delta).norm() < 0.02 * delta.norm());
  // Up-milling: the radial force pushes the tool off the wall (-Y) and the
  // wall's normal points to -Y, so the error is an undercut (> 0).
  CHECK(p->normal.y() == doctest::Approx(-1.0));
  CHECK(p->delta_mm.dot(p->normal) > 0.0);
  CHECK(p->delta_mm.dot(p->normal) == deflex::test::within(-delta.y(), 0.02));
  // A flank cut: the error is the mid-range of the wall profile e(z), which
  // spans the mean-force value (the tool bends most at the top of the cut... or
  // the generating forces differ from the mean: only bracket it loosely).
  CHECK(p->flank);
  CHECK(p->flank_min_mm <= p->error_mm);
  CHECK(p->error_mm <= p->flank_max_mm);
  CHECK(p->error_mm == doctest::Approx(0.5 * (p->flank_min_mm + p->flank_max_mm)));
  CHECK(p->flank_z_min_mm >= 0.0);
  CHECK(p->flank_z_max_mm <= 10.0 + f.s.slice_mm);
}

TEST_CASE("gain 0 changes nothing: offsets zero, the program byte-identical") {
  Fixture f;
  f.s.gain = 0.0;
  auto r = compensate::compensate(f.motions, f.ph, f.s);
  for (const V3& o : r.offsets) CHECK(o.norm() == 0.0);
  CHECK(compensate::apply_offsets(f.prog, f.opt.dialect, f.motions, r.offsets) == kWall);
}

TEST_CASE("mirror fixed point: the deflected tool lands on the programmed wall") {
  Fixture f;
  auto r = compensate::compensate(f.motions, f.ph, f.s);
  CHECK(r.converged);
  CHECK(r.compensated_points >= 2);
  std::size_t checked = 0;
  for (const auto& p : r.final) {
    // End points of fully engaged moves: commanded offset + deflection at the
    // compensated position is (nearly) zero along the normal.
    if (p.index != p.count || p.air || p.ap_mm < 9.9 || r.offsets[p.motion].norm() == 0) continue;
    const double residual = compensate::landing_error(p, r.offsets[p.motion]);
    CHECK(std::fabs(residual) <= 0.01 * f.s.tolerance_mm + 1e-9);
    // ...and the as-written error there (the nominal point at the programmed
    // position, the compensated one less its offset) was outside the tolerance.
    const V3 programmed = p.tip_mm - r.offsets[p.motion];
    const compensate::Point* written = nullptr;
    for (const auto& q : r.nominal)
      if (!written || (q.tip_mm - programmed).norm() < (written->tip_mm - programmed).norm()) written = &q;
    REQUIRE(written != nullptr);
    CHECK((written->tip_mm - programmed).norm() < 1e-9);
    CHECK(std::fabs(written->error_mm) > f.s.tolerance_mm);
    ++checked;
  }
  CHECK(checked >= 2);
  // Offsets point into the wall (+Y) and stay under the cap.
  for (const V3& o : r.offsets) {
    CHECK(o.norm() <= f.s.max_offset_mm + 1e-12);
    CHECK(o.y() >= 0.0);
  }
  // A stiffer setup (tool only: no holder, spindle or machine) deflects less.
  Fixture g;
  g.ph.tool_only = true;
  auto rg = compensate::compensate(g.motions, g.ph, g.s);
  double a = 0, b = 0;
  for (const V3& o : r.offsets) a = std::max(a, o.norm());
  for (const V3& o : rg.offsets) b = std::max(b, o.norm());
  CHECK(b < a);
}

TEST_CASE("one causal pass is the fixed point: a fresh simulation of its output lands every compensated point") {
  // A ball-end raster (the sample tool T5, D16) over a wave in a box: the first
  // row cuts 2-4 mm deep and deflects 0.2-0.3 mm, the next rows see the stock
  // the compensated rows before them left. The pass chooses each end point with
  // the motions before it already compensated; simulating its output from
  // scratch must reproduce its points, and every compensated end point must sit
  // at the mirror fixed point (or at the cap, the step bound, or astride a jump
  // of the force model narrower than 1% of the tolerance).
  std::string text = "%\nO0002\nN1 G21 G90 G17 G40 G49 G80 G54\nN2 T5 M06\nN3 S8000 M03\nN4 G00 X0. Y0. Z5.\nN5 G01 Z-1. F2500.\n";
  int n = 6;
  for (int r = 0; r < 3; ++r) {
    const double y = 0.25 * r;
    text += "N" + std::to_string(n++) + " Y" + std::to_string(y) + "\n";
    for (int i = 1; i <= 40; ++i) {
      const double x = r % 2 == 0 ? 0.4 * i : 16.0 - 0.4 * i;
      const double z = -1.0 - 2.0 * std::sin(x / 15.0) * std::cos(y / 20.0);
      text += "N" + std::to_string(n++) + " X" + std::to_string(x) + " Z" + std::to_string(z) + "\n";
    }
  }
  text += "N" + std::to_string(n) + " G00 Z5.\nN" + std::to_string(n + 1) + " M30\n%\n";
  Fixture f;
  const test::Interpreted in = test::interpret_text(text);
  REQUIRE(in.errors == 0);
  const std::vector<interp::Motion>& motions = in.motions;
  stock::ZMap box = stock::make_stock("box:-10,-10,-10,30,10,1.3", {});
  f.ph.stock = &box;
  f.s.tolerance_mm = 0.005;
  auto r = compensate::compensate(motions, f.ph, f.s);
  CHECK(r.converged);
  REQUIRE(r.compensated_points > 20);
  // As written, the first row is far outside the tolerance.
  double before = 0;
  for (const auto& p : r.nominal)
    if (!p.air) before = std::max(before, std::fabs(p.error_mm));
  CHECK(before > 2 * f.s.tolerance_mm);
  const auto again = compensate::simulate(r.motions, r.offsets, f.ph, f.s);
  REQUIRE(again.size() == r.final.size());
  std::size_t at_fixed_point = 0;
  for (std::size_t i = 0; i < again.size(); ++i) {
    const auto &a = again[i], &b = r.final[i];
    REQUIRE(a.motion == b.motion);
    CHECK((a.delta_mm - b.delta_mm).norm() <= 1e-9);
    CHECK((a.normal - b.normal).norm() <= 1e-12);
    if (a.index != a.count || a.air || r.offsets[a.motion].norm() == 0) continue;
    const double residual = compensate::landing_error(a, r.offsets[a.motion]);
    CHECK(std::fabs(residual) <= f.s.tolerance_mm);
    if (std::fabs(residual) <= 0.01 * f.s.tolerance_mm) ++at_fixed_point;
  }
  // Almost all of them exactly there (the rest astride a force-model jump or at the step bound).
  CHECK(at_fixed_point >= r.compensated_points * 9 / 10);
}

TEST_CASE("split moves: the entry and exit of a long wall pass land inside the tolerance") {
  Fixture f;
  const std::vector<bool> split_ok = compensate::splittable(f.prog, f.motions);
  auto plain = compensate::compensate(f.motions, f.ph, f.s);
  auto r = compensate::compensate(f.motions, f.ph, f.s, {}, &split_ok);
  REQUIRE(r.split_points > 0);
  REQUIRE(r.motions.size() == f.motions.size() + r.split_points);
  // Landing error against the design intent at every engaged sample:
  // commanded offset (ramped along the move) + deflection, along the normal.
  auto worst = [](const compensate::Result& res) {
    double w = 0;
    for (const auto& p : res.final) {
      if (p.air || p.plunge) continue;
      const V3 end = res.offsets[p.motion], start = p.motion ? res.offsets[p.motion - 1] : V3(V3::Zero());
      const double u = static_cast<double>(p.index) / p.count;
      w = std::max(w, std::fabs(compensate::landing_error(p, start + u * (end - start))));
    }
    return w;
  };
  CHECK(worst(plain) > f.s.tolerance_mm);  // without splitting the entry ramp leaves it
  CHECK(worst(r) <= f.s.tolerance_mm);
  // Written, read back and checked: inserted blocks are plain G1 X Y Z lines on the move.
  compensate::WriteStats ws;
  std::string out = compensate::apply_offsets(f.prog, f.opt.dialect, r.motions, r.offsets, &ws, &r.inserted);
  CHECK(ws.blocks_inserted == r.split_points);
  CHECK_NOTHROW(compensate::safety_check(f.prog, r.motions, out, f.opt, compensate::movable(r.motions), 0.1, &r.inserted));
  // An inserted block pushed off its move is caught.
  std::string bad = out;
  std::size_t at = bad.find("G1 X");
  REQUIRE(at != std::string::npos);
  bad.replace(bad.find("Y", at), 2, "Y5");
  CHECK_THROWS_AS(compensate::safety_check(f.prog, r.motions, bad, f.opt, compensate::movable(r.motions), 0.1, &r.inserted),
                  Error);
}

TEST_CASE("split moves: none where the offset stands at its cap (a vertex there would change nothing)") {
  // The side-wall sample's pass (the D12 flat T6 of the sample library
  // 12 mm deep, a_e 2.5 mm): the wall deflects 0.17 mm, over the cap of
  // 0.1 mm, so along the middle of the pass the offset stands at the cap and
  // the straight ramp between two capped vertices lands every sample as well
  // as a vertex would. Vertices go where the offset changes: its ramps into
  // and out of the cap, max_step_mm at a time.
  const char* kDeep =
      "%\nO0002\nN1 G21 G90 G17 G40 G49 G80 G54\nN2 T6 M06\nN3 S6366 M03\nN4 G00 X-10. Y3.5 Z5.\n"
      "N5 G01 Z-12. F2546.4\nN6 X110.\nN7 G00 Z5.\nN8 M30\n%\n";
  Fixture f;
  gcode::Program prog{SourceText("deep.nc", kDeep)};
  const test::Interpreted in = test::interpret_text(kDeep);
  REQUIRE(in.errors == 0);
  stock::ZMap box = stock::make_stock("box:0,-40,-30,100,0,0", {});
  f.ph.stock = &box;
  f.s.tolerance_mm = 0.01;
  f.s.max_splits_per_move = 1000;  // no budget: only the placement rule limits them
  const std::vector<bool> split_ok = compensate::splittable(prog, in.motions);
  const auto r = compensate::compensate(in.motions, f.ph, f.s, {}, &split_ok);
  double largest_mm = 0;
  for (const V3& o : r.offsets) largest_mm = std::max(largest_mm, o.norm());
  REQUIRE(largest_mm > 0.9 * f.s.max_offset_mm);
  // Inserted vertices whose offset equals both neighbours' (flat: nothing changes there).
  std::size_t flat = 0;
  for (std::size_t i = 1; i + 1 < r.motions.size(); ++i)
    if (r.inserted[i] && (r.offsets[i] - r.offsets[i - 1]).norm() < 1e-12 &&
        (r.offsets[i + 1] - r.offsets[i]).norm() < 1e-12)
      ++flat;
  MESSAGE("capped pass: ", r.split_points, " vertices inserted, ", flat, " of them flat");
  // At most one ramp's worth flat at each end of the capped stretch (placed
  // before the ramp had climbed); a vertex at every sample of the capped
  // 100 mm (200 samples) is what a rule blind to the cap writes.
  const auto ramp = static_cast<std::size_t>(std::ceil(f.s.max_offset_mm / f.s.max_step_mm));
  CHECK(flat <= 2 * ramp);
  CHECK(r.split_points <= 6 * ramp);
}

TEST_CASE("an arc whose compensation varies is linearised: G1 chords, the arc block keeps the last piece") {
  // Along the wall of the fixture, an arc bulging 2 mm away from it: a_e falls
  // from 2 mm at its ends to nothing in the middle, so moving it whole by one
  // offset cannot land both.
  const char* kArc =
      "%\nO0003\nN1 G21 G90 G17 G40 G49 G80 G54\nN2 T1 M06\nN3 S8000 M03\nN4 G00 X-10. Y-3. Z5.\n"
      "N5 G01 Z-10. F800.\nN6 X20.\nN7 G3 X50. Y-3. I15. J57.25\nN8 G1 X80.\nN9 X110.\nN10 G00 Z5.\nN11 M30\n%\n";
  Fixture f;
  gcode::Program prog{SourceText("arc.nc", kArc)};
  const test::Interpreted in = test::interpret_text(kArc);
  REQUIRE(in.errors == 0);
  const std::vector<interp::Motion>& motions = in.motions;
  const std::vector<bool> split_ok = compensate::splittable(prog, motions);
  std::size_t arc = 0;
  while (motions[arc].kind != interp::MotionKind::arc_ccw) ++arc;
  REQUIRE(split_ok[arc]);
  const std::uint32_t arc_line = motions[arc].line;
  auto landing = [&](const compensate::Result& res, bool arcs_only) {
    double w = 0;
    for (const auto& p : res.final) {
      if (p.air || p.plunge || (arcs_only && p.line != arc_line)) continue;
      const V3 end = res.offsets[p.motion], start = p.motion ? res.offsets[p.motion - 1] : V3(V3::Zero());
      const double u = static_cast<double>(p.index) / p.count;
      w = std::max(w, std::fabs(compensate::landing_error(p, start + u * (end - start))));
    }
    return w;
  };
  // Not allowed to split: the arc is kept whole, reported, and lands outside.
  std::vector<bool> lines_only = split_ok;
  lines_only[arc] = false;
  auto kept = compensate::compensate(motions, f.ph, f.s, {}, &lines_only);
  REQUIRE(kept.nonuniform_arcs.size() == 1);
  CHECK(kept.nonuniform_arcs[0] == arc_line);
  CHECK(landing(kept, true) > f.s.tolerance_mm);
  // Allowed: chords within the chordal tolerance, every sample inside the tolerance.
  auto r = compensate::compensate(motions, f.ph, f.s, {}, &split_ok);
  CHECK(r.linearised_arcs == 1);
  CHECK(r.nonuniform_arcs.empty());
  CHECK(landing(r, true) <= f.s.tolerance_mm);
  std::size_t chords = 0;
  for (std::size_t i = 0; i < r.motions.size(); ++i)
    if (r.inserted[i] && r.motions[i].line == arc_line) {
      ++chords;
      CHECK(r.motions[i].kind == interp::MotionKind::linear);
    }
  // Sagitta r (1 - cos(dtheta / 2)) <= 1 um on a 57.25 mm radius over 30.3 degrees: 25 chords.
  CHECK(chords >= 20);
  compensate::WriteStats ws;
  std::string out = compensate::apply_offsets(prog, f.opt.dialect, r.motions, r.offsets, &ws, &r.inserted);
  CHECK(ws.blocks_inserted == r.split_points);
  const auto can = compensate::movable(r.motions);
  CHECK_NOTHROW(compensate::safety_check(prog, r.motions, out, f.opt, can, 0.1, &r.inserted));
  // Read back: the arc block is still a G3 whose start and end are on one circle
  // (a control alarms when they are not), about the nominal centre moved by at
  // most the offset.
  const test::Interpreted back = test::interpret_text(out);
  REQUIRE(back.errors == 0);
  const interp::Motion* a = nullptr;
  for (const auto& m : back.motions)
    if (m.kind == interp::MotionKind::arc_ccw) a = &m;
  REQUIRE(a);
  auto radius = [&](const interp::Vec3& p) { return std::hypot(p[0] - a->center_mm[0], p[1] - a->center_mm[1]); };
  CHECK(std::fabs(radius(a->start_mm) - radius(a->end_mm)) <= 2e-4);
  CHECK(std::hypot(a->center_mm[0] - 35.0, a->center_mm[1] - 54.25) <= 0.1);
  CHECK(out.find("G3 X50.") != std::string::npos);
  // A tampered chord (off the arc by 0.5 mm) is caught.
  std::string bad = out;
  const std::size_t at = bad.find("G1 X", bad.find("N6"));
  REQUIRE(at != std::string::npos);
  const std::size_t y = bad.find('Y', at);
  bad.insert(y + 1, "1");
  CHECK_THROWS_AS(compensate::safety_check(prog, r.motions, bad, f.opt, can, 0.1, &r.inserted), Error);
}

TEST_CASE("--feed-limit lowers F where the peak force exceeds the limit, and only there") {
  Fixture f;
  const double limit_N = 250;
  auto nominal = compensate::simulate(f.motions, {}, f.ph, f.s);
  double peak = 0;
  for (const auto& p : nominal) peak = std::max(peak, p.peak_N);
  REQUIRE(peak > limit_N);  // the wall cut exceeds it as written
  f.s.feed_limit_N = limit_N;
  const std::vector<bool> split_ok = compensate::splittable(f.prog, f.motions);
  auto r = compensate::compensate(f.motions, f.ph, f.s, {}, &split_ok);
  REQUIRE_FALSE(r.feed_lowered_lines.empty());
  // At the lowered feeds the peak is at the limit or under it (C35 has no edge
  // terms: the force is proportional to the feed per tooth).
  double after = 0;
  for (const auto& p : r.final) after = std::max(after, p.peak_N);
  CHECK(after <= limit_N * (1 + 1e-6));
  CHECK(after > 0.9 * limit_N);
  for (std::size_t i = 0; i < r.motions.size(); ++i) CHECK(r.feeds_mm_per_min[i] <= 800.0);
  compensate::WriteStats ws;
  std::string out = compensate::apply_offsets(f.prog, f.opt.dialect, r.motions, r.offsets, &ws, &r.inserted,
                                              &r.feeds_mm_per_min);
  CHECK(ws.feeds_changed >= 1);
  const auto can = compensate::movable(r.motions);
  CHECK_NOTHROW(compensate::safety_check(f.prog, r.motions, out, f.opt, can, 0.1, &r.inserted, &r.feeds_mm_per_min));
  // Without the feed plan, the F change is a change in more than coordinates.
  CHECK_THROWS_AS(compensate::safety_check(f.prog, r.motions, out, f.opt, can, 0.1, &r.inserted), Error);
  // A feed written higher than planned is caught.
  std::string bad = out;
  const std::size_t at = bad.find(" F", bad.find("N6"));
  REQUIRE(at != std::string::npos);
  bad.replace(at, 2, " F9");
  CHECK_THROWS_AS(compensate::safety_check(f.prog, r.motions, bad, f.opt, can, 0.1, &r.inserted, &r.feeds_mm_per_min),
                  Error);
}

TEST_CASE("flank cuts: the side-wall sample's wall profile e(z), its mid-range driven to zero") {
  // samples/programs/side_wall.nc: T6 D12 flat end, a_p 12, down-milling along
  // +X, the wall face normal +Y (Morelli 2021 test IIM).
  Fixture f;
  const std::string text = test::read_file("samples/programs/side_wall.nc");
  const test::Interpreted in = test::interpret_text(text);
  REQUIRE(in.errors == 0);
  gcode::Program prog{SourceText("side_wall.nc", text)};
  const std::vector<bool> split_ok = compensate::splittable(prog, in.motions);
  stock::ZMap box = stock::make_stock("box:0,-40,-30,100,0,0", {});
  f.ph.stock = &box;
  f.ph.k = force::find_material(force::load_material_library("samples/materials.yaml"), "Al6082-T4").k;
  f.s.tolerance_mm = 0.01;
  f.s.threads = 0;
  f.s.flank_profiles = true;
  auto r = compensate::compensate(in.motions, f.ph, f.s, {}, &split_ok);
  CHECK(r.converged);
  REQUIRE(r.compensated_points > 0);
  std::size_t flank = 0;
  double worst_written = 0;
  for (const auto& p : r.nominal) {
    if (p.air || p.plunge || !p.flank) continue;
    ++flank;
    // The design normal is the wall's, and agrees with the profile's convention:
    // down-milling generates at the exit, n = wall_normal(pi) = +Y' = +Y here.
    CHECK(p.normal.y() == doctest::Approx(1.0));
    CHECK(p.flank_min_mm <= p.flank_max_mm);
    CHECK(p.error_mm == doctest::Approx(0.5 * (p.flank_min_mm + p.flank_max_mm)));
    REQUIRE_FALSE(p.flank_profile.empty());
    for (const auto& q : p.flank_profile) {
      CHECK(q.error_mm >= p.flank_min_mm - 1e-12);
      CHECK(q.error_mm <= p.flank_max_mm + 1e-12);
      CHECK(q.z_mm <= 12.0 + f.s.slice_mm);
    }
    worst_written = std::max({worst_written, std::fabs(p.flank_min_mm), std::fabs(p.flank_max_mm)});
  }
  REQUIRE(flank > 100);
  CHECK(worst_written > f.s.tolerance_mm);  // as written it is worth compensating
  // Independent path at a steady point (first pass, X 50): the textbook
  // engagement (a_e 2.5, a_p 12, down-milling), the same slicing, and the full
  // cross compliance of force/flank.hpp (feed +X: feed frame = machine axes).
  const compensate::Point* mid = nullptr;
  for (const auto& p : r.nominal)
    if (p.flank && !p.air && std::fabs(p.tip_mm.x() - 50.0) < 0.26 && std::fabs(p.tip_mm.y() - 3.5) < 1e-6) mid = &p;
  REQUIRE(mid != nullptr);
  {
    const auto& tool = stiffness::find_tool(f.ph.tools, "T6");
    const force::Cutter c = force::cutter_of(tool);
    const auto cs = force::make_slices(c, f.s.slice_mm, tool.flute_length_mm);
    force::Engagement e;
    force::simple_engagement(cs, 2.5, 12.0, force::MillingMode::down, e);
    const auto cross = stiffness::beam_cross_compliance(tool, f.ph.machine, false);
    const auto sc = force::slice_compliance(cs, [&](double z, double zp) -> force::Mat3 { return cross.at(z, zp); });
    const double phi = force::generating_phi(force::MillingMode::down);
    const auto prof = force::flank_error_profile({cs, f.ph.k, 0.1, e, phi, force::wall_normal(phi)}, sc);
    CHECK(force::wall_normal(phi).y() == doctest::Approx(1.0));  // the design normal, +Y
    CHECK(mid->flank_min_mm == deflex::test::within(prof.min_mm, 0.03));
    CHECK(mid->flank_max_mm == deflex::test::within(prof.max_mm, 0.03));
    CHECK(mid->flank_z_min_mm == deflex::test::within(prof.z_of_min_mm, 0.05));
    CHECK(mid->flank_z_max_mm == deflex::test::within(prof.z_of_max_mm, 0.05));
  }
  // Re-simulated from scratch, the compensated program: every compensated end
  // point's mid-range inside the tolerance, and no worse band than as written.
  const auto again = compensate::simulate(r.motions, r.offsets, f.ph, f.s);
  REQUIRE(again.size() == r.final.size());
  std::size_t checked = 0;
  for (std::size_t i = 0; i < again.size(); ++i) {
    const auto& a = again[i];
    if (a.air || a.plunge || !a.flank || r.offsets[a.motion].norm() == 0) continue;
    if (a.index != a.count) continue;  // end points: where the mirror solved
    // The same place as written: the nearest flank point of the line.
    const compensate::Point* wp = nullptr;
    for (const auto& q : r.nominal)
      if (q.line == a.line && q.flank && !q.air &&
          (!wp || (q.tip_mm - a.tip_mm).norm() < (wp->tip_mm - a.tip_mm).norm()))
        wp = &q;
    REQUIRE(wp != nullptr);
    REQUIRE((wp->tip_mm - a.tip_mm).norm() < 0.5);
    const auto& w = *wp;
    const double o_n = r.offsets[a.motion].dot(a.normal);
    CHECK(std::fabs(compensate::landing_error(a, r.offsets[a.motion])) <= f.s.tolerance_mm);
    const double band_after = std::max(std::fabs(o_n + a.flank_min_mm), std::fabs(o_n + a.flank_max_mm));
    const double band_written = std::max(std::fabs(w.flank_min_mm), std::fabs(w.flank_max_mm));
    INFO("x " << a.tip_mm.x() << " offset " << o_n << " e(z) " << a.flank_min_mm << ".." << a.flank_max_mm
              << ", as written " << w.flank_min_mm << ".." << w.flank_max_mm);
    // Where the wall was outside the tolerance as written, the band is no
    // wider now; elsewhere (the exit, the offset ramping down under
    // max_step_mm) it stays inside the tolerance.
    if (band_written > f.s.tolerance_mm) {
      CHECK(band_after <= band_written + 1e-9);
      ++checked;
    } else {
      CHECK(band_after <= f.s.tolerance_mm);
    }
  }
  CHECK(checked >= 2);
}

}  // TEST_SUITE
