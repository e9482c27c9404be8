#include "deflex/report/workpiece.hpp"

#include <Eigen/Eigenvalues>
#include <cstdio>
#include <sstream>

#include "deflex/report/compliance.hpp"
#include "deflex/report/json.hpp"

namespace deflex::report {

namespace {

using V3 = Eigen::Vector3d;

struct Principal {
  double compliance_mm_per_N;
  V3 direction;
};

// Eigenvalues of the symmetric part, largest first; each direction's largest
// component made positive so the output does not flip between runs.
std::vector<Principal> principal(const stiffness::Compliance& c) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(0.5 * (c + c.transpose()));
  std::vector<Principal> out;
  for (int k = 2; k >= 0; --k) {
    V3 d = es.eigenvectors().col(k);
    Eigen::Index i = 0;
    d.cwiseAbs().maxCoeff(&i);
    if (d(i) < 0) d = -d;
    out.push_back({es.eigenvalues()(k), d});
  }
  return out;
}

std::string point(const V3& p) { return "(" + formatted("%.3f", p(0)) + ", " + formatted("%.3f", p(1)) + ", " + formatted("%.3f", p(2)) + ")"; }

Json mesh_json(const stiffness::WorkpieceInfo& m) {
  return {{"nodes", m.nodes},
          {"elements", m.elements},
          {"dofs", m.dofs},
          {"fixed_nodes", m.fixed_nodes},
          {"straightened_elements", m.straightened},
          {"element_size_mm", significant(m.mesh_mm, 6)},
          {"patch_radius_mm", significant(m.patch_radius_mm, 6)},
          {"thinnest_wall_mm", significant(m.thinnest_wall_mm, 6)},
          {"mesh_seconds", fixed(m.mesh_seconds, 3)},
          {"solve_seconds", fixed(m.solve_seconds, 3)}};
}

}  // namespace

std::string workpiece_json(const WorkpieceTitle& t, const stiffness::WorkpieceInfo& mesh,
                           const std::vector<stiffness::PointCompliance>& points) {
  Json list = Json::array();
  for (const auto& p : points) {
    Json pr = Json::array();
    for (const auto& q : principal(p.matrix_mm_per_N))
      pr.push_back({{"compliance_mm_per_N", significant(q.compliance_mm_per_N, 7)},
                    {"direction", xyz(q.direction(0), q.direction(1), q.direction(2), 6)}});
    list.push_back({{"point_mm", xyz(p.point_mm(0), p.point_mm(1), p.point_mm(2), 6)},
                    {"surface_mm", xyz(p.surface_mm(0), p.surface_mm(1), p.surface_mm(2), 6)},
                    {"load_centroid_mm", xyz(p.load_centroid_mm(0), p.load_centroid_mm(1), p.load_centroid_mm(2), 6)},
                    {"compliance_mm_per_N", compliance_matrix_json(p.matrix_mm_per_N)},
                    {"principal", pr}});
  }
  return line({{"part", t.part},
               {"fixtures", t.fixtures},
               {"material", t.material},
               {"E_MPa", significant(t.elastic.E_MPa, 7)},
               {"poisson", significant(t.elastic.poisson, 7)},
               {"mesh", mesh_json(mesh)},
               {"points", list}});
}

std::string workpiece_text(const WorkpieceTitle& t, const stiffness::WorkpieceInfo& m,
                           const std::vector<stiffness::PointCompliance>& points) {
  std::ostringstream o;
  o << "part " << t.part << ", material " << t.material << " (E " << formatted("%g", t.elastic.E_MPa) << " MPa, nu "
    << formatted("%g", t.elastic.poisson) << "), held by";
  for (const auto& f : t.fixtures) o << " " << f;
  o << "\nmesh: " << m.nodes << " nodes, " << m.elements << " quadratic tets, " << m.dofs << " dofs, "
    << m.fixed_nodes << " nodes held; elements " << formatted("%.3g", m.mesh_mm) << " mm (thinnest wall "
    << formatted("%.3g", m.thinnest_wall_mm) << " mm), load patch radius " << formatted("%.3g", m.patch_radius_mm)
    << " mm; meshed in " << formatted("%.1f", m.mesh_seconds) << " s, solved in " << formatted("%.1f", m.solve_seconds) << " s";
  if (m.straightened) o << "; " << m.straightened << " elements folded on curved faces made straight-sided";
  o << "\n";
  for (const auto& p : points) {
    o << "\npoint " << point(p.point_mm) << " mm, on the surface at " << point(p.surface_mm) << "\n"
      << "C, mm/N (rows: displacement x, y, z; columns: force Fx, Fy, Fz; machine axes):\n";
    o << compliance_matrix_text(p.matrix_mm_per_N);
    o << "principal compliances (um/N along the direction):\n";
    for (const auto& q : principal(p.matrix_mm_per_N))
      o << "  " << formatted("%10.4g", 1e3 * q.compliance_mm_per_N) << " along " << point(q.direction) << "\n";
  }
  return o.str();
}

}  // namespace deflex::report
