// The workpiece's compliance against closed forms: a narrow cantilever strip
// (Euler-Bernoulli), a wide cantilever plate under a load along its free edge
// (cylindrical bending), the mesh refinement, Maxwell-Betti symmetry, and an
// STL of the same solid.
#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>
#include <cstdio>

#include "../support.hpp"
#include "deflex/stiffness/workpiece.hpp"
#include "helpers.hpp"
#include "workpiece_parts.hpp"

using namespace deflex;
using namespace deflex::stiffness;
using namespace deflex::stiffness::testing;
using V3 = Eigen::Vector3d;

namespace {

// Every face node at z <= 0 (the base) held: a rigid clamp of the base face.
std::vector<Fixture> base_clamp(double x, double y) {
  char b[128];
  std::snprintf(b, sizeof b, "box:-1,-1,-1,%g,%g,0.001", x + 1, y + 1);
  return {parse_fixture(b)};
}

// Euler-Bernoulli tip compliance of a cantilever of length L, width b (along
// the load's normal plane) and thickness t: L^3 / (3 E I), I = b t^3 / 12.
double cantilever_mm_per_N(double L, double b, double t, double E) { return L * L * L / (3 * E * b * t * t * t / 12); }

}  // namespace

TEST_SUITE("stiffness") {

TEST_CASE("workpiece: a narrow strip 10 x 2 x 40 mm clamped at its base is an Euler-Bernoulli cantilever within 3 %") {
  const test::TempDir dir("workpiece");
  const PartSurface part = read_part_surface(box_step(dir, "strip", 10, 2, 40));
  const WorkpieceModel model(part, base_clamp(10, 2), aluminium());
  const WorkpieceInfo& info = model.info();
  CHECK(info.thinnest_wall_mm == doctest::Approx(2.0));
  CHECK(info.mesh_mm == doctest::Approx(1.0));  // half the wall
  const PointCompliance c = model.compliance_at(V3(5, 1, 40));  // the middle of the top face
  CHECK((c.surface_mm - V3(5, 1, 40)).norm() < 1e-9);
  // The lever arm is the height of the load patch's centroid, a little below
  // the top face (the patch is the part of a ball inside the body).
  const double L = c.load_centroid_mm(2);
  CHECK(L > 39.5);
  const double expected = cantilever_mm_per_N(L, 10, 2, 70000);
  const double got = c.matrix_mm_per_N(1, 1);
  MESSAGE("strip: C_yy ", got, " mm/N, Euler-Bernoulli ", expected, " (L ", L, " mm), ", 100 * (got / expected - 1),
          " %; ", info.nodes, " nodes, ", info.elements, " tets, ", info.dofs, " dofs, mesh ", info.mesh_seconds,
          " s, solve ", info.solve_seconds, " s");
  CHECK(got == deflex::test::within(expected, 0.03));
  // Bending about the other axis: b and t exchanged.
  const double expected_x = cantilever_mm_per_N(L, 2, 10, 70000);
  MESSAGE("strip: C_xx ", c.matrix_mm_per_N(0, 0), " mm/N, Euler-Bernoulli ", expected_x);
  CHECK(c.matrix_mm_per_N(0, 0) == deflex::test::within(expected_x, 0.05));
  CHECK(symmetric_positive_definite(c.matrix_mm_per_N, 1e-8));
  // Several points solved together (more than one batch) give each point's
  // own matrix, patch and surface point.
  std::vector<V3> pts;
  for (int k = 0; k < 20; ++k) pts.push_back(V3(1 + 0.4 * k, 2, 10 + 1.5 * k));
  const std::vector<PointCompliance> all = model.compliance_at(pts);
  REQUIRE(all.size() == pts.size());
  for (std::size_t k = 0; k < pts.size(); k += 3) {
    const PointCompliance one = model.compliance_at(pts[k]);
    CHECK((all[k].surface_mm - one.surface_mm).norm() < 1e-12);
    CHECK((all[k].load_centroid_mm - one.load_centroid_mm).norm() < 1e-12);
    CHECK((all[k].matrix_mm_per_N - one.matrix_mm_per_N).norm() <= 1e-9 * one.matrix_mm_per_N.norm());
  }
}

TEST_CASE("workpiece: a wide plate 100 x 2 x 40 mm under a load along its free edge bends as a plate strip, L^3 (1 - nu^2) / (3 E I)") {
  // A unit force spread evenly along the free top edge; the deflection at the
  // middle of the edge. Far from the free sides the plate cannot contract
  // sideways (the clamped base holds its width): it bends in plane strain,
  // the beam's E becomes E / (1 - nu^2) (cylindrical bending: Timoshenko &
  // Woinowsky-Krieger, Theory of Plates and Shells, 2nd ed. 1959, ch. 1),
  // plus the Timoshenko beam's shear, L / (k G b t), k = 5/6 (0.2 % here).
  // The free sides make the middle of a 100 mm plate (2.5 L wide) some 3 %
  // softer than that limit; a plate twice as wide is at it. By Maxwell-Betti
  // the middle's deflection under the spread load is the mean, along the edge,
  // of the edge's deflection under a unit load at the middle: transfer().
  // Elements of 2 mm (one quadratic tet across the wall, 0.3 % stiffer than
  // converged on the strip above) keep it to seconds.
  const test::TempDir dir("workpiece");
  const double nu = 0.33, E = 70000, G = E / (2 * (1 + nu));
  std::vector<double> ratio;
  for (double b : {100.0, 200.0}) {
    const PartSurface part = read_part_surface(box_step(dir, "plate", b, 2, 40));
    WorkpieceOptions o;
    o.mesh_mm = 2;
    const WorkpieceModel model(part, base_clamp(b, 2), aluminium(), o);
    const V3 middle(b / 2, 1, 40);
    const int n = 20;
    double mean = 0;
    for (int i = 0; i <= n; ++i) {
      const double w = (i == 0 || i == n) ? 0.5 / n : 1.0 / n;  // trapezoid rule
      mean += w * model.transfer(V3(b * i / n, 1, 40), middle)(1, 1);
    }
    const double L = model.compliance_at(middle).load_centroid_mm(2);
    const double strip = cantilever_mm_per_N(L, b, 2, E) * (1 - nu * nu) + L / (5.0 / 6 * G * b * 2);
    ratio.push_back(mean / strip);
    const WorkpieceInfo& info = model.info();
    MESSAGE("plate ", b, " mm wide: middle of the edge under a unit edge load ", mean, " mm/N, plate strip ", strip,
            ", ", 100 * (ratio.back() - 1), " %; beam (plane stress) ", cantilever_mm_per_N(L, b, 2, E), "; ",
            info.nodes, " nodes, ", info.elements, " tets, ", info.dofs, " dofs, mesh ", info.mesh_seconds,
            " s, solve ", info.solve_seconds, " s");
  }
  CHECK(ratio[0] == deflex::test::within(1, 0.03));
  CHECK(ratio[0] > 1);  // the free sides soften it
  CHECK(ratio[1] == deflex::test::within(1, 0.01));
}

TEST_CASE("workpiece: the compliance converges as the mesh is refined; the default mesh within 2 % of the finest") {
  const test::TempDir dir("workpiece");
  const PartSurface part = read_part_surface(box_step(dir, "strip", 10, 2, 40));
  std::vector<double> c;
  for (double h : {2.0, 0.0, 0.6}) {
    WorkpieceOptions o;
    o.mesh_mm = h;
    const WorkpieceModel model(part, base_clamp(10, 2), aluminium(), o);
    c.push_back(model.compliance_at(V3(5, 1, 40)).matrix_mm_per_N(1, 1));
    MESSAGE("mesh ", model.info().mesh_mm, " mm: C_yy ", c.back(), " mm/N, ", model.info().dofs, " dofs, ",
            model.info().mesh_seconds + model.info().solve_seconds, " s");
  }
  // Stiffness-based elements converge from below (too stiff when coarse).
  CHECK(c[0] <= c[1] * (1 + 1e-6));
  CHECK(std::abs(c[1] - c[2]) <= std::abs(c[0] - c[2]));
  CHECK(c[1] == deflex::test::within(c[2], 0.02));
}

TEST_CASE("workpiece: the 3x3 compliance is symmetric positive definite, and the transfer reciprocal (Maxwell-Betti)") {
  const test::TempDir dir("workpiece");
  const PartSurface part = read_part_surface(box_step(dir, "strip", 10, 2, 40));
  WorkpieceOptions o;
  o.mesh_mm = 2;
  const WorkpieceModel model(part, base_clamp(10, 2), aluminium(), o);
  for (const V3& p : {V3(0, 1, 20), V3(3, 2, 35), V3(10, 0.5, 12)}) {
    const Compliance c = model.compliance_at(p).matrix_mm_per_N;
    CHECK(symmetric_positive_definite(c, 1e-8));
    CHECK(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(c).eigenvalues().minCoeff() > 0);
  }
  const Compliance ab = model.transfer(V3(3, 2, 35), V3(7, 0, 20)), ba = model.transfer(V3(7, 0, 20), V3(3, 2, 35));
  CHECK((ab - ba.transpose()).norm() < 1e-8 * ab.norm());
  // Lower on the strip, nearer the clamp: stiffer.
  CHECK(model.compliance_at(V3(5, 2, 20)).matrix_mm_per_N(1, 1) < model.compliance_at(V3(5, 2, 38)).matrix_mm_per_N(1, 1));
}

TEST_CASE("workpiece: an STL of the strip gives the STEP's compliance") {
  const test::TempDir dir("workpiece");
  WorkpieceOptions o;
  o.mesh_mm = 2;
  const WorkpieceModel step(read_part_surface(box_step(dir, "strip", 10, 2, 40)), base_clamp(10, 2), aluminium(), o);
  const PartSurface stl = read_part_surface(box_stl(dir, "strip", 10, 2, 40));
  CHECK(stl.stl);
  const WorkpieceModel from_stl(stl, base_clamp(10, 2), aluminium(), o);
  const double a = step.compliance_at(V3(5, 1, 40)).matrix_mm_per_N(1, 1);
  const double b = from_stl.compliance_at(V3(5, 1, 40)).matrix_mm_per_N(1, 1);
  CHECK(b == deflex::test::within(a, 0.01));
}

}  // TEST_SUITE
