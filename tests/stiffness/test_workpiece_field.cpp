// The workpiece's compliance field (stiffness/workpiece_field.hpp): nodes
// solved once, the field between them against the FEM asked directly.
#include <doctest/doctest.h>

#include <cmath>

#include "deflex/stiffness/workpiece.hpp"
#include "deflex/stiffness/workpiece_field.hpp"
#include "helpers.hpp"
#include "workpiece_parts.hpp"

using namespace deflex;
using namespace deflex::stiffness;
using namespace deflex::stiffness::testing;
using V3 = Eigen::Vector3d;

TEST_SUITE("stiffness") {

TEST_CASE("workpiece field: exact at its nodes, within 1 % of the FEM between them on a bending strip") {
  // The 10 x 2 x 40 mm strip clamped at its base; nodes every 1 mm over the
  // upper half of its face y = 2, where C_yy grows with the cube of the
  // height (from 0.0058 to 0.044 mm/N).
  const test::TempDir dir("workpiece-field");
  const PartSurface part = read_part_surface(box_step(dir, "strip", 10, 2, 40));
  Material al;
  al.E_MPa = 70000;
  al.poisson = 0.33;
  const std::vector<Fixture> clamp = {parse_fixture("box:-1,-1,-1,11,3,0.001")};
  const WorkpieceModel model(part, clamp, al);
  std::vector<V3> pts;
  for (int i = 1; i <= 9; ++i)
    for (int k = 20; k <= 40; ++k) pts.push_back(V3(i, 2, k));
  pts.push_back(V3(1.2, 2, 20.3));  // a second point in a node's cell is not a node
  const WorkpieceField field(model, pts, std::vector<V3>(pts.size(), V3::UnitY()), 1.0);
  CHECK(field.nodes() == 9 * 21);
  const Compliance at_node = field.at(V3(5, 2, 30), V3::UnitY());
  CHECK((at_node - model.compliance_at(V3(5, 2, 30)).matrix_mm_per_N).norm() <= 1e-12 * at_node.norm());
  // Between nodes: the fit against the FEM asked there, and the nearest
  // node's value against it (what the fit is there to beat).
  double worst = 0, worst_nearest = 0;
  for (const V3& q : {V3(2.5, 2, 24.37), V3(5.5, 2, 31.5), V3(7.3, 2, 38.6), V3(4.1, 2, 35.55), V3(8.5, 2, 22.5)}) {
    const double direct = model.compliance_at(q).matrix_mm_per_N(1, 1), interpolated = field.at(q, V3::UnitY())(1, 1);
    const V3 nearest(std::round(q.x()), q.y(), std::round(q.z()));
    const double at_nearest = model.compliance_at(nearest).matrix_mm_per_N(1, 1);
    worst = std::max(worst, std::fabs(interpolated / direct - 1));
    worst_nearest = std::max(worst_nearest, std::fabs(at_nearest / direct - 1));
  }
  MESSAGE("workpiece field: C_yy between nodes 1 mm apart within ", 100 * worst, " % of the FEM; the nearest node's ",
          100 * worst_nearest, " %");
  CHECK(worst < 0.01);
  CHECK(worst_nearest > 2 * worst);
}

}  // TEST_SUITE
