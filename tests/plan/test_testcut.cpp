// The calibration test cut's plan (plan/testcut.hpp): the features' depths
// and geometry, the block check, the program's lines, the plan YAML and its
// located errors. The program read back and simulated is in
// tests/job/test_testcut.cpp.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <sstream>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/plan/testcut.hpp"
#include "deflex/profile/profile.hpp"
#include "../support.hpp"
#include "support.hpp"

using namespace deflex;

namespace {

using test::error_of;
using test::flat10;
const plan::TestBlock kBlock = test::kTestBlock;

// The lines of `text` (1-based: lines[0] is empty).
std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> v{""};
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) v.push_back(l);
  return v;
}

}  // namespace

TEST_SUITE("plan") {
  TEST_CASE("testcut: every a_e x a_p on each face, a_p against the axial pitch, walls down-milled on the right of the feed") {
    const plan::TestCutter t = flat10();
    const plan::TestCutPlan p = plan::plan_testcut(kBlock, t, {});
    // pi D / (N tan 30 deg) = 13.603 mm: 0.4 and 1.25 of it (single flute, overlap).
    const double pitch = std::numbers::pi * 10 / (4 * std::tan(std::numbers::pi / 6));
    CHECK(plan::axial_pitch_mm(t) == doctest::Approx(pitch));
    REQUIRE(p.features.size() == 12);
    int x = 0, y = 0;
    for (const plan::WallFeature& f : p.features) {
      CAPTURE(f.id);
      const int k = f.feed_axis == 0 ? x++ : y++;
      CHECK(f.id == std::string("W") + (f.feed_axis == 0 ? "X" : "Y") + std::to_string(k + 1));
      CHECK(f.ae_mm == doctest::Approx(std::vector<double>{1, 2.5, 5}[k % 3]));
      CHECK(f.ap_mm == deflex::test::within((k < 3 ? 0.4 : 1.25) * pitch, 1e-3));
      CHECK(f.z1_mm == 0);
      CHECK(f.z0_mm == doctest::Approx(-f.ap_mm));
      CHECK(f.u1_mm - f.u0_mm == doctest::Approx(6));
      // Material on the right of the feed: the normal is the feed turned left.
      CHECK(f.normal[0] == -f.feed_direction[1]);
      CHECK(f.normal[1] == f.feed_direction[0]);
      // The wall plane a_e inside its face.
      if (f.feed_axis == 0) CHECK(f.point_mm[1] == doctest::Approx(200 - f.ae_mm));
      else CHECK(f.point_mm[0] == doctest::Approx(f.ae_mm));
      // The path: down outside the block, in, along, out, all at the floor.
      REQUIRE(f.path.size() == 6);
      const int in = 1 - f.feed_axis;
      const double face = f.feed_axis == 0 ? 200 : 0, R = 5;
      CHECK(std::abs(f.path[1][in] - face) >= R + 1);
      CHECK(f.path[1][2] == doctest::Approx(-f.ap_mm));
      CHECK(std::abs(f.path[2][in] - f.point_mm[in]) == doctest::Approx(R));
      // The probe region one radius in from each end of the segment.
      CHECK(f.u0_mm == doctest::Approx(f.path[2][f.feed_axis] + R));
      CHECK(f.u1_mm == doctest::Approx(f.path[3][f.feed_axis] - R));
    }
    CHECK(p.features[0].morelli == "I");  // a_e 0.1 D below the pitch: one flute at a time
    CHECK(p.features[3].morelli.size() > 2);  // above it: overlapping flutes
    // No cut reaches another's wall: the reaches along a face are apart, and
    // the back face's cuts stay clear of the left face's strip.
    for (std::size_t i = 0; i + 1 < p.features.size(); ++i) {
      const plan::WallFeature &a = p.features[i], &b = p.features[i + 1];
      if (a.feed_axis != b.feed_axis) continue;
      CHECK(b.path[2][b.feed_axis] - 5 - (a.path[3][a.feed_axis] + 5) >= 3 - 1e-9);
    }
    CHECK(p.features[0].path[2][0] - 5 >= 0 + 5 + 3 - 1e-9);
  }

  TEST_CASE("testcut: the depths asked for, every a_e at every a_p on both faces; out of range refused") {
    plan::TestCutOptions o;
    o.ae_mm = {0.5, 3};
    o.ap_mm = {2, 8, 12.5};
    const plan::TestCutPlan p = plan::plan_testcut(kBlock, flat10(), o);
    REQUIRE(p.features.size() == 12);
    for (std::size_t k = 0; k < 12; ++k) {
      CAPTURE(p.features[k].id);
      CHECK(p.features[k].ae_mm == o.ae_mm[k % 2]);
      CHECK(p.features[k].ap_mm == o.ap_mm[(k % 6) / 2]);
      CHECK(p.features[k].z0_mm == -o.ap_mm[(k % 6) / 2]);
    }
    o.ap_mm = {20};  // beyond 90 % of the 22 mm of flutes
    CHECK(error_of([&] { plan::check_testcut(kBlock, flat10(), o); }, ErrorKind::settings) ==
          "ap_mm: each axial depth must be in (0.500, 19.800] mm: a wall above T1's corner radius, within 90 % of its flute length");
    o.ap_mm = {5};
    o.ae_mm = {5.5};
    CHECK(error_of([&] { plan::check_testcut(kBlock, flat10(), o); }, ErrorKind::settings).starts_with("ae_mm: each radial depth must be in (0, 5.000] mm"));
  }

  TEST_CASE("testcut with a ball: slope patches at 15, 30, 45 deg chamfer the front edge; the ball tangent to the plane, never in it") {
    plan::TestCutter t = flat10();
    t.type = stock::EndShape::ball;
    t.diameter_mm = 6;
    t.corner_radius_mm = 3;
    const plan::TestCutPlan p = plan::plan_testcut(kBlock, t, {});
    REQUIRE(p.features.size() == 3);
    const double R = 3;
    for (std::size_t k = 0; k < 3; ++k) {
      const plan::WallFeature& f = p.features[k];
      CAPTURE(f.id);
      const double th = std::vector<double>{15, 30, 45}[k] * std::numbers::pi / 180;
      CHECK(f.kind == "slope");
      CHECK(f.id == "S" + std::to_string(k + 1));
      CHECK(f.normal[1] == doctest::Approx(-std::sin(th)));
      CHECK(f.normal[2] == doctest::Approx(std::cos(th)));
      CHECK(f.ap_mm == deflex::test::within(0.8 * R, 1e-3));  // the wedge at most 0.8 R thick
      CHECK(f.z0_mm == deflex::test::within(-0.8 * R, 1e-3));
      // Every cutting pass: the ball centre R off the plane (tangent) where
      // it cuts along the strike, the last pass's contact past the front face.
      int along = 0;
      double lowest_contact_y = 1e9;
      for (std::size_t i = 3; i < f.path.size(); ++i) {
        const plan::Vec3 &a = f.path[i - 1], &b = f.path[i];
        if (!(a[1] == b[1] && a[2] == b[2] && b[0] > a[0])) continue;  // along +X at one height
        ++along;
        const plan::Vec3 c{b[0], b[1], b[2] + R};  // the ball centre
        const double d = (c[0] - f.point_mm[0]) * f.normal[0] + (c[1] - f.point_mm[1]) * f.normal[1] + (c[2] - f.point_mm[2]) * f.normal[2];
        CHECK(d == deflex::test::within(R, 2e-3 / R));
        lowest_contact_y = std::min(lowest_contact_y, c[1] - R * f.normal[1]);
        // Never lower than the wedge's bottom edge (z0 at the front face)
        // reached by the ball, one stepover past it at most.
        CHECK(b[2] >= f.z0_mm - R * (1 - std::cos(th)) - f.ae_mm * std::sin(th) - 1e-3);
      }
      CHECK(along >= 8);
      CHECK(lowest_contact_y <= kBlock.y0_mm);
    }
  }

  TEST_CASE("testcut with a bull nose: the wall starts above the corner radius, the floor a_p down") {
    plan::TestCutter t = flat10();
    t.type = stock::EndShape::bull;
    t.corner_radius_mm = 1;
    const plan::TestCutPlan p = plan::plan_testcut(kBlock, t, {});
    for (const plan::WallFeature& f : p.features) {
      CAPTURE(f.id);
      CHECK(f.z0_mm == doctest::Approx(-f.ap_mm + 1));
      CHECK(f.path[1][2] == doctest::Approx(-f.ap_mm));  // the floor itself is a_p down
    }
  }

  TEST_CASE("testcut: a block too small names the smallest that fits, which fits; depths for a ball and bad options are refused") {
    const plan::TestCutter t = flat10();
    const plan::Vec3 need = plan::smallest_block_mm(t, {});
    const std::string m = error_of([&] { plan::check_testcut({0, 0, -30, 100, 100, 0}, t, {}); }, ErrorKind::settings);
    CHECK(m.find("is too small for the test cut of T1: the smallest block that fits is") != std::string::npos);
    CHECK(m.find(std::to_string(static_cast<int>(need[0])) + " x ") != std::string::npos);
    CHECK_NOTHROW(plan::plan_testcut({0, 0, -need[2], need[0], need[1], 0}, t, {}));
    CHECK_THROWS(plan::plan_testcut({0, 0, -need[2], need[0] - 1, need[1], 0}, t, {}));
    CHECK_THROWS(plan::plan_testcut({0, 0, -need[2] + 1, need[0], need[1], 0}, t, {}));
    plan::TestCutter ball = t;
    ball.type = stock::EndShape::ball;
    plan::TestCutOptions depths;
    depths.ap_mm = {3};
    CHECK(error_of([&] { plan::check_testcut(kBlock, ball, depths); }, ErrorKind::settings).find("slope patches take no") !=
          std::string::npos);
    plan::TestCutOptions o;
    o.ae_fractions = {0.7};
    CHECK(error_of([&] { plan::check_testcut(kBlock, t, o); }, ErrorKind::settings).find("radial depth") != std::string::npos);
    o = {};
    o.fz_mm = 0;
    CHECK(error_of([&] { plan::check_testcut(kBlock, t, o); }, ErrorKind::settings) == "fz_mm must be in (0, 1] mm per tooth");
  }

  TEST_CASE("testcut: the program's lines of each feature are its cut, in every dialect") {
    for (const std::string& name : profile::dialect_names()) {
      CAPTURE(name);
      const profile::Dialect d = profile::load_dialect(name);
      plan::TestCutPlan p = plan::plan_testcut(kBlock, flat10(), {});
      std::ostringstream out;
      plan::write_testcut(out, p, d, {"HEADER"});
      std::vector<std::string> l = lines_of(out.str());
      // The Heidenhain TNC's N words, on every line but the tape marks.
      for (std::string& s : l)
        if (d.n_policy == profile::NPolicy::required && s != "%" && !s.empty()) {
          REQUIRE(s.starts_with("N"));
          s.erase(0, s.find(' ') + 1);
        }
      CHECK(l[1] == "%");
      CHECK(l.back() == "%");
      CHECK(out.str().find(" M3\n") != std::string::npos);
      for (const plan::WallFeature& f : p.features) {
        CAPTURE(f.id);
        REQUIRE(f.last_line == f.first_line + 3);
        CHECK(l[f.first_line].starts_with("G1 Z-"));
        CHECK(l[f.first_line + 2].starts_with(f.feed_axis == 0 ? "X" : "Y"));
        CHECK(l[f.last_line].starts_with(f.feed_axis == 0 ? "Y" : "X"));
        CHECK((l[f.first_line - 1] + l[f.first_line - 2]).find(f.id + ": WALL FED") != std::string::npos);
      }
      // Rapids only at the clearance plane: every G0 line has no Z, or Z5.
      for (const std::string& s : l)
        if (s.starts_with("G0 ") || s.find(" G0 ") != std::string::npos) CHECK((s.find(" Z") == std::string::npos || s.find(" Z5.") != std::string::npos));
    }
  }

  TEST_CASE("testcut plan YAML: read back as written; a bad plan is refused at file:line:col") {
    plan::TestCutPlan p = plan::plan_testcut(kBlock, flat10(), {});
    p.machine = "mill3";
    p.material = "Al7075-T6";
    p.dialect = "fanuc";
    std::ostringstream out;
    plan::write_testcut(out, p, profile::load_dialect("fanuc"), {});
    std::ostringstream y;
    plan::write_plan_yaml(y, p, "testcut.nc");
    const plan::TestCutPlan q = plan::read_plan_yaml(y.str(), "testcut.yaml");
    CHECK(q.machine == "mill3");
    CHECK(q.block.y1_mm == 200);
    CHECK(q.tool.diameter_mm == 10);
    REQUIRE(q.features.size() == p.features.size());
    for (std::size_t i = 0; i < q.features.size(); ++i) {
      const plan::WallFeature &a = p.features[i], &b = q.features[i];
      CHECK(b.id == a.id);
      CHECK(b.normal == a.normal);
      CHECK(b.point_mm == a.point_mm);
      CHECK(b.u0_mm == a.u0_mm);
      CHECK(b.z0_mm == a.z0_mm);
      CHECK(b.ae_mm == a.ae_mm);
      CHECK(b.ap_mm == a.ap_mm);
      CHECK(b.first_line == a.first_line);
      CHECK(b.last_line == a.last_line);
      CHECK(b.morelli == a.morelli);
    }
    auto refused = [&](const std::string& from, const std::string& to) {
      std::string text = y.str();
      const std::size_t at = text.find(from);
      REQUIRE(at != std::string::npos);
      text.replace(at, from.size(), to);
      return error_of([&] { plan::read_plan_yaml(text, "testcut.yaml"); }, ErrorKind::config);
    };
    CHECK(refused("  - id: WX2\n", "  - id: wx2\n").starts_with("testcut.yaml:"));
    CHECK(refused("  - id: WX2\n", "  - id: wx2\n").find(": error: features[1].id must be uppercase") != std::string::npos);
    // The line and column of the value at fault: WX1's normal on line 24.
    CHECK(refused("normal: [0.0000, 1.0000, 0.0000]", "normal: [0.0000, 2.0000, 0.0000]") ==
          "testcut.yaml:24:13: error: features[0].normal must be a unit vector");
    CHECK(refused("    mode: down\n", "    mode: up\n").find("mode must be down") != std::string::npos);
    CHECK(refused("    kind: wall\n", "    kind: wall\n    colour: red\n").find("unknown key 'colour'") != std::string::npos);
    CHECK(refused("u_mm: [", "u_mm: [900, ").find("u_mm must be a list of 2 numbers") != std::string::npos);
    CHECK(refused("  - id: WX2\n", "  - id: WX1\n").find("given twice") != std::string::npos);
  }
}
