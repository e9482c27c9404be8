// measure::read_probe_targets and measure::join_probe_log: which point each
// logged position is, and the error there.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdio>

#include "deflex/measure/probe.hpp"
#include "support.hpp"

using namespace deflex;
using deflex::test::check_located;
using deflex::test::error_text;

namespace {

const std::string kProgram =
    "%\nO1000 (PROBE THE TEST CUT)\nG21 G90 G54\n"
    "(DEFLEX PROBE 1 TOP AT 0.000 0.000 0.000 N 0.000 0.000 1.000 BALL 1.000)\nG38.2 Z-5. F100\n"
    "N20 (DEFLEX PROBE 2 WX1 AT 10.000 5.000 -2.250 N 1.000 0.000 0.000 BALL 1.000)\nG38.2 X5. F100\n"
    "(DEFLEX PROBE 3 Wall_2 AT 5.000 10.000 -2.250 N 0.600 0.800 0.000 BALL 0.500)\nG38.2 Y5. F100\nM30\n%\n";

std::vector<measure::ProbeTarget> targets() { return measure::read_probe_targets(kProgram, "probe.nc"); }

std::string targets_error(const std::string& comment) {
  return error_text([&] { measure::read_probe_targets("G0 X0\n" + comment + "\n", "p.nc"); });
}

// A stylus centre that reads error e_mm at target t.
Eigen::Vector3d centre(const measure::ProbeTarget& t, double e_mm) {
  return t.point_mm + (e_mm + t.ball_radius_mm) * t.normal;
}

std::string linuxcnc_line(const Eigen::Vector3d& c) {
  char b[200];
  std::snprintf(b, sizeof b, "%f %f %f %f %f %f %f %f %f\n", c.x(), c.y(), c.z(), 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
  return b;
}

std::string dprnt_line(int id, const Eigen::Vector3d& c) {
  char b[200];  // DPRNT[PT<id>*X#5061[44]*Y#5062[44]*Z#5063[44]], leading zeros as blanks
  std::snprintf(b, sizeof b, "PT%d X%9.4f Y%9.4f Z%9.4f\r\n", id, c.x(), c.y(), c.z());
  return b;
}

const std::vector<double> kErrors = {0.0125, -0.0375, 0.0125};  // mm; exact in 4 decimals along these normals

}  // namespace

TEST_SUITE("measure") {

TEST_CASE("probe targets: the DEFLEX PROBE comments, anywhere on a line, the rest of the program ignored") {
  const auto t = targets();
  REQUIRE(t.size() == 3);
  CHECK(t[1].id == 2);
  CHECK(t[1].feature == "WX1");
  CHECK(t[1].point_mm == Eigen::Vector3d(10.0, 5.0, -2.25));
  CHECK(t[1].normal == Eigen::Vector3d(1, 0, 0));
  CHECK(t[1].ball_radius_mm == 1.0);
  CHECK(t[1].line == 6);
  CHECK(t[2].feature == "Wall_2");
  CHECK(t[2].ball_radius_mm == 0.5);
  CHECK((t[2].normal - Eigen::Vector3d(0.6, 0.8, 0)).norm() < 1e-15);
}

TEST_CASE("probe targets: a normal within 1e-3 of unit length is renormalised, one beyond is an error") {
  const auto t = measure::read_probe_targets(
      "(DEFLEX PROBE 1 A AT 0.000 0.000 0.000 N 0.000 1.0009 0.000 BALL 1.000)\n", "p.nc");
  CHECK(t[0].normal == Eigen::Vector3d(0, 1, 0));
  const std::string bad = "(DEFLEX PROBE 1 A AT 0.000 0.000 0.000 N 0.000 0.500 0.000 BALL 1.000)";
  check_located(targets_error(bad), "p.nc:2:42", "the normal has length 0.5", bad, 42);
}

TEST_CASE("probe targets: malformed comments, ids out of order, no target are located errors") {
  const std::string no_ball = "(DEFLEX PROBE 1 A AT 0.000 0.000 0.000 N 0.000 0.000 1.000)";
  check_located(targets_error(no_ball), "p.nc:2:59", "expected BALL", no_ball, 59);
  const std::string no_point = "(DEFLEX PROBE 1 A AT 10 0.000 0.000 N 0.000 0.000 1.000 BALL 1.000)";
  check_located(targets_error(no_point), "p.nc:2:22", "'10' is not a number with a decimal point", no_point, 22);
  const std::string nan = "(DEFLEX PROBE 1 A AT nan 0.000 0.000 N 0.000 0.000 1.000 BALL 1.000)";
  check_located(targets_error(nan), "p.nc:2:22", "'nan' is not a number", nan, 22);
  const std::string radius = "(DEFLEX PROBE 1 A AT 0.000 0.000 0.000 N 0.000 0.000 1.000 BALL 0.000)";
  check_located(targets_error(radius), "p.nc:2:65", "the ball radius must be > 0", radius, 65);
  const std::string open = "(DEFLEX PROBE 1 A AT 0.000 0.000 0.000";
  check_located(targets_error(open), "p.nc:2:1", "without ')'", open, 1);
  const std::string two = "(DEFLEX PROBE 2 A AT 0.000 0.000 0.000 N 0.000 0.000 1.000 BALL 1.000)";
  check_located(targets_error(two), "p.nc:2:15", "probe point 2 out of order: expected 1", two, 15);
  check_located(error_text([] { measure::read_probe_targets("G0 X0\n", "p.nc"); }), "p.nc:1:1",
                "no (DEFLEX PROBE ...) comment", "G0 X0", 1);
}

TEST_CASE("round trip: a LinuxCNC log written from known errors gives them back") {
  const auto t = targets();
  std::string log;
  for (std::size_t i = 0; i < t.size(); ++i) log += linuxcnc_line(centre(t[i], kErrors[i]));
  const auto m = measure::join_probe_log(t, measure::read_linuxcnc_probe_log(log, "probe.txt"), false, "probe.txt", log);
  REQUIRE(m.size() == 3);
  for (std::size_t i = 0; i < m.size(); ++i) {
    CHECK(std::abs(m[i].error_mm - kErrors[i]) < 1e-9);
    CHECK((m[i].surface_mm - (t[i].point_mm + kErrors[i] * t[i].normal)).norm() < 1e-9);
    CHECK(m[i].id == t[i].id);
    CHECK(m[i].line == i + 1);
  }
  CHECK(m[2].feature == "Wall_2");
}

TEST_CASE("round trip: DPRNT output in another order gives the errors back by id") {
  const auto t = targets();
  const std::string text = "%\r\n" + dprnt_line(3, centre(t[2], kErrors[2])) + dprnt_line(1, centre(t[0], kErrors[0])) +
                           dprnt_line(2, centre(t[1], kErrors[1])) + "%\r\n";
  const auto m = measure::join_probe_log(t, measure::read_dprnt(text, "dprnt.txt"), true, "dprnt.txt", text);
  REQUIRE(m.size() == 3);
  for (std::size_t i = 0; i < m.size(); ++i) {
    CHECK(m[i].id == static_cast<int>(i + 1));
    CHECK(std::abs(m[i].error_mm - kErrors[i]) < 1e-9);
  }
  CHECK(m[0].line == 3);  // PT1 is the log's third line
}

TEST_CASE("join: a log with a line fewer or more than the probe program") {
  const auto t = targets();
  const std::string two = linuxcnc_line(centre(t[0], 0)) + linuxcnc_line(centre(t[1], 0));
  const auto join = [&](const std::string& log) {
    return error_text([&] { measure::join_probe_log(t, measure::read_linuxcnc_probe_log(log, "l.txt"), false, "l.txt", log); });
  };
  check_located(join(two), "l.txt:2:1", "the log has 2 probe positions, the probe program 3 points: 1 missing",
                linuxcnc_line(centre(t[1], 0)).substr(0, linuxcnc_line(centre(t[1], 0)).size() - 1), 1);
  const std::string four = two + linuxcnc_line(centre(t[2], 0)) + linuxcnc_line(centre(t[2], 0));
  const std::string extra = linuxcnc_line(centre(t[2], 0)).substr(0, linuxcnc_line(centre(t[2], 0)).size() - 1);
  check_located(join(four), "l.txt:4:1", "the log has 4 probe positions, the probe program 3 points", extra, 1);
}

TEST_CASE("join: DPRNT with an id not in the probe program, or a point never printed") {
  const auto t = targets();
  const auto join = [&](const std::string& text) {
    return error_text([&] { measure::join_probe_log(t, measure::read_dprnt(text, "d.txt"), true, "d.txt", text); });
  };
  const std::string ok1 = dprnt_line(1, centre(t[0], 0)), ok2 = dprnt_line(2, centre(t[1], 0)),
                    ok3 = dprnt_line(3, centre(t[2], 0)), nine = dprnt_line(9, centre(t[2], 0));
  check_located(join(ok1 + nine + ok2 + ok3), "d.txt:2:1", "point 9 is not in the probe program (its points are 1 to 3)",
                nine.substr(0, nine.size() - 2), 1);
  CHECK(join(ok1 + ok3) == "d.txt: error: 1 of the probe program's 3 points never printed: 2");
}

TEST_CASE("join: an error beyond the limit names the likely cause") {
  const auto t = targets();
  std::string inch, offset;
  for (std::size_t i = 0; i < t.size(); ++i) {
    inch += linuxcnc_line(centre(t[i], 0.01) / 25.4);
    offset += linuxcnc_line(centre(t[i], 0.01) + Eigen::Vector3d(0, 0, 10));
  }
  const auto join = [&](const std::string& log, double limit_mm) {
    return error_text([&] {
      measure::join_probe_log(t, measure::read_linuxcnc_probe_log(log, "l.txt"), false, "l.txt", log, limit_mm);
    });
  };
  // Point 1 (at the origin, 1 mm ball) reads -0.96 mm in inches: within the limit. Point 2 is the first beyond.
  check_located(join(inch, 2.0), "l.txt:2:1", "the log reads right in inches", test::lines_of(inch)[1], 1);
  check_located(join(offset, 2.0), "l.txt:1:1", "wrong work offset", test::lines_of(offset)[0], 1);
  CHECK(join(offset, 2.0).find("probe point 1 (TOP) is 10.010 mm off the intended surface") != std::string::npos);
  CHECK(join(offset, 20.0).empty());  // a larger limit lets it pass
  CHECK(!error_text([&] { measure::join_probe_log(t, {}, false, "l.txt", "", 0.0); }, ErrorKind::settings).empty());
}

}  // TEST_SUITE
