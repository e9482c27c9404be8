// Morelli et al. 2021 (seeds/003_…): force-shape codes of Table 3 and the peak
// angle of Eq. 6 against the simulated force.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/force/mechanistic.hpp"
#include "deflex/force/morelli.hpp"

using namespace deflex::force;

TEST_SUITE("force") {

TEST_CASE("Morelli 2021 Table 3: D 12, 4 flutes, helix 45, a_r 2.5 -> IIM, IIML, IImL") {
  MorelliInput in;  // defaults are the paper's tool, a_r and coefficients
  in.ap_mm = 12;
  CHECK(morelli_shape_code(in) == "IIM");
  in.ap_mm = 15;
  CHECK(morelli_shape_code(in) == "IIML");
  in.ap_mm = 18;
  CHECK(morelli_shape_code(in) == "IImL");
}

TEST_CASE("Morelli angles: Eq. 1-3 and the critical depths") {
  MorelliInput in;
  in.ap_mm = 12;
  const MorelliAngles a = morelli_angles(in);
  CHECK(a.alpha_en == doctest::Approx(std::acos(1 - 5.0 / 12)));
  CHECK(a.k_b == doctest::Approx(2.0 / 12));
  CHECK(a.alpha_sw == doctest::Approx(2.0));
  CHECK(a.ap_c * a.k_b == doctest::Approx(a.alpha_en));
  // Shallow cut below the critical depth: Type I.
  in.ap_mm = 0.9 * a.ap_c;
  CHECK(morelli_type(in, morelli_angles(in)) == 1);
  // Radial depth beyond a_r,c: Type III.
  in.ap_mm = 2;
  in.ar_mm = 11.9;
  const MorelliAngles b = morelli_angles(in);
  CHECK(in.ar_mm >= b.ar_c);
  CHECK(morelli_shape_code(in).rfind("III", 0) == 0);
}

TEST_CASE("Eq. 6: the single-flute slot F_y peaks at phi_max in the simulation") {
  // One flute, slot, no edge forces: F_y(theta) of the mechanistic model must peak
  // where Morelli's Eq. 6 (with its arctangent restored) says.
  for (double ap : {3.0, 6.0, 9.0}) {
    MorelliInput in;
    in.flutes = 1;
    in.ar_mm = 12;
    in.ap_mm = ap;
    const MorelliAngles a = morelli_angles(in);
    Cutter c;
    c.type = CutterType::flat;
    c.diameter_mm = 12;
    c.flutes = 1;
    c.helix_deg = 45;
    c.flute_length_mm = 30;
    const CutterSlices sl = make_slices(c, 0.01, ap);
    Engagement e;
    simple_engagement(sl, 12, ap, MillingMode::down, e);
    Coefficients k;
    k.Ktc_N_per_mm2 = in.Ktc_N_per_mm2;
    k.Krc_N_per_mm2 = in.Krc_N_per_mm2;
    const int steps = 7200;
    const auto F = revolution_forces(sl, k, 0.1, e, steps);
    const auto it = std::max_element(F.begin(), F.end(),
                                      [](const Vec3& p, const Vec3& q) { return p.y() < q.y(); });
    const double theta_peak = 2 * std::numbers::pi * (it - F.begin()) / steps;
    INFO("a_p " << ap);
    CHECK(theta_peak == doctest::Approx(a.phi_max).epsilon(0.004));
  }
}

TEST_CASE("Morelli key points of Table 2 for the IIM case") {
  MorelliInput in;
  in.ap_mm = 12;
  const MorelliAngles a = morelli_angles(in);
  const auto kp = morelli_key_points(in);
  REQUIRE(kp.size() == 3);  // z_3, then z_L^1 and z_M^1 for the M overlap
  CHECK(kp[0].name == "z_3");
  CHECK(kp[0].z_mm == doctest::Approx(12 - a.alpha_en / a.k_b));
  CHECK(kp[1].z_mm == doctest::Approx((a.phi_z - a.alpha_en) / a.k_b));
  CHECK(kp[2].z_mm == doctest::Approx(12 - a.phi_z / a.k_b));
}

TEST_CASE("Morelli classification refuses impossible input") {
  MorelliInput in;
  in.ar_mm = 13;  // wider than the tool
  CHECK_THROWS_AS(morelli_shape_code(in), deflex::Error);
}

}  // TEST_SUITE
