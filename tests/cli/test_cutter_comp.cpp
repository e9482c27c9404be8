// G41/G42: the tool-centre path the control computes,
// against LinuxCNC's rs274 (which computes cutter compensation itself), and
// the Fanuc corners against their closed form. What compensate makes of
// programs under G41/G42 is in tests/job/test_cutter_comp.cpp.
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

TEST_SUITE("cli") {
  TEST_CASE("G41: a Z move at a corner keeps the corner's programmed point; --centre prints the tool's") {
    test::TempDir dir("ccz");
    const std::string z = test::edited_copy(dir, "samples/programs/side_wall_g41.nc", "z.nc", "N24 X110. F2546.4\n",
                                            "N24 X50. F2546.4\nN25 Z-11.\nN27 X110.\n");
    CHECK(test::run_cli({"path", "--lines", z}).out.find("15 G1 50.000000 -2.500000 -11.000000\n") != std::string::npos);
    CHECK(test::run_cli({"path", "--lines", "--centre", z}).out.find("15 G1 50.000000 3.500000 -11.000000\n") !=
          std::string::npos);
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
