// The design surface: part-model contacts and normals, path-fitted normals, and
// the surface error along the part's normal, on analytic surfaces whose
// normals are known in closed form.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <thread>
#include <unistd.h>
#include <vector>

#include "../sample_physics.hpp"
#include "../support.hpp"
#include "deflex/compensate/apply.hpp"
#include "deflex/compensate/compensate.hpp"
#include "deflex/compensate/gouge.hpp"
#include "deflex/force/material.hpp"
#include "deflex/part/part.hpp"
#include "deflex/part/path_normals.hpp"
#include "deflex/stiffness/machine.hpp"
#include "deflex/stock/build.hpp"

using namespace deflex;
using V3 = Eigen::Vector3d;

namespace {

constexpr double deg = 180.0 / std::numbers::pi;

// An analytic surface z = f(x, y) with its gradient.
struct Surface {
  std::string name;
  std::function<double(double, double)> f;
  std::function<V3(double, double)> normal;  // outward (upward) unit normal
};

Surface plane_across(double slope_deg) {
  const double t = std::tan(slope_deg / deg);
  return {"plane " + std::to_string(static_cast<int>(slope_deg)) + " deg across the feed",
          [t](double, double y) { return t * y; }, [t](double, double) { return V3(0, -t, 1).normalized(); }};
}
Surface sphere(double r) {
  return {"sphere R" + std::to_string(static_cast<int>(r)),
          [r](double x, double y) { return std::sqrt(r * r - x * x - y * y) - r; },
          [r](double x, double y) { return V3(x, y, std::sqrt(r * r - x * x - y * y)).normalized(); }};
}
Surface cylinder_along_x(double r) {
  return {"cylinder R" + std::to_string(static_cast<int>(r)) + " along X",
          [r](double, double y) { return std::sqrt(r * r - y * y) - r; },
          [r](double, double y) { return V3(0, y, std::sqrt(r * r - y * y)).normalized(); }};
}

// The height field over [-a, a]^2 as triangles (counter-clockwise from above), grid h.
std::vector<stock::Triangle> mesh(const Surface& s, double a, double h) {
  std::vector<stock::Triangle> t;
  const int n = static_cast<int>(std::lround(2 * a / h));
  auto p = [&](int i, int j) {
    const double x = -a + i * h, y = -a + j * h;
    return std::array<double, 3>{x, y, s.f(x, y)};
  };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      t.push_back({{p(i, j), p(i + 1, j), p(i + 1, j + 1)}});
      t.push_back({{p(i, j), p(i + 1, j + 1), p(i, j + 1)}});
    }
  return t;
}

double angle_deg(const V3& a, const V3& b) { return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * deg; }

// The tip of a ball of radius R touching the surface at (u, v).
V3 ball_tip(const Surface& s, double u, double v, double R) {
  return V3(u, v, s.f(u, v)) + R * s.normal(u, v) - R * V3::UnitZ();
}

// The closed box lo..hi as triangles, counter-clockwise seen from outside.
std::vector<stock::Triangle> box_triangles(const V3& lo, const V3& hi) {
  std::vector<stock::Triangle> t;
  auto corner = [&](int i) { return std::array<double, 3>{i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z()}; };
  // Each face's corners in order round its outward normal.
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    t.push_back({{corner(f[0]), corner(f[1]), corner(f[2])}});
    t.push_back({{corner(f[0]), corner(f[2]), corner(f[3])}});
  }
  return t;
}

// The tip of a drop-cutter ball of radius R whose centre lies over (x, y),
// and the surface's normal at its contact (u, v), found by fixed-point
// iteration: (u, v) = (x, y) - R n_xy(u, v).
std::pair<V3, V3> drop_tip(const Surface& s, double x, double y, double R) {
  double u = x, v = y;
  for (int it = 0; it < 100; ++it) {
    const V3 n = s.normal(u, v);
    u = x - R * n.x();
    v = y - R * n.y();
  }
  return {ball_tip(s, u, v, R), s.normal(u, v)};
}

// A vertical wall x <= wall_x (outward normal +X) on a floor z <= 0, as a
// closed solid: x in [-20, wall_x] up to z = 10 (the wall), x in [wall_x, 20]
// up to z = 0 (the floor), y in [-20, 20], base z = -10.
std::vector<stock::Triangle> step_triangles(double wall_x) {
  std::vector<stock::Triangle> box;
  auto quad = [&](std::array<double, 3> a, std::array<double, 3> b, std::array<double, 3> c, std::array<double, 3> d) {
    box.push_back({{a, b, c}});
    box.push_back({{a, c, d}});
  };
  const double w = wall_x;
  quad({-20, -20, 10}, {w, -20, 10}, {w, 20, 10}, {-20, 20, 10});   // top of the wall block
  quad({w, -20, 10}, {w, -20, 0}, {w, 20, 0}, {w, 20, 10});         // the wall, normal +X
  quad({w, -20, 0}, {20, -20, 0}, {20, 20, 0}, {w, 20, 0});         // the floor
  quad({20, -20, 0}, {20, -20, -10}, {20, 20, -10}, {20, 20, 0});   // +X side
  quad({-20, 20, 10}, {-20, 20, -10}, {-20, -20, -10}, {-20, -20, 10});  // -X side
  quad({-20, -20, -10}, {20, -20, -10}, {20, -20, 0}, {-20, -20, 0});    // front (with the step)
  quad({-20, -20, 0}, {w, -20, 0}, {w, -20, 10}, {-20, -20, 10});
  quad({20, 20, -10}, {-20, 20, -10}, {-20, 20, 0}, {20, 20, 0});        // back
  quad({w, 20, 0}, {-20, 20, 0}, {-20, 20, 10}, {w, 20, 10});
  quad({-20, -20, -10}, {-20, 20, -10}, {20, 20, -10}, {20, -20, -10});  // base
  return box;
}

// The samples' tools, machine and `material` on the stock and the part.
compensate::Physics sample_physics(const stock::ZMap& zmap, const part::PartModel& pm, const std::string& material) {
  compensate::Physics ph = test::sample_physics(material);
  ph.stock = &zmap;
  ph.part = &pm;
  return ph;
}

std::vector<Surface> analytic() { return {plane_across(0), plane_across(20), plane_across(45), sphere(30), cylinder_along_x(25)}; }

}  // namespace

TEST_SUITE("part") {

TEST_CASE("part model: ball contacts on analytic surfaces give their normals within 0.2 deg, gaps within the mesh sagitta") {
  stiffness::Tool ball;
  ball.type = stock::EndShape::ball;
  ball.diameter_mm = 10;
  ball.corner_radius_mm = 5;
  ball.flute_length_mm = 20;
  const part::CutterShape shape = part::cutter_shape(ball);
  for (const Surface& s : analytic()) {
    const part::PartModel pm(mesh(s, 12, 0.5));
    double worst_deg = 0, worst_gap = 0;
    for (double u = -6; u <= 6; u += 0.7)
      for (double v = -6; v <= 6; v += 0.9) {
        const part::Contact c = pm.contact(shape, ball_tip(s, u, v, 5), V3::Zero());
        REQUIRE(c.found);
        worst_deg = std::max(worst_deg, angle_deg(c.normal, s.normal(c.point_mm.x(), c.point_mm.y())));
        worst_gap = std::max(worst_gap, std::fabs(c.gap_mm));
      }
    INFO(s.name << ": worst normal " << worst_deg << " deg, worst gap " << worst_gap << " mm");
    CHECK(worst_deg < 0.2);
    CHECK(worst_gap < 0.0025);  // a facet stands off the surface by up to its sagitta: 0.707^2 / (8 x 25) = 0.0025 mm
  }
}

TEST_CASE("part model: flat and bull-nose flank and floor contacts") {
  const std::vector<stock::Triangle> box = step_triangles(0);
  const part::PartModel pm(box);
  for (auto type : {stock::EndShape::flat, stock::EndShape::bull}) {
    stiffness::Tool t;
    t.type = type;
    t.diameter_mm = 12;
    t.corner_radius_mm = type == stock::EndShape::bull ? 2 : 0;
    t.flute_length_mm = 30;
    const part::CutterShape shape = part::cutter_shape(t);
    // Flank on the wall, 0.05 mm off it, tip 1 mm above the floor: contact on the wall.
    const part::Contact w = pm.contact(shape, V3(6.05, 0, 1), V3(-6, 0, 4));
    CHECK(angle_deg(w.normal, V3::UnitX()) < 1e-6);
    CHECK(w.gap_mm == deflex::test::within(0.05, 1e-6));
    // End face 0.03 mm into the floor, away from the wall: contact on the floor.
    const part::Contact f = pm.contact(shape, V3(12, 0, -0.03), V3::Zero());
    CHECK(angle_deg(f.normal, V3::UnitZ()) < 1e-6);
    CHECK(f.gap_mm == deflex::test::within(-0.03, 1e-6));
  }
}

TEST_CASE("part model: a flat or bull-nose end buried in a block: the gap is minus its depth, not minus its corner") {
  // The block x, y in [0, 100], z in [-30, 0]: its top's outward normal +Z, the wall x = 100's +X.
  const part::PartModel pm(box_triangles(V3(0, 0, -30), V3(100, 100, 0)));
  const stiffness::ToolLibrary lib = stiffness::load_tool_library("samples/tools.yaml");
  for (const std::string id : {"T1", "T2"}) {  // flat D10, bull D12 r1
    const stiffness::Tool& t = lib.tools.at(id);
    const part::CutterShape shape = part::cutter_shape(t);
    const double R = 0.5 * t.diameter_mm;
    // Plunged straight down into the top, from less than the corner to 12 mm.
    for (double depth_mm : {0.1, 0.5, 3.0, 12.0}) {
      const part::Contact c = pm.contact(shape, V3(50, 50, -depth_mm), V3::Zero());
      INFO(id << " plunged " << depth_mm << " mm: gap " << c.gap_mm);
      CHECK(c.gap_mm == deflex::test::within(-depth_mm, 1e-6));
      CHECK(angle_deg(c.normal, V3::UnitZ()) < 1e-6);
      CHECK_FALSE(c.depth_at_least);
    }
    // 20 mm down a 30 mm block: the core's deepest point is 15 mm from the top
    // and from the bottom, and the depth says it is a bound.
    const part::Contact through = pm.contact(shape, V3(50, 50, -20), V3::Zero());
    INFO(id << " plunged 20 mm: gap " << through.gap_mm);
    CHECK(through.gap_mm == deflex::test::within(-15 - shape.rho_mm, 1e-4));
    CHECK(through.depth_at_least);
    // The flank 3 mm into the wall x = 100, the tip 15 mm down.
    const part::Contact w = pm.contact(shape, V3(100 + R - 3, 50, -15), V3(-R, 0, 4));
    INFO(id << " flank in the wall: gap " << w.gap_mm);
    CHECK(w.gap_mm == deflex::test::within(-3, 1e-6));
    CHECK(angle_deg(w.normal, V3::UnitX()) < 1e-6);
    CHECK_FALSE(w.depth_at_least);
  }
}

TEST_CASE("path normals: fitted through the tip points of a raster, within 2 deg of the analytic normal") {
  const double R = 5, step = 1.0, spacing = 0.5;
  for (const Surface& s : analytic()) {
    auto tip_at = [&](double x, double y) { return drop_tip(s, x, y, R); };
    std::vector<V3> tips;
    for (double y = -8; y <= 8 + 1e-9; y += step)
      for (double x = -8; x <= 8 + 1e-9; x += spacing) tips.push_back(tip_at(x, y).first);
    const part::PathNormals pn(tips);
    double worst = 0;
    for (double y = -5; y <= 5 + 1e-9; y += step)
      for (double x = -5; x <= 5 + 1e-9; x += 1.5) {
        const auto [tip, n] = tip_at(x, y);
        const auto est = pn.normal_at(tip);
        REQUIRE(est);
        worst = std::max(worst, angle_deg(*est, n));
      }
    INFO(s.name << ": worst " << worst << " deg");
    CHECK(worst < 2.0);
  }
  // One pass alone spans no surface: no estimate.
  std::vector<V3> line;
  for (double x = 0; x <= 10; x += 0.5) line.emplace_back(x, 0, 0.1 * x);
  CHECK_FALSE(part::PathNormals(line).normal_at(V3(5, 0, 0.5)));
}

TEST_CASE("path normals on the edge passes of a raster: determined by the points, or none") {
  // The first and last passes have neighbours on one side only, and within
  // the search radius often one other pass: two rows of points determine a
  // plane's slope across the feed but not a quadratic's. A normal returned
  // there must be as good as inside (its error times a 0.1 mm deflection
  // under 2 um: 1.15 deg); where the points cannot give one, none.
  const double R = 5, spacing = 0.5;
  for (double step : {0.8, 2.0, 3.0})
    for (const Surface& s : analytic()) {
      auto tip_at = [&](double x, double y) { return drop_tip(s, x, y, R); };
      std::vector<V3> tips;
      const int passes = static_cast<int>(std::floor(16 / step)) + 1;
      for (int k = 0; k < passes; ++k)
        for (double x = -8; x <= 8 + 1e-9; x += spacing) {
          // As a program writes them: to 3 decimals.
          const V3 t = tip_at(x, -8 + k * step).first;
          tips.emplace_back(std::round(t.x() * 1000) / 1000, std::round(t.y() * 1000) / 1000,
                            std::round(t.z() * 1000) / 1000);
        }
      const part::PathNormals pn(tips);
      double worst = 0;
      int none_edge = 0, none_next = 0;
      for (int k : {0, 1, passes - 2, passes - 1})
        for (double x = -8; x <= 8 + 1e-9; x += spacing) {
          const auto [tip, n] = tip_at(x, -8 + k * step);
          const auto est = pn.normal_at(tip);
          if (!est) {
            ++(k == 0 || k == passes - 1 ? none_edge : none_next);
            continue;
          }
          worst = std::max(worst, angle_deg(*est, n));
        }
      INFO(s.name << ", step-over " << step << ": worst " << worst << " deg; none on " << none_edge
                  << " points of the edge passes, " << none_next << " of the passes next to them");
      CHECK(worst < 1.15);
      CHECK(none_next == 0);  // neighbours on both sides: always determined
      // The edge passes: determined where the passes on their one side lie
      // within the search radius (8 mm in 3D: a 3 mm step-over on a 45 deg
      // slope puts the second one 8.5 mm away).
      if (step < 3) CHECK(none_edge == 0);
    }
}

TEST_CASE("path normals: a point asked again gets, bit for bit, what a new fit gives it, none included") {
  // Edge passes of a wide raster: some points get no normal. Each answer is
  // kept by its query; asked again (from two threads at once too), the kept
  // answer must be the one a PathNormals that has never been asked gives.
  const double R = 5, spacing = 0.5, step = 3.0;
  const std::vector<Surface> surfaces = analytic();
  const Surface& s = surfaces[2];  // the 45 deg plane: the second pass is 8.5 mm from the edge one
  std::vector<V3> tips;
  for (int k = 0; k < 6; ++k)
    for (double x = -8; x <= 8 + 1e-9; x += spacing) tips.push_back(drop_tip(s, x, -8 + k * step, R).first);
  std::vector<V3> queries;
  for (int k : {0, 2, 5})
    for (double x = -8; x <= 8 + 1e-9; x += 1.5) queries.push_back(drop_tip(s, x, -8 + k * step, R).first);
  std::vector<std::optional<V3>> fresh;
  for (const V3& q : queries) fresh.push_back(part::PathNormals(tips).normal_at(q));
  const part::PathNormals pn(tips);
  auto same = [](const std::optional<V3>& a, const std::optional<V3>& b) {
    return a.has_value() == b.has_value() && (!a || (a->array() == b->array()).all());
  };
  int none = 0;
  for (int round = 0; round < 2; ++round)
    for (std::size_t i = 0; i < queries.size(); ++i) {
      CAPTURE(round);
      CAPTURE(i);
      CHECK(same(pn.normal_at(queries[i]), fresh[i]));
      none += round == 0 && !fresh[i];
    }
  CHECK(none > 0);
  CHECK(none < static_cast<int>(queries.size()));
  std::vector<std::optional<V3>> a(queries.size()), b(queries.size());
  std::thread t([&] {
    for (std::size_t i = 0; i < queries.size(); ++i) a[i] = pn.normal_at(queries[queries.size() - 1 - i]);
  });
  for (std::size_t i = 0; i < queries.size(); ++i) b[i] = pn.normal_at(queries[i]);
  t.join();
  for (std::size_t i = 0; i < queries.size(); ++i) {
    CHECK(same(a[queries.size() - 1 - i], fresh[i]));
    CHECK(same(b[i], fresh[i]));
  }
}

TEST_CASE("a freeform raster without a part: no point moves on a normal off by more than 2 um of error") {
  // samples/strategies/zigzag_45.nc finishes z = 5 sin(6x deg) cos(4.5y deg)
  // with a D10 ball (T7) at 45 deg, 2 mm apart; on a raw box the load is
  // high. The true normal at a CL point is the surface's at the ball's
  // contact (found by fixed-point iteration from the ball's centre): e against
  // delta . n of the true surface, at every point that carries a normal.
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("deflex-ffn-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const auto r = test::run_cli({"compensate", "samples/strategies/zigzag_45.nc", "--stock", "box:0,0,-30,120,80,6",
                                "--material", "Al7075-T6", "--report", dir.string(), "-o", (dir / "out.nc").string()});
  REQUIRE(r.rc == 0);
  const test::Csv pts = test::read_csv((dir / "points.csv").string());
  const double k = std::numbers::pi / 180, R = 5;
  auto true_normal = [&](double x_tip, double y_tip) {
    double u = x_tip, v = y_tip;
    V3 n;
    for (int it = 0; it < 60; ++it) {
      n = V3(-5 * 6 * k * std::cos(6 * k * u) * std::cos(4.5 * k * v),
             5 * 4.5 * k * std::sin(6 * k * u) * std::sin(4.5 * k * v), 1).normalized();
      u = x_tip - R * n.x();
      v = y_tip - R * n.y();
    }
    return n;
  };
  std::size_t path = 0, undetermined = 0, moved_undetermined = 0;
  double worst_um = 0;
  for (std::size_t i = 0; i < pts.rows.size(); ++i) {
    const std::string& src = pts.rows[i][std::find(pts.header.begin(), pts.header.end(), "normal_source") - pts.header.begin()];
    if (src == "undetermined") {
      ++undetermined;
      moved_undetermined += pts.num(i, "offset_mm") != 0;
      continue;
    }
    REQUIRE(src == "path");
    ++path;
    const double x = pts.num(i, "x_mm"), y = pts.num(i, "y_mm");
    // The ball's contact lies on the part (X 0..120, Y 0..80) only inside it.
    if (x < R || x > 120 - R || y < R || y > 80 - R) continue;
    const V3 d(pts.num(i, "dx_mm"), pts.num(i, "dy_mm"), pts.num(i, "dz_mm"));
    worst_um = std::max(worst_um, 1000 * std::fabs(pts.num(i, "surface_error_as_written_mm") - d.dot(true_normal(x, y))));
  }
  MESSAGE("path normals " << path << ", undetermined " << undetermined << ", worst |e - delta.n_true| " << worst_um << " um");
  CHECK(path > 10000);
  CHECK(worst_um <= 2.0);
  CHECK(moved_undetermined == 0);
  // The cusp of an edge pass is its neighbours' (no 5 mm "cusp" of a guessed normal).
  const auto summary = nlohmann::json::parse(test::read_file((dir / "summary.json").string()));
  CHECK(summary.at("cusp_height_mm").at("max").get<double>() < 0.2);
  fs::remove_all(dir);
}

TEST_CASE("gouge check: a pass dug into the part and a pass standing off are named, the exact pass is clean") {
  const Surface s = plane_across(20);
  const part::PartModel pm(mesh(s, 30, 1.0));
  const stiffness::ToolLibrary lib = stiffness::load_tool_library("samples/tools.yaml");
  const std::string id = "T7";  // ball D10
  const double R = 0.5 * lib.tools.at(id).diameter_mm;
  auto pass = [&](double y, double dz) {
    const V3 a = ball_tip(s, -10, y, R) + dz * V3::UnitZ(), b = ball_tip(s, 10, y, R) + dz * V3::UnitZ();
    return test::linear_motion({a.x(), a.y(), a.z()}, {b.x(), b.y(), b.z()});
  };
  std::vector<interp::Motion> m = {pass(0, 0), pass(2, -0.05), pass(4, 0.04)};
  // An approach square to the slope ending on it (line 13) and a retract
  // from it (line 14) stand off the face until they arrive: not a standoff.
  const V3 on = ball_tip(s, 0, 6, R), n = s.normal(0, 6);
  const V3 off = on + 3.0 * n;
  m.push_back(test::linear_motion({off.x(), off.y(), off.z()}, {on.x(), on.y(), on.z()}));
  m.push_back(test::linear_motion({on.x(), on.y(), on.z()}, {off.x(), off.y(), off.z()}));
  for (std::size_t i = 0; i < m.size(); ++i) m[i].line = static_cast<std::uint32_t>(10 + i);
  const compensate::PartGaps g = compensate::part_gaps(m, pm, lib, [&](const interp::Motion&) { return id; }, {}, 0.02, 1.0);
  REQUIRE(g.overcut.lines == std::vector<std::uint32_t>{11});
  REQUIRE(g.standoff.lines == std::vector<std::uint32_t>{12});
  // Moved 0.05 straight down on a 20 deg slope: 0.05 cos 20 into it.
  CHECK(g.overcut.worst_mm == deflex::test::within(0.05 * std::cos(20 / deg), 1e-3));
  CHECK(g.standoff.worst_mm == deflex::test::within(0.04 * std::cos(20 / deg), 1e-3));
  // A program checked in pieces (compensate reads a long one so): the same gaps.
  compensate::PartGaps merged;
  for (std::size_t k = 0; k < m.size(); ++k)
    compensate::merge(merged, compensate::part_gaps({m[k]}, pm, lib, [&](const interp::Motion&) { return id; }, {},
                                                    0.02, 1.0));
  CHECK(merged.points == g.points);
  for (auto [a, b] : {std::pair{&merged.overcut, &g.overcut}, std::pair{&merged.standoff, &g.standoff}}) {
    CHECK(a->points == b->points);
    CHECK(a->lines == b->lines);
    CHECK(a->worst_mm == b->worst_mm);
    CHECK(a->worst_line == b->worst_line);
  }
}

TEST_CASE("a raster across a 20 deg slope: e = delta . n of the part, and compensated with --part it judges inside the tolerance") {
  // Ball D10 (T7) passes along X across a plane rising 20 deg in +Y: the
  // travel rule's normal (perpendicular to the feed in its vertical plane) is
  // +Z here, 20 deg off the surface's. Stock: the plane + 1 mm along Z.
  const Surface s = plane_across(20);
  const double R = 5, t = std::tan(20 / deg), lift = R / std::cos(20 / deg) - R;
  std::string text = "%\nO0003\nN1 G21 G90 G17 G40 G49 G80 G54\nN2 T7 M06\nN3 S10000 M03\nN4 G00 X-6. Y0. Z8.\n";
  int n = 5;
  auto z_at = [&](double y) { return t * y + lift; };
  text += "N" + std::to_string(n++) + " G01 Z" + std::to_string(z_at(0)) + " F1600.\n";
  for (int r = 0; r < 6; ++r) {
    const double y = 0.8 * r;
    if (r) text += "N" + std::to_string(n++) + " Y" + std::to_string(y) + " Z" + std::to_string(z_at(y)) + "\n";
    for (int i = 1; i <= 60; ++i)
      text += "N" + std::to_string(n++) + " X" + std::to_string(r % 2 == 0 ? -6 + 0.5 * i : 24 - 0.5 * i) + "\n";
  }
  text += "N" + std::to_string(n) + " G00 Z30.\nN" + std::to_string(n + 1) + " M30\n%\n";
  const test::Interpreted in = test::interpret_text(text);
  REQUIRE(in.errors == 0);
  std::vector<stock::Triangle> surface = mesh(s, 40, 2.0), raised = surface;
  for (auto& tri : raised)
    for (auto& v : tri.p) v[2] += 1.0;
  const stock::ZMap zmap = stock::zmap_from_triangles(raised, 0.05);
  const part::PartModel pm(surface);
  const compensate::Physics ph = sample_physics(zmap, pm, "C35");
  compensate::Settings st;
  st.tolerance_mm = 0.002;
  st.threads = 1;
  // As the CLI runs it: moves whose error along them would leave the
  // tolerance under the ramp of their end offsets are split.
  const gcode::Program prog{SourceText("t.nc", text)};
  const std::vector<bool> split = compensate::splittable(prog, in.motions);
  const compensate::Result r = compensate::compensate(in.motions, ph, st, {}, &split);
  CHECK(r.converged);
  // As written: every cutting point's normal is the part's, and its error is
  // the deflection along the analytic normal.
  const V3 n_plane = s.normal(0, 0);
  std::size_t cutting = 0, outside = 0;
  double worst_de = 0;
  for (const compensate::Point& p : r.nominal) {
    if (p.air || p.plunge) continue;
    ++cutting;
    CHECK(p.normal_source == compensate::NormalSource::part);
    worst_de = std::max(worst_de, std::fabs(p.error_mm - p.delta_mm.dot(n_plane)));
    outside += std::fabs(p.error_mm) > st.tolerance_mm;
  }
  INFO("cutting points " << cutting << ", outside as written " << outside << ", worst |e - delta.n| " << worst_de);
  CHECK(cutting > 200);
  CHECK(worst_de <= 2e-4);
  REQUIRE(outside > cutting / 10);
  // Judged as simulate --reference --part does: the output simulated afresh,
  // each point's landing (offset + deflection) along the part's normal.
  const auto judged = compensate::simulate(r.motions, r.offsets, ph, st);
  std::size_t after = 0;
  double worst = 0;
  for (const compensate::Point& p : judged) {
    if (p.air || p.plunge) continue;
    const V3 end = r.offsets[p.motion], start = p.motion ? r.offsets[p.motion - 1] : V3(V3::Zero());
    const double u = p.count ? static_cast<double>(p.index) / p.count : 1.0;
    const double e = (start + u * (end - start) + p.delta_mm).dot(p.normal);
    worst = std::max(worst, std::fabs(e));
    after += std::fabs(e) > st.tolerance_mm * 1.01;
  }
  INFO("compensated: worst " << worst << " mm");
  CHECK(after == 0);
}

TEST_CASE("a flat end finishing a wall standing on the floor: the design normal is the wall's, not the floor's") {
  // The last level of a pocket wall: T6 (flat D12) down-milling the wall
  // x = 0 (0.3 mm left on it) with its tip on the floor z = 0. The floor and
  // the wall are both where the cutter stands; the flank cut's search starts
  // on the wall side (the side the engaged edge cuts), so the wall's normal
  // +X is the one the flank's wall profile e(z) is taken along (its
  // mid-range the point's error, micrometres), not the floor's +Z (along which
  // the error would be delta_z, next to nothing).
  const part::PartModel pm(step_triangles(0));
  const stock::ZMap zmap = stock::zmap_from_triangles(step_triangles(0.3), 0.05);
  const compensate::Physics ph = sample_physics(zmap, pm, "Al7075-T6");
  compensate::Settings st;
  st.threads = 1;
  const test::Interpreted in =
      test::interpret_text("G21 G90 G17\nT6 M6\nS8000 M3\nG0 X6. Y15. Z20.\nG1 Z0. F1000\nG1 Y-15. F1600\nG0 Z20.\nM30\n");
  REQUIRE(in.errors == 0);
  std::size_t on_wall = 0;
  for (const compensate::Point& p : compensate::simulate(in.motions, {}, ph, st)) {
    if (p.air || p.plunge || p.line != 6 || std::fabs(p.tip_mm.y()) > 10) continue;
    ++on_wall;
    CHECK(p.normal_source == compensate::NormalSource::part);
    CHECK(angle_deg(p.normal, V3::UnitX()) < 1e-6);
    CHECK(p.flank);
    CHECK(p.error_mm == deflex::test::within(0.5 * (p.flank_min_mm + p.flank_max_mm), 1e-12));
    CHECK(p.error_mm > 1e-3);                           // the wall's error, micrometres
    CHECK(std::fabs(p.delta_mm.z()) < 0.1 * p.error_mm);  // what the floor's normal would have seen
  }
  CHECK(on_wall > 30);
}

TEST_CASE("gouge check: a tangential arc onto a wall and off it is a lead-in, not a standoff; a pass beside the wall is") {
  // T6 (flat D12) along the wall x = 0 (the part at x < 0), its tip 1 mm
  // over the floor: quarter arcs of radius 6 in (line 6) and out (line 8) of
  // the exact pass (line 7) stand off the wall by up to 6 mm on purpose;
  // the pass 0.5 mm off the wall (line 11) is what the check is for.
  const part::PartModel pm(step_triangles(0));
  const stiffness::ToolLibrary lib = stiffness::load_tool_library("samples/tools.yaml");
  const test::Interpreted in = test::interpret_text(
      "G21 G90 G17\nT6 M6\nS8000 M3\nG0 X12. Y-20. Z20.\nG1 Z1. F1000\nG2 X6. Y-14. I0. J6. F1600\nG1 Y14.\n"
      "G2 X12. Y20. I6. J0.\nG0 Z20.\nX6.5 Y-14. Z1.\nG1 Y14. F1600\nM30\n");
  REQUIRE(in.errors == 0);
  const compensate::PartGaps g =
      compensate::part_gaps(in.motions, pm, lib, [](const interp::Motion&) { return std::string("T6"); }, {}, 0.02, 1.0);
  CHECK(g.overcut.lines.empty());
  CHECK(g.standoff.lines == std::vector<std::uint32_t>{11});
  CHECK(g.standoff.worst_mm == deflex::test::within(0.5, 1e-3));
}

}  // TEST_SUITE
