// Roughing over a target surface (plan/roughing.hpp), checked against closed
// forms (a flat end and a ball on an inclined plane) and the invariant of a
// roughing: the stock it leaves is nowhere nearer than the allowance to the
// target, and on the open flat exactly the allowance (plus the scallop).
#include <doctest/doctest.h>

#include <cmath>
#include <sstream>

#include "../support.hpp"
#include "deflex/plan/roughing.hpp"
#include "deflex/stock/sweep.hpp"

using namespace deflex;

namespace {

constexpr double kCell = 0.05;

// A Z-map over [0, 40] x [0, 30] whose cell centres lie on f(x, y).
template <class F>
stock::ZMap surface(F f) {
  const stock::GridSpec g = stock::grid_covering(0, 0, 40, 30, kCell);
  stock::ZMap z(g, 0.0f, -40);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) z.set(i, j, static_cast<float>(f(z.cx(i), z.cy(j))));
  return z;
}

// The plan's passes swept with its tool into a box over the target's grid.
stock::ZMap rest_after(const stock::ZMap& target, const plan::RoughingPlan& p, const plan::RoughingOptions& o) {
  stock::ZMap z(target.grid(), static_cast<float>(p.top_mm), -40);
  for (const auto& pass : p.passes) stock::sweep_polyline(z, o.tool, pass);
  return z;
}

stock::ToolProfile tool(stock::EndShape k, double r, double rc = 0) {
  stock::ToolProfile t;
  t.kind = k;
  t.radius_mm = r;
  t.corner_radius_mm = k == stock::EndShape::ball ? r : rc;
  return t;
}

}  // namespace

TEST_SUITE("plan") {
  TEST_CASE("drop_height: flat end and ball on an inclined plane, closed forms") {
    const double s = std::tan(20 * M_PI / 180);
    const stock::ZMap z = surface([s](double x, double) { return s * x; });
    // A flat end rests on its rim, uphill: tip = s (x + R).
    CHECK(std::fabs(plan::drop_height(z, tool(stock::EndShape::flat, 5), 20, 15) - s * 25) <= s * kCell);
    // A ball touches the plane where its normal does: tip = s x + R (sqrt(1 + s^2) - 1).
    const double ball = plan::drop_height(z, tool(stock::EndShape::ball, 4), 20, 15);
    CHECK(std::fabs(ball - (s * 20 + 4 * (std::sqrt(1 + s * s) - 1))) <= 2e-4);
    // Outside the grid by more than the radius: nothing under the tool.
    CHECK(plan::drop_height(z, tool(stock::EndShape::flat, 5), -6, 15) == stock::no_material);
    // The grown cutter: a flat end R becomes a bull nose R + a with corner a.
    const stock::ToolProfile g = plan::grown(tool(stock::EndShape::flat, 5), 0.5);
    CHECK(g.kind == stock::EndShape::bull);
    CHECK(g.radius_mm == 5.5);
    CHECK(g.corner_radius_mm == 0.5);
  }

  TEST_CASE("a flat end on a plane sloped along the lines leaves a sqrt(1 + s^2) over it, never less") {
    const double s = std::tan(20 * M_PI / 180);
    const stock::ZMap target = surface([s](double x, double) { return s * x; });
    plan::RoughingOptions o;
    o.tool = tool(stock::EndShape::flat, 5);
    o.allowance_mm = 0.5;
    o.stepdown_mm = 3;
    o.stepover_mm = 4;
    const double top = s * 40 + 2;
    const plan::RoughingPlan p = plan::plan_roughing(target, top, o);
    // Levels at most stepdown apart, the last on the lowest floor; lines start outside the stock.
    REQUIRE(p.levels_mm.size() >= 2);
    double prev = top;
    for (double l : p.levels_mm) {
      CHECK(prev - l <= o.stepdown_mm + 1e-9);
      prev = l;
    }
    CHECK(p.levels_mm.back() == p.floor_min_mm);
    CHECK(p.x_start_mm < -o.tool.radius_mm - o.allowance_mm);
    const stock::ZMap rest = rest_after(target, p, o);
    const double expected = 0.5 * std::sqrt(1 + s * s);
    // Inside: the plane offset along its normal. At the stock's edges (a
    // corner of the target) the allowance is vertical, a itself.
    double lo = 1e9, hi = -1e9, all_lo = 1e9;
    for (int j = 0; j < rest.grid().ny; ++j)
      for (int i = 0; i < rest.grid().nx; ++i) {
        const double left = rest.at(i, j) - target.at(i, j);
        all_lo = std::min(all_lo, left);
        if (rest.cx(i) < 6 || rest.cx(i) > 34) continue;
        lo = std::min(lo, left);
        hi = std::max(hi, left);
      }
    // Between two lines p apart the end reaches only sqrt(R^2 - (p/2)^2) downhill
    // of its centre: the leftover rises by s (R - that) midway (the staircase
    // of a raster along a slope).
    const double half = (p.line_y_mm[1] - p.line_y_mm[0]) / 2, R = o.tool.radius_mm;
    const double ripple = s * (R - std::sqrt(R * R - half * half));
    CHECK(lo >= expected - s * kCell - 1e-3);
    CHECK(lo <= expected + s * kCell + 1e-3);
    CHECK(hi <= expected + ripple + s * kCell + o.merge_tol_mm + 1e-3);
    CHECK(hi >= expected + ripple - s * kCell - 1e-3);
    CHECK(all_lo >= o.allowance_mm - s * kCell - 1e-3);
  }

  TEST_CASE("ball and bull nose over a dome: never into the allowance, the allowance plus the scallop on the flat") {
    // A dome of radius 8 on a flat at z = 0; both sloped in every direction.
    auto dome = [](double x, double y) {
      const double r2 = (x - 20) * (x - 20) + (y - 15) * (y - 15);
      return r2 < 64 ? std::sqrt(64 - r2) : 0.0;
    };
    const stock::ZMap target = surface(dome);
    for (const stock::ToolProfile& t : {tool(stock::EndShape::ball, 3), tool(stock::EndShape::bull, 4, 1)}) {
      CAPTURE(static_cast<int>(t.kind));
      plan::RoughingOptions o;
      o.tool = t;
      o.allowance_mm = 0.3;
      o.stepdown_mm = 0;  // one level: a semi-finishing pass
      o.stepover_mm = 0.5;
      const plan::RoughingPlan p = plan::plan_roughing(target, 10, o);
      CHECK(p.levels_mm.size() == 1);
      const stock::ZMap rest = rest_after(target, p, o);
      double lo = 1e9, flat_hi = -1e9;
      for (int j = 0; j < rest.grid().ny; ++j)
        for (int i = 0; i < rest.grid().nx; ++i) {
          const double left = rest.at(i, j) - target.at(i, j);
          lo = std::min(lo, left);
          const double r = std::hypot(rest.cx(i) - 20, rest.cy(j) - 15);
          if (r > 8 + t.radius_mm + 1) flat_hi = std::max(flat_hi, left);
        }
      // Cell centres and samples 0.25 mm apart on slopes up to vertical: a few
      // hundredths may be eaten at the dome's foot; the allowance absorbs it.
      CHECK(lo >= 0.3 - 0.03);
      // On the flat: a ball leaves scallops of p^2 / 8R between lines; a bull nose's flat bottom none.
      const double scallop = t.kind == stock::EndShape::ball ? 0.5 * 0.5 / (8 * 3) : 0.0;
      CHECK(flat_hi <= 0.3 + scallop + 2e-3);
      CHECK(flat_hi >= 0.3 - 1e-3);
    }
  }

  TEST_CASE("the written program reads back as the plan, tool called, every level entered outside the stock") {
    const stock::ZMap target = surface([](double x, double y) { return 2 * std::sin(x / 6) * std::cos(y / 5); });
    plan::RoughingOptions o;
    o.tool = tool(stock::EndShape::flat, 4);
    o.tool_number = 12;
    o.stepdown_mm = 1.5;
    const plan::RoughingPlan p = plan::plan_roughing(target, 3, o);
    std::ostringstream text;
    plan::write_roughing(text, p, o, profile::load_dialect("fanuc"), {"TEST (PARENS)"});
    const test::Interpreted r = test::interpret_text(text.str());
    CHECK(r.errors == 0);
    CHECK(r.warnings == 0);
    CHECK(text.str().find("(TEST [PARENS])") != std::string::npos);
    CHECK(text.str().find("T12 M6") != std::string::npos);
    CHECK(text.str().find("G43 H12") != std::string::npos);
    std::vector<plan::Point> cut;
    for (const interp::Motion& m : r.motions)
      if (m.kind == interp::MotionKind::linear) cut.push_back(m.end_mm);
    std::size_t n = 0;
    for (const auto& pass : p.passes) n += pass.size();
    REQUIRE(cut.size() == n);
    std::size_t k = 0;
    double worst = 0;
    for (const auto& pass : p.passes) {
      CHECK(pass.front()[0] < 0);  // the plunge of each level is outside the stock
      for (const plan::Point& q : pass) {
        for (int a = 0; a < 3; ++a) worst = std::max(worst, std::fabs(cut[k][a] - q[a]));
        ++k;
      }
    }
    CHECK(worst <= 0.0005 + 1e-9);  // three decimals
    CHECK_THROWS_AS(plan::plan_roughing(target, -5, o), Error);  // the stock top under the target: nothing to rough
  }
}
