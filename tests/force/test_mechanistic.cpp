// Mechanistic force model against closed forms (Altintas 2012 ch. 2, a direct
// quadrature of the same element law, the ball-end slot integral) and invariants.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "../support.hpp"
#include "edge_coefficients.hpp"
#include "deflex/force/mechanistic.hpp"

using namespace deflex::force;

namespace {

constexpr double pi = std::numbers::pi;

Cutter flat(double D, int flutes, double helix_deg) {
  Cutter c;
  c.type = deflex::stock::EndShape::flat;
  c.diameter_mm = D;
  c.flutes = flutes;
  c.helix_deg = helix_deg;
  c.flute_length_mm = 30;
  return c;
}

Cutter ball(double D, int flutes, double helix_deg) {
  Cutter c = flat(D, flutes, helix_deg);
  c.type = deflex::stock::EndShape::ball;
  return c;
}

using deflex::test::al_like;

// Altintas 2012 ch. 2, average forces per revolution of a flat end mill between
// entry and exit angles (independent of the helix). Fz carries the sign of the
// Engin & Altintas transform (dFz = -dFa on the cylinder).
Vec3 altintas_mean(const Coefficients& k, int N, double a, double f, double st, double ex) {
  auto fx = [&](double p) {
    return N * a * f / (8 * pi) * (k.Ktc_N_per_mm2 * std::cos(2 * p) -
                                   k.Krc_N_per_mm2 * (2 * p - std::sin(2 * p))) +
           N * a / (2 * pi) * (-k.Kte_N_per_mm * std::sin(p) + k.Kre_N_per_mm * std::cos(p));
  };
  auto fy = [&](double p) {
    return N * a * f / (8 * pi) * (k.Ktc_N_per_mm2 * (2 * p - std::sin(2 * p)) +
                                   k.Krc_N_per_mm2 * std::cos(2 * p)) -
           N * a / (2 * pi) * (k.Kte_N_per_mm * std::cos(p) + k.Kre_N_per_mm * std::sin(p));
  };
  auto fz = [&](double p) {
    return N * a / (2 * pi) * (k.Kac_N_per_mm2 * f * std::cos(p) - k.Kae_N_per_mm * p);
  };
  return {fx(ex) - fx(st), fy(ex) - fy(st), fz(ex) - fz(st)};
}

// Direct quadrature over the axial depth of the helical flat end mill at one
// rotation angle, with the element law written the way Altintas 2012 ch. 2 does
// (dFx = -dFt cos - dFr sin, dFy = dFt sin - dFr cos, dFz = -dFa here).
Vec3 helical_reference(const Coefficients& k, const Cutter& c, double a, double f, double st,
                       double ex, double theta) {
  const int nz = 20000;
  const double dz = a / nz, kb = 2 * std::tan(c.helix_deg * pi / 180) / c.diameter_mm;
  Vec3 F = Vec3::Zero();
  for (int t = 0; t < c.flutes; ++t)
    for (int i = 0; i < nz; ++i) {
      const double z = (i + 0.5) * dz;
      double p = std::fmod(theta + t * 2 * pi / c.flutes - kb * z, 2 * pi);
      if (p < 0) p += 2 * pi;
      if (p < st || p > ex) continue;
      const double h = f * std::sin(p);
      const double Ft = (k.Ktc_N_per_mm2 * h + k.Kte_N_per_mm) * dz;
      const double Fr = (k.Krc_N_per_mm2 * h + k.Kre_N_per_mm) * dz;
      const double Fa = (k.Kac_N_per_mm2 * h + k.Kae_N_per_mm) * dz;
      F += Vec3(-Ft * std::cos(p) - Fr * std::sin(p), Ft * std::sin(p) - Fr * std::cos(p), -Fa);
    }
  return F;
}

void check_close(const Vec3& got, const Vec3& want, double rel) {
  // Each component within rel of the resultant (a component can be ~0).
  const double scale = want.norm();
  for (int a = 0; a < 3; ++a) {
    INFO("axis " << a << " got " << got[a] << " want " << want[a]);
    CHECK(std::abs(got[a] - want[a]) <= rel * scale);
  }
}

}  // namespace

TEST_SUITE("force") {

TEST_CASE("flat end mill mean forces match Altintas' closed form within 0.5%") {
  const Coefficients k = al_like();
  const double f = 0.1, ap = 6;
  struct Case {
    double D, helix;
    int N;
    double ae;
    MillingMode mode;
  };
  const Case cases[] = {
      {12, 30, 4, 12, MillingMode::down},  // slot
      {12, 30, 4, 6, MillingMode::up},     // half immersion up
      {12, 45, 4, 2.5, MillingMode::down}, // Morelli's radial depth
      {10, 0, 2, 3, MillingMode::up},      // straight flutes
      {16, 35, 3, 4, MillingMode::down},   // 3 flutes
  };
  for (const Case& cs : cases) {
    const Cutter c = flat(cs.D, cs.N, cs.helix);
    const CutterSlices sl = make_slices(c, 0.05, ap);
    Engagement e;
    simple_engagement(sl, cs.ae, ap, cs.mode, e);
    const auto [start, end] = deflex::test::textbook_immersion(cs.D, cs.ae, cs.mode == MillingMode::up);
    const Vec3 want = altintas_mean(k, cs.N, ap, f, start, end);
    for (int steps : {360, 1000}) {  // 1000 % 3 != 0: the general (all-teeth) path
      const auto F = revolution_forces(sl, k, f, e, steps);
      INFO("D " << cs.D << " ae " << cs.ae << " steps " << steps);
      check_close(summarize(F).mean_N, want, 0.005);
    }
  }
}

TEST_CASE("immersion of a flat end: Altintas's entry and exit angles, and Morelli's a_e 2.5 mm on D 12 mm") {
  for (const double ae : {0.5, 2.5, 6.0, 9.0, 12.0})
    for (const MillingMode mode : {MillingMode::up, MillingMode::down}) {
      CAPTURE(ae);
      const auto [start, end] = deflex::test::textbook_immersion(12, ae, mode == MillingMode::up);
      const AngleInterval iv = immersion_interval(6, 6, ae, mode);
      CHECK(iv.start == doctest::Approx(start));
      CHECK(iv.end == doctest::Approx(end));
    }
  // acos(7/12) = 0.947970 rad (Morelli 2021 Eq. 1 for its tests); half immersion pi/2.
  CHECK(immersion_interval(6, 6, 2.5, MillingMode::down).start == deflex::test::within(2.193623, 1e-6));
  CHECK(immersion_interval(6, 6, 2.5, MillingMode::up).end == deflex::test::within(0.947970, 1e-6));
  CHECK(immersion_interval(6, 6, 6, MillingMode::up).end == doctest::Approx(pi / 2));
}

TEST_CASE("cutting side of an engaged interval: across the entry from 0, past pi up to pi, the back half none") {
  auto check = [](AngleInterval iv, double start, double end) {
    const AngleInterval c = cutting_side(iv);
    CHECK(c.start == doctest::Approx(start));
    CHECK(c.end == doctest::Approx(end));
  };
  check({0.2, 1.0}, 0.2, 1.0);
  check({2 * pi - 0.1, 2 * pi + 0.3}, 0, 0.3);  // across the entry at phi = 0
  check({2.0, 3.5}, 2.0, pi);                   // past the exit at pi
  check({4.0, 5.0}, 0, 0);                      // the back half: none
  check({0.1, 2 * pi + 0.2}, 0, pi);            // nearly the whole circle (a plunge)
  check({2 * pi - 0.5, 2 * pi}, 0, 0);          // up to the entry, not past it
}

TEST_CASE("instantaneous helical flat end mill force matches direct quadrature") {
  const Coefficients k = al_like();
  const Cutter c = flat(12, 4, 30);
  const double ap = 8, ae = 4, f = 0.12;
  const CutterSlices sl = make_slices(c, 0.02, ap);
  Engagement e;
  simple_engagement(sl, ae, ap, MillingMode::down, e);
  const auto [start, end] = deflex::test::textbook_immersion(12, ae, false);
  const int steps = 720;
  const auto F = revolution_forces(sl, k, f, e, steps);
  const double peak = summarize(F).peak_abs_N.norm();
  for (int j : {0, 37, 100, 181, 250, 333, 511, 700}) {
    const double theta = 2 * pi * j / steps;
    const Vec3 ref = helical_reference(k, c, ap, f, start, end, theta);
    INFO("step " << j);
    CHECK((F[j] - ref).norm() < 0.01 * peak);
    CHECK((force_at_angle(sl, k, f, e, theta) - ref).norm() < 0.01 * peak);
  }
}

TEST_CASE("straight-fluted single tooth: force at an angle is the element law times a_p") {
  const Coefficients k = al_like();
  const Cutter c = flat(10, 1, 0);
  const double ap = 3, f = 0.2;
  const CutterSlices sl = make_slices(c, 0.5, ap);
  Engagement e;
  simple_engagement(sl, 10, ap, MillingMode::down, e);  // slot
  for (double p : {0.3, 1.0, 1.7, 2.9}) {
    const double h = f * std::sin(p);
    const double Ft = (k.Ktc_N_per_mm2 * h + k.Kte_N_per_mm) * ap;
    const double Fr = (k.Krc_N_per_mm2 * h + k.Kre_N_per_mm) * ap;
    const double Fa = (k.Kac_N_per_mm2 * h + k.Kae_N_per_mm) * ap;
    const Vec3 want(-Ft * std::cos(p) - Fr * std::sin(p), Ft * std::sin(p) - Fr * std::cos(p), -Fa);
    const Vec3 got = force_at_angle(sl, k, f, e, p);
    CHECK((got - want).norm() < 1e-9 * want.norm());
  }
  // Outside the cut (back half) there is no force.
  CHECK(force_at_angle(sl, k, f, e, 4.0).norm() == 0.0);
}

TEST_CASE("ball end in a full slot at a_p = R: mean force matches the hemisphere integral") {
  // Smaoui 2011 coefficients (K_T, K_R, K_A) on a ball, slot [0, pi] on every disc:
  // mean over a revolution, N teeth, integrating Eq. 4-5 over phi and z in [0, R]
  // (cos kappa = (R - z)/R):  Fx = -N f (K_R pi R/4 + K_A R/2) / 4,
  // Fy = N f K_T R / 4,  Fz = N f (K_R R/2 - K_A pi R/4) / pi.
  const double R = 8, f = 0.1;
  const int N = 2;
  const Coefficients k = from_smaoui(3600, 3400, 500);
  const Cutter c = ball(2 * R, N, 9);
  const CutterSlices sl = make_slices(c, R / 400, R);
  Engagement e;
  simple_engagement(sl, 2 * R, R, MillingMode::down, e);
  const Vec3 want(-N * f * (3400 * pi * R / 4 + 500 * R / 2) / 4, N * f * 3600 * R / 4,
                  N * f * (3400 * R / 2 - 500 * pi * R / 4) / pi);
  const auto F = revolution_forces(sl, k, f, e, 360);
  check_close(summarize(F).mean_N, want, 0.005);
}

TEST_CASE("forces are periodic in the tooth pitch") {
  const Coefficients k = al_like();
  Cutter bull = flat(10, 3, 35);
  bull.type = deflex::stock::EndShape::bull;
  bull.corner_radius_mm = 1.5;
  for (const Cutter& c : {flat(12, 4, 30), ball(10, 2, 30), bull}) {
    const CutterSlices sl = make_slices(c, 0.1, 6);
    for (MillingMode m : {MillingMode::up, MillingMode::down}) {
      Engagement e;
      simple_engagement(sl, 3, 4.5, m, e);
      int loaded = 0;
      for (double theta = 0.05; theta < 2 * pi; theta += 0.1) {
        const Vec3 a = force_at_angle(sl, k, 0.08, e, theta);
        const Vec3 b = force_at_angle(sl, k, 0.08, e, theta + sl.pitch());
        INFO(std::string(to_string(c.type)) << " theta " << theta);
        loaded += a.norm() > 0;
        CHECK((a - b).norm() <= 1e-9 * a.norm());
      }
      CHECK(loaded > 20);  // the test is not vacuous: mostly in the cut
    }
  }
}

TEST_CASE("zero feed with zero edge coefficients gives zero force; force is affine in f_z") {
  Coefficients k = al_like();
  const CutterSlices sl = make_slices(ball(10, 2, 30), 0.1, 5);
  Engagement e;
  simple_engagement(sl, 10, 3, MillingMode::up, e);
  const auto with_edge = revolution_forces(sl, k, 0.0, e, 360);
  CHECK(summarize(with_edge).peak_abs_N.norm() > 1.0);  // edge forces alone rub
  k.Kte_N_per_mm = k.Kre_N_per_mm = k.Kae_N_per_mm = 0;
  const auto none = revolution_forces(sl, k, 0.0, e, 360);
  CHECK(summarize(none).peak_abs_N.norm() == 0.0);
  // Linear in f_z without edge terms: F(2f) = 2 F(f) at every angle.
  const auto f1 = revolution_forces(sl, k, 0.05, e, 360);
  const auto f2 = revolution_forces(sl, k, 0.10, e, 360);
  for (std::size_t j = 0; j < f1.size(); ++j) CHECK((f2[j] - 2 * f1[j]).norm() < 1e-9 * (1 + f2[j].norm()));
}

TEST_CASE("an air cut gives no force and an empty engagement") {
  const CutterSlices sl = make_slices(flat(10, 2, 30), 0.1, 5);
  Engagement e;
  simple_engagement(sl, 0.0, 3, MillingMode::down, e);
  CHECK(e.empty());
  CHECK(summarize(revolution_forces(sl, al_like(), 0.1, e, 90)).peak_abs_N.norm() == 0.0);
}

TEST_CASE("bull nose of corner radius R is a ball; of tiny radius, nearly flat") {
  const Coefficients k = al_like();
  Cutter b = ball(10, 2, 30);
  Cutter t = b;
  t.type = deflex::stock::EndShape::bull;
  t.corner_radius_mm = 5;
  const CutterSlices sb = make_slices(b, 0.05, 4), st = make_slices(t, 0.05, 4);
  Engagement eb, et;
  simple_engagement(sb, 2, 4, MillingMode::down, eb);
  simple_engagement(st, 2, 4, MillingMode::down, et);
  const auto Fb = revolution_forces(sb, k, 0.1, eb, 360), Ft = revolution_forces(st, k, 0.1, et, 360);
  for (std::size_t j = 0; j < Fb.size(); ++j) CHECK((Fb[j] - Ft[j]).norm() < 1e-9 * (1 + Fb[j].norm()));

  Cutter f = flat(10, 2, 30);
  Cutter tn = f;
  tn.type = deflex::stock::EndShape::bull;
  tn.corner_radius_mm = 0.01;
  const CutterSlices sf = make_slices(f, 0.05, 4), stn = make_slices(tn, 0.05, 4);
  Engagement ef, etn;
  simple_engagement(sf, 2, 4, MillingMode::down, ef);
  simple_engagement(stn, 2, 4, MillingMode::down, etn);
  const Vec3 mf = summarize(revolution_forces(sf, k, 0.1, ef, 360)).mean_N;
  const Vec3 mt = summarize(revolution_forces(stn, k, 0.1, etn, 360)).mean_N;
  CHECK((mf - mt).norm() < 0.02 * mf.norm());
}

TEST_CASE("edge geometry: ball radius, axial immersion and constant-lead lag") {
  const Cutter b = ball(10, 2, 30);
  for (double z : {0.5, 2.0, 4.9}) {
    const EdgePoint p = edge_point(b, z);
    CHECK(p.r_mm == doctest::Approx(std::sqrt(z * (10 - z))));
    CHECK(p.sin_kappa == doctest::Approx(p.r_mm / 5));
    CHECK(p.cos_kappa == doctest::Approx((5 - z) / 5));
    CHECK(p.lag == doctest::Approx(z * std::tan(pi / 6) / 5));
  }
  const EdgePoint top = edge_point(b, 7);
  CHECK(top.r_mm == doctest::Approx(5));
  CHECK(top.sin_kappa == doctest::Approx(1));
  // The lag at the equator of a constant-lead ball is tan(i0) (Lee & Altintas 1996).
  CHECK(edge_point(b, 5).lag == doctest::Approx(std::tan(pi / 6)));
}

TEST_CASE("surface-generating force in down-milling: the force when an edge is at phi = pi") {
  // Straight 3-flute slot: when tooth 0 is at pi (h = 0, no cutting force), tooth 2
  // is at pi + 4 pi/3 = pi/3 and carries the whole load.
  Coefficients k = al_like();
  k.Kte_N_per_mm = k.Kre_N_per_mm = k.Kae_N_per_mm = 0;
  const double ap = 2, f = 0.1;
  const CutterSlices sl = make_slices(flat(12, 3, 0), 0.5, ap);
  Engagement e;
  simple_engagement(sl, 12, ap, MillingMode::down, e);
  const auto sf = surface_generating_forces(sl, k, f, e, pi);
  REQUIRE(sf.size() == 4);
  const double p = pi / 3, h = f * std::sin(p);
  const double Ft = k.Ktc_N_per_mm2 * h * ap, Fr = k.Krc_N_per_mm2 * h * ap;
  const Vec3 want(-Ft * std::cos(p) - Fr * std::sin(p), Ft * std::sin(p) - Fr * std::cos(p),
                  -k.Kac_N_per_mm2 * h * ap);
  for (const auto& s : sf) CHECK((s.force_N - want).norm() < 1e-9 * want.norm());
  const SurfaceForcePeak pk = peak_normal(sf, pi);
  CHECK(pk.normal_N == doctest::Approx(-want.y()));  // normal of the -Y wall is -Y
}

}  // TEST_SUITE

TEST_SUITE("force") {

TEST_CASE("surface-generating forces equal the force at the instant each slice passes the normal") {
  // The tabled double loop against the direct evaluation, on a helical ball end
  // and a bull nose in up- and down-milling.
  const Coefficients k = al_like();
  Cutter bull = flat(12, 4, 35);
  bull.type = deflex::stock::EndShape::bull;
  bull.corner_radius_mm = 2;
  for (const Cutter& c : {ball(10, 2, 30), bull}) {
    const CutterSlices sl = make_slices(c, 0.1, 8);
    for (MillingMode m : {MillingMode::up, MillingMode::down}) {
      Engagement e;
      simple_engagement(sl, 3, 4, m, e);
      const double nphi = m == MillingMode::up ? 0.0 : pi;
      const auto sf = surface_generating_forces(sl, k, 0.07, e, nphi);
      // The slices below a_p = 4 that reach the wall (r > R - a_e): all of the bull
      // nose's, the ball's above r(z) = 2 mm, i.e. z > 5 - sqrt(21) = 0.42 mm.
      std::vector<std::size_t> engaged;
      for (std::size_t i = 0; i < e.slices.size(); ++i)
        if (!e.slices[i].empty()) engaged.push_back(i);
      CHECK(engaged.size() == (c.type == deflex::stock::EndShape::ball ? 36u : 40u));
      REQUIRE(sf.size() == engaged.size());
      for (std::size_t q = 0; q < sf.size(); ++q) {
        const std::size_t i = engaged[q];
        const Vec3 want = force_at_angle(sl, k, 0.07, e, nphi + sl.slices[i].lag);
        CHECK(sf[q].z_mm == doctest::Approx(sl.slices[i].z_mm));
        CHECK((sf[q].force_N - want).norm() <= 1e-9 * (1 + want.norm()));
      }
    }
  }
}

}  // TEST_SUITE
