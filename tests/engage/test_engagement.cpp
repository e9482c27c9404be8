// Engagement on a Z-map against the textbook geometry: full slot, half
// immersion (Altintas's acos(1 - 2 a_e / D)), ball at depth a_p (Bagci Eq. 2), ramps,
// plunges, air cuts, and the order "engage on the stock as cut so far, then cut".
#include <doctest/doctest.h>

#include "../support.hpp"

#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include "deflex/engage/path.hpp"
#include "deflex/engage/simulator.hpp"
#include "deflex/force/cutter.hpp"
#include "deflex/force/engagement.hpp"
#include "deflex/stock/build.hpp"

using namespace deflex;
using namespace deflex::engage;
using std::numbers::pi;

namespace {

force::Cutter cutter(stock::EndShape t, double D = 10) {
  force::Cutter c;
  c.type = t;
  c.diameter_mm = D;
  c.flutes = 2;
  c.helix_deg = 30;
  c.flute_length_mm = 20;
  return c;
}

interp::Motion line(stock::Point3 a, stock::Point3 b) { return test::linear_motion(a, b, 1000); }

// A zig-zag of `rows` rows, 0.6 mm apart, of `steps` short wavy segments
// `dx` mm long each, from (-6, 3, -0.4).
std::vector<interp::Motion> wavy_zigzag(int rows, int steps, double dx) {
  std::vector<interp::Motion> path;
  stock::Point3 p{-6, 3, -0.4};
  for (int k = 0; k < rows; ++k) {
    const double y = 3 + 0.6 * k;
    if (k > 0) {
      const stock::Point3 q{p[0], y, p[2]};
      path.push_back(line(p, q));
      p = q;
    }
    for (int s = 0; s < steps; ++s) {
      const double x = p[0] + (k % 2 == 0 ? dx : -dx);
      const stock::Point3 q{x, y, -0.4 + 0.15 * std::sin(x / 3)};
      path.push_back(line(p, q));
      p = q;
    }
  }
  return path;
}

struct Last {
  CLSample cl;
  Metrics m;
  force::Engagement e;
};

// Runs the motions and returns the result at the last CL sample.
Last run(stock::ZMap& z, const force::CutterSlices& cs, std::initializer_list<interp::Motion> ms,
         const Process& proc = {}, const SimOptions& o = {}) {
  Last last;
  Simulator sim(z, cs, proc, o, [&](const CLSample& s, const Metrics& met, const force::Engagement& e) {
    last.cl = s;
    last.m = met;
    last.e = e;
  });
  for (const interp::Motion& m : ms) sim.run(m);
  sim.finish();
  return last;
}

// Tolerance of an interval end: the bisection bracket of the default options.
const double angle_tol = 2 * pi / Options{}.angle_samples / (1 << Options{}.refine_steps);

double vf(const Process& p, int flutes) { return p.fz_mm * flutes * p.spindle_rpm / 60; }

}  // namespace

TEST_SUITE("engage") {

TEST_CASE("full slot: [0, pi] on every engaged slice; a_p, a_e, MRR, CWE, up/down") {
  const auto cs = force::make_slices(cutter(stock::EndShape::flat), 0.1, 20);
  auto z = stock::zmap_from_box(stock::parse_box("box:0,-20,-20,100,20,0"));
  const double ap = 3;
  const Process proc;
  const Last r = run(z, cs, {line({-10, 0, -ap}, {50, 0, -ap})}, proc);
  REQUIRE_FALSE(r.m.air_cut);
  for (std::size_t i = 0; i < cs.slices.size(); ++i) {
    CAPTURE(i);
    if (cs.slices[i].z_mm < ap) {
      REQUIRE(r.e.slices[i].size() == 1);
      CHECK(std::fabs(r.e.slices[i][0].start) <= angle_tol);
      CHECK(std::fabs(r.e.slices[i][0].end - pi) <= angle_tol);
    } else {
      CHECK(r.e.slices[i].empty());
    }
  }
  CHECK(r.m.ap_mm == doctest::Approx(ap));
  CHECK(r.m.ae_mm == deflex::test::within(10, 1e-4));
  CHECK(r.m.d_eff_mm == doctest::Approx(10));
  CHECK(r.m.up_share == deflex::test::within(0.5, 1e-3));
  // Removal rate = feed speed x slot cross-section D a_p; contact = half cylinder.
  CHECK(r.m.mrr_mm3_per_s == deflex::test::within(vf(proc, 2) * 10 * ap, 1e-3));
  CHECK(r.m.cwe_area_mm2 == deflex::test::within(pi * 5 * ap, 1e-3));
}

TEST_CASE("half immersion, up and down milling, four feed directions: the textbook interval") {
  const auto cs = force::make_slices(cutter(stock::EndShape::flat), 0.1, 20);
  const double R = 5, ap = 2;
  const Process proc;
  for (const double ae : {2.0, 5.0, 7.5})
    for (const auto mode : {force::MillingMode::up, force::MillingMode::down})
      for (int dir = 0; dir < 4; ++dir) {
        CAPTURE(ae);
        CAPTURE(dir);
        CAPTURE(mode == force::MillingMode::up);
        // Feed direction X' and the up-milling side Y' = Z x X'.
        const double fx[] = {1, 0, -1, 0}, fy[] = {0, 1, 0, -1};
        const double yx = -fy[dir], yy = fx[dir];
        const double side = mode == force::MillingMode::up ? 1 : -1;  // material on +Y' (up) or -Y'
        // Material: the half plane beyond the wall at (R - a_e) on that side, as an
        // axis-aligned box 100 mm deep around the origin.
        const double w = R - ae;
        double x0 = -50, x1 = 50, y0 = -50, y1 = 50;
        const double nx = side * yx, ny = side * yy;  // unit normal into the material
        if (nx > 0.5) x0 = w;
        if (nx < -0.5) x1 = -w;
        if (ny > 0.5) y0 = w;
        if (ny < -0.5) y1 = -w;
        stock::ZMap z = stock::zmap_from_box({x0, y0, -20, x1, y1, 0});
        const Last r = run(z, cs, {line({-30 * fx[dir], -30 * fy[dir], -ap}, {10 * fx[dir], 10 * fy[dir], -ap})}, proc);
        const auto [want_start, want_end] = test::textbook_immersion(2 * R, ae, mode == force::MillingMode::up);
        for (std::size_t i = 0; i < cs.slices.size() && cs.slices[i].z_mm < ap; ++i) {
          REQUIRE(r.e.slices[i].size() == 1);
          CHECK(std::fabs(r.e.slices[i][0].start - want_start) <= angle_tol);
          CHECK(std::fabs(r.e.slices[i][0].end - want_end) <= angle_tol);
        }
        CHECK(r.m.ae_mm == deflex::test::within(ae, 2e-3));
        CHECK(r.m.ap_mm == doctest::Approx(ap));
        CHECK(r.m.mrr_mm3_per_s == deflex::test::within(vf(proc, 2) * ae * ap, 2e-3));
        if (ae <= R) CHECK(std::fabs(r.m.up_share - (mode == force::MillingMode::up ? 1.0 : 0.0)) < 1e-3);
      }
}

TEST_CASE("ball at depth a_p: exactly the slices below a_p, D_eff = 2 sqrt(a_p (D - a_p))") {
  const double D = 10, R = 5, dz = 0.1;
  const auto cs = force::make_slices(cutter(stock::EndShape::ball, D), dz, 20);
  const Process proc;
  for (const double ap : {0.33, 1.0, 2.03, 4.5}) {
    CAPTURE(ap);
    auto z = stock::zmap_from_box(stock::parse_box("box:0,-20,-20,100,20,0"));
    const Last r = run(z, cs, {line({-10, 0, -ap}, {50, 0, -ap})}, proc);
    for (std::size_t i = 0; i < cs.slices.size(); ++i) {
      CAPTURE(i);
      if (cs.slices[i].z_mm < ap) {
        REQUIRE(r.e.slices[i].size() == 1);
        CHECK(std::fabs(r.e.slices[i][0].start) <= angle_tol);
        CHECK(std::fabs(r.e.slices[i][0].end - pi) <= angle_tol);
      } else {
        CHECK(r.e.slices[i].empty());
      }
    }
    const double deff = 2 * std::sqrt(ap * (D - ap));
    CHECK(r.m.ap_mm == doctest::Approx(ap));
    CHECK(r.m.d_eff_mm == doctest::Approx(deff));
    // Independent check: the widest engaged slice spans a_e, just under D_eff.
    const double top_slice_z = (std::floor(ap / dz - 0.5) + 0.5) * dz;
    const double r_top = std::sqrt(top_slice_z * (D - top_slice_z));
    CHECK(r.m.ae_mm == deflex::test::within(2 * r_top, 1e-4));
    CHECK(r.m.ae_mm <= deff);
    // Removal rate / feed speed = cross-section of the trench (a circular segment).
    const double seg = R * R * std::acos((R - ap) / R) - (R - ap) * std::sqrt(2 * R * ap - ap * ap);
    CHECK(r.m.mrr_mm3_per_s / vf(proc, 2) == deflex::test::within(seg, 0.01));
  }
}

TEST_CASE("air cut above the stock and over cut ground") {
  const auto cs = force::make_slices(cutter(stock::EndShape::ball), 0.1, 20);
  auto z = stock::zmap_from_box(stock::parse_box("box:0,-20,-20,100,20,0"));
  Last r = run(z, cs, {line({10, 0, 0.5}, {60, 0, 0.5})});
  CHECK(r.m.air_cut);
  CHECK(r.e.empty());
  CHECK(r.m.mrr_mm3_per_s == 0);
  CHECK(r.m.ap_mm == 0);
  // Out along y = 0 at depth 1, back along the same line: the way back cuts
  // (almost) nothing because the engagement sees the stock as cut so far. While
  // the outward cut is still pending it is exact (pure air); once committed, the
  // trench wall is resolved to a Z-map cell, so grazing slivers remain.
  int engaged_out = 0, air_back_pending = 0, n_back = 0;
  double mrr_out = 0, mrr_back_max = 0;
  Simulator sim(z, cs, {}, {}, [&](const CLSample& s, const Metrics& m, const force::Engagement&) {
    if (s.motion == 0) {
      engaged_out += !m.air_cut;
      mrr_out = m.mrr_mm3_per_s;
      return;
    }
    if (60 - s.point.tip_mm[0] < 20) air_back_pending += m.air_cut;
    mrr_back_max = std::max(mrr_back_max, m.mrr_mm3_per_s);
    ++n_back;
  });
  sim.run(line({-10, 0, -1}, {60, 0, -1}));
  sim.run(line({60, 0, -1}, {20, 0, -1}));
  sim.finish();
  CHECK(engaged_out > 100);
  CHECK(n_back == 80);
  CHECK(air_back_pending == 39);
  CHECK(mrr_back_max < 0.01 * mrr_out);
}

TEST_CASE("descending ramp: the ball engages the hemisphere facing the travel") {
  // A sphere moving along d cuts where its outward normal n has n . d > 0; with
  // n = (sin k sin phi, sin k cos phi, -cos k) and d = (cos a, 0, sin a) that is
  // sin(phi) > cot(k) tan(a): phi in (-asin c, pi + asin c), c = -cot(k) tan(a).
  const auto cs = force::make_slices(cutter(stock::EndShape::ball), 0.1, 20);
  auto z = stock::zmap_from_box(stock::parse_box("box:-50,-50,-40,50,50,0"));
  const double a = -30 * pi / 180;
  const double run_xy = 20;
  const Last r = run(z, cs, {line({-10, 0, 2}, {-10 + run_xy, 0, 2 + run_xy * std::tan(a)})});
  CHECK(r.m.ramp_angle == doctest::Approx(a));
  CHECK_FALSE(r.m.plunge);
  for (std::size_t i = 0; i < cs.slices.size() && cs.slices[i].z_mm < 5; ++i) {
    CAPTURE(i);
    const force::Slice& s = cs.slices[i];
    const double c = -s.cos_kappa / s.sin_kappa * std::tan(a);
    if (c >= 1) {
      REQUIRE(r.e.slices[i].size() == 1);
      CHECK(r.e.slices[i][0].end - r.e.slices[i][0].start == doctest::Approx(2 * pi));
      continue;
    }
    const double lo = -std::asin(c), hi = pi + std::asin(c);
    REQUIRE(r.e.slices[i].size() == 1);
    const auto& iv = r.e.slices[i][0];
    const double start = iv.start > pi ? iv.start - 2 * pi : iv.start;  // unwrapped
    CHECK(std::fabs(start - lo) <= 2 * angle_tol);
    CHECK(std::fabs(start + (iv.end - iv.start) - hi) <= 2 * angle_tol);
  }
}

TEST_CASE("plunge: a flat end cuts with its bottom only, a ball with its lower half") {
  const Process proc;
  auto z = stock::zmap_from_box(stock::parse_box("box:-20,-20,-40,20,20,0"));
  const auto flat = force::make_slices(cutter(stock::EndShape::flat), 0.1, 20);
  Last r = run(z, flat, {line({0, 0, 5}, {0, 0, -3})}, proc);
  CHECK(r.m.plunge);
  CHECK(r.m.ramp_angle == doctest::Approx(-pi / 2));
  CHECK(r.e.empty());  // the flanks slide along their own earlier positions
  CHECK_FALSE(r.m.air_cut);
  CHECK(r.m.bottom_area_mm2 == deflex::test::within(pi * 25, 1e-9));
  CHECK(r.m.mrr_mm3_per_s == deflex::test::within(vf(proc, 2) * pi * 25, 1e-9));
  CHECK(r.m.ap_mm == 0);  // no flank cuts

  auto z2 = stock::zmap_from_box(stock::parse_box("box:-20,-20,-40,20,20,0"));
  const auto ball = force::make_slices(cutter(stock::EndShape::ball), 0.1, 20);
  r = run(z2, ball, {line({0, 0, 5}, {0, 0, -8})}, proc);
  for (std::size_t i = 0; i < ball.slices.size(); ++i) {
    CAPTURE(i);
    if (ball.slices[i].z_mm < 5) {
      REQUIRE(r.e.slices[i].size() == 1);
      CHECK(r.e.slices[i][0].end - r.e.slices[i][0].start == doctest::Approx(2 * pi));
    } else {
      CHECK(r.e.slices[i].empty());
    }
  }
  // Removal rate of a plunging ball: v times its cross-section pi R^2 (slice sum).
  CHECK(r.m.mrr_mm3_per_s == deflex::test::within(vf(proc, 2) * pi * 25, 2e-3));
}

TEST_CASE("batched parallel evaluation and commits beside it give the same results on 1 thread and on all") {
  const auto cs = force::make_slices(cutter(stock::EndShape::ball), 0.05, 12);
  const std::vector<interp::Motion> path = wavy_zigzag(4, 60, 0.5);
  // The reference: one thread, each commit done before anything goes on;
  // then commits beside the evaluations on one thread (run when waited for)
  // and on all, with the default and with a short keep (commits that the
  // next batch's tiles meet, so it waits, and ones it does not).
  struct Config {
    int threads;
    bool beside;
    double keep_mm;
  };
  const Config configs[] = {{1, false, 0}, {1, true, 0}, {0, true, 0}, {0, true, 2}, {1, false, 2}};
  std::vector<Metrics> results[5];
  std::vector<float> cells[5];
  for (int run_ = 0; run_ < 5; ++run_) {
    auto z = stock::zmap_from_box(stock::parse_box("box:0,0,-20,40,20,0"));
    SimOptions o;
    o.threads = configs[run_].threads;
    o.commit_beside = configs[run_].beside;
    o.keep_mm = configs[run_].keep_mm;
    o.batch_mm = 3;
    Simulator sim(z, cs, {}, o, [&](const CLSample&, const Metrics& m, const force::Engagement&) {
      results[run_].push_back(m);
    });
    for (const auto& m : path) sim.run(m);
    sim.finish();
    for (int j = 0; j < z.grid().ny; ++j)
      for (int i = 0; i < z.grid().nx; ++i) cells[run_].push_back(z.at(i, j));
  }
  int engaged = 0;
  for (int run_ = 1; run_ < 5; ++run_) {
    CAPTURE(run_);
    const int ref = configs[run_].keep_mm > 0 ? 4 : 0;  // the sequential run with the same keep
    REQUIRE(results[ref].size() == results[run_].size());
    for (std::size_t i = 0; i < results[ref].size(); ++i) {
      CHECK(results[ref][i].mrr_mm3_per_s == results[run_][i].mrr_mm3_per_s);
      CHECK(results[ref][i].ae_mm == results[run_][i].ae_mm);
      CHECK(results[ref][i].ap_mm == results[run_][i].ap_mm);
      engaged += !results[ref][i].air_cut;
    }
    CHECK(cells[ref] == cells[run_]);  // the stock as cut, cell for cell
  }
  CHECK(engaged > 4 * static_cast<int>(results[0].size()) / 2);
}

TEST_CASE("probe_ahead: each sample as probe() meets it after run() of the motions before, up to the first commit") {
  // A wavy raster with an arc and a rapid, probed ahead from every motion on
  // against probing one at a time and running each: the engagement bit for
  // bit, the window ending at the motion whose run() commits.
  const auto cs = force::make_slices(cutter(stock::EndShape::ball), 0.05, 12);
  std::vector<interp::Motion> path = wavy_zigzag(3, 30, 0.7);
  const stock::Point3 p = path.back().end_mm;
  interp::Motion arc;
  arc.kind = interp::MotionKind::arc_ccw;
  arc.fixed = interp::Fixed::no;
  arc.feed_mm_per_min = 1000;
  arc.start_mm = p;
  arc.center_mm = {p[0], p[1] + 2, p[2]};
  arc.end_mm = {p[0], p[1] + 4, p[2]};
  path.push_back(arc);
  interp::Motion rapid = line(arc.end_mm, {arc.end_mm[0] + 3, arc.end_mm[1], arc.end_mm[2]});
  rapid.kind = interp::MotionKind::rapid;
  path.push_back(rapid);
  path.push_back(line(rapid.end_mm, {rapid.end_mm[0] + 3, rapid.end_mm[1] - 1, rapid.end_mm[2]}));
  for (int threads : {1, 0}) {
    CAPTURE(threads);
    auto z = stock::zmap_from_box(stock::parse_box("box:-10,0,-20,40,20,0"));
    SimOptions o;
    o.threads = threads;
    o.batch_mm = 3;
    Simulator sim(z, cs, {}, o);
    int compared = 0, windows = 0;
    for (std::size_t i = 0; i < path.size(); ++i) {
      std::vector<std::vector<std::optional<Metrics>>> ahead(path.size() - i, std::vector<std::optional<Metrics>>(64));
      const std::size_t covered = sim.probe_ahead(
          std::span<const interp::Motion>(path).subspan(i),
          [&](std::size_t j, int k, const CLSample&, const Metrics& m, const force::Engagement&) {
            ahead[j][static_cast<std::size_t>(k)] = m;
          });
      REQUIRE(covered >= 1);
      windows += covered > 1;
      // One at a time: probe each sample, then run the motion.
      for (std::size_t j = 0; j < covered; ++j) {
        const interp::Motion& m = path[i + j];
        if (m.kind != interp::MotionKind::rapid) {
          const std::vector<Point3> v = motion_vertices(m, o.path);
          for (int k = 1; k < static_cast<int>(v.size()); ++k) {
            CLSample cl;
            force::Engagement e;
            const Metrics one = sim.probe(m, v, k, cl, e);
            REQUIRE(ahead[j][static_cast<std::size_t>(k)]);
            const Metrics& a = *ahead[j][static_cast<std::size_t>(k)];
            CHECK(a.ap_mm == one.ap_mm);
            CHECK(a.ae_mm == one.ae_mm);
            CHECK(a.cwe_area_mm2 == one.cwe_area_mm2);
            CHECK(a.mrr_mm3_per_s == one.mrr_mm3_per_s);
            ++compared;
          }
        }
        // Only the window's last motion may commit: probing ahead of it
        // would see a stock its run changes.
        const std::size_t pending = sim.pending_count();
        sim.run(m);
        if (j + 1 < covered) CHECK(sim.pending_count() > pending);
      }
      i += covered - 1;
    }
    CHECK(compared > 60);
    CHECK(windows > 5);
  }
}

TEST_CASE("CL samples: end points, spacing, arcs on the arc, plunge keeps the feed frame") {
  PathOptions o;
  o.cl_spacing_mm = 0.5;
  interp::Motion arc;
  arc.kind = interp::MotionKind::arc_ccw;
  arc.fixed = interp::Fixed::no;
  arc.start_mm = {10, 0, 0};
  arc.end_mm = {0, 10, 0};
  arc.center_mm = {0, 0, 0};
  const interp::Motion ms[] = {line({0, 0, 0}, {0, 2.2, 0}), line({0, 2.2, 0}, {0, 2.2, -1}), arc};
  std::array<double, 2> feed{1, 0};
  const auto s = cl_samples(ms, o, &feed);
  REQUIRE(s.size() >= 5 + 2 + 32);
  CHECK(s[4].point.tip_mm[1] == 2.2);  // the end point is a sample, exactly
  CHECK(s[4].index == 5);
  CHECK(s[4].count == 5);
  CHECK(s[0].point.tip_mm[1] == doctest::Approx(0.44));
  // The plunge keeps the previous XY direction (+Y) as its feed frame.
  CHECK(s[5].point.feed_x == doctest::Approx(0));
  CHECK(s[5].point.feed_y == doctest::Approx(1));
  CHECK(s[5].point.dir[2] == doctest::Approx(-1));
  for (std::size_t k = 7; k < s.size(); ++k) {
    const auto& p = s[k].point;
    CHECK(std::hypot(p.tip_mm[0], p.tip_mm[1]) == doctest::Approx(10));
    // Counter-clockwise tangent is Z x radius.
    CHECK(p.feed_x == doctest::Approx(-p.tip_mm[1] / 10));
    CHECK(p.feed_y == doctest::Approx(p.tip_mm[0] / 10));
    if (k > 7)
      CHECK(std::hypot(p.tip_mm[0] - s[k - 1].point.tip_mm[0], p.tip_mm[1] - s[k - 1].point.tip_mm[1]) <= 0.5);
  }
  CHECK(s.back().point.tip_mm == arc.end_mm);
}

TEST_CASE("slot along an arc: [0, pi] in the arc's own feed frame") {
  const auto cs = force::make_slices(cutter(stock::EndShape::flat), 0.1, 20);
  auto z = stock::zmap_from_box(stock::parse_box("box:-40,-40,-20,40,40,0"));
  interp::Motion arc;
  arc.kind = interp::MotionKind::arc_cw;
  arc.fixed = interp::Fixed::no;
  arc.start_mm = {0, 25, -2};
  arc.end_mm = {25, 0, -2};
  arc.center_mm = {0, 0, -2};
  // Enter from outside the stock, then a quarter circle.
  const Last r = run(z, cs, {line({-50, 25, -2}, {0, 25, -2}), arc});
  // A slot along a circle of radius 25: the tool's wake is the annulus behind,
  // so every slice is engaged on the front half, [0, pi] in the frame of the exact
  // tangent, up to the chords: the tool arrives along a chord turned by half the
  // chord angle.
  const interp::Arc a = arc_of(arc);
  const int chords = static_cast<int>(motion_vertices(arc, PathOptions{}).size()) - 1;
  const double half_chord = interp::arc_angle(a) / chords / 2;
  for (std::size_t i = 0; i < cs.slices.size() && cs.slices[i].z_mm < 2; ++i) {
    REQUIRE(r.e.slices[i].size() == 1);
    const auto& iv = r.e.slices[i][0];
    const double start = iv.start > pi ? iv.start - 2 * pi : iv.start;
    CHECK(std::fabs(start) < half_chord + angle_tol);
    CHECK(std::fabs(start + iv.end - iv.start - pi) < half_chord + angle_tol);
  }
  CHECK(r.m.ae_mm == deflex::test::within(10, 1e-3));
}

}  // TEST_SUITE
