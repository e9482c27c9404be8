// The probing program of a test cut (plan/probe.hpp): where the points are,
// the comment another reader parses, the Fanuc program's structure. The
// LinuxCNC program read by rs274 and checked against the cut stock is in
// tests/job/test_testcut.cpp.
#include <doctest/doctest.h>

#include <cmath>
#include <regex>
#include <sstream>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/plan/probe.hpp"
#include "../support.hpp"
#include "support.hpp"

using namespace deflex;

namespace {

plan::TestCutPlan test_plan() { return plan::plan_testcut(test::kTestBlock, test::flat10(), {}); }

double dot(const plan::Vec3& a, const plan::Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
plan::Vec3 minus(const plan::Vec3& a, const plan::Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }

}  // namespace

TEST_SUITE("plan") {
  TEST_CASE("probe: points over each probe region, each start and end on the normal line at r + approach and r - overtravel") {
    const plan::TestCutPlan tc = test_plan();
    plan::ProbeOptions o;
    o.ball_diameter_mm = 3;
    o.step_mm = 0.25;
    const plan::ProbeProgram pp = plan::plan_probe(tc, o);
    REQUIRE(pp.features.size() == tc.features.size());
    int id = 0;
    for (std::size_t k = 0; k < pp.features.size(); ++k) {
      const plan::WallFeature& f = tc.features[k];
      CAPTURE(f.id);
      // 3 positions along, heights every 0.25 mm from the floor + r + 0.1 to the top - 0.1.
      const std::size_t heights = pp.features[k].size() / 3;
      CHECK(pp.features[k].size() == 3 * heights);
      CHECK(heights == static_cast<std::size_t>(std::floor((f.z1_mm - 0.1 - (f.z0_mm + 1.6)) / 0.25 + 1e-9)) + 2);
      for (const plan::ProbePoint& p : pp.features[k]) {
        CHECK(p.id == ++id);
        CHECK(p.feature == f.id);
        // On the intended plane, inside the probe region.
        CHECK(dot(minus(p.surface_mm, f.point_mm), f.normal) == doctest::Approx(0).epsilon(1e-9));
        CHECK(p.surface_mm[f.feed_axis] >= f.u0_mm - 1e-9);
        CHECK(p.surface_mm[f.feed_axis] <= f.u1_mm + 1e-9);
        CHECK(p.surface_mm[2] >= f.z0_mm + 1.5 + 0.1 - 1e-9);
        CHECK(p.surface_mm[2] <= f.z1_mm - 0.1 + 1e-9);
        const plan::Vec3 s = minus(p.start_mm, p.surface_mm), e = minus(p.end_mm, p.surface_mm);
        CHECK(dot(s, f.normal) == doctest::Approx(1.5 + 2));
        CHECK(dot(e, f.normal) == doctest::Approx(1.5 - 1));
        CHECK(std::hypot(s[0], s[1], s[2]) == doctest::Approx(3.5));  // on the normal line
        CHECK(std::hypot(e[0], e[1], e[2]) == doctest::Approx(0.5));
      }
    }
    // The comment, byte for byte.
    plan::ProbePoint pt;
    pt.id = 12;
    pt.feature = "WX1";
    pt.surface_mm = {10, 5, -2.25};
    pt.normal = {-0.0, 1, 0};
    CHECK(plan::probe_comment(pt, 1) == "DEFLEX PROBE 12 WX1 AT 10.000 5.000 -2.250 N 0.0000 1.0000 0.0000 BALL 1.000");
  }

  TEST_CASE("probe: the options are checked first; a stylus too short for the deepest point is refused") {
    const plan::TestCutPlan tc = test_plan();
    auto message = [&](const plan::ProbeOptions& o) {
      return test::error_of([&] { (void)plan::plan_probe(tc, o); }, ErrorKind::settings);
    };
    plan::ProbeOptions o;
    o.step_mm = 0.2;
    CHECK(message(o) == "step_mm must be in [0.25, 0.5] mm");
    o = {};
    o.probe_length_mm = 10;  // the deepest ball centre is 17.004 - 1.1 = 15.904 below the top
    CHECK(message(o).find("the stylus needs at least 16.904 mm") != std::string::npos);
    o.probe_length_mm = 17;
    CHECK_NOTHROW(plan::plan_probe(tc, o));
    o = {};
    o.ball_diameter_mm = 12;  // no height on a 5.4 mm wall
    CHECK(message(o).find("WX1: the wall") != std::string::npos);
  }

  TEST_CASE("probe, Fanuc: G31 for each point, then DPRNT of its id; POPEN/PCLOS around; only feeds below the clearance") {
    const plan::TestCutPlan tc = test_plan();
    plan::ProbeOptions o;
    o.probe_tool = 20;
    const plan::ProbeProgram pp = plan::plan_probe(tc, o);
    std::ostringstream out;
    plan::write_probe(out, pp, profile::load_dialect("fanuc"), {"HEADER"});
    std::istringstream in(out.str());
    std::vector<std::string> l;
    for (std::string s; std::getline(in, s);) l.push_back(s);
    const std::regex comment(
        R"(\(DEFLEX PROBE (\d+) ([A-Z0-9_]+) AT (-?\d+\.\d{3}) (-?\d+\.\d{3}) (-?\d+\.\d{3}) N (-?\d\.\d{4}) (-?\d\.\d{4}) (-?\d\.\d{4}) BALL (\d+\.\d{3})\))");
    const std::regex g31(R"(G31 X(-?[\d.]+) Y(-?[\d.]+) Z(-?[\d.]+) F100\.)");
    int points = 0, popen = -1, pclos = -1;
    bool below = false;
    for (std::size_t i = 0; i < l.size(); ++i) {
      if (l[i] == "POPEN") popen = static_cast<int>(i);
      if (l[i] == "PCLOS") pclos = static_cast<int>(i);
      if (l[i].starts_with("G1 Z-")) below = true;
      if (l[i] == "G1 Z5. F1000.") below = false;
      if (below) CHECK_MESSAGE(l[i].find("G0") == std::string::npos, l[i]);
      std::smatch m;
      if (!std::regex_match(l[i], m, comment)) continue;
      ++points;
      CHECK(std::stoi(m[1]) == points);
      const plan::ProbePoint& p = [&]() -> const plan::ProbePoint& {
        for (const auto& f : pp.features)
          for (const auto& q : f)
            if (q.id == points) return q;
        FAIL("no point");
        return pp.features[0][0];
      }();
      CHECK(m[2] == p.feature);
      CHECK(std::stod(m[3]) == doctest::Approx(p.surface_mm[0]));
      CHECK(std::stod(m[7]) == doctest::Approx(p.normal[1]));
      // The probing move to the end, then the skip position printed with the id.
      REQUIRE(i + 2 < l.size());
      std::smatch g;
      REQUIRE(std::regex_match(l[i + 1], g, g31));
      CHECK(std::stod(g[1]) == doctest::Approx(p.end_mm[0]));
      CHECK(std::stod(g[2]) == doctest::Approx(p.end_mm[1]));
      CHECK(std::stod(g[3]) == doctest::Approx(p.end_mm[2]));
      CHECK(l[i + 2] == "DPRNT[PT" + std::to_string(points) + "*X#5061[44]*Y#5062[44]*Z#5063[44]]");
      CHECK(popen >= 0);
      CHECK(pclos < 0);
    }
    std::size_t total = 0;
    for (const auto& f : pp.features) total += f.size();
    CHECK(static_cast<std::size_t>(points) == total);
    CHECK(pclos > popen);
    CHECK(out.str().find("T20 M6\nG54 G0 G43 H20 Z5.\n") != std::string::npos);
    CHECK(out.str().find("G38") == std::string::npos);
    CHECK(out.str().find("ACTIVATE THE PROBE") != std::string::npos);
  }
}
