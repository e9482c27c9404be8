// The chain's lateral modes at the tool tip (modes.hpp): the generalized
// eigenproblem K phi = omega^2 M phi on the lateral dofs of beam_chain.
#include "deflex/stiffness/modes.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <Eigen/Dense>

#include "beam_chain.hpp"
#include "deflex/diag/diagnostics.hpp"

namespace deflex::stiffness {
namespace {

void require_density(const Material& m, const std::string& whose) {
  if (m.density_kg_per_m3 > 0) return;
  throw Error(ErrorKind::config, whose + ": its material has no density: the modal model needs one (add " +
                                     "density_kg_per_m3: to its {E_MPa, poisson} material, or use a preset)");
}

// The lateral dofs (w, theta) of the chain in one list, the tip's w first.
std::vector<int> lateral_dofs(const std::vector<std::array<int, 3>>& d) {
  std::vector<int> out{d.front()[chain::W]};
  for (const auto& n : d)
    for (int k : {chain::W, chain::THETA})
      if (n[k] >= 0 && std::find(out.begin(), out.end(), n[k]) == out.end()) out.push_back(n[k]);
  return out;
}

// K and M on the lateral dofs with every massless dof condensed out (Guyan
// reduction, exact for a dof that carries no inertia): a joint between two
// springs, e.g. a tool clamp straight onto the spindle with no holder, has a
// node without mass, and M must be positive definite for the solver.
struct Reduced {
  Eigen::MatrixXd K, M;  // n x n, tip w at index 0
};

Reduced reduce(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M) {
  std::vector<Eigen::Index> keep, drop;
  for (Eigen::Index i = 0; i < K.rows(); ++i) (M(i, i) > 0 ? keep : drop).push_back(i);
  const auto nk = static_cast<Eigen::Index>(keep.size()), nd = static_cast<Eigen::Index>(drop.size());
  Eigen::MatrixXd Kkk(nk, nk), Mkk(nk, nk), Kkd(nk, nd), Kdd(nd, nd);
  for (Eigen::Index a = 0; a < nk; ++a) {
    for (Eigen::Index b = 0; b < nk; ++b) Kkk(a, b) = K(keep[a], keep[b]), Mkk(a, b) = M(keep[a], keep[b]);
    for (Eigen::Index b = 0; b < nd; ++b) Kkd(a, b) = K(keep[a], drop[b]);
  }
  for (Eigen::Index a = 0; a < nd; ++a)
    for (Eigen::Index b = 0; b < nd; ++b) Kdd(a, b) = K(drop[a], drop[b]);
  if (nd > 0) Kkk -= Kkd * Kdd.llt().solve(Kkd.transpose());
  return {Kkk, Mkk};
}

}  // namespace

std::vector<Mode> tip_modes(const Tool& t, const MachineStiffness& m, bool tool_only, int count,
                            const BeamOptions& opt) {
  require_density(t.material, "tool " + t.id);
  if (!tool_only && m.holder) require_density(m.holder->material, "the machine profile's holder");
  const chain::Chain c = chain::build_chain(t, m, tool_only, chain::station_heights(t, opt), opt.max_element_mm);
  int ndof = 0;
  const auto dofs = chain::number_dofs(c, ndof);
  if (dofs.front()[chain::W] < 0) throw Error(ErrorKind::internal, "modal model: the tool tip is fixed");
  const Eigen::MatrixXd K_all(chain::assemble(c, dofs, ndof)), M_all(chain::assemble_mass(c, dofs, ndof));
  // The lateral dofs alone: in the chain they are coupled to no axial dof.
  const std::vector<int> lat = lateral_dofs(dofs);
  const Reduced r = reduce(K_all(lat, lat), M_all(lat, lat));

  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(r.K, r.M);  // phi^T M phi = 1
  if (eig.info() != Eigen::Success) throw Error(ErrorKind::internal, "modal model: the eigensolver failed");
  // Static tip compliance, to leave out modes the tip does not see (round-off).
  const double static_tip = r.K.ldlt().solve(Eigen::VectorXd::Unit(r.K.rows(), 0))(0);
  std::vector<Mode> modes;
  for (Eigen::Index i = 0; i < eig.eigenvalues().size(); ++i) {
    const double w2 = eig.eigenvalues()(i), tip = eig.eigenvectors()(0, i);
    if (!(w2 > 0) || tip * tip / w2 < 1e-14 * static_tip) continue;
    modes.push_back({std::sqrt(w2) / (2 * std::numbers::pi), m.dynamics.damping_ratio, w2 / (tip * tip)});
    if (count > 0 && static_cast<int>(modes.size()) == count) break;
  }
  return modes;
}

}  // namespace deflex::stiffness
