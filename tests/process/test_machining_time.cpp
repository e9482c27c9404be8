// Machining time against hand computations. Unless a case says otherwise the
// machine is `hand()`: every axis 1000 mm/s^2, max feed 1000 mm/s, rapids
// 100 mm/s, corner tolerance 0.1 mm; so a move from rest to rest over L at
// cruise v (ramps fitting) takes L/v + v/a.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "../support.hpp"
#include "deflex/process/machining_time.hpp"

using namespace deflex;
using process::machining_time;
using doctest::Approx;

namespace {

profile::AxisLimits hand() {
  profile::AxisLimits k;
  k.max_feed_mm_per_min = {60000, 60000, 60000};
  k.rapid_mm_per_min = {6000, 6000, 6000};
  k.acceleration_mm_per_s2 = {1000, 1000, 1000};
  k.corner_tolerance_mm = 0.1;
  return k;
}

interp::Motion g1(interp::Vec3 a, interp::Vec3 b, double f_mm_per_min, int tool = 1) {
  interp::Motion m = test::linear_motion(a, b, f_mm_per_min);
  m.tool = tool;
  return m;
}

interp::Motion g0(interp::Vec3 a, interp::Vec3 b, int tool = 1) {
  interp::Motion m = g1(a, b, 0, tool);
  m.kind = interp::MotionKind::rapid;
  m.fixed = interp::Fixed::rapid;
  return m;
}

interp::Motion arc(interp::Vec3 a, interp::Vec3 b, interp::Vec3 c, bool ccw, double f_mm_per_min, int plane = 17) {
  interp::Motion m = g1(a, b, f_mm_per_min);
  m.kind = ccw ? interp::MotionKind::arc_ccw : interp::MotionKind::arc_cw;
  m.center_mm = c;
  m.plane = static_cast<std::uint8_t>(plane);
  return m;
}

double total_s(const std::vector<interp::Motion>& ms, const profile::AxisLimits& k = hand(),
               const std::vector<double>& feeds = {}) {
  return machining_time(ms, k, feeds).program.total_s;
}

// Rest to rest over L at cruise v, acceleration a, ramps fitting.
double rest_to_rest_s(double L, double v, double a) { return L / v + v / a; }

// From v0 up to cruise v, down to v1, over L (both ramps fitting).
double leg_s(double L, double v0, double v, double v1, double a) {
  return (v - v0) / a + (v - v1) / a + (L - (2 * v * v - v0 * v0 - v1 * v1) / (2 * a)) / v;
}

}  // namespace

TEST_SUITE("process") {

TEST_CASE("a single long move reaches its feed: t = L/v + v/a") {
  // 100 mm at F3000 (50 mm/s), a = 1000: ramps of 1.25 mm each, 2.05 s.
  const auto r = machining_time({g1({0, 0, 0}, {100, 0, 0}, 3000)}, hand());
  CHECK(r.program.total_s == Approx(2.05).epsilon(1e-12));
  CHECK(r.program.cutting_s == Approx(2.05).epsilon(1e-12));
  CHECK(r.program.rapid_s == 0.0);
  CHECK(r.program.cutting_mm == Approx(100));
  CHECK(r.motion_s.size() == 1);
  CHECK(r.motion_s[0] == Approx(2.05).epsilon(1e-12));
}

TEST_CASE("a short move never reaches its feed: triangular, t = 2 sqrt(L/a)") {
  // 1 mm at 100 mm/s would need 10 mm of ramps: peak sqrt(a L) = 31.6 mm/s.
  CHECK(total_s({g1({0, 0, 0}, {1, 0, 0}, 6000)}) == Approx(2 * std::sqrt(1.0 / 1000)).epsilon(1e-12));
  CHECK(process::segment_time_s(1, 0, 0, 100, 1000) == Approx(0.0632455532).epsilon(1e-9));
}

TEST_CASE("segment_time_s: cruise only, and one ramp taking the whole length") {
  CHECK(process::segment_time_s(10, 50, 50, 50, 1000) == Approx(0.2));
  // 0 -> 100 mm/s over exactly 5 mm at 1000 mm/s^2: 0.1 s, no cruise.
  CHECK(process::segment_time_s(5, 0, 100, 100, 1000) == Approx(0.1));
  CHECK(process::segment_time_s(0, 0, 0, 100, 1000) == 0.0);
}

TEST_CASE("collinear consecutive moves do not slow down") {
  std::vector<interp::Motion> ms;
  for (int i = 0; i < 4; ++i) ms.push_back(g1({25.0 * i, 0, 0}, {25.0 * (i + 1), 0, 0}, 3000));
  CHECK(total_s(ms) == Approx(2.05).epsilon(1e-12));
  // A zero-length block between them changes nothing.
  ms.insert(ms.begin() + 2, g1({50, 0, 0}, {50, 0, 0}, 3000));
  const auto r = machining_time(ms, hand());
  CHECK(r.program.total_s == Approx(2.05).epsilon(1e-12));
  CHECK(r.motion_s[2] == 0.0);
}

TEST_CASE("a 90-degree corner: junction speed sqrt(a tol (1 + sqrt 2)), time by hand") {
  // Blend radius tol sin45 / (1 - sin45) = tol (1 + sqrt 2) = 0.2414 mm;
  // corner speed sqrt(1000 * 0.2414) = 15.54 mm/s, under the 100 mm/s feed.
  const double a = 1000, v = 100, L = 100;
  const double vc = std::sqrt(a * 0.1 * (1 + std::numbers::sqrt2));
  CHECK(process::corner_speed_mm_per_s({1, 0, 0}, {0, 1, 0}, a, 0.1) == Approx(vc).epsilon(1e-12));
  // Each leg: 0 -> v (5 mm), cruise, v -> vc (4.88 mm); the second mirrors it.
  const double leg = v / a + (v - vc) / a + (L - v * v / (2 * a) - (v * v - vc * vc) / (2 * a)) / v;
  CHECK(leg == Approx(1.0856686).epsilon(1e-6));
  CHECK(leg_s(L, 0, v, vc, a) == Approx(leg).epsilon(1e-12));
  const std::vector<interp::Motion> ms = {g1({0, 0, 0}, {100, 0, 0}, 6000), g1({100, 0, 0}, {100, 100, 0}, 6000)};
  CHECK(total_s(ms) == Approx(2 * leg).epsilon(1e-12));
  // Between a full stop and no corner at all.
  CHECK(total_s(ms) < 2 * rest_to_rest_s(L, v, a));
  CHECK(total_s(ms) > rest_to_rest_s(2 * L, v, a));
  // Z takes no part in an XY corner: a sluggish Z changes nothing.
  profile::AxisLimits slow_z = hand();
  slow_z.acceleration_mm_per_s2[2] = 1;
  CHECK(total_s(ms, slow_z) == Approx(2 * leg).epsilon(1e-12));
  // A larger tolerance rounds more and runs faster.
  profile::AxisLimits loose = hand();
  loose.corner_tolerance_mm = 1;
  CHECK(total_s(ms, loose) < total_s(ms));
}

TEST_CASE("corner speed: straight on is unlimited, a reversal stops") {
  CHECK(std::isinf(process::corner_speed_mm_per_s({1, 0, 0}, {1, 0, 0}, 1000, 0.1)));
  CHECK(process::corner_speed_mm_per_s({1, 0, 0}, {-1, 0, 0}, 1000, 0.1) == 0.0);
  // Going back along the same line: two rest-to-rest moves.
  const std::vector<interp::Motion> ms = {g1({0, 0, 0}, {100, 0, 0}, 3000), g1({100, 0, 0}, {0, 0, 0}, 3000)};
  CHECK(total_s(ms) == Approx(2 * 2.05).epsilon(1e-12));
}

TEST_CASE("an arc at its centripetal limit: L / sqrt(a r) plus the ramps") {
  // Full circle r = 10 at F60000: sqrt(1000 * 10) = 100 mm/s caps it.
  const double L = 2 * std::numbers::pi * 10;
  const auto fast = arc({10, 0, 0}, {10, 0, 0}, {0, 0, 0}, true, 60000);
  CHECK(total_s({fast}) == Approx(rest_to_rest_s(L, 100, 1000)).epsilon(1e-12));  // 0.7283 s
  CHECK(machining_time({fast}, hand()).program.cutting_mm == Approx(L).epsilon(1e-12));
  // Below the limit the feed rules: F3000 = 50 mm/s.
  const auto slow = arc({10, 0, 0}, {10, 0, 0}, {0, 0, 0}, false, 3000);
  CHECK(total_s({slow}) == Approx(rest_to_rest_s(L, 50, 1000)).epsilon(1e-12));
  // G18 (ZX plane): the slower of Z and X sets both the centripetal limit,
  // sqrt(250 * 10) = 50 mm/s, and the ramps.
  profile::AxisLimits slow_z = hand();
  slow_z.acceleration_mm_per_s2[2] = 250;
  const auto zx = arc({10, 0, 0}, {10, 0, 0}, {0, 0, 0}, true, 60000, 18);
  CHECK(total_s({zx}, slow_z) == Approx(rest_to_rest_s(L, 50, 250)).epsilon(1e-12));
  // ... while an XY arc does not care about Z.
  CHECK(total_s({fast}, slow_z) == Approx(rest_to_rest_s(L, 100, 1000)).epsilon(1e-12));
}

TEST_CASE("a helix: true length, centripetal limit on the in-plane speed") {
  // Full turn r = 10, rise 20*pi: length sqrt(2) * 20 pi, in-plane share 1/sqrt(2).
  // In-plane speed capped at 100 mm/s -> path 141.4 mm/s; path accel capped by
  // the plane (1000 sqrt 2) and by Z (1000 sqrt 2) alike.
  const double rise = 20 * std::numbers::pi, L = std::numbers::sqrt2 * rise;
  const auto h = arc({10, 0, 0}, {10, 0, rise}, {0, 0, 0}, true, 60000);
  const double v = 100 * std::numbers::sqrt2, a = 1000 * std::numbers::sqrt2;
  CHECK(total_s({h}) == Approx(rest_to_rest_s(L, v, a)).epsilon(1e-12));
}

TEST_CASE("a line into a tangent arc keeps its speed") {
  // +X into a CCW quarter about (10, 10): tangent +X at its start; 50 mm/s is
  // under the arc's 100 mm/s limit, so it is one move of 10 + 5 pi mm.
  const std::vector<interp::Motion> ms = {g1({0, 0, 0}, {10, 0, 0}, 3000),
                                          arc({10, 0, 0}, {20, 10, 0}, {10, 10, 0}, true, 3000)};
  CHECK(total_s(ms) == Approx(rest_to_rest_s(10 + 5 * std::numbers::pi, 50, 1000)).epsilon(1e-12));
}

TEST_CASE("axis limits are projected: a 45-degree XY move runs at sqrt(2) x the axis limit") {
  // Max feed 3000 mm/min (50 mm/s) per axis, F10000 asks for more: each axis
  // runs at its own limit, the path at 50 sqrt(2) mm/s, accelerating at
  // 1000 sqrt(2): the diagonal takes what one axis alone takes, 2.05 s.
  profile::AxisLimits k = hand();
  k.max_feed_mm_per_min = {3000, 3000, 3000};
  CHECK(process::along({50, 50, 50}, {std::numbers::sqrt2 / 2, std::numbers::sqrt2 / 2, 0}) ==
        Approx(50 * std::numbers::sqrt2));
  CHECK(total_s({g1({0, 0, 0}, {100, 100, 0}, 10000)}, k) == Approx(2.05).epsilon(1e-12));
  CHECK(total_s({g1({0, 0, 0}, {100, 0, 0}, 10000)}, k) == Approx(2.05).epsilon(1e-12));
  // A slow Z: a 45-degree XZ ramp is held by Z alone (10 mm/s -> 14.1 on the path).
  k.max_feed_mm_per_min[2] = 600;
  const double v = 10 * std::numbers::sqrt2;
  CHECK(total_s({g1({0, 0, 0}, {100, 0, -100}, 10000)}, k) ==
        Approx(rest_to_rest_s(100 * std::numbers::sqrt2, v, 1000 * std::numbers::sqrt2)).epsilon(1e-12));
}

TEST_CASE("the feed override vector replaces F of cutting motions, not of rapids") {
  const std::vector<interp::Motion> ms = {g0({0, 0, 50}, {0, 0, 0}), g1({0, 0, 0}, {100, 0, 0}, 3000)};
  const double rapid_s = rest_to_rest_s(50, 100, 1000);  // 0.6 s
  CHECK(total_s(ms) == Approx(rapid_s + 2.05).epsilon(1e-12));
  // Halved: 100/25 + 25/1000 = 4.025 s; doubled: 100/100 + 0.1 = 1.1 s.
  CHECK(total_s(ms, hand(), {0, 1500}) == Approx(rapid_s + 4.025).epsilon(1e-12));
  CHECK(total_s(ms, hand(), {99999, 6000}) == Approx(rapid_s + 1.1).epsilon(1e-12));
  CHECK_THROWS_AS(total_s(ms, hand(), {0}), Error);
  CHECK_THROWS_AS(total_s(ms, hand(), {0, 0}), Error);
}

TEST_CASE("rapids run at the rapid rate and stop at both ends") {
  // G0 100 mm at 100 mm/s: 1 + 0.1 s, whatever the feed of the motion.
  const auto r = machining_time({g0({0, 0, 0}, {100, 0, 0})}, hand());
  CHECK(r.program.rapid_s == Approx(1.1).epsilon(1e-12));
  CHECK(r.program.rapid_mm == Approx(100));
  CHECK(r.program.cutting_s == 0.0);
  // G1 then a collinear G0: exact stop between them (1.05 s + 0.6 s) ...
  const std::vector<interp::Motion> mixed = {g1({0, 0, 0}, {50, 0, 0}, 3000), g0({50, 0, 0}, {100, 0, 0})};
  CHECK(total_s(mixed) == Approx(rest_to_rest_s(50, 50, 1000) + rest_to_rest_s(50, 100, 1000)).epsilon(1e-12));
  // ... as between two collinear rapids.
  const std::vector<interp::Motion> two = {g0({0, 0, 0}, {50, 0, 0}), g0({50, 0, 0}, {100, 0, 0})};
  CHECK(total_s(two) == Approx(2 * rest_to_rest_s(50, 100, 1000)).epsilon(1e-12));
  // Projected like feeds: a slow Z rapid (3000 mm/min) holds a 45-degree XZ rapid.
  profile::AxisLimits k = hand();
  k.rapid_mm_per_min[2] = 3000;
  CHECK(total_s({g0({0, 0, 0}, {50, 0, 50})}, k) ==
        Approx(rest_to_rest_s(50 * std::numbers::sqrt2, 50 * std::numbers::sqrt2, 1000 * std::numbers::sqrt2))
            .epsilon(1e-12));
}

TEST_CASE("per tool: the split sums to the program, a tool change is a stop") {
  const std::vector<interp::Motion> ms = {
      g0({0, 0, 50}, {0, 0, 0}, 1), g1({0, 0, 0}, {100, 0, 0}, 3000, 1),
      g1({100, 0, 0}, {200, 0, 0}, 3000, 2),  // collinear, but the tool changed
      g0({200, 0, 0}, {200, 0, 50}, 2)};
  const auto r = machining_time(ms, hand());
  REQUIRE(r.per_tool.size() == 2);
  const auto& t1 = r.per_tool.at(1);
  const auto& t2 = r.per_tool.at(2);
  CHECK(t1.total_s == Approx(0.6 + 2.05).epsilon(1e-12));
  CHECK(t2.total_s == Approx(2.05 + 0.6).epsilon(1e-12));
  CHECK(t1.cutting_mm == Approx(100));
  CHECK(t2.rapid_mm == Approx(50));
  CHECK(t1.total_s + t2.total_s == Approx(r.program.total_s).epsilon(1e-12));
  CHECK(t1.cutting_s + t2.cutting_s == Approx(r.program.cutting_s).epsilon(1e-12));
  CHECK(t1.rapid_mm + t2.rapid_mm == Approx(r.program.rapid_mm).epsilon(1e-12));
  double sum = 0;
  for (double t : r.motion_s) sum += t;
  CHECK(sum == Approx(r.program.total_s).epsilon(1e-12));
}

TEST_CASE("from G-code: per tool and the default limits") {
  const auto p = test::interpret_text(
      "G21 G90 G17 G54\nT1 M6\nS8000 M3\nG0 X0 Y0 Z5.\nG1 Z0. F600.\nG1 X100. F3000.\nG0 Z5.\n"
      "T2 M6\nS8000 M3\nG0 X0.\nG1 Z0. F600.\nG1 Y50. F3000.\nG0 Z5.\nM30\n");
  REQUIRE(p.errors == 0);
  const profile::AxisLimits k;  // defaults: 2000 mm/s^2, rapids 500 / 500 / 400 mm/s, tolerance 0.01 mm
  const auto r = machining_time(p.motions, k);
  REQUIRE(r.per_tool.size() == 2);
  // The plunge (10 mm/s) turns 90 degrees into the cut (50 mm/s) through the
  // corner speed sqrt(2000 * 0.01 * (1 + sqrt 2)) = 6.95 mm/s.
  const double a = 2000, vc = std::sqrt(a * 0.01 * (1 + std::numbers::sqrt2));
  const double plunge_s = leg_s(5, 0, 10, vc, a);
  CHECK(r.per_tool.at(1).cutting_s == Approx(plunge_s + leg_s(100, vc, 50, 0, a)).epsilon(1e-12));
  CHECK(r.per_tool.at(2).cutting_s == Approx(plunge_s + leg_s(50, vc, 50, 0, a)).epsilon(1e-12));
  // T2's rapids: X100 -> X0 never reaches 500 mm/s (it needs 125 mm of
  // ramps), nor Z0 -> Z5 its 400 mm/s: two triangles.
  CHECK(r.per_tool.at(2).rapid_s == Approx(2 * std::sqrt(100 / a) + 2 * std::sqrt(5 / a)).epsilon(1e-12));
  CHECK(r.program.total_s == Approx(r.per_tool.at(1).total_s + r.per_tool.at(2).total_s).epsilon(1e-12));
}

TEST_CASE("one million motions in one pass: the look-ahead carries the speed through all of them") {
  // Collinear 0.1 mm moves: the look-ahead must carry the speed through all of
  // them, so the whole is one 100 km move at 50 mm/s. (Its speed is a
  // benchmark's to show, not a test's: bench/.)
  const std::size_t n = 1000000;
  std::vector<interp::Motion> ms(n, g1({0, 0, 0}, {0, 0, 0}, 3000));
  for (std::size_t i = 0; i < n; ++i) {
    ms[i].start_mm[0] = 0.1 * static_cast<double>(i);
    ms[i].end_mm[0] = 0.1 * static_cast<double>(i + 1);
  }
  const auto r = machining_time(ms, hand());
  CHECK(r.program.total_s == Approx(rest_to_rest_s(100000, 50, 1000)).epsilon(1e-9));
}

TEST_CASE("a ramp over many look-ahead batches: the clock settles only what no later stop can slow") {
  // 40 mm along X in 40,000 collinear pieces of 1 um at 600 mm/s: the braking
  // ramp (v^2 / 2a = 180 mm would not fit; the peak is sqrt(a L) = 200 mm/s)
  // spans all of them, far more than a batch of the clock; the time is the
  // triangle's, 2 sqrt(L/a), as for one move. Then three such runs with stops
  // between (rapids), fed one motion at a time in pieces of odd sizes.
  const int n = 40000;
  std::vector<interp::Motion> ms;
  for (int i = 0; i < n; ++i) ms.push_back(g1({i * 1e-3, 0, 0}, {(i + 1) * 1e-3, 0, 0}, 36000));
  const double want = 2 * std::sqrt(40.0 / 1000);
  CHECK(machining_time(ms, hand()).program.total_s == Approx(want).epsilon(1e-9));
  std::vector<interp::Motion> three;
  for (int r = 0; r < 3; ++r) {
    three.insert(three.end(), ms.begin(), ms.end());
    three.push_back(g0({40, 0, 0}, {0, 0, 0}));
  }
  const process::MachiningTime whole = machining_time(three, hand());
  const double rapid = 40.0 / 100 + 100.0 / 1000;  // L/v + v/a at the rapid limit
  CHECK(whole.program.total_s == Approx(3 * (want + rapid)).epsilon(1e-9));
  process::MachiningClock clock(hand());
  for (const interp::Motion& m : three) clock.add(m);
  const process::MachiningTime fed = clock.finish();
  CHECK(fed.program.total_s == whole.program.total_s);
  CHECK(fed.program.cutting_mm == whole.program.cutting_mm);
  CHECK(fed.per_tool.at(1).cutting_s == whole.per_tool.at(1).cutting_s);
}

}  // TEST_SUITE
