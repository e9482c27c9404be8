// The spindle's load (mean torque, power) against Altintas' closed form and a
// direct quadrature of the element law, and the feed share that meets a peak
// force limit against re-evaluated forces.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "../support.hpp"
#include "edge_coefficients.hpp"
#include "deflex/force/mechanistic.hpp"
#include "deflex/profile/spindle.hpp"

using namespace deflex::force;

namespace {

constexpr double pi = std::numbers::pi;

Cutter cutter(deflex::stock::EndShape type, double D, int flutes, double helix_deg) {
  Cutter c;
  c.type = type;
  c.diameter_mm = D;
  c.flutes = flutes;
  c.helix_deg = helix_deg;
  c.flute_length_mm = 30;
  return c;
}

// The mean of sum r dF_t over a revolution by brute force: every tooth at
// every one of `steps` rotation angles, every slice, the element law as
// mechanistic.hpp writes it (dF_t = K_tc f sin(phi) sin(k) db + K_te dS where
// sin(phi) > 0 and phi is engaged). N m.
double torque_by_quadrature(const CutterSlices& cs, const Coefficients& k, double f, const Engagement& e, int steps) {
  double sum = 0;
  for (int j = 0; j < steps; ++j) {
    const double theta = 2 * pi * (j + 0.5) / steps;
    for (std::size_t i = 0; i < cs.slices.size() && i < e.slices.size(); ++i) {
      const Slice& s = cs.slices[i];
      for (int t = 0; t < cs.cutter.flutes; ++t) {
        double phi = std::fmod(theta + t * cs.pitch() - s.lag, 2 * pi);
        if (phi < 0) phi += 2 * pi;
        bool in = false;
        for (const AngleInterval& iv : e.slices[i])
          in = in || (phi >= iv.start && phi <= iv.end) || (phi + 2 * pi >= iv.start && phi + 2 * pi <= iv.end);
        if (!in || std::sin(phi) <= 0) continue;
        sum += s.r_mm * (k.Ktc_N_per_mm2 * f * std::sin(phi) * s.sin_kappa * s.width_mm + k.Kte_N_per_mm * s.edge_mm);
      }
    }
  }
  return sum / steps / 1000.0;
}

double peak(const std::vector<Vec3>& f) {
  double p = 0;
  for (const Vec3& v : f) p = std::max(p, v.norm());
  return p;
}

}  // namespace

TEST_SUITE("force") {

TEST_CASE("mean torque of a flat end mill: Altintas' closed form, and P = F_t v_c in a slot") {
  // Altintas 2012 ch. 2: between entry and exit angles the mean tangential force
  // of N teeth over a revolution is N a / (2 pi) [K_tc f (cos st - cos ex) + K_te (ex - st)],
  // whatever the helix; it acts at R.
  const Coefficients k = deflex::test::al_like();
  const double f = 0.1, a = 6;
  struct Case {
    double D, helix, ae;
    int N;
    MillingMode mode;
  };
  for (const Case& c : {Case{12, 30, 12, 4, MillingMode::down}, Case{12, 45, 2.5, 4, MillingMode::down},
                        Case{10, 0, 3, 2, MillingMode::up}, Case{16, 35, 4, 3, MillingMode::up}}) {
    const CutterSlices sl = make_slices(cutter(deflex::stock::EndShape::flat, c.D, c.N, c.helix), 0.05, a);
    Engagement e;
    simple_engagement(sl, c.ae, a, c.mode, e);
    const auto [st, ex] = deflex::test::textbook_immersion(c.D, c.ae, c.mode == MillingMode::up);
    const double Ft_N = c.N * a / (2 * pi) * (k.Ktc_N_per_mm2 * f * (std::cos(st) - std::cos(ex)) + k.Kte_N_per_mm * (ex - st));
    const MeanTorque m = mean_torque(sl, k, f, e);
    INFO("D " << c.D << " ae " << c.ae);
    CHECK(m.total_Nm() == deflex::test::within(Ft_N * c.D / 2 / 1000, 1e-3));
    // The edge part does not depend on the feed; the cutting part is linear in it.
    const MeanTorque half = mean_torque(sl, k, f / 2, e);
    CHECK(half.edge_Nm == deflex::test::within(m.edge_Nm, 1e-12));
    CHECK(half.cutting_Nm == deflex::test::within(m.cutting_Nm / 2, 1e-12));
    // P = F_t v_c, v_c = pi D n / 60 (m/s), in kW.
    const double rpm = 6366, vc_m_per_s = pi * c.D / 1000 * rpm / 60;
    CHECK(deflex::profile::power_from_torque_kW(m.total_Nm(), rpm) == deflex::test::within(Ft_N * vc_m_per_s / 1000, 1e-3));
  }
}

TEST_CASE("mean torque of ball and bull ends: the closed form against a direct quadrature") {
  const Coefficients k = deflex::test::al_like();
  Cutter bull = cutter(deflex::stock::EndShape::bull, 10, 3, 35);
  bull.corner_radius_mm = 1.5;
  for (const Cutter& c : {cutter(deflex::stock::EndShape::ball, 10, 2, 30), bull}) {
    const CutterSlices sl = make_slices(c, 0.05, 5);
    for (MillingMode mode : {MillingMode::up, MillingMode::down}) {
      Engagement e;
      simple_engagement(sl, 3, 4, mode, e);
      const double want = torque_by_quadrature(sl, k, 0.08, e, 7200);
      REQUIRE(want > 0.1);  // in the cut
      INFO(to_string(c.type));
      CHECK(mean_torque(sl, k, 0.08, e).total_Nm() == deflex::test::within(want, 2e-3));
    }
  }
}

TEST_CASE("the feed share of a peak force limit: the forces at that share meet the limit") {
  const CutterSlices sl = make_slices(cutter(deflex::stock::EndShape::flat, 12, 4, 45), 0.05, 12);
  Engagement e;
  simple_engagement(sl, 2.5, 12, MillingMode::down, e);
  const double f = 0.1;
  const int steps = 360;
  const AngleGrid g = make_angle_grid(steps);
  for (const bool edges : {true, false}) {
    Coefficients k = deflex::test::al_like();
    if (!edges) k.Kte_N_per_mm = k.Kre_N_per_mm = k.Kae_N_per_mm = 0;
    std::vector<Vec3> total(steps), edge(steps);
    revolution_forces(sl, g, k, f, e, total);
    revolution_forces(sl, g, k, 0.0, e, edge);
    const double written = peak(total), edge_alone = peak(edge);
    INFO("edge terms " << edges << ": peak " << written << " N, edges alone " << edge_alone << " N");
    const double limit = edge_alone + 0.4 * (written - edge_alone);
    const double s = peak_feed_share(total, edge, limit);
    std::vector<Vec3> at(steps);
    revolution_forces(sl, g, k, s * f, e, at);
    CHECK(peak(at) <= limit * (1 + 1e-9));
    CHECK(peak(at) >= limit * (1 - 1e-6));
    if (edges) {
      // Scaling the feed by limit / peak (the edge forces forgotten) misses the limit.
      revolution_forces(sl, g, k, limit / written * f, e, at);
      CHECK(peak(at) > 1.05 * limit);
    } else {
      CHECK(s == deflex::test::within(limit / written, 1e-9));
    }
    CHECK(peak_feed_share(total, edge, 2 * written) == 1.0);
    if (edges) CHECK(peak_feed_share(total, edge, 0.9 * edge_alone) == 0.0);
  }
}

}  // TEST_SUITE
