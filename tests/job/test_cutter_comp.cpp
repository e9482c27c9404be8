// G41/G42 through job::compensate: what deflex compensated is what the
// control will run (each compensated point on the centre path the control
// computes from the written program), and a program under G41 compensates
// as its centre-path equivalent. The centre path itself, against LinuxCNC's
// rs274 and the Fanuc closed form, is in tests/cli/test_cutter_comp.cpp.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support.hpp"

namespace fs = std::filesystem;
using namespace deflex;

namespace {

const char* kG41 = "samples/programs/side_wall_g41.nc";

// The distance from q to motion m (a segment, or an arc of its XY circle
// whose Z runs linearly with the angle), mm.
double distance_to(const interp::Motion& m, const std::array<double, 3>& q) {
  const auto& a = m.start_mm;
  const auto& b = m.end_mm;
  if (m.kind == interp::MotionKind::arc_cw || m.kind == interp::MotionKind::arc_ccw) {
    const double cx = m.center_mm[0], cy = m.center_mm[1];
    const double a0 = std::atan2(a[1] - cy, a[0] - cx), a1 = std::atan2(b[1] - cy, b[0] - cx);
    const double aq = std::atan2(q[1] - cy, q[0] - cx), dir = m.kind == interp::MotionKind::arc_ccw ? 1 : -1;
    auto sweep = [&](double from, double to) {
      double s = dir * (to - from);
      while (s < 0) s += 2 * M_PI;
      while (s >= 2 * M_PI) s -= 2 * M_PI;
      return s;
    };
    const double total = sweep(a0, a1) == 0 ? 2 * M_PI : sweep(a0, a1), at = sweep(a0, aq);
    if (at <= total) {
      const double rad = std::hypot(a[0] - cx, a[1] - cy), z = a[2] + (b[2] - a[2]) * at / total;
      return std::hypot(std::hypot(q[0] - cx, q[1] - cy) - rad, q[2] - z);
    }
    return std::min(std::hypot(std::hypot(q[0] - a[0], q[1] - a[1]), q[2] - a[2]),
                    std::hypot(std::hypot(q[0] - b[0], q[1] - b[1]), q[2] - b[2]));
  }
  double ab2 = 0, t = 0;
  for (int k = 0; k < 3; ++k) ab2 += (b[k] - a[k]) * (b[k] - a[k]), t += (q[k] - a[k]) * (b[k] - a[k]);
  t = ab2 > 0 ? std::clamp(t / ab2, 0.0, 1.0) : 0.0;
  double d2 = 0;
  for (int k = 0; k < 3; ++k) d2 += std::pow(q[k] - (a[k] + t * (b[k] - a[k])), 2);
  return std::sqrt(d2);
}

// Compensates `program` with a report and measures how far each point of the
// report (the commanded centre, offsets applied) lies from the centre path
// the control computes from the written program: what deflex compensated is
// what the control will run.
struct OnPath {
  std::size_t rows = 0;
  double worst_mm = 0;    // but the start-up's points
  double startup_mm = 0;  // the start-up's (the first one's)
  std::string err;
  std::size_t blocks_inserted = 0;
};
OnPath compensated_on_path(const test::TempDir& dir, const std::string& program, const std::string& stock,
                           const std::string& dialect) {
  OnPath r;
  const std::string out = dir / "onpath.nc", rep = dir / "onpath";
  fs::remove_all(rep);
  job::Settings s;
  s.program = program;
  s.stock = stock;
  s.read.dialect = dialect;
  s.output = out;
  s.report_dir = rep;
  const auto c = test::compensate_job(s);
  r.err = c.err;
  REQUIRE_MESSAGE(c.ok(), c.err);
  r.blocks_inserted = c.result->written.blocks_inserted;
  // The control's path: the written program through deflex's interpreter
  // (its centre path equals rs274's, above), with D6 = 6 mm.
  const test::Interpreted control = test::interpret_text(test::read_file(out), dialect, nullptr, false, 6.0);
  REQUIRE_MESSAGE(control.errors == 0, control.diagnostics);
  std::uint32_t startup_line = 0;
  for (const interp::Motion& m : control.motions)
    if (m.comp && m.fixed == interp::Fixed::cutter_comp && !startup_line) startup_line = m.line;
  std::istringstream csv(test::read_file(rep + "/points.csv"));
  std::string row;
  std::getline(csv, row);  // header: line,x_mm,y_mm,z_mm,...
  for (; std::getline(csv, row); ++r.rows) {
    std::istringstream f(row);
    std::string cell;
    std::array<double, 3> q{};
    std::getline(f, cell, ',');
    for (double& v : q) {
      std::getline(f, cell, ',');
      v = std::stod(cell);
    }
    double best = 1e9;
    for (const interp::Motion& m : control.motions) best = std::min(best, distance_to(m, q));
    // The start-up's end is where the control meets the first move, which
    // deflex may have turned a little: it slides along that move.
    const bool startup = std::stoul(row.substr(0, row.find(','))) == startup_line;
    (startup ? r.startup_mm : r.worst_mm) = std::max(startup ? r.startup_mm : r.worst_mm, best);
  }
  return r;
}

// points.csv prints 4 decimals: half a digit on each axis, then 1 um.
const double kCsvRounding = 0.5e-4 * std::sqrt(3.0) + 1e-3;

}  // namespace

TEST_SUITE("job") {
  TEST_CASE("G41 sample: the side wall on its face compensates as its centre-path equivalent") {
    test::TempDir dir("cc41");
    // The equivalent: each G41 start-up and G40 exit as a plain move to the
    // centre point (the face at Y-2.5 / Y-5 plus the radius 6).
    std::string text = test::read_file(kG41);
    const std::vector<std::pair<std::string, std::string>> to_centre = {
        {"N22 G41 D6 X-10. Y-2.5\n", "N22 X-10. Y3.5\n"}, {"N26 G40 X120. Y10. F1000.\n", "N26 X120. Y10. F1000.\n"},
        {"N34 G41 D6 X-10. Y-5.\n", "N34 X-10. Y1.\n"}, {"N38 G40 X120. Y10. F1000.\n", "N38 X120. Y10. F1000.\n"}};
    for (const auto& [from, to] : to_centre) {
      REQUIRE(text.find(from) != std::string::npos);
      text.replace(text.find(from), from.size(), to);
    }
    const std::string g41 = kG41, centre = dir / "centre.nc";
    test::write_file(centre, text);
    CHECK(test::path_text(g41, true) == test::path_text(centre));
    const std::string out41 = dir / "out41.nc", outc = dir / "outc.nc";
    const auto a = test::compensate_side_wall(g41, out41), b = test::compensate_side_wall(centre, outc);
    REQUIRE_MESSAGE(a.ok(), a.err);
    REQUIRE(b.ok());
    // The same program as written: the same predicted errors.
    CHECK(a.result->summary["surface_error_as_written_mm"] == b.result->summary["surface_error_as_written_mm"]);
    CHECK(a.result->figures.error_as_written.points > 0);
    CHECK(a.err.find("[left_alone]") == std::string::npos);
    // What deflex compensated is what the control will run.
    const OnPath on = compensated_on_path(dir, g41, "box:0,-40,-30,100,0,0", "fanuc");
    CHECK(on.rows > 300);
    CHECK(on.worst_mm <= kCsvRounding);
    MESSAGE("G41 sample: " << on.rows << " compensated points, the farthest " << on.worst_mm
                           << " mm from the control's centre path");
    test::check_deflection_physics(test::read_csv(dir / "onpath/points.csv"), 0.01);
    // The D words and the G41 blocks stay as written; the face moved into
    // the material (-Y) in down-milling, as the centre path did, and back out
    // before the pass leaves the stock (the centre's N24 as written); the
    // end's X so that the control's perpendicular to the last part (turned by
    // 0.02 mm over 10.4 mm) lands on X110. The digits are a regression
    // snapshot of deflex's output; the physics is checked on points.csv
    // above, and here the face's deepest offset in the pass is the centre's,
    // into the material (the face at Y-2.5, the centre at Y3.5 as written).
    const std::string written = test::read_file(out41);
    CHECK(written.find("N22 G41 D6 X-10. Y-2.5\n") != std::string::npos);
    CHECK(written.find("N34 G41 D6 X-10. Y-5.\n") != std::string::npos);
    CHECK(written.find("N24 X110.011 Y-2.519 F2546.4\n") != std::string::npos);
    CHECK(test::read_file(outc).find("N24 X110. F2546.4\n") != std::string::npos);
    // The least Y written between N22 and N24 (the first pass).
    auto deepest_y_mm = [](const std::string& program) {
      const std::size_t from = program.find("\nN22 "), to = program.find("\nN24 ");
      REQUIRE(from < to);
      const std::string pass = program.substr(from, to - from);
      double y = std::numeric_limits<double>::infinity();
      const std::regex word(R"(Y(-?[0-9.]+))");
      for (auto it = std::sregex_iterator(pass.begin(), pass.end(), word); it != std::sregex_iterator(); ++it)
        y = std::min(y, std::stod((*it)[1]));
      return y;
    };
    const double face_offset_mm = deepest_y_mm(written) - -2.5,
                 centre_offset_mm = deepest_y_mm(test::read_file(outc)) - 3.5;
    CHECK(face_offset_mm == doctest::Approx(centre_offset_mm));
    CHECK(face_offset_mm < 0);
  }

  TEST_CASE("G41/G42 round a boss with outside corners and an arc: what deflex compensated is what the control runs") {
    // Chords of the centre path only where the compensated contour is a
    // line: the arc's points lie on the control's arc, the corner pieces on
    // the control's corners (arcs on LinuxCNC, the offsets' intersection on
    // Fanuc), in both dialects.
    test::TempDir dir("ccboss");
    const std::string boss = dir / "boss.nc";
    test::write_file(boss, "%\nO7001 (BOSS 60 X 40 - G41 OUTSIDE CONTOUR)\nN10 G21 G90 G17 G40 G49 G80\nN12 T6 M06\n"
                           "N14 G00 G54 X-20. Y-20. S6366 M03\nN16 G43 H6 Z5. M08\nN18 G01 Z-5. F1000.\n"
                           "N20 G41 D6 X0. Y-5.\nN22 Y40. F2546.4\nN24 X50.\nN26 G02 X60. Y30. R10.\nN28 G01 Y0.\n"
                           "N30 X-5.\nN32 G40 X-20. Y-20. F1000.\nN34 G00 Z50.\nN36 M30\n%\n");
    // The same boss the other way round under G42 (up-milling).
    const std::string boss42 = dir / "boss42.nc";
    test::write_file(boss42, "%\nO7002 (BOSS 60 X 40 - G42 OUTSIDE CONTOUR)\nN10 G21 G90 G17 G40 G49 G80\nN12 T6 M06\n"
                             "N14 G00 G54 X-20. Y-20. S6366 M03\nN16 G43 H6 Z5. M08\nN18 G01 Z-5. F1000.\n"
                             "N20 G42 D6 X-5. Y0.\nN22 X60. F2546.4\nN24 Y30.\nN26 G03 X50. Y40. R10.\nN28 G01 X0.\n"
                             "N30 Y-5.\nN32 G40 X-20. Y-20. F1000.\nN34 G00 Z50.\nN36 M30\n%\n");
    for (const auto& [program, dialect] : {std::pair{boss, "fanuc"}, std::pair{boss, "linuxcnc"},
                                            std::pair{boss42, "fanuc"}, std::pair{boss42, "linuxcnc"}}) {
      const std::string what = program + " " + dialect;
      CAPTURE(what);
      const OnPath on = compensated_on_path(dir, program, "box:-2,-2,-10,62,42,0", dialect);
      CHECK(on.rows > 400);
      CHECK(on.blocks_inserted > 0);
      // Exact on the lines and the arc; at a corner, or where a move deflex
      // split meets the start-up, the control's point slides along the path
      // by r times the turn deflex gave a short part, which bends the path
      // there by a few um (9 um at most here, within the 10 um tolerance).
      CHECK(on.worst_mm <= 0.01);
      // The start-up's end slides along the first move the same way: within
      // the offset cap.
      CHECK(on.startup_mm <= 0.1);
      MESSAGE(what << ": " << on.rows << " points, the farthest " << on.worst_mm
                      << " mm from the control's path (the start-up's " << on.startup_mm << " mm)");
    }
  }

  TEST_CASE("G41 in practice: a Z move at a corner, a retract before G40, a hexagon, a corner near the arc threshold") {
    test::TempDir dir("ccz");
    // A Z move at a corner keeps the corner's programmed point: the block
    // stays Z only (where `path` prints the point: tests/cli/test_cutter_comp.cpp).
    const std::string z =
        test::edited_copy(dir, kG41, "z.nc", "N24 X110. F2546.4\n", "N24 X50. F2546.4\nN25 Z-11.\nN27 X110.\n");
    const auto zr = test::compensate_side_wall(z, dir / "z_out.nc");
    REQUIRE_MESSAGE(zr.ok(), zr.err);
    CHECK(test::read_file(dir / "z_out.nc").find("\nN25 Z-11.\n") != std::string::npos);
    // A retract under compensation before G40 comes alone.
    const std::string rt = test::edited_copy(dir, kG41, "rt.nc", "N26 G40 X120. Y10. F1000.\nN28 G00 Z5.\n",
                                             "N26 X120. Y10. F1000.\nN28 G00 Z5.\nN29 G40\n");
    const auto rr = test::compensate_side_wall(rt, dir / "rt_out.nc");
    CHECK_MESSAGE(rr.ok(), rr.err);
    // A corner turning 0.0498 rad: LinuxCNC's arc threshold is 0.05 rad,
    // and compensation may turn it across: the read-back pairs all the same.
    job::Settings k;
    k.program = test::edited_copy(dir, kG41, "k.nc", "N24 X110. F2546.4\n", "N24 X50. F2546.4\nN25 X110. Y-5.4905\n");
    k.read.dialect = "linuxcnc";
    k.stock = "box:0,-40,-30,100,0,0";
    k.output = dir / "k_out.nc";
    const auto kr = test::compensate_job(k);
    CHECK_MESSAGE(kr.ok(), kr.err);
    // A hexagon boss (120 deg corners): the compensated points on the control's path.
    const std::string hex = dir / "hex.nc";
    test::write_file(hex, "%\nN10 G21 G90 G17 G40 G49 G80\nN12 T6 M06\nN14 G00 G54 X-20. Y0. S6366 M03\n"
                          "N16 G43 H6 Z5. M08\nN18 G01 Z-5. F1000.\nN20 G41 D6 X4.999 Y15.000\nG1 X5.000 Y25.000 F2546.4\n"
                          "G1 X17.500 Y46.651\nG1 X42.500 Y46.651\nG1 X55.000 Y25.000\nG1 X42.500 Y3.349\n"
                          "G1 X17.500 Y3.349\nG1 X5.000 Y25.000\nG1 X17.500 Y46.651\nG40 X-20. Y60. F1000.\nG00 Z50.\n"
                          "M30\n%\n");
    for (const std::string dialect : {"fanuc", "linuxcnc"}) {
      CAPTURE(dialect);
      const OnPath on = compensated_on_path(dir, hex, "box:4,2,-10,56,48,0", dialect);
      CHECK(on.worst_mm <= 0.01);  // as round the boss: 2 um on Fanuc, 9 um on LinuxCNC next to its corner arcs
      MESSAGE("hexagon " << dialect << ": " << on.rows << " points, the farthest " << on.worst_mm << " mm");
    }
  }
}
