#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "../support.hpp"
#include "deflex/stiffness/beam.hpp"
#include "helpers.hpp"

using namespace deflex::stiffness;
using namespace deflex::stiffness::testing;

namespace {
const double pi = std::numbers::pi;

// Bagci / Smaoui cantilever, Euler-Bernoulli: delta/F = 64 a^3 / (3 pi E D^4)
// (paper 000 Eq. 4) for a load at distance a from the clamp.
double euler_bernoulli_mm_per_N(double a, double d, double E) {
  return 64 * a * a * a / (3 * pi * E * std::pow(d, 4));
}
// Timoshenko adds the shear term a / (k G A).
double timoshenko_mm_per_N(double a, double d, const Material& m) {
  const double G = m.E_MPa / (2 * (1 + m.poisson));
  const double A = pi * d * d / 4;
  return euler_bernoulli_mm_per_N(a, d, m.E_MPa) + a / (shear_coefficient_circle(m.poisson) * G * A);
}
}  // namespace

TEST_SUITE("stiffness") {
  TEST_CASE("beam: plain cylinder matches the Timoshenko closed form along its length") {
    const Tool t = cylinder(16, 40);  // L/D = 2.5: shear is ~5% of the deflection
    const ComplianceTable c = beam_compliance(t, {}, true);
    for (double h : {0.0, 7.5, 20.0, 33.0}) {
      const double a = t.stickout_mm - h;
      const double expect = timoshenko_mm_per_N(a, 16, t.material);
      CHECK(c.at(h)(0, 0) == deflex::test::within(expect, 0.01));
      CHECK(c.at(h)(1, 1) == deflex::test::within(expect, 0.01));
      // Axial bar: a / (E A).
      CHECK(c.at(h)(2, 2) == deflex::test::within(a / (t.material.E_MPa * pi * 64), 0.01));
    }
    // Shear matters here: Euler-Bernoulli alone is more than 3% stiffer.
    CHECK(c.at(0)(0, 0) > 1.03 * euler_bernoulli_mm_per_N(40, 16, t.material.E_MPa));
  }

  TEST_CASE("beam: a slender cylinder tends to Euler-Bernoulli (paper 000 Eq. 4)") {
    const Tool t = cylinder(4, 120);  // L/D = 30
    const ComplianceTable c = beam_compliance(t, {}, true);
    CHECK(c.at(0)(0, 0) == deflex::test::within(euler_bernoulli_mm_per_N(120, 4, 210000), 0.01));
  }

  TEST_CASE("beam: Timoshenko element is exact for a single prismatic element") {
    const Material m{"steel", 210000, 0.3};
    const BeamSection s = circular_section(10, m);
    const double L = 25;
    // Cantilever from one element: clamp node 1, invert the free 2x2 block.
    const Eigen::Matrix2d kff = timoshenko_element(L, s).bottomRightCorner<2, 2>();
    const double w = kff.inverse()(0, 0);
    CHECK(w == deflex::test::within(timoshenko_mm_per_N(L, 10, m), 1e-9));
    // Rigid-body motions carry no force.
    const Eigen::Vector4d translate(1, 0, 1, 0), rotate(0, 1, L, 1);
    CHECK((timoshenko_element(L, s) * translate).norm() < 1e-6 * s.EI_Nmm2);
    CHECK((timoshenko_element(L, s) * rotate).norm() < 1e-6 * s.EI_Nmm2);
  }

  TEST_CASE("beam: the tool of paper 001 gives C_xx within 5% of its FEM 2.664e-4 mm/N") {
    // Smaoui 2011 Eq. 18: a1 = 2.664e-4 mm/N, tool clamped at 80 mm stick-out,
    // load at the tip. T5 uses ratio 0.8 over the 10 mm ball part (see tools.yaml).
    const ToolLibrary lib = load_tool_library(sample_path("samples/tools.yaml"));
    const Tool& t = find_tool(lib, "T5");
    const Compliance c = beam_compliance(t, {}, true).at(0);
    CHECK(c(0, 0) == deflex::test::within(2.664e-4, 0.05));
    CHECK(c(1, 1) == deflex::test::within(2.64e-4, 0.05));
    // Axial much stiffer than lateral (paper Eq. 20: c3 = 7.8e-6 vs 2.66e-4).
    CHECK(c(2, 2) < 0.05 * c(0, 0));
  }

  TEST_CASE("beam: C(h) is symmetric positive definite and falls towards the holder") {
    const ToolLibrary lib = load_tool_library(sample_path("samples/tools.yaml"));
    const MachineStiffness m = load_machine_stiffness(sample_path("samples/machines/mill3.yaml"));
    for (const auto& entry : lib.tools) {
      const std::string& id = entry.first;  // not a binding: INFO's lambda captures it (clang 14)
      const auto& t = entry.second;
      for (bool tool_only : {true, false}) {
        const ComplianceTable c = beam_compliance(t, m, tool_only);
        double prev = 1e300;
        for (const auto& r : c.rows()) {
          INFO(id << " h=" << r.height_mm);
          CHECK(symmetric_positive_definite(r.matrix_mm_per_N));
          CHECK(r.matrix_mm_per_N(0, 0) < prev);
          prev = r.matrix_mm_per_N(0, 0);
        }
      }
    }
  }

  TEST_CASE("beam: deflection is linear in the force") {
    const ToolLibrary lib = load_tool_library(sample_path("samples/tools.yaml"));
    const MachineStiffness m = load_machine_stiffness(sample_path("samples/machines/mill3.yaml"));
    const ComplianceTable c = beam_compliance(find_tool(lib, "T2"), m, false);
    const Eigen::Vector3d f1(120, -40, 15), f2(-30, 80, 60);
    const double h = 3.3;
    CHECK(deflection_mm(c, h, Eigen::Vector3d::Zero()).norm() == 0.0);
    CHECK((deflection_mm(c, h, 2.5 * f1) - 2.5 * deflection_mm(c, h, f1)).norm() <
          1e-12 * deflection_mm(c, h, f1).norm());
    CHECK((deflection_mm(c, h, f1 + f2) - deflection_mm(c, h, f1) - deflection_mm(c, h, f2)).norm() <
          1e-12 * deflection_mm(c, h, f1).norm());
  }

  TEST_CASE("beam: a stiffer machine never increases the compliance") {
    const ToolLibrary lib = load_tool_library(sample_path("samples/tools.yaml"));
    const MachineStiffness soft = load_machine_stiffness(sample_path("samples/machines/mill3.yaml"));
    MachineStiffness stiff = soft;
    stiff.holder->nose_diameter_mm *= 1.2;
    stiff.holder->base_diameter_mm *= 1.2;
    *stiff.tool_clamp->radial_N_per_mm *= 3;
    *stiff.tool_clamp->rotational_Nmm_per_rad *= 3;
    stiff.spindle->rotational_Nmm_per_rad.reset();  // rigid
    stiff.structure_mm_per_N *= 0.5;
    for (const auto& entry : lib.tools) {
      const std::string& id = entry.first;  // not a binding: INFO's lambda captures it (clang 14)
      const auto& t = entry.second;
      const ComplianceTable cs = beam_compliance(t, soft, false);
      const ComplianceTable ck = beam_compliance(t, stiff, false);
      const ComplianceTable c0 = beam_compliance(t, stiff, true);
      for (const auto& r : cs.rows()) {
        INFO(id << " h=" << r.height_mm);
        const double scale = r.matrix_mm_per_N.norm();
        CHECK(min_eig_difference(r.matrix_mm_per_N, ck.at(r.height_mm)) > -1e-12 * scale);
        CHECK(min_eig_difference(ck.at(r.height_mm), c0.at(r.height_mm)) > -1e-12 * scale);
        CHECK(ck.at(r.height_mm)(0, 0) < r.matrix_mm_per_N(0, 0));
      }
    }
  }

  TEST_CASE("beam: machine parts add in series exactly") {
    // A cylinder on a radial spring only: tip compliance gains exactly 1/k.
    const Tool t = cylinder(12, 50);
    MachineStiffness m;
    m.spindle = Springs{};
    m.spindle->radial_N_per_mm = 2.0e5;
    const double c0 = beam_compliance(t, {}, true).at(0)(0, 0);
    const double c1 = beam_compliance(t, m, false).at(0)(0, 0);
    CHECK(c1 - c0 == deflex::test::within(1 / 2.0e5, 1e-6));
    // A rotational spring k_r adds a^2 / k_r at lever arm a.
    m.spindle = Springs{};
    m.spindle->rotational_Nmm_per_rad = 1.0e9;
    const double c2 = beam_compliance(t, m, false).at(10)(0, 0);
    CHECK(c2 - beam_compliance(t, {}, true).at(10)(0, 0) == deflex::test::within(40.0 * 40 / 1e9, 1e-6));
  }

  TEST_CASE("beam: the table interpolates between stations") {
    const ToolLibrary lib = load_tool_library(sample_path("samples/tools.yaml"));
    const Tool& t = find_tool(lib, "T4");
    const ComplianceTable coarse = beam_compliance(t, {}, true, BeamOptions{8, 2.0});
    const ComplianceTable fine = beam_compliance(t, {}, true, BeamOptions{380, 2.0});
    // 8 stations against 380: within 0.32 % at the worst height (the coarse
    // table's cubic between stations), a fraction of a micrometre.
    for (double h = 0.1; h < t.flute_length_mm; h += 1.3)
      CHECK(coarse.at(h)(0, 0) == deflex::test::within(fine.at(h)(0, 0), 4e-3));
  }
}
