// The chain's lateral modes at the tool tip (stiffness/modes.hpp): frequencies
// and modal stiffness of a slender cantilever against Euler-Bernoulli's closed
// form, the Timoshenko effect of a stubby one, and the modal sum = the static
// tip compliance.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "../support.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "deflex/stiffness/beam.hpp"
#include "deflex/stiffness/modes.hpp"
#include "helpers.hpp"

using namespace deflex;
using namespace deflex::stiffness;
using namespace deflex::stiffness::testing;

namespace {
const double pi = std::numbers::pi;

// Euler-Bernoulli cantilever: f_n = (beta_n L)^2 / (2 pi L^2) sqrt(EI / (rho A))
// (Blevins, Formulas for Natural Frequency and Mode Shape, table 8-1). E in
// N/mm^2, rho A in t/mm (kg/m^3 * 1e-12 * area): sqrt gives mm^2/s.
double eb_frequency_Hz(double betaL, double d_mm, double L_mm, const Material& m) {
  const double I = pi * std::pow(d_mm, 4) / 64, A = pi * d_mm * d_mm / 4;
  return betaL * betaL / (2 * pi * L_mm * L_mm) * std::sqrt(m.E_MPa * I / (m.density_kg_per_m3 * 1e-12 * A));
}

double modal_compliance_sum(const std::vector<Mode>& modes) {
  double s = 0;
  for (const Mode& m : modes) s += 1 / m.stiffness_N_per_mm;
  return s;
}

// Few stations: the modal tests need the mesh, not the table.
const BeamOptions kCoarse{4, 2.0};
}  // namespace

TEST_SUITE("stiffness") {
  TEST_CASE("modes: a slender carbide cantilever's first three frequencies are Euler-Bernoulli's") {
    const Tool t = cylinder(4, 200, *material_preset("carbide"));  // L/D = 50: shear, rotary inertia < 0.3 %
    const std::vector<Mode> modes = tip_modes(t, {}, true, 3, kCoarse);
    REQUIRE(modes.size() == 3);
    const double betaL[3] = {1.87510, 4.69409, 7.85476};
    for (int n = 0; n < 3; ++n) {
      const double expect = eb_frequency_Hz(betaL[n], 4, 200, t.material);
      CAPTURE(n);
      MESSAGE("mode " << n + 1 << ": " << modes[n].frequency_Hz << " Hz, Euler-Bernoulli " << expect << " Hz ("
                      << 100 * (modes[n].frequency_Hz / expect - 1) << " %)");
      CHECK(modes[n].frequency_Hz == deflex::test::within(expect, 0.01));
      CHECK(modes[n].frequency_Hz < expect);  // Timoshenko: shear and rotary inertia only lower it
      CHECK(modes[n].damping_ratio == 0.03);  // the dynamics: default
    }
    // Tip-normalised EB cantilever modes have modal mass m/4 (the integral of
    // phi^2 over the length is L phi(L)^2 / 4), so k_1 = omega_1^2 rho A L / 4.
    const double w1 = 2 * pi * eb_frequency_Hz(betaL[0], 4, 200, t.material);
    const double rhoAL_t = t.material.density_kg_per_m3 * 1e-12 * pi * 4 * 200;
    MESSAGE("k_1 " << modes[0].stiffness_N_per_mm << " N/mm, closed form " << w1 * w1 * rhoAL_t / 4);
    CHECK(modes[0].stiffness_N_per_mm == deflex::test::within(w1 * w1 * rhoAL_t / 4, 0.01));
  }

  TEST_CASE("modes: a stubby tool's first frequency falls below Euler-Bernoulli's (Timoshenko)") {
    const Tool t = cylinder(16, 40, *material_preset("carbide"));  // L/D = 2.5
    const std::vector<Mode> modes = tip_modes(t, {}, true, 1, kCoarse);
    REQUIRE(modes.size() == 1);
    const double eb = eb_frequency_Hz(1.87510, 16, 40, t.material);
    MESSAGE("stubby: " << modes[0].frequency_Hz << " Hz, Euler-Bernoulli " << eb << " Hz");
    CHECK(modes[0].frequency_Hz < 0.97 * eb);
    CHECK(modes[0].frequency_Hz > 0.8 * eb);
  }

  TEST_CASE("modes: the modal compliances of all modes sum to the static tip compliance") {
    SUBCASE("tool only, a plain cylinder") {
      const Tool t = cylinder(10, 50, *material_preset("carbide"));
      const double c0 = beam_compliance(t, {}, true).at(0)(0, 0);
      CHECK(modal_compliance_sum(tip_modes(t, {}, true, 0)) == deflex::test::within(c0, 1e-6));
    }
    SUBCASE("the full chain of the sample machine and tool") {
      const Tool& t = find_tool(load_tool_library(sample_path("samples/tools.yaml")), "T3");
      const MachineStiffness m = load_machine_stiffness(sample_path("samples/machines/mill3.yaml"));
      // The structure compliance is a massless spring in series, not in the modal model.
      const double c0 = beam_compliance(t, m, false).at(0)(0, 0) - m.structure_mm_per_N(0, 0);
      const std::vector<Mode> all = tip_modes(t, m, false, 0);
      MESSAGE("T3 on mill3: " << all.size() << " modes, the lowest " << all[0].frequency_Hz << " Hz (k "
                              << all[0].stiffness_N_per_mm << " N/mm); sum 1/k " << modal_compliance_sum(all)
                              << " mm/N, static " << c0);
      CHECK(modal_compliance_sum(all) == deflex::test::within(c0, 1e-6));
      // The lowest modes hold most of it; frequencies ascend.
      const std::vector<Mode> low = tip_modes(t, m, false, 3);
      REQUIRE(low.size() == 3);
      CHECK(low[0].frequency_Hz == all[0].frequency_Hz);
      CHECK(low[0].frequency_Hz < low[1].frequency_Hz);
      CHECK(low[1].frequency_Hz < low[2].frequency_Hz);
    }
    SUBCASE("a clamp spring straight onto the spindle: a massless node between two springs") {
      const Tool t = cylinder(10, 50, *material_preset("carbide"));
      MachineStiffness m;
      m.tool_clamp = Springs{4e5, 6e8, std::nullopt};
      m.spindle = Springs{2e5, 2e9, 4e5};
      const double c0 = beam_compliance(t, m, false).at(0)(0, 0);
      CHECK(modal_compliance_sum(tip_modes(t, m, false, 0)) == deflex::test::within(c0, 1e-6));
    }
  }

  TEST_CASE("modes: a material without density is a config error naming what to add") {
    Tool t = cylinder(10, 50);  // the helper's custom steel has no density
    try {
      tip_modes(t, {}, true, 3);
      FAIL("no error");
    } catch (const Error& e) {
      CHECK(e.kind() == ErrorKind::config);
      CHECK(std::string(e.what()).find("tool cyl") == 0);
      CHECK(std::string(e.what()).find("density_kg_per_m3") != std::string::npos);
    }
    t.material = *material_preset("carbide");
    MachineStiffness m;
    m.holder = Holder{60, 32, 44, Material{"custom", 210000, 0.3}};
    CHECK_THROWS_WITH_AS(tip_modes(t, m, false, 3), doctest::Contains("holder"), Error);
    CHECK(tip_modes(t, m, true, 3).size() == 3);  // tool only: the holder's material is not needed
  }
}
