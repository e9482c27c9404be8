// Chains of short moves: sweep_lines leaves a move's cells that the next chained
// move lowers further to that move (end_handoff); the Z-map must stay the same,
// bit for bit, as sweeping the moves one by one (sweep_line with start_cut when
// chained, which is what sweep_lines did before the hand-off).
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <span>
#include <vector>

#include "../support.hpp"
#include "deflex/stock/sweep.hpp"

using namespace deflex::stock;

namespace {

constexpr double pi = std::numbers::pi;

double sweep_one_by_one(ZMap& z, std::span<const LineSweep> s, bool first_start_cut) {
  double v = 0;
  for (std::size_t k = 0; k < s.size(); ++k)
    v += sweep_line(z, s[k], k == 0 ? first_start_cut : s[k].a() == s[k - 1].b());
  return v;
}

ToolProfile random_tool(std::mt19937& rng, int kind) {
  std::uniform_real_distribution<double> u01(0, 1);
  const double R = 1 + 3 * u01(rng);
  if (kind == 0) return {EndShape::ball, R, R};
  if (kind == 1) return {EndShape::flat, R, 0};
  return {EndShape::bull, R, R * (0.1 + 0.9 * u01(rng))};
}

// A CAM-like chain inside [cx - 7, cx + 7]^2 around z = 0 (shape by mode).
std::vector<Point3> random_chain(std::mt19937& rng, int mode, double cx, double cy) {
  std::uniform_real_distribution<double> u01(0, 1);
  std::vector<Point3> pts{{cx + 4 * (u01(rng) - 0.5), cy + 4 * (u01(rng) - 0.5), -0.5 - u01(rng)}};
  const int n = 8 + static_cast<int>(rng() % 40);
  if (mode == 5) {  // arc or helix as chords (start tangent anywhere)
    const double r = 0.5 + 6 * u01(rng), t0 = 2 * pi * u01(rng);
    const Point3 c{pts[0][0] - r * std::cos(t0), pts[0][1] - r * std::sin(t0), pts[0][2]};
    deflex::interp::Arc a{pts[0], {}, c, 17, u01(rng) < 0.5};
    const double t1 = t0 + (a.cw ? -1 : 1) * (0.2 + 5 * u01(rng));
    a.end_mm = {c[0] + r * std::cos(t1), c[1] + r * std::sin(t1), pts[0][2] + (u01(rng) - 0.5) * 2};
    return arc_polyline(a, std::clamp(arc_chord_count(a, 0.0005 + 0.01 * u01(rng)), 2, 80));
  }
  double heading = 2 * pi * u01(rng);
  const double slope = mode == 1 ? 1.5 * u01(rng) * u01(rng) : mode == 2 ? -1.5 * u01(rng) * u01(rng) : 0;
  for (int k = 0; k < n; ++k) {
    double step = 0.3 + 0.3 * u01(rng);  // typical finishing CL spacing
    double dz = slope * step;
    switch (mode) {
      case 0:  // level, gentle turns
        heading += (u01(rng) - 0.5) * 0.2;
        break;
      case 1:
      case 2:  // ramps, now and then a sharp turn
        heading += u01(rng) < 0.15 ? (u01(rng) - 0.5) * 3 : (u01(rng) - 0.5) * 0.2;
        break;
      case 3:  // zig-zag: sharp turns and exact reversals, level or not
        if (u01(rng) < 0.4) heading += u01(rng) < 0.5 ? pi : (u01(rng) - 0.5) * 4;
        step = 0.05 + u01(rng);
        dz = u01(rng) < 0.5 ? 0 : (u01(rng) - 0.5) * step;
        break;
      case 4:  // tiny moves, many shorter than a cell
        step = std::pow(10.0, -5 + 5 * u01(rng));
        heading += (u01(rng) - 0.5) * 1.0;
        dz = (u01(rng) - 0.5) * step * (u01(rng) < 0.3 ? 0 : 1);
        break;
      default:  // mixed: steep ramps, reversals on a ramp, plunges and retracts
        heading += u01(rng) < 0.2 ? pi : (u01(rng) - 0.5) * 1.5;
        step = 0.02 + 0.8 * u01(rng);
        dz = (u01(rng) - 0.5) * step * (u01(rng) < 0.2 ? 8 : 1);
        break;
    }
    Point3 p = pts.back();
    if (std::hypot(p[0] - cx, p[1] - cy) > 5) heading = std::atan2(cy - p[1], cx - p[0]);
    if (mode >= 6 && u01(rng) < 0.08) {
      p[2] += u01(rng) < 0.5 ? -0.3 : 0.3;  // plunge or retract
    } else {
      p[0] += step * std::cos(heading);
      p[1] += step * std::sin(heading);
      p[2] = std::clamp(p[2] + dz, -3.0, 0.5);
    }
    pts.push_back(p);
  }
  return pts;
}

}  // namespace

TEST_SUITE("stock") {

TEST_CASE("chained moves leaving cells to the next one equal one-by-one sweeps, bit for bit") {
  std::mt19937 rng(4711);
  std::uniform_real_distribution<double> u01(0, 1);
  const double cells[] = {0.05, 0.07, 0.1};
  int cases = 0, differing = 0;
  long long handed[3] = {0, 0, 0};  // per tool kind
  for (int mode = 0; mode < 7; ++mode)
    for (int kind = 0; kind < 3; ++kind)
      for (int rep = 0; rep < 16; ++rep, ++cases) {
        const ToolProfile t = random_tool(rng, kind);
        const double c = cells[rng() % 3];
        // Far from the origin now and then (coarser rounding), grid not aligned to the path.
        const double ox = rep % 4 == 3 ? 400 + 100 * u01(rng) : 10 * u01(rng), oy = 10 * u01(rng);
        const int n_cells = static_cast<int>(26 / c);
        const GridSpec g{ox - 12.3 * u01(rng), oy - 12.3 * u01(rng), c, n_cells, n_cells};
        const double cx = g.x0_mm + 13, cy = g.y0_mm + 13;
        ZMap fast(g, 0.0f, -50), ref(g, 0.0f, -50);
        if (rep % 2 == 1)  // a pre-cut surface: earlier passes leave some cells lower than the new ones
          for (ZMap* z : {&fast, &ref})
            sweep_line_reference(*z, LineSweep({EndShape::ball, 4, 4}, {cx - 13, cy - 2, -1.2},
                                               {cx + 13, cy + 3, -0.8}));
        const std::vector<Point3> pts = random_chain(rng, mode, cx, cy);
        std::vector<LineSweep> segs;
        for (std::size_t k = 1; k < pts.size(); ++k) segs.emplace_back(t, pts[k - 1], pts[k]);
        if (rep % 5 == 4 && segs.size() > 4) {  // a break in the chain: a move not starting where the last ended
          const std::size_t k = segs.size() / 2;
          Point3 a = segs[k].a();
          a[0] += 0.3;
          segs[k] = LineSweep(t, a, segs[k].b());
        }
        for (std::size_t k = 0; k + 1 < segs.size(); ++k)
          for (int j = 0; j < g.ny; ++j) {
            double x0, x1;
            if (segs[k].row_range(ref.cy(j), x0, x1, true) && segs[k].end_handoff(segs[k + 1], ref.cy(j), x0, x1))
              handed[kind] += static_cast<long long>((x1 - x0) / c);
          }
        // Batches as the simulator commits them (each one's start is cut already).
        double vfast = 0, vref = 0;
        for (std::size_t k = 0; k < segs.size();) {
          const std::size_t n = std::min<std::size_t>(1 + rng() % 30, segs.size() - k);
          const std::span<const LineSweep> batch = std::span<const LineSweep>(segs).subspan(k, n);
          vfast += sweep_lines(fast, batch, k > 0);
          vref += sweep_one_by_one(ref, batch, k > 0);
          k += n;
        }
        int diff = 0;
        for (int j = 0; j < g.ny; ++j)
          for (int i = 0; i < g.nx; ++i)
            diff += std::bit_cast<std::uint32_t>(fast.at(i, j)) != std::bit_cast<std::uint32_t>(ref.at(i, j));
        if (diff != 0) {
          CAPTURE(mode);
          CAPTURE(kind);
          CAPTURE(rep);
          CHECK(diff == 0);
          ++differing;
        }
        // Volumes only differ by the order of the additions.
        CHECK(vfast == deflex::test::within(vref, 1e-9));
      }
  CHECK(differing == 0);
  CHECK(cases == 336);
  MESSAGE(cases, " random chains; cells left to the next move: ~", handed[0], " ball, ~", handed[1], " flat, ~",
          handed[2], " bull");
  for (const long long h : handed) CHECK(h > 100'000);  // the hand-off is exercised for every kind
}

TEST_CASE("cells left to the next move: inside its row range and its height is not above") {
  // Move pairs of every kind, slope and turn (incl. reversals), long and very short,
  // large tools and coordinates far from the origin: on every row, each cell of
  // end_handoff is one the next move evaluates, to a height <= this move's, and
  // lower than this move's by a margin far above the rounding of the kernels.
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> u01(0, 1);
  long long checked = 0;
  int pairs = 0;
  for (int it = 0; it < 3000; ++it) {
    const int kind = it % 3;
    const double R = it % 7 == 0 ? 10 + 15 * u01(rng) : 0.5 + 8 * u01(rng);
    const ToolProfile t = kind == 0 ? ToolProfile{EndShape::ball, R, R}
                          : kind == 1 ? ToolProfile{EndShape::flat, R, 0}
                                      : ToolProfile{EndShape::bull, R, R * (0.05 + 0.95 * u01(rng))};
    auto slope = [&] {
      const double r = u01(rng);
      if (r < 0.3) return 0.0;
      const double m = r < 0.8 ? 0.3 * u01(rng) : 3 * u01(rng);
      return u01(rng) < 0.5 ? m : -m;
    };
    auto length = [&] { return std::pow(10.0, -3 + 3.5 * u01(rng)); };
    const double far = it % 4 == 0 ? 1000 * u01(rng) : 0;
    const Point3 a{far + u01(rng), -far + u01(rng), -far / 10 + u01(rng)};
    const double h0 = 2 * pi * u01(rng);
    const double r = u01(rng);
    const double turn = r < 0.3 ? 0 : r < 0.45 ? pi : r < 0.7 ? (u01(rng) - 0.5) * 0.3 : 2 * pi * u01(rng);
    const double L0 = length(), L1 = length();
    const Point3 b{a[0] + L0 * std::cos(h0), a[1] + L0 * std::sin(h0), a[2] + slope() * L0};
    const Point3 c{b[0] + L1 * std::cos(h0 + turn), b[1] + L1 * std::sin(h0 + turn), b[2] + slope() * L1};
    const LineSweep k(t, a, b), n(t, b, c);
    const double cell = R / (20 + 40 * u01(rng)), gx0 = a[0] - 1000 * cell - cell * u01(rng);
    std::vector<float> hk, hn;
    bool any = false;
    const bool start_cut = u01(rng) < 0.5;
    for (double y = b[1] - R - cell * u01(rng); y <= b[1] + R; y += cell) {
      double x0, x1, na, nb;
      if (!k.row_range(y, x0, x1, start_cut) || !k.end_handoff(n, y, x0, x1)) continue;
      REQUIRE(n.row_range(y, na, nb, true));
      const int i0 = static_cast<int>(std::ceil((x0 - gx0) / cell - 0.5));
      const int i1 = static_cast<int>(std::floor((x1 - gx0) / cell - 0.5));
      if (i1 < i0) continue;
      const int cnt = i1 - i0 + 1;
      hk.resize(static_cast<std::size_t>(cnt));
      hn.resize(static_cast<std::size_t>(cnt));
      k.row_heights(y, gx0, cell, i0, cnt, hk.data());
      n.row_heights(y, gx0, cell, i0, cnt, hn.data());
      for (int i = 0; i < cnt; ++i) {
        const double x = gx0 + (i0 + i + 0.5) * cell;
        CAPTURE(it);
        CAPTURE(x);
        CAPTURE(y);
        REQUIRE(x >= na);
        REQUIRE(x <= nb);
        REQUIRE(hn[static_cast<std::size_t>(i)] <= hk[static_cast<std::size_t>(i)]);
        // With the margin of handoff.cpp (>= 1.4e-5 mm lower; rounding is far below).
        const double lk = k.lower_height(x, y);
        if (lk != std::numeric_limits<double>::infinity()) REQUIRE(n.lower_height(x, y) <= lk - 1e-5);
      }
      checked += cnt;
      any = true;
    }
    pairs += any;
  }
  MESSAGE(pairs, " move pairs hand cells over, ", checked, " cells checked");
  CHECK(pairs > 1000);
  CHECK(checked > 1'000'000);
}

TEST_CASE("short pieces of a row (hand-off gaps) equal the cells one by one, bit for bit") {
  // The vector kernels finish a piece with a partly used block of 4 cells.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-3, 3);
  const ToolProfile tools[] = {{EndShape::ball, 4, 4}, {EndShape::flat, 3, 0}, {EndShape::bull, 4, 1.5}};
  const double c = 0.05, gx0 = -7.1;
  int compared = 0;
  for (const ToolProfile& t : tools)
    for (int k = 0; k < 60; ++k) {
      const Point3 a{u(rng), u(rng), u(rng)}, b{a[0] + u(rng) / 5, a[1] + u(rng) / 5, a[2] + (k % 3 ? u(rng) / 5 : 0)};
      const LineSweep s(t, a, b);
      const double y = a[1] + u(rng);
      for (int n = 1; n <= 13; ++n) {
        const int i0 = static_cast<int>((a[0] - gx0) / c) - 60 + static_cast<int>(rng() % 120);
        std::vector<float> piece(static_cast<std::size_t>(n));
        s.row_heights(y, gx0, c, i0, n, piece.data());
        for (int i = 0; i < n; ++i) {
          float one;
          s.row_heights(y, gx0, c, i0 + i, 1, &one);
          const float p = piece[static_cast<std::size_t>(i)];
          REQUIRE(std::bit_cast<std::uint32_t>(one) == std::bit_cast<std::uint32_t>(p));
          ++compared;
        }
      }
    }
  CHECK(compared == 3 * 60 * 91);
}

TEST_CASE("a straight chain leaves most of each move's front half-disc to the next move") {
  // What makes chains of short moves fast: a level ball move 0.5 mm long evaluates
  // its band and only a sliver of the D16 front half-disc.
  const ToolProfile ball{EndShape::ball, 8, 8};
  const LineSweep k(ball, {0, 0, -1}, {0.5, 0, -1}), n(ball, {0.5, 0, -1}, {1, 0, -1});
  double half_disc = 0, left = 0;
  for (double y = -8; y <= 8; y += 0.05) {
    double x0, x1;
    if (std::fabs(y) < 8) half_disc += std::sqrt(64 - y * y) * 0.05;
    if (k.row_range(y, x0, x1, true) && k.end_handoff(n, y, x0, x1)) left += (x1 - x0) * 0.05;
  }
  CHECK(left > 0.98 * half_disc);
  CHECK(left < half_disc);
}

}  // TEST_SUITE
