// G41/G42: the tool-centre path the control computes,
// against LinuxCNC's rs274 (which computes cutter compensation itself), and
// the Fanuc corners against their closed form.
#include <doctest/doctest.h>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "../support.hpp"

namespace fs = std::filesystem;
using namespace deflex;

namespace {

struct Point {
  std::string kind;
  std::array<double, 3> p;
};

// rs274's canonical moves of `program` with tool 6 of diameter 12 mm. Its
// standalone tool table is in inches whatever the program's units (D0.5
// gives a radius of 6.35 mm on a G21 program), hence 12 / 25.4.
std::vector<Point> rs274_moves(const fs::path& dir, const std::string& program) {
  const fs::path prog = dir / "p.ngc", tbl = dir / "tools.tbl", out = dir / "out.txt";
  test::write_file(prog.string(), program);
  test::write_file(tbl.string(), "T6 P6 D0.472440945 ;\n");
  const std::string cmd = "/usr/bin/rs274 -t " + tbl.string() + " -g " + prog.string() + " " + out.string() +
                          " </dev/null >/dev/null 2>&1";
  REQUIRE(std::system(cmd.c_str()) == 0);
  std::vector<Point> v;
  const std::regex call(R"((STRAIGHT_TRAVERSE|STRAIGHT_FEED|ARC_FEED)\((.*)\))");
  std::istringstream in(test::read_file(out.string()));
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (!std::regex_search(line, m, call)) continue;
    std::vector<double> x;
    std::istringstream as(m[2].str());
    for (std::string t; std::getline(as, t, ',');) x.push_back(std::stod(t));
    if (m[1] == "ARC_FEED") v.push_back({x[4] < 0 ? "G2" : "G3", {x[0], x[1], x[5]}});
    else v.push_back({m[1] == "STRAIGHT_TRAVERSE" ? "G0" : "G1", {x[0], x[1], x[2]}});
  }
  return v;
}

// Both start at 0,0,0; rs274 prints zero-length moves on tool changes.
std::vector<Point> moving(const std::vector<Point>& v) {
  std::vector<Point> out;
  std::array<double, 3> last{0, 0, 0};
  for (const Point& p : v) {
    if (p.p != last) out.push_back(p);
    last = p.p;
  }
  return out;
}

const char* kHead = "G21 G90 G17 G40\nT6 M6\n";

// Contours with every kind of corner: the names say what each shows.
const std::vector<std::pair<const char*, const char*>> kContours = {
    {"G41 outside the square: entry on an outside corner (arc), inside corners",
     "G0 X-20 Y-20\nG0 Z-5\nG41 G1 X0 Y0 F500\nG1 X50\nG1 Y30\nG1 X0\nG1 Y0\nG40 G1 X-20 Y-20\nM2\n"},
    {"G41 lines and arcs: outside corners (arcs), line-arc and arc-line corners, Z move under compensation",
     "G0 X-20 Y-20\nG0 Z-5\nG41 G1 X0 Y0 F500\nG1 Y30\nG1 X40\nG2 X50 Y20 I0 J-10\nG1 Y0\nG1 X30\n"
     "G3 X20 Y10 I-10 J0\nG1 X0 Y0.5\nG1 Z-4\nG1 X-5 Y-10\nG40 G1 X-20 Y-20\nM2\n"},
    {"G41 small turns (below 0.05 rad no arc and no intersection), a G0 under compensation",
     "G0 X-20 Y0 Z-5\nG41 G1 X0 Y0 F500\nG1 X20 Y0.01\nG1 X40 Y0.03\nG1 X60 Y0.15\nG1 X80 Y0.6\nG1 Z-4\n"
     "G1 X80 Y40\nG0 X40\nG1 X40 Y80\nG40 G1 X0 Y100\nM2\n"},
    {"G41 small outside turns, 2.86 deg (no arc) then 2.87 deg (arc)",
     "G0 X-20 Y0 Z-5\nG41 G1 X0 Y0 F500\nG1 X20 Y-0.0001\nG1 X40 Y-0.001\nG1 X60 Y-0.01\nG1 X80 Y-0.1\n"
     "G1 X100 Y-1\nG1 X120 Y-1.998902\nG1 X140 Y-3.00109\nG40 G1 X160 Y-20\nM2\n"},
    {"G40 alone, then a Z move that leaves the offset",
     "G0 X-20 Y0 Z-5\nG41 G1 X0 Y0 F500\nG1 X20 Y0\nG1 Z-4\nG1 X20 Y-20\nG40\nG1 Z0\nG1 X40 Y-40\nM2\n"},
    {"G42 round a profile of arcs (tangent, S-bends, inside and outside), then G41 with an arc turning back",
     "G0 X-30 Y-30 Z10\nG0 Z-5\nG42 G1 X0 Y-10 F500\nG1 X0 Y40\nG2 X20 Y60 I20 J0\nG1 X60\nG2 X80 Y40 I0 J-20\n"
     "G1 Y20\nG3 X100 Y0 I20 J0\nG1 X120\nG2 X120 Y-40 I0 J-20\nG1 X40\nG2 X20 Y-20 I0 J20\nG3 X0 Y0 I-20 J0\n"
     "G1 X-10 Y20\nG40 G1 X-30 Y30\nG0 Z10\nG41 G1 X10 Y10\nG1 X50 Y10\nG1 X50 Y50\nG3 X10 Y50 I-20 J0\n"
     "G1 X10 Y10\nG2 X30 Y30 R20\nG1 X40 Y12\nG40 G1 X60 Y60\nM2\n"},
    {"G42 pocket, inside arcs and a full circle",
     "G0 X50 Y50 Z5\nG1 Z-3 F300\nG42 G1 X50 Y20 F500\nG1 X80\nG3 X90 Y30 R10\nG1 Y70\nG3 X80 Y80 I-10 J0\nG1 X20\n"
     "G3 X10 Y70 I0 J-10\nG1 Y30\nG3 X20 Y20 I10 J0\nG1 X50\nG3 X50 Y20 I0 J30\nG40 G1 X50 Y50\nM2\n"},
};

}  // namespace

TEST_SUITE("cli") {
  TEST_CASE("G41/G42: the tool-centre path equals LinuxCNC's rs274 within 1 um") {
    REQUIRE_MESSAGE(fs::exists("/usr/bin/rs274"), "rs274 missing: run scripts/install-deps.sh --test");
    const fs::path dir = fs::temp_directory_path() / ("deflex-cc-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    for (const auto& [name, body] : kContours) {
      const std::string what = name;
      CAPTURE(what);
      const std::string program = std::string(kHead) + body;
      const std::vector<Point> theirs = moving(rs274_moves(dir, program));
      const test::Interpreted ours = test::interpret_text(program, "linuxcnc", nullptr, false, 6.0);
      REQUIRE_MESSAGE(ours.errors == 0, ours.diagnostics);
      std::vector<Point> mine;
      for (const interp::Motion& m : ours.motions) mine.push_back({interp::to_string(m.kind), m.end_mm});
      mine = moving(mine);
      REQUIRE(mine.size() == theirs.size());
      // rs274 prints 4 decimals: half a last digit, then 1 um.
      double worst = 0;
      for (std::size_t i = 0; i < mine.size(); ++i) {
        CHECK(mine[i].kind == theirs[i].kind);
        for (int k = 0; k < 3; ++k) worst = std::max(worst, std::fabs(mine[i].p[k] - theirs[i].p[k]));
      }
      CHECK(worst <= 0.5e-4 + 1e-3);
      MESSAGE(what << ": " << mine.size() << " moves, worst " << worst << " mm");
    }
    fs::remove_all(dir);
  }

  TEST_CASE("G41/G42: what the control alarms on stops with an error at its line") {
    struct Case { const char* body; const char* message; };
    const Case cases[] = {
        {"G0 X-20 Y0 Z-5\nG41 G1 X0 Y0 F500\nG1 X20\nG1 Y3\nG1 X40\nG40 G1 X60 Y-20\nM2\n",
         "t.nc:7:1: error: cutter compensation gouge: the tool centre path of the move at line 6 runs backwards"},
        {"G0 X-20 Y0 Z-5\nG41 G1 X0 Y0 F500\nG1 X20\nG3 X25 Y5 R5\nG40 G1 X60 Y-20\nM2\n",
         "t.nc:6:1: error: the tool radius 6.0000 mm is not less than the arc radius 5.0000 mm"},
        {"G0 X-2 Y0 Z-5\nG41 G1 X0 Y0 F500\nG1 X20\nG40 G1 X60 Y-20\nM2\n",
         "t.nc:4:1: error: the cutter compensation start-up move (2.0000 mm) is not longer than the tool radius"},
        {"G0 X-20 Y0 Z-5\nG41 G2 X0 Y20 R20 F500\nG40 G1 X60 Y-20\nM2\n",
         "t.nc:4:1: error: cutter compensation starts on an arc"},
        {"G0 X-20 Y0 Z-5\nG41 G1 X0 Y0 F500\nG28 Z0\nM2\n", "t.nc:5:1: error: G28/G30 under cutter compensation"},
        {"G0 X-20 Y0 Z-5\nG41 G1 X0 Y0 F500\nG18\nM2\n", "error: a plane change under cutter compensation"},
        {"G18 G0 X-20 Y0 Z-5\nG41 G1 X0 F500\nM2\n", "error: cutter compensation in G18 is not interpreted"},
        {"G0 X-20 Y0 Z-5\nG41 G1 X0 Y0 F500\nG1 X20\nG42 G1 X40\nM2\n", "error: a change of side or radius"},
    };
    for (const Case& c : cases) {
      CAPTURE(c.body);
      const test::Interpreted r = test::interpret_text(std::string(kHead) + c.body, "linuxcnc", nullptr, false, 6.0);
      CHECK(r.errors == 1);
      CHECK_MESSAGE(r.diagnostics.find(c.message) != std::string::npos, r.diagnostics);
    }
  }

  TEST_CASE("G41 on Fanuc: type A start-up and outside corners at the offsets' intersection (closed form)") {
    // G41 round the outside of a 50 x 30 rectangle, clockwise, r = 6: the
    // start-up ends perpendicular to the first side; each 90 deg outside
    // corner is the intersection of the offset sides, r beyond it on both
    // axes; the 120 deg turn at the last corner (acute) goes round by two points.
    const std::string program = std::string(kHead) +
                                "G0 X-20. Y-20. Z-5.\nG41 D6 G1 X0. Y0. F500.\nG1 Y30.\nG1 X50.\nG1 Y0.\n"
                                "G1 X0.\nG1 X10. Y17.320508\nG40 G1 X-20. Y40.\nM30\n";
    const test::Interpreted r = test::interpret_text(program, "fanuc", nullptr, false, 6.0);
    REQUIRE_MESSAGE(r.errors == 0, r.diagnostics);
    std::vector<std::array<double, 3>> e;
    for (const interp::Motion& m : r.motions) e.push_back(m.end_mm);
    REQUIRE(e.size() == 9);
    auto near = [](const std::array<double, 3>& a, double x, double y) {
      return std::fabs(a[0] - x) < 1e-6 && std::fabs(a[1] - y) < 1e-6;  // 17.320508 is 10 tan 60 deg to 8e-8
    };
    CHECK(near(e[1], -6, 0));    // start-up: perpendicular to the side along +Y
    CHECK(near(e[2], -6, 36));   // outside corner (0, 30)
    CHECK(near(e[3], 56, 36));   // (50, 30)
    CHECK(near(e[4], 56, -6));   // (50, 0)
    // Corner (0, 0) turning from -X to 60 deg: 120 deg, acute: the bottom
    // side goes on r past the corner, then a line to r before the next side.
    const double c60 = 0.5, s60 = std::sqrt(3.0) / 2;
    CHECK(near(e[5], -6, -6));
    CHECK(near(e[6], -s60 * 6 - c60 * 6, c60 * 6 - s60 * 6));
    CHECK(near(e[7], 10 - s60 * 6, 17.320508 + c60 * 6));  // the next side's perpendicular end (G40 follows)
    CHECK(r.motions[6].corner);
    CHECK(near(e[8], -20, 40));
  }

  TEST_CASE("G41/G42 radius: the machine profile's tool_offsets (radius + wear) before the tool library") {
    const fs::path dir = fs::temp_directory_path() / ("deflex-ccr-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string prog = (dir / "c.nc").string();
    test::write_file(prog, "%\nO1\nG21 G90 G17 G40 G49 G80\nT6 M06\nG0 G54 X-20. Y-20. S5000 M3\nG43 H6 Z5.\n"
                           "G1 Z-5. F300.\nG41 D6 G1 X0. Y0.\nG1 Y30.\nG1 X50.\nG40 G1 X70. Y50.\nG0 Z50.\nM30\n%\n");
    // The tool library's T6 is a flat D12: r 6.
    test::CliResult lib = test::run_cli({"path", prog, "--centre", "--lines"});
    REQUIRE(lib.rc == 0);
    CHECK(lib.out.find("8 G1 -6.000000 0.000000 -5.000000\n") != std::string::npos);
    CHECK(lib.out.find("10 G1 50.000000 36.000000 -5.000000\n") != std::string::npos);
    // Without --centre: the program's own points.
    test::CliResult plain = test::run_cli({"path", prog, "--lines"});
    CHECK(plain.out.find("10 G1 50.000000 30.000000 -5.000000\n") != std::string::npos);
    // A profile with D6 = 5.98 mm radius, wear -0.01: 5.97 mm.
    std::string mill3 = test::read_file("samples/machines/mill3.yaml");
    mill3 += "tool_offsets:\n  6: {radius_mm: 5.98, wear_mm: -0.01}\n";
    const std::string machine = (dir / "m.yaml").string();
    test::write_file(machine, mill3);
    test::CliResult reg = test::run_cli({"path", prog, "--centre", "--lines", "--machine", machine});
    REQUIRE(reg.rc == 0);
    CHECK(reg.out.find("10 G1 50.000000 35.970000 -5.000000\n") != std::string::npos);
    // A D register neither knows: an error naming both.
    std::string d9 = test::read_file(prog);
    d9.replace(d9.find("D6"), 2, "D99");
    test::write_file(prog, d9);
    test::CliResult none = test::run_cli({"path", prog, "--centre"});
    CHECK(none.rc == 1);
    CHECK(none.err.find("D99: no radius for cutter compensation (no tool_offsets entry 99 in the machine profile "
                        "and no tool T99 in the tool library)") != std::string::npos);
    fs::remove_all(dir);
  }
}

namespace {


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

// Compensates `program` with --report and measures how far each point of the
// report (the commanded centre, offsets applied) lies from the centre path
// the control computes from the written program: what deflex compensated is
// what the control will run.
struct OnPath {
  std::size_t rows = 0;
  double worst_mm = 0;    // but the start-up's points
  double startup_mm = 0;  // the start-up's (the first one's)
  std::string err;
};
OnPath compensated_on_path(const fs::path& dir, const std::string& program, const std::string& stock,
                           const std::string& dialect) {
  OnPath r;
  const std::string out = (dir / "onpath.nc").string(), rep = (dir / "onpath").string();
  fs::remove_all(rep);
  const test::CliResult c =
      test::run_cli({"compensate", program, "--stock", stock, "--dialect", dialect, "-o", out, "--report", rep});
  r.err = c.err;
  REQUIRE_MESSAGE(c.rc == 0, c.err);
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

TEST_SUITE("cli") {
  TEST_CASE("G41 sample: the side wall on its face compensates as its centre-path equivalent") {
    const fs::path dir = fs::temp_directory_path() / ("deflex-cc41-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    // The equivalent: each G41 start-up and G40 exit as a plain move to the
    // centre point (the face at Y-2.5 / Y-5 plus the radius 6).
    std::string text = test::read_file("samples/programs/side_wall_g41.nc");
    const std::vector<std::pair<std::string, std::string>> to_centre = {
        {"N22 G41 D6 X-10. Y-2.5\n", "N22 X-10. Y3.5\n"}, {"N26 G40 X120. Y10. F1000.\n", "N26 X120. Y10. F1000.\n"},
        {"N34 G41 D6 X-10. Y-5.\n", "N34 X-10. Y1.\n"}, {"N38 G40 X120. Y10. F1000.\n", "N38 X120. Y10. F1000.\n"}};
    for (const auto& [from, to] : to_centre) {
      REQUIRE(text.find(from) != std::string::npos);
      text.replace(text.find(from), from.size(), to);
    }
    const std::string g41 = "samples/programs/side_wall_g41.nc", centre = (dir / "centre.nc").string();
    test::write_file(centre, text);
    CHECK(test::run_cli({"path", "--centre", g41}).out == test::run_cli({"path", centre}).out);
    const std::string out41 = (dir / "out41.nc").string(), outc = (dir / "outc.nc").string();
    auto compensate = [&](const std::string& in, const std::string& out) {
      return test::run_cli({"compensate", in, "--stock", "box:0,-40,-30,100,0,0", "-o", out});
    };
    const test::CliResult a = compensate(g41, out41), b = compensate(centre, outc);
    REQUIRE_MESSAGE(a.rc == 0, a.err);
    REQUIRE(b.rc == 0);
    // The same program as written: the same predicted errors.
    auto as_written = [](const std::string& err) {
      const std::size_t at = err.find("  predicted error, as written");
      return err.substr(at, err.find('\n', at) - at);
    };
    CHECK(as_written(a.err) == as_written(b.err));
    CHECK(a.err.find("[left_alone]") == std::string::npos);
    // What deflex compensated is what the control will run.
    const OnPath on = compensated_on_path(dir, g41, "box:0,-40,-30,100,0,0", "fanuc");
    CHECK(on.rows > 300);
    CHECK(on.worst_mm <= kCsvRounding);
    MESSAGE("G41 sample: " << on.rows << " compensated points, the farthest " << on.worst_mm
                           << " mm from the control's centre path");
    test::check_deflection_physics(test::read_csv((dir / "onpath/points.csv").string()), 0.01);
    // The D words and the G41 blocks stay as written; the face moved into
    // the material (-Y) in down-milling, as the centre path did (Y3.421 at
    // its end); the end's X so that the control's perpendicular to the last
    // part (turned by 0.02 mm over 14.9 mm) lands on X110. The digits are a
    // regression snapshot of deflex's output; the physics is checked on
    // points.csv above, and here the face's offset is the centre's, into the
    // material (the face at Y-2.5, the centre at Y3.5 as written).
    const std::string written = test::read_file(out41);
    CHECK(written.find("N22 G41 D6 X-10. Y-2.5\n") != std::string::npos);
    CHECK(written.find("N34 G41 D6 X-10. Y-5.\n") != std::string::npos);
    CHECK(written.find("N24 X110.008 Y-2.579 F2546.4\n") != std::string::npos);
    CHECK(test::read_file(outc).find("N24 X110. Y3.421 F2546.4\n") != std::string::npos);
    auto end_y_mm = [](const std::string& program) {
      std::smatch m;
      REQUIRE(std::regex_search(program, m, std::regex(R"(\nN24 X[0-9.]+ Y(-?[0-9.]+) )")));
      return std::stod(m[1]);
    };
    const double face_offset_mm = end_y_mm(written) - -2.5, centre_offset_mm = end_y_mm(test::read_file(outc)) - 3.5;
    CHECK(face_offset_mm == doctest::Approx(centre_offset_mm));
    CHECK(face_offset_mm < 0);
    fs::remove_all(dir);
  }
}

TEST_SUITE("cli") {
  TEST_CASE("G41/G42 round a boss with outside corners and an arc: what deflex compensated is what the control runs") {
    // Chords of the centre path only where the compensated contour is a
    // line: the arc's points lie on the control's arc, the corner pieces on
    // the control's corners (arcs on LinuxCNC, the offsets' intersection on
    // Fanuc), in both dialects.
    const fs::path dir = fs::temp_directory_path() / ("deflex-ccboss-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string boss = (dir / "boss.nc").string();
    test::write_file(boss, "%\nO7001 (BOSS 60 X 40 - G41 OUTSIDE CONTOUR)\nN10 G21 G90 G17 G40 G49 G80\nN12 T6 M06\n"
                           "N14 G00 G54 X-20. Y-20. S6366 M03\nN16 G43 H6 Z5. M08\nN18 G01 Z-5. F1000.\n"
                           "N20 G41 D6 X0. Y-5.\nN22 Y40. F2546.4\nN24 X50.\nN26 G02 X60. Y30. R10.\nN28 G01 Y0.\n"
                           "N30 X-5.\nN32 G40 X-20. Y-20. F1000.\nN34 G00 Z50.\nN36 M30\n%\n");
    // The same boss the other way round under G42 (up-milling).
    const std::string boss42 = (dir / "boss42.nc").string();
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
      CHECK(on.err.find("blocks inserted") != std::string::npos);
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
    fs::remove_all(dir);
  }
}

TEST_SUITE("cli") {
  TEST_CASE("G41 in practice: a Z move at a corner, a retract before G40, a hexagon, a corner near the arc threshold") {
    const fs::path dir = fs::temp_directory_path() / ("deflex-ccz-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string sample = test::read_file("samples/programs/side_wall_g41.nc");
    auto edited = [&](const std::string& name, const std::string& from, const std::string& to) {
      std::string t = sample;
      REQUIRE(t.find(from) != std::string::npos);
      t.replace(t.find(from), from.size(), to);
      const std::string path = (dir / name).string();
      test::write_file(path, t);
      return path;
    };
    // A Z move at a corner keeps the corner's programmed point: the block
    // stays Z only, `path` prints the contour's point, `--centre` the tool's.
    const std::string z = edited("z.nc", "N24 X110. F2546.4\n", "N24 X50. F2546.4\nN25 Z-11.\nN27 X110.\n");
    CHECK(test::run_cli({"path", "--lines", z}).out.find("15 G1 50.000000 -2.500000 -11.000000\n") != std::string::npos);
    CHECK(test::run_cli({"path", "--lines", "--centre", z}).out.find("15 G1 50.000000 3.500000 -11.000000\n") !=
          std::string::npos);
    const std::string zo = (dir / "z_out.nc").string();
    const test::CliResult zr = test::run_cli({"compensate", z, "--stock", "box:0,-40,-30,100,0,0", "-o", zo});
    REQUIRE_MESSAGE(zr.rc == 0, zr.err);
    CHECK(test::read_file(zo).find("\nN25 Z-11.\n") != std::string::npos);
    // A retract under compensation before G40 comes alone.
    const std::string rt = edited("rt.nc", "N26 G40 X120. Y10. F1000.\nN28 G00 Z5.\n",
                                  "N26 X120. Y10. F1000.\nN28 G00 Z5.\nN29 G40\n");
    const test::CliResult rr =
        test::run_cli({"compensate", rt, "--stock", "box:0,-40,-30,100,0,0", "-o", (dir / "rt_out.nc").string()});
    CHECK_MESSAGE(rr.rc == 0, rr.err);
    // A corner turning 0.0498 rad: LinuxCNC's arc threshold is 0.05 rad,
    // and compensation may turn it across: the read-back pairs all the same.
    const std::string k = edited("k.nc", "N24 X110. F2546.4\n", "N24 X50. F2546.4\nN25 X110. Y-5.4905\n");
    const test::CliResult kr = test::run_cli(
        {"compensate", k, "--dialect", "linuxcnc", "--stock", "box:0,-40,-30,100,0,0", "-o", (dir / "k_out.nc").string()});
    CHECK_MESSAGE(kr.rc == 0, kr.err);
    // A hexagon boss (120 deg corners): the compensated points on the control's path.
    const std::string hex = (dir / "hex.nc").string();
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
    fs::remove_all(dir);
  }

  TEST_CASE("G41: a D change under compensation, nearly concentric arcs") {
    const test::Interpreted d = test::interpret_text(
        std::string(kHead) + "G0 X-20 Y0 Z-5\nG41 D6 G1 X0 Y0 F500\nG1 X50\nG1 Y30 D1\nG40 G1 X0 Y50\nM2\n",
        "linuxcnc", nullptr, false, 6.0);
    CHECK(d.diagnostics.find("t.nc:6:8: error: a change of D under cutter compensation is not interpreted") !=
          std::string::npos);
    // A bore of quarter arcs, one written 1 um off its neighbour's circle:
    // the offsets of two nearly concentric arcs cross far away; the corner
    // is a tangent, and the centre path the exact bore's within 1 um.
    auto bore = [&](const char* j) {
      return test::interpret_text(std::string(kHead) + "G0 X50 Y50 Z-5\nG41 G1 X50 Y30 F500\nG3 X70 Y50 I0 J20\n"
                                                       "G3 X50 Y70 I-20 J0\nG3 X30 Y50 I0 " + j + "\nG3 X50 Y30 I20 J0\n"
                                                       "G40 G1 X50 Y50\nM2\n",
                                  "linuxcnc", nullptr, false, 6.0);
    };
    const test::Interpreted a = bore("J-20"), b = bore("J-20.001");
    REQUIRE(a.errors == 0);
    REQUIRE(b.errors == 0);
    REQUIRE(a.motions.size() == b.motions.size());
    for (std::size_t i = 0; i < a.motions.size(); ++i)
      for (int k = 0; k < 3; ++k) CHECK(std::fabs(a.motions[i].end_mm[k] - b.motions[i].end_mm[k]) < 2e-3);
  }
}
