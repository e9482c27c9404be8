// The spindle's load along a program and what --feed-limit does with it: the
// feed lowered by the share the model gives (checked by simulating again at the
// lowered feed), the edge forces taken into account, and the plausibility
// findings where the cut asks more than the spindle's rating.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "../support.hpp"
#include "deflex/compensate/compensate.hpp"
#include "deflex/compensate/plausibility.hpp"
#include "deflex/force/material.hpp"
#include "deflex/stock/build.hpp"

using namespace deflex;

namespace {

// Side milling of a wall along +X with the D10 flat end T1 of the sample
// library (a_e 2 mm, a_p 10 mm), in Al7075-T6, whose sample coefficients
// carry edge forces: the force is affine in the feed, not proportional.
const char* kWall =
    "%\nO0001\nN1 G21 G90 G17 G40 G49 G80 G54\nN2 T1 M06\nN3 S8000 M03\nN4 G00 X-10. Y-3. Z5.\n"
    "N5 G01 Z-10. F800.\nN6 X20.\nN7 X50.\nN8 X80.\nN9 X110.\nN10 G00 Z5.\nN11 M30\n%\n";

struct Wall {
  test::Interpreted in = test::interpret_text(kWall);
  stock::ZMap stock = stock::make_stock("box:0,0,-20,100,20,0", {});
  compensate::Physics ph;
  compensate::Settings s;
  Wall() {
    REQUIRE(in.errors == 0);
    ph.tools = stiffness::load_tool_library("samples/tools.yaml");
    ph.machine = stiffness::load_machine_stiffness("samples/machines/mill3.yaml");
    ph.k = force::find_material(force::load_material_library("samples/materials.yaml"), "Al7075-T6").k;
    ph.stock = &stock;
    s.tolerance_mm = 0.002;
    s.threads = 1;
    s.gain = 0;  // nothing moves: the points at the lowered feeds are on the same path
  }
  std::vector<compensate::Point> run(double feed_scale = 1) const {
    std::vector<interp::Motion> m = in.motions;
    for (interp::Motion& x : m) x.feed_mm_per_min *= feed_scale;
    return compensate::simulate(m, {}, ph, s);
  }
};

bool cutting(const compensate::Point& p) { return !p.air && !p.plunge; }

// A rating that allows `torque_Nm` at every speed.
profile::SpindleRating flat_rating(double torque_Nm, double max_rpm = 20000) {
  profile::SpindleRating r;
  r.set = true;
  r.max_rpm = max_rpm;
  r.s1.rpm = {0, max_rpm};
  r.s1.torque_Nm = {torque_Nm, torque_Nm};
  return r;
}

}  // namespace

TEST_SUITE("compensate") {

TEST_CASE("spindle load: torque and power at every cutting point, P = M 2 pi n / 60") {
  Wall w;
  const auto pts = w.run();
  std::size_t n = 0;
  for (const compensate::Point& p : pts) {
    if (!cutting(p)) continue;
    ++n;
    CHECK(p.spindle_rpm == 8000);
    CHECK(p.torque_Nm > 0);
    CHECK(p.power_kW == deflex::test::within(p.torque_Nm * 2 * std::numbers::pi * 8000 / 60 / 1000, 1e-12));
    CHECK(p.feed_share == 1);  // no feed limit: not computed
  }
  CHECK(n > 50);
}

// The lowest feed run on the wall's cutting blocks (N6..N9, programmed F800).
double lowest_cutting_feed(const compensate::Result& r) {
  double lowest = 800;
  for (std::size_t i = 0; i < r.motions.size(); ++i)
    if (r.motions[i].kind == interp::MotionKind::linear && r.motions[i].moves_xy())
      lowest = std::min(lowest, r.feeds_mm_per_min[i]);
  return lowest;
}

TEST_CASE("--feed-limit with edge forces: at the lowered feed the peak force meets the limit") {
  Wall w;
  // A limit between the edge forces alone (the feed far down) and the peak as written.
  double peak = 0, edge = 0;
  for (const auto& p : w.run()) peak = std::max(peak, p.peak_N);
  for (const auto& p : w.run(1e-9)) edge = std::max(edge, p.peak_N);
  REQUIRE(edge > 0.3 * peak);  // the edge forces matter here
  const double limit_N = edge + 0.5 * (peak - edge);
  w.s.feed_limit_N = limit_N;
  const auto r = compensate::compensate(w.in.motions, w.ph, w.s);
  REQUIRE_FALSE(r.feed_lowered_lines.empty());
  double after = 0;
  for (const auto& p : r.final) after = std::max(after, p.peak_N);
  CHECK(after <= limit_N * (1 + 1e-6));
  CHECK(after >= 0.99 * limit_N);  // lowered no more than the 0.1 mm/min rounding asks
  // Scaling F by limit / peak, the edge forces forgotten, would run faster and miss the limit.
  CHECK(lowest_cutting_feed(r) < 800 * limit_N / peak - 1);
}

TEST_CASE("--feed-limit and the spindle's S1 curve: the feed lowered by the torque's share") {
  Wall w;
  const auto full = w.run(1.0), half = w.run(0.5);
  REQUIRE(full.size() == half.size());
  // The torque is affine in the feed: M = M_c + M_e at F, M_c / 2 + M_e at F / 2.
  double most = 0, edge = 0;
  for (std::size_t i = 0; i < full.size(); ++i) {
    most = std::max(most, full[i].torque_Nm);
    edge = std::max(edge, 2 * half[i].torque_Nm - full[i].torque_Nm);
  }
  REQUIRE(edge > 0.1 * most);  // the edge's part is there: a plain ratio would be wrong
  const double allowed_Nm = edge + 0.4371 * (most - edge);  // a share off the 0.1 mm/min rounding steps
  double share = 1;  // the least over the cutting blocks' points (N6..N9 all at F800)
  for (std::size_t i = 0; i < full.size(); ++i) {
    if (!cutting(full[i]) || full[i].torque_Nm <= allowed_Nm) continue;
    const double Mc = 2 * (full[i].torque_Nm - half[i].torque_Nm), Me = full[i].torque_Nm - Mc;
    share = std::min(share, (allowed_Nm - Me) / Mc);
  }
  REQUIRE(share < 1);
  w.ph.spindle = flat_rating(allowed_Nm);
  w.s.feed_limit_N = 1e9;  // the force limit never binds here
  const auto r = compensate::compensate(w.in.motions, w.ph, w.s);
  REQUIRE_FALSE(r.feed_lowered_lines.empty());
  CHECK(lowest_cutting_feed(r) == deflex::test::within(std::floor(800 * share * 10) / 10, 1e-9));
  double after = 0;
  for (const auto& p : r.final) after = std::max(after, p.torque_Nm);
  CHECK(after <= allowed_Nm * (1 + 1e-9));
  CHECK(after >= 0.99 * allowed_Nm);
}

TEST_CASE("spindle findings: over the S1 rating, within S6 or not, above max_rpm, and none within it") {
  Wall w;
  const auto pts = w.run();
  double most = 0;
  std::size_t over = 0;
  for (const auto& p : pts) most = std::max(most, cutting(p) ? p.torque_Nm : 0.0);
  const double allowed_Nm = 0.8 * most;
  for (const auto& p : pts) over += cutting(p) && p.torque_Nm > allowed_Nm;
  profile::SpindleRating r = flat_rating(allowed_Nm);
  const auto pl = compensate::plausibility(pts, w.ph.tools, w.s, nullptr, false, &r);
  const compensate::Finding* f = pl.find("spindle_load");
  REQUIRE(f);
  CHECK(f->count == over);
  CHECK(f->worst == doctest::Approx(1.25));
  CHECK(f->message.find("25 % over its continuous (S1) rating") != std::string::npos);
  CHECK(f->message.find("{feed_limit_N} keeps the feed within it") != std::string::npos);
  CHECK_FALSE(pl.find("spindle_speed"));
  // S6 given: within it, or above it too.
  r.s6 = flat_rating(2 * most).s1;
  CHECK(compensate::plausibility(pts, w.ph.tools, w.s, nullptr, false, &r).find("spindle_load")->message.find(
            "within its S6 rating") != std::string::npos);
  r.s6 = flat_rating(0.9 * most).s1;
  CHECK(compensate::plausibility(pts, w.ph.tools, w.s, nullptr, false, &r).find("spindle_load")->message.find(
            "above its S6 rating too") != std::string::npos);
  // A rating the cut stays within, and a top speed under the program's S.
  const profile::SpindleRating ample = flat_rating(2 * most, 6000);
  const auto within = compensate::plausibility(pts, w.ph.tools, w.s, nullptr, false, &ample);
  CHECK_FALSE(within.find("spindle_load"));
  const compensate::Finding* speed = within.find("spindle_speed");
  REQUIRE(speed);
  CHECK(speed->worst == 8000);
  CHECK(speed->limit == 6000);
  // No rating: nothing said.
  CHECK_FALSE(compensate::plausibility(pts, w.ph.tools, w.s).find("spindle_load"));
}

TEST_CASE("--feed-limit under the edge forces alone: lowered tenfold at most, and said") {
  Wall w;
  w.s.feed_limit_N = 1;  // 1 N: even the edge forces alone exceed it
  std::vector<compensate::Point> nominal;
  compensate::PointSinks sinks;
  sinks.nominal = [&](const compensate::Point& p) { nominal.push_back(p); };
  const auto r = compensate::compensate(w.in.motions, w.ph, w.s, {}, nullptr, &sinks);
  CHECK(lowest_cutting_feed(r) == 80);
  for (std::size_t i = 0; i < r.motions.size(); ++i)
    if (r.motions[i].kind == interp::MotionKind::linear && r.motions[i].moves_xy()) CHECK(r.feeds_mm_per_min[i] == 80);
  const auto pl = compensate::plausibility(nominal, w.ph.tools, w.s);
  const compensate::Finding* f = pl.find("feed_limit");
  REQUIRE(f);
  CHECK(f->worst == 0);
  CHECK(f->message.find("lowered tenfold") != std::string::npos);
}

}  // TEST_SUITE
