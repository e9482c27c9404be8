// Z-map storage, box parsing, line/arc sweeps against closed-form trenches.
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "../support.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "deflex/stock/build.hpp"
#include "deflex/stock/sweep.hpp"

using namespace deflex;
using namespace deflex::stock;

namespace {

// XY distance from p to the segment a-b.
double seg_dist(double x, double y, const Point3& a, const Point3& b) {
  const double dx = b[0] - a[0], dy = b[1] - a[1], l2 = dx * dx + dy * dy;
  double t = l2 > 0 ? ((x - a[0]) * dx + (y - a[1]) * dy) / l2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(x - a[0] - t * dx, y - a[1] - t * dy);
}

// Height (mm) of a cutter's lower surface above its tip at radial distance rho,
// written out here rather than taken from the library: flat out to D/2 - r,
// then the corner circle of radius r (r = 0 flat end, r = D/2 ball), r -
// sqrt(r^2 - (rho - (D/2 - r))^2); no tool beyond D/2 (infinite).
double lower_surface_mm(const ToolProfile& tool, double rho) {
  const double R = tool.radius_mm;
  const double r = tool.kind == EndShape::ball ? R : tool.kind == EndShape::flat ? 0.0 : tool.corner_radius_mm;
  if (rho > R) return std::numeric_limits<double>::infinity();
  const double u = std::max(0.0, rho - (R - r));
  return r - std::sqrt(std::max(0.0, r * r - u * u));
}

// Brute force: the lowest lower-surface height over n + 1 tool positions.
double brute_lower(const ToolProfile& tool, const Point3& a, const Point3& b, double x, double y, int n) {
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= n; ++k) {
    const double t = static_cast<double>(k) / n;
    const double px = a[0] + t * (b[0] - a[0]), py = a[1] + t * (b[1] - a[1]), pz = a[2] + t * (b[2] - a[2]);
    best = std::min(best, pz + lower_surface_mm(tool, std::hypot(x - px, y - py)));
  }
  return best;
}

// 40 random short moves (up to 2 mm across, rising or falling) for each of a
// ball, a flat and a bull-nose end: the bounds of the skips are checked on them.
std::vector<LineSweep> random_moves(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<LineSweep> moves;
  for (const ToolProfile& t : {ToolProfile{EndShape::ball, 4, 4}, ToolProfile{EndShape::flat, 3, 0},
                               ToolProfile{EndShape::bull, 5, 1.5}})
    for (int k = 0; k < 40; ++k) {
      const Point3 a{5 + 20 * u(rng), 5 + 20 * u(rng), -2 * u(rng)};
      const Point3 b{a[0] + 4 * (u(rng) - 0.5), a[1] + 4 * (u(rng) - 0.5), a[2] + (u(rng) - 0.5)};
      moves.emplace_back(t, a, b);
    }
  return moves;
}

// A 30 x 30 mm box at 0.1 mm with a ball's trench across it: cells at many
// heights for the stock-side tests of the skips.
ZMap trenched_box() {
  ZMap z = zmap_from_box(parse_box("box:0,0,-20,30,30,0"), 0.1);
  sweep_line_reference(z, LineSweep({EndShape::ball, 4, 4}, {0, 12, -0.6}, {30, 14, -0.9}));
  return z;
}

}  // namespace

TEST_SUITE("stock") {

TEST_CASE("row skip: row_floor bounds the lower surface from below, row_above the stock from above") {
  // The two bounds sweep_rows uses to leave a row alone: checked
  // against lower_height at every cell of random rows and the cells themselves.
  int rows = 0;
  for (const LineSweep& s : random_moves(14))
    for (double y = s.y_min(); y <= s.y_max(); y += 0.37, ++rows) {
      const double f = s.row_floor(y);
      // Equal up to rounding where the row touches the footprint's rim (5e-8
      // mm seen); sweep_rows keeps a margin of 1e-3 mm.
      for (double x = s.x_min(); x <= s.x_max(); x += 0.05) CHECK(f <= s.lower_height(x, y) + 1e-6);
    }
  CHECK(rows > 1000);
  const ZMap z = trenched_box();
  for (int j = 0; j < z.grid().ny; j += 7)
    for (int i0 = 0; i0 < z.grid().nx; i0 += 29) {
      const int i1 = std::min(z.grid().nx - 1, i0 + 90);
      float top = no_material;
      for (int i = i0; i <= i1; ++i) top = std::max(top, z.at(i, j));
      CHECK(z.row_above(j, i0, i1, top - 1e-4f));
      CHECK_FALSE(z.row_above(j, i0, i1, 1e-3f));  // nothing above the box top
    }
}

TEST_CASE("span skip: span_floor bounds the lower surface over a span, cells_above is exact") {
  std::mt19937 rng(15);
  std::uniform_real_distribution<double> u(0, 1);
  int spans = 0;
  for (const LineSweep& s : random_moves(15))
    for (double y = s.y_min(); y <= s.y_max(); y += 0.37)
      for (double x0 = s.x_min() - 1; x0 <= s.x_max(); x0 += 0.8, ++spans) {
        const double x1 = x0 + 1.6 * u(rng), f = s.span_floor(y, x0, x1);
        CHECK(f >= s.row_floor(y));  // never weaker than the row's bound
        for (double x = x0; x <= x1; x += 0.05) CHECK(f <= s.lower_height(x, y) + 1e-6);
      }
  CHECK(spans > 1000);
  const ZMap z = trenched_box();
  for (int j = 0; j < z.grid().ny; j += 3)
    for (int i0 = -5; i0 < z.grid().nx; i0 += 7) {
      const int i1 = i0 + static_cast<int>(u(rng) * 80);
      float top = no_material;
      for (int i = std::max(i0, 0); i <= std::min(i1, z.grid().nx - 1); ++i) top = std::max(top, z.at(i, j));
      CHECK(z.cells_above(j, i0, i1, top - 1e-4f) == (top > no_material));
      CHECK_FALSE(z.cells_above(j, i0, i1, top));
    }
}

TEST_CASE("span skip: the second pass of a finishing raster updates a fraction of its footprint") {
  // Two ball passes 0.25 mm apart along X over a box, the second in moves of
  // 0.4 mm: under and behind the ball the first pass and the moves before cut
  // deeper, so the skips leave most of each move's cells alone. The result is
  // the reference's, cell for cell (the chain test above checks the rest).
  ZMap fast = zmap_from_box(parse_box("box:0,0,-20,40,20,0"), 0.05);
  ZMap ref = zmap_from_box(parse_box("box:0,0,-20,40,20,0"), 0.05);
  const ToolProfile ball{EndShape::ball, 4, 4};
  std::vector<LineSweep> first, second;
  for (int k = 0; k < 75; ++k) {
    const double x = 5 + 0.4 * k;
    first.emplace_back(ball, Point3{x, 10, -0.5 - 0.01 * k}, Point3{x + 0.4, 10, -0.5 - 0.01 * (k + 1)});
    second.emplace_back(ball, Point3{x, 10.25, -0.5 - 0.01 * k}, Point3{x + 0.4, 10.25, -0.5 - 0.01 * (k + 1)});
  }
  sweep_lines(fast, first, false);
  for (const LineSweep& l : first) sweep_line_reference(ref, l);
  const SweepWork before = sweep_work();
  for (const LineSweep& l : second) sweep_lines(fast, std::span<const LineSweep>(&l, 1), &l != &second[0]);
  const SweepWork after = sweep_work();
  for (const LineSweep& l : second) sweep_line_reference(ref, l);
  int differ = 0;  // beyond the float rounding of the same height
  for (int j = 0; j < ref.grid().ny; ++j)
    for (int i = 0; i < ref.grid().nx; ++i) differ += std::fabs(static_cast<double>(fast.at(i, j)) - ref.at(i, j)) > 1e-6;
  CHECK(differ == 0);
  // A move's footprint is about 8.4 x 8 mm: 27,000 cells at 0.05 mm.
  const double per_move = static_cast<double>(after.cells - before.cells) / static_cast<double>(second.size());
  CHECK(after.moves - before.moves == second.size());
  CHECK(per_move < 2700);  // a tenth
}

TEST_CASE("box spec parsing") {
  const BoxSpec b = parse_box("box:10,-5,0,-10,5,-20");
  CHECK(b.x0_mm == -10);
  CHECK(b.x1_mm == 10);
  CHECK(b.y0_mm == -5);
  CHECK(b.z0_mm == -20);
  CHECK(b.z1_mm == 0);
  CHECK(parse_box("box: 1.5 ,2,3,4,5,6e0").x0_mm == 1.5);
  for (const char* bad : {"box:1,2,3,4,5", "box:1,2,3,4,5,6,7", "box:1,2,x,4,5,6", "cube:0,0,0,1,1,1",
                          "box:0,0,0,0,1,1", "box:1,2,3,4,5,"}) {
    CAPTURE(bad);
    CHECK_THROWS_AS(parse_box(bad), Error);
  }
}

TEST_CASE("box z-map: heights, overhanging cells, outside") {
  const ZMap z = zmap_from_box(parse_box("box:0,0,-10,10.02,5,2"), 0.05);
  CHECK(z.grid().nx == 201);  // 10.02 / 0.05 = 200.4 -> one overhanging column
  CHECK(z.height_at(5, 2.5) == doctest::Approx(2));
  CHECK(z.at(200, 10) == no_material);  // its centre 10.025 is outside the box
  CHECK(z.height_at(-0.01, 2) == no_material);
  CHECK(z.base_z_mm() == -10);
  // Only the tiles holding the empty column (201 cells -> 4 tiles across, 2 down).
  CHECK(z.allocated_tiles() == z.tiles_y());
}

TEST_CASE("ball along a line leaves the circular trench, exact at cell centres") {
  const double c = 0.05, R = 5, top = 0, ap = 2;
  ZMap z = zmap_from_box(parse_box("box:0,0,-20,60,30,0"), c);
  const ToolProfile ball{EndShape::ball, R, R};
  const Point3 a{10, 15.01, top - ap}, b{50, 15.01, top - ap};
  const double removed = sweep_line(z, ball, a, b);
  const double half_width = std::sqrt(ap * (2 * R - ap));
  int checked = 0;
  for (int j = 0; j < z.grid().ny; ++j)
    for (int i = 0; i < z.grid().nx; ++i) {
      const double x = z.cx(i), y = z.cy(j), d = seg_dist(x, y, a, b);
      const double expect = d >= R ? top : std::min(top, a[2] + R - std::sqrt(R * R - d * d));
      if (std::fabs(z.at(i, j) - expect) > 1e-5) {
        CAPTURE(x);
        CAPTURE(y);
        REQUIRE(z.at(i, j) == deflex::test::within(expect, 1e-6));
      }
      ++checked;
    }
  CHECK(checked == z.grid().nx * z.grid().ny);
  // Across the middle of the trench: lowered exactly within the analytic half width.
  const int i = z.ix(30);
  for (int j = 0; j < z.grid().ny; ++j) {
    const double dy = std::fabs(z.cy(j) - a[1]);
    if (dy < half_width - 1e-9) CHECK(z.at(i, j) < top);
    if (dy > half_width + 1e-9) CHECK(z.at(i, j) == top);
  }
  // Removed volume: circular segment area x length + a spherical cap (two half caps).
  const double h = ap;
  const double seg = R * R * std::acos((R - h) / R) - (R - h) * std::sqrt(2 * R * h - h * h);
  const double cap = std::numbers::pi * h * h * (3 * R - h) / 3;
  CHECK(removed == deflex::test::within(seg * 40 + cap, 2e-3));
}

TEST_CASE("flat end along a diagonal line leaves a rectangular trench") {
  const double c = 0.05, R = 3;
  ZMap z = zmap_from_box(parse_box("box:0,0,-20,40,40,0"), c);
  const ToolProfile flat{EndShape::flat, R, 0};
  const Point3 a{8, 9, -1.5}, b{31, 27, -1.5};
  sweep_line(z, flat, a, b);
  for (int j = 0; j < z.grid().ny; j += 3)
    for (int i = 0; i < z.grid().nx; i += 3) {
      const double d = seg_dist(z.cx(i), z.cy(j), a, b);
      if (d < R - 1e-9) CHECK(z.at(i, j) == doctest::Approx(-1.5));
      if (d > R + 1e-9) CHECK(z.at(i, j) == 0);
    }
}

TEST_CASE("bull nose along a line: torus profile across the trench") {
  // D 8 mm, corner radius r 1 mm, tip at Z -0.8 mm. Across a straight trench the
  // floor at distance rho from the path is the tool's lower surface at radius
  // rho (lower_surface_mm); beyond D/2 the stock is untouched.
  const double D = 8, r = 1, tip_z = -0.8;
  ZMap z = zmap_from_box(parse_box("box:0,0,-20,40,20,0"), 0.05);
  const ToolProfile bull{EndShape::bull, D / 2, r};
  sweep_line(z, bull, {5, 10, tip_z}, {35, 10, tip_z});
  const int i = z.ix(20);
  int on_corner = 0;
  for (int j = 0; j < z.grid().ny; ++j) {
    const double rho = std::fabs(z.cy(j) - 10);
    CAPTURE(rho);
    if (rho > D / 2) {
      CHECK(z.at(i, j) == 0);
      continue;
    }
    const double want = std::min(0.0, tip_z + lower_surface_mm(bull, rho));
    CHECK(z.at(i, j) == deflex::test::within(want, 1e-6));
    on_corner += rho > D / 2 - r && want < 0;
  }
  CHECK(on_corner >= 10);  // the corner's arc is sampled, not only the flat floor
  // Half-way round the corner, rho = 3.5 mm: 1 - sqrt(0.75) = 0.133975 mm above the tip.
  CHECK(lower_surface_mm(bull, 3.5) == deflex::test::within(1 - std::sqrt(0.75), 1e-6));
}

TEST_CASE("ramps and plunges: closed-form envelope equals the brute-force minimum") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-9, 9);
  const ToolProfile tools[] = {{EndShape::ball, 4, 4}, {EndShape::flat, 4, 0}, {EndShape::bull, 4, 1.5}};
  const Point3 segs[][2] = {
      {{0, 0, 0}, {6, 2, -3}},    // descending ramp
      {{0, 0, -3}, {5, -3, 1}},   // ascending ramp
      {{0, 0, 0}, {0.5, 0, -8}},  // steep ramp
      {{1, 1, 2}, {1, 1, -4}},    // plunge
      {{-2, 1, 0}, {4, 1, 0}},    // horizontal
  };
  const int n = 40000;
  for (const ToolProfile& t : tools)
    for (const auto& s : segs) {
      const LineSweep sw(t, s[0], s[1]);
      for (int k = 0; k < 60; ++k) {
        const double x = u(rng), y = u(rng);
        const double exact = sw.lower_height(x, y), brute = brute_lower(t, s[0], s[1], x, y, n);
        CAPTURE(static_cast<int>(t.kind));
        CAPTURE(x);
        CAPTURE(y);
        if (std::isinf(brute)) {
          // Only a grazing footprint between two brute-force positions may differ.
          CHECK((std::isinf(exact) || seg_dist(x, y, s[0], s[1]) > t.radius_mm - 1e-3));
          continue;
        }
        REQUIRE(std::isfinite(exact));
        CHECK(exact <= brute + 1e-9);  // the exact minimum is never above a sampled one
        CHECK(brute - exact < 2e-3);   // sampling step 2.5e-5 of the segment
      }
    }
}

TEST_CASE("arc and helix: toroidal trench within the chordal tolerance") {
  const double R = 3, tol = 1e-3;
  ZMap z = zmap_from_box(parse_box("box:-30,-30,-20,30,30,0"), 0.05);
  const ToolProfile ball{EndShape::ball, R, R};
  // Quarter circle of radius 20 about the origin, ccw from +X to +Y, helix -1 -> -2.
  interp::Arc arc{{20, 0, -1}, {0, 20, -2}, {0, 0, -1}, 17, false};
  CHECK(arc_angle(arc) == doctest::Approx(std::numbers::pi / 2));
  CHECK(arc_length_mm(arc) == doctest::Approx(std::hypot(10 * std::numbers::pi, 1.0)));
  sweep_arc(z, ball, arc, tol);
  // Along the path, the depth follows the helix; the profile across is the ball's.
  for (double th = 0.2; th < 1.4; th += 0.1)
    for (double off = -2.5; off <= 2.5; off += 0.25) {
      const double rho = 20 + off;
      const int i = z.ix(rho * std::cos(th)), j = z.iy(rho * std::sin(th));
      const double rc = std::hypot(z.cx(i), z.cy(j));  // cell centre radius
      const double zt = -1 - (std::atan2(z.cy(j), z.cx(i)) / (std::numbers::pi / 2));
      const double d = rc - 20;
      // Locally a ramp of slope m: the envelope of a ball along a ramp lies
      // sqrt(R^2 - d^2) (sqrt(1 + m^2) - 1) below the tip-height profile
      // (minimum of R + m s - sqrt(R^2 - d^2 - s^2) over s).
      const double m = 1.0 / (20 * std::numbers::pi / 2);
      const double expect = std::min(0.0, zt + R - std::sqrt(R * R - d * d) * std::sqrt(1 + m * m));
      // The chords sit at most tol inside the arc.
      CHECK(std::fabs(z.at(i, j) - expect) < 2 * tol);
    }
  // Full circle (start == end) sweeps 2 pi.
  interp::Arc full{{5, 0, -1}, {5, 0, -1}, {0, 0, -1}, 17, true};
  CHECK(arc_angle(full) == doctest::Approx(2 * std::numbers::pi));
  CHECK(arc_point(full, 0.25)[1] == doctest::Approx(-5));  // clockwise from +X goes to -Y
  // G18 (ZX) arc: the point moves in X and Z, Y stays.
  interp::Arc zx{{0, 1, 0}, {5, 1, 5}, {5, 1, 0}, 18, true};
  const Point3 mid = arc_point(zx, 0.5);
  CHECK(mid[1] == doctest::Approx(1));
  CHECK(std::hypot(mid[0] - 5, mid[2]) == doctest::Approx(5));
}

TEST_CASE("500 x 500 mm stock at the default resolution stays well under 1 GB") {
  ZMap z = zmap_from_box(parse_box("box:0,0,-50,500,500,0"), default_cell_mm);
  CHECK(z.grid().nx == 10000);
  CHECK(z.allocated_tiles() == 0);
  CHECK(z.allocated_bytes() < 2'000'000);  // tile headers only
  // Even with every tile allocated (the whole top cut), the map is < 1 GB.
  CHECK(z.worst_case_bytes() < 500'000'000ull);
  const ToolProfile ball{EndShape::ball, 5, 5};
  for (int k = 0; k < 3; ++k) sweep_line(z, ball, {0, 100.0 + 100 * k, -1}, {500, 100.0 + 100 * k, -1});
  // A D10 trench is 200 cells wide: at most 5 tile rows of 157 tiles per pass.
  CHECK(z.allocated_tiles() <= 3 * 5 * 157);
  CHECK(z.allocated_tiles() >= 3 * 157);
  CHECK(z.allocated_bytes() < 40'000'000);
  MESSAGE("500x500 mm at ", default_cell_mm, " mm: worst case ", z.worst_case_bytes() / 1e6,
          " MB; after 3 passes ", z.allocated_bytes() / 1e6, " MB (", z.allocated_tiles(), " tiles)");
}

TEST_CASE("chained sweeps in parallel bands equal one-by-one sweeps, cell for cell") {
  // Horizontal, rising, falling, plunge, retract, diagonal: the start_cut
  // shortcut must never skip a cell that a full sweep would lower.
  const std::vector<Point3> pts = {{5, 5, -1},  {15, 5, -1},  {20, 8, -0.5}, {26, 12, -2.5}, {26, 12, -4},
                                   {26, 12, -1}, {12, 20, -1.2}, {12, 30, -0.8}, {30, 30, -0.8}, {30, 20, -3}};
  for (const ToolProfile& t : {ToolProfile{EndShape::ball, 4, 4}, ToolProfile{EndShape::flat, 3, 0},
                               ToolProfile{EndShape::bull, 4, 1}}) {
    ZMap a = zmap_from_box(parse_box("box:0,0,-20,40,40,0"), 0.1);
    ZMap b = zmap_from_box(parse_box("box:0,0,-20,40,40,0"), 0.1);
    std::vector<LineSweep> segs;
    double va = 0;
    for (std::size_t k = 1; k < pts.size(); ++k) {
      segs.emplace_back(t, pts[k - 1], pts[k]);
      va += sweep_line(a, segs.back());
    }
    const double vb = sweep_lines(b, std::span<const LineSweep>(segs).first(3), false) +
                      sweep_lines(b, std::span<const LineSweep>(segs).subspan(3), true);
    int diff = 0;
    for (int j = 0; j < a.grid().ny; ++j)
      for (int i = 0; i < a.grid().nx; ++i) diff += a.at(i, j) != b.at(i, j);
    CHECK(diff == 0);
    // Removed volumes differ only by rounding (cells lowered in another order).
    CHECK(vb == deflex::test::within(va, 1e-9));
  }
}

TEST_CASE("row kernels equal lower_height; AVX2 lanes equal the scalar tail") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-6, 6), dz(-3, 3);
  const ToolProfile tools[] = {{EndShape::ball, 4, 4}, {EndShape::flat, 3, 0}, {EndShape::bull, 4, 1.5}};
  const double c = 0.05, gx0 = -12.3;
  int compared = 0;
  for (const ToolProfile& t : tools)
    for (int k = 0; k < 40; ++k) {
      const Point3 a{u(rng), u(rng), dz(rng)};
      Point3 b{a[0] + u(rng) / 4, a[1] + u(rng) / 4, a[2] + (k % 3 == 0 ? 0.0 : dz(rng) / 4)};
      if (k % 10 == 0) b = {a[0], a[1], a[2] - 1};  // plunge
      const LineSweep s(t, a, b);
      for (double y = s.y_min() - 0.3; y < s.y_max() + 0.3; y += 0.37) {
        const int i0 = static_cast<int>(std::floor((s.x_min() - 0.3 - gx0) / c)), n = static_cast<int>((s.x_max() - s.x_min() + 0.6) / c);
        std::vector<float> row(static_cast<std::size_t>(n));
        s.row_heights(y, gx0, c, i0, n, row.data());
        for (int i = 0; i < n; ++i) {
          const double x = gx0 + (i0 + i + 0.5) * c, h = s.lower_height(x, y);
          float one;
          s.row_heights(y, gx0, c, i0 + i, 1, &one);  // scalar path
          CAPTURE(static_cast<int>(t.kind));
          CAPTURE(x);
          CAPTURE(y);
          REQUIRE(std::bit_cast<std::uint32_t>(one) == std::bit_cast<std::uint32_t>(row[static_cast<std::size_t>(i)]));
          if (std::isinf(h) || std::isinf(one)) {
            // Only a cell on the footprint's rim may differ (by rounding).
            if (std::isinf(h) != std::isinf(one)) CHECK(std::fabs(seg_dist(x, y, a, b) - t.radius_mm) < 1e-9);
            continue;
          }
          REQUIRE(std::fabs(one - h) <= 1e-9 + 1e-6 * std::fabs(h));
          ++compared;
        }
      }
    }
  CHECK(compared > 100000);
}

TEST_CASE("chains of short moves with the fast paths equal straightforward sweeps, cell for cell") {
  // Random CAM-like chains (0.05-1 mm moves, smooth or sharp turns) rising,
  // descending (gently and steeply), level and plunging, committed in batches as
  // the simulator does (each batch's start is cut already), against the
  // reference sweep of every move over its whole footprint.
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> u01(0, 1);
  const ToolProfile tools[] = {{EndShape::ball, 3, 3}, {EndShape::flat, 2.5, 0}, {EndShape::bull, 3, 1}, {EndShape::bull, 3, 2.5}};
  for (const ToolProfile& t : tools)
    for (int mode = 0; mode < 5; ++mode) {  // 0 level, 1 rising, 2 descending, 3 steep descents, 4 mixed + plunges
      CAPTURE(static_cast<int>(t.kind));
      CAPTURE(t.corner_radius_mm);
      CAPTURE(mode);
      // A pre-cut surface, so earlier "passes" leave cells below the new ones.
      ZMap fast = trenched_box(), ref = trenched_box();
      std::vector<Point3> pts{{6 + 4 * u01(rng), 6 + 4 * u01(rng), -0.5}};
      double heading = 2 * std::numbers::pi * u01(rng);
      for (int k = 0; k < 160; ++k) {
        heading += u01(rng) < 0.1 ? (u01(rng) - 0.5) * 3 : (u01(rng) - 0.5) * 0.3;
        const double step = 0.05 + 0.95 * u01(rng);
        Point3 p = pts.back();
        // Stay inside [5, 25]^2: turn back toward the centre.
        if (p[0] < 5 || p[0] > 25 || p[1] < 5 || p[1] > 25) heading = std::atan2(15 - p[1], 15 - p[0]);
        double dzs = 0;
        switch (mode) {
          case 1: dzs = 0.1 * u01(rng); break;
          case 2: dzs = -0.1 * u01(rng); break;
          case 3: dzs = u01(rng) < 0.5 ? -2 * u01(rng) : 0.5 * u01(rng); break;
          case 4: dzs = (u01(rng) - 0.5) * 0.6; break;
        }
        p[2] = std::clamp(p[2] + dzs * step, -3.0, 0.5);
        if (mode == 4 && u01(rng) < 0.08) {
          p[2] = pts.back()[2] + (u01(rng) < 0.5 ? -0.5 : 0.5);  // plunge or retract
        } else {
          p[0] += step * std::cos(heading);
          p[1] += step * std::sin(heading);
        }
        pts.push_back(p);
      }
      std::vector<LineSweep> segs;
      double vref = 0;
      for (std::size_t k = 1; k < pts.size(); ++k) {
        segs.emplace_back(t, pts[k - 1], pts[k]);
        vref += sweep_line_reference(ref, segs.back());
      }
      double vfast = 0;
      for (std::size_t k = 0; k < segs.size();) {
        const std::size_t n = std::min<std::size_t>(1 + rng() % 25, segs.size() - k);
        vfast += sweep_lines(fast, std::span<const LineSweep>(segs).subspan(k, n), k > 0);
        k += n;
      }
      int higher = 0, lower = 0;
      double worst = 0;
      for (int j = 0; j < ref.grid().ny; ++j)
        for (int i = 0; i < ref.grid().nx; ++i) {
          const float a = fast.at(i, j), b = ref.at(i, j);
          if (a == b) continue;
          const double d = static_cast<double>(a) - b;
          worst = std::max(worst, std::fabs(d));
          (d > 0 ? higher : lower) += std::fabs(d) > 1e-6;
        }
      CHECK(higher == 0);  // no cell the reference lowers is skipped
      CHECK(lower == 0);
      CHECK(worst <= 1e-6);  // float rounding of the same height only
      CHECK(vfast == deflex::test::within(vref, 1e-6));
    }
}

TEST_CASE("max_height_in follows the cuts") {
  ZMap z = zmap_from_box(parse_box("box:0,0,-10,20,20,0"), 0.05);
  CHECK(z.max_height_in(5, 5, 8, 8) == 0);
  const ToolProfile flat{EndShape::flat, 6, 0};
  sweep_line(z, flat, {-10, 10, -2}, {30, 10, -2});  // cuts y in [4, 16] to -2
  CHECK(z.max_height_in(2, 8, 18, 12) == doctest::Approx(-2));
  CHECK(z.max_height_in(2, 3, 18, 12) == 0);  // touches the uncut row y < 4
  CHECK(z.max_height_in(30, 30, 40, 40) == no_material);
}

TEST_CASE("lower_row: cells, removed volume and row / tile maxima equal a per-cell reference") {
  // Random spans (every length 1..200, so every masked tail) over a grid whose
  // edge cuts tiles, heights around the current ones (ties, +inf, below the base).
  GridSpec g;
  g.cell_mm = 0.5;
  g.nx = 150;
  g.ny = 70;
  const double base = -5;
  ZMap z(g, 0.0f, base);
  std::vector<float> ref(static_cast<std::size_t>(g.nx) * g.ny, 0.0f);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> pick(0, 9);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<float> h;
  for (int it = 0; it < 20000; ++it) {
    const int j = std::uniform_int_distribution<int>(0, g.ny - 1)(rng);
    const int n = std::uniform_int_distribution<int>(1, 200)(rng);
    const int i0 = std::uniform_int_distribution<int>(-20, g.nx - 1)(rng);
    h.resize(static_cast<std::size_t>(n));
    double vref = 0;
    for (int k = 0; k < n; ++k) {
      const int i = i0 + k;
      const float cur = (i >= 0 && i < g.nx) ? ref[static_cast<std::size_t>(j) * g.nx + i] : 0.0f;
      const int c = pick(rng);
      float v = c == 0   ? std::numeric_limits<float>::infinity()
                : c == 1 ? cur
                : c == 2 ? static_cast<float>(base - 1)
                         : static_cast<float>(cur == no_material ? -1 : cur - 0.3 * u(rng) + 0.05);
      h[static_cast<std::size_t>(k)] = v;
      if (i < 0 || i >= g.nx) continue;
      float& r = ref[static_cast<std::size_t>(j) * g.nx + i];
      if (v < r) {
        if (r > static_cast<float>(base)) vref += static_cast<double>(r) - std::max(static_cast<double>(v), base);
        r = v < static_cast<float>(base) ? no_material : v;
      }
    }
    const double v = z.lower_row(j, i0, n, h.data());
    REQUIRE(v == deflex::test::within(vref * g.cell_mm * g.cell_mm, 1e-9));
    if (it % 500 == 0 || it + 1 == 20000) {
      for (int jj = 0; jj < g.ny; ++jj)
        for (int i = 0; i < g.nx; ++i)
          REQUIRE(std::bit_cast<std::uint32_t>(z.at(i, jj)) ==
                  std::bit_cast<std::uint32_t>(ref[static_cast<std::size_t>(jj) * g.nx + i]));
      // Row maxima (one-row rectangles) and tile maxima (whole tiles) equal the cells'.
      const int T = ZMap::tile_cells;
      for (int jj = 0; jj < g.ny; ++jj)
        for (int t0 = 0; t0 < g.nx; t0 += T) {
          float m = no_material;
          for (int i = t0; i < std::min(g.nx, t0 + T); ++i) m = std::max(m, z.at(i, jj));
          if (t0 + T > g.nx) m = std::max(m, 0.0f);  // the tile's cells past the grid keep the start height
          const float got = z.max_height_in(z.cx(t0), z.cy(jj), z.cx(std::min(g.nx, t0 + T) - 1), z.cy(jj));
          REQUIRE(got == m);
          REQUIRE(z.none_above(z.cx(t0), z.cy(jj), z.cx(std::min(g.nx, t0 + T) - 1), z.cy(jj), m));
          if (m != no_material)
            REQUIRE_FALSE(z.none_above(z.cx(t0), z.cy(jj), z.cx(std::min(g.nx, t0 + T) - 1), z.cy(jj),
                                       std::nextafter(m, -std::numeric_limits<float>::infinity())));
        }
      for (int tj = 0; tj < g.ny; tj += T)
        for (int t0 = 0; t0 < g.nx; t0 += T) {
          float m = no_material;
          for (int jj = tj; jj < std::min(g.ny, tj + T); ++jj)
            for (int i = t0; i < std::min(g.nx, t0 + T); ++i) m = std::max(m, z.at(i, jj));
          if (t0 + T > g.nx) m = std::max(m, 0.0f);
          REQUIRE(z.max_height_in(z.cx(t0), z.cy(tj), z.cx(std::min(g.nx, t0 + T) - 1),
                                  z.cy(std::min(g.ny, tj + T) - 1)) == m);
        }
    }
  }
}

TEST_CASE("row_ranges equals row_range per row, bit for bit") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  const ToolProfile tools[] = {{EndShape::ball, 8, 8}, {EndShape::bull, 5, 1.5}, {EndShape::flat, 3, 0}};
  long long rows = 0, hits = 0;
  for (int it = 0; it < 3000; ++it) {
    const ToolProfile& t = tools[it % 3];
    const Point3 a{10 * u(rng), 10 * u(rng), u(rng)};
    Point3 b{a[0] + 0.5 * u(rng), a[1] + 0.5 * u(rng), a[2] + 0.3 * u(rng)};
    switch (it / 3 % 7) {  // axis-aligned, level, plunges, retracts, long moves
      case 1: b[1] = a[1]; break;
      case 2: b[0] = a[0]; break;
      case 3: b[2] = a[2]; break;
      case 4: b[0] = a[0], b[1] = a[1], b[2] = a[2] - 1; break;
      case 5: b[0] = a[0], b[1] = a[1], b[2] = a[2] + 1; break;
      case 6: b[0] = a[0] + 20 * u(rng), b[1] = a[1] + 20 * u(rng); break;
      default: break;
    }
    const LineSweep s(t, a, b);
    std::vector<double> ys, x0, x1;
    for (double y = s.y_min() - 0.3; y <= s.y_max() + 0.3; y += 0.05 + 0.01 * u(rng)) ys.push_back(y);
    ys.push_back(a[1]);
    ys.push_back(b[1]);
    ys.push_back(a[1] + t.radius_mm);
    ys.push_back(a[1] - t.radius_mm);
    const int n = static_cast<int>(ys.size());
    x0.assign(ys.size(), 0);
    x1.assign(ys.size(), 0);
    std::vector<unsigned char> ok(ys.size());
    for (const bool cut : {false, true}) {
      s.row_ranges(ys.data(), n, x0.data(), x1.data(), ok.data(), cut);
      for (int k = 0; k < n; ++k) {
        double r0 = 0, r1 = 0;
        const bool want = s.row_range(ys[static_cast<std::size_t>(k)], r0, r1, cut);
        ++rows;
        REQUIRE(static_cast<bool>(ok[static_cast<std::size_t>(k)]) == want);
        if (!want) continue;
        ++hits;
        REQUIRE(std::bit_cast<std::uint64_t>(x0[static_cast<std::size_t>(k)]) == std::bit_cast<std::uint64_t>(r0));
        REQUIRE(std::bit_cast<std::uint64_t>(x1[static_cast<std::size_t>(k)]) == std::bit_cast<std::uint64_t>(r1));
      }
    }
  }
  CHECK(hits > 100000);
  CHECK(hits < rows);
}

}  // TEST_SUITE
