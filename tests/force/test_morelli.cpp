// Morelli et al. 2021, "Surface error shape identification for 3-axis milling
// operations", Procedia CIRP 101 (docs/physics.md): force-shape codes of Table 3, key points of
// Table 2 for its three tests, and the peak angle of Eq. 6 against the
// simulated force.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "../support.hpp"
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
    c.type = deflex::stock::EndShape::flat;
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
    CHECK(theta_peak == deflex::test::within(a.phi_max, 0.004));
  }
}

TEST_CASE("Morelli Table 2: key-point positions of the paper's three tests (IIM, IIML, IImL)") {
  // The paper's tests (Sec. 3.1, Table 3): D 12 mm, 4 flutes, helix 45 deg,
  // a_r 2.5 mm, down milling. It draws the key points in Fig. 3 without printing
  // their positions; worked by hand from its inputs and Table 2's expressions:
  // alpha_en = acos(1 - 2 a_r / D) = acos(7/12) = 0.947970 rad (Eq. 1),
  // k_b = 2 tan(45 deg) / D = 1/6 rad/mm (Eq. 3), phi_z = pi/2; so
  // alpha_en / k_b = 5.68782 mm and phi_z / k_b = 9.42478 mm, and
  // z_3 = a_p - 5.68782, z_L^i = i 9.42478 - 5.68782, z_M^i = a_p - i 9.42478,
  // z_m^i = i 9.42478, z_2m^i = z_3 - i 9.42478. Table 1 picks which apply:
  // flute 2 overlaps M at a_p 12 and 15 (alpha_sw < phi_z + alpha_en = 2.519 rad),
  // m at 18 (alpha_sw = 3 rad); flute 3 overlaps L from a_p 15 on
  // (alpha_en + alpha_sw >= pi).
  struct Point {
    const char* name;
    double z_mm;
  };
  struct Test {
    double ap_mm;
    std::vector<Point> points;
  };
  const Test tests[] = {
      {12, {{"z_3", 6.31218}, {"z_L^1", 3.73696}, {"z_M^1", 2.57522}}},
      {15, {{"z_3", 9.31218}, {"z_L^1", 3.73696}, {"z_M^1", 5.57522}, {"z_L^2", 13.16174}}},
      {18,
       {{"z_3", 12.31218},
        {"z_L^1", 3.73696},
        {"z_m^1", 9.42478},
        {"z_M^1", 8.57522},
        {"z_2m^1", 2.88740},
        {"z_L^2", 13.16174}}},
  };
  for (const Test& t : tests) {
    MorelliInput in;  // defaults are the paper's tool, a_r and coefficients
    in.ap_mm = t.ap_mm;
    const auto kp = morelli_key_points(in);
    CAPTURE(t.ap_mm);
    REQUIRE(kp.size() == t.points.size());
    for (std::size_t i = 0; i < kp.size(); ++i) {
      CHECK(kp[i].name == t.points[i].name);
      CHECK(kp[i].z_mm == deflex::test::within(t.points[i].z_mm, 1e-5));
    }
  }
}

TEST_CASE("Morelli classification refuses impossible input") {
  MorelliInput in;
  in.ar_mm = 13;  // wider than the tool
  CHECK_THROWS_AS(morelli_shape_code(in), deflex::Error);
}

}  // TEST_SUITE
