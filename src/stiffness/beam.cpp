// Timoshenko beam finite elements of the chain tip -> tool -> [tool clamp] ->
// [holder] -> [spindle springs] -> ground (beam_chain.hpp), solved for loads at
// the stations.
#include "deflex/stiffness/beam.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include "beam_chain.hpp"
#include "deflex/diag/diagnostics.hpp"

namespace deflex::stiffness {

double shear_coefficient_circle(double nu) { return 6 * (1 + nu) / (7 + 6 * nu); }

BeamSection circular_section(double d, const Material& m, double bore) {
  const double pi = std::numbers::pi;
  const double I = pi * (std::pow(d, 4) - std::pow(bore, 4)) / 64;
  const double A = pi * (d * d - bore * bore) / 4;
  const double G = m.E_MPa / (2 * (1 + m.poisson));
  return {m.E_MPa * I, m.E_MPa * A, shear_coefficient_circle(m.poisson) * G * A};
}

Eigen::Matrix4d timoshenko_element(double L, const BeamSection& s) {
  const double phi = 12 * s.EI_Nmm2 / (s.kGA_N * L * L);
  const double c = s.EI_Nmm2 / ((1 + phi) * L * L * L);
  Eigen::Matrix4d k;
  k << 12, 6 * L, -12, 6 * L,                            //
      6 * L, (4 + phi) * L * L, -6 * L, (2 - phi) * L * L,  //
      -12, -6 * L, 12, -6 * L,                           //
      6 * L, (2 - phi) * L * L, -6 * L, (4 + phi) * L * L;
  return c * k;
}

namespace {

using namespace chain;

// The chain solved for unit lateral (column 2 s) and axial (column 2 s + 1) loads
// at each station node; x holds the displacements of every dof.
struct StationSolve {
  std::vector<double> stations_mm;
  std::vector<int> w_dof, u_dof;  // the station nodes' dofs; -1: fixed
  Eigen::MatrixXd x;
};

StationSolve solve_stations(const Tool& t, const MachineStiffness& m, bool tool_only,
                            const BeamOptions& opt) {
  StationSolve r;
  r.stations_mm = station_heights(t, opt);
  const std::vector<double>& stations = r.stations_mm;
  const Chain chain = build_chain(t, m, tool_only, stations, opt.max_element_mm);
  int ndof = 0;
  const auto dofs = number_dofs(chain, ndof);
  const Eigen::SparseMatrix<double> K = assemble(chain, dofs, ndof);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(K);
  if (ldlt.info() != Eigen::Success) throw Error(ErrorKind::internal, "beam stiffness matrix is singular");

  // Unit lateral and axial loads at each station node; the compliance is the
  // displacement of the loaded dof.
  for (std::size_t s = 0; s < stations.size(); ++s) {
    const auto it = std::lower_bound(chain.node_z_mm.begin(), chain.node_z_mm.end(),
                                     stations[s] - 1e-9);
    const auto node = static_cast<std::size_t>(it - chain.node_z_mm.begin());
    r.w_dof.push_back(dofs[node][W]);
    r.u_dof.push_back(dofs[node][U]);
  }
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(ndof, 2 * static_cast<Eigen::Index>(stations.size()));
  for (std::size_t s = 0; s < stations.size(); ++s) {
    // A station on a fixed dof (flutes up to a rigid clamp) has no compliance.
    if (r.w_dof[s] >= 0) rhs(r.w_dof[s], 2 * s) = 1;
    if (r.u_dof[s] >= 0) rhs(r.u_dof[s], 2 * s + 1) = 1;
  }
  r.x = ldlt.solve(rhs);
  return r;
}

// Displacement of dof `dof` in load case `col` (0 on a fixed dof).
double disp(const StationSolve& r, int dof, Eigen::Index col) { return dof >= 0 ? r.x(dof, col) : 0.0; }

}  // namespace

ComplianceTable beam_compliance(const Tool& t, const MachineStiffness& m, bool tool_only,
                                const BeamOptions& opt) {
  const StationSolve r = solve_stations(t, m, tool_only, opt);
  std::vector<ComplianceRow> rows;
  for (std::size_t s = 0; s < r.stations_mm.size(); ++s) {
    const auto c = static_cast<Eigen::Index>(2 * s);
    const double cb = disp(r, r.w_dof[s], c), ca = disp(r, r.u_dof[s], c + 1);
    Compliance C = Eigen::Vector3d(cb, cb, ca).asDiagonal();
    if (!tool_only) C += m.structure_mm_per_N;
    rows.push_back({r.stations_mm[s], C});
  }
  return ComplianceTable(std::move(rows));
}

CrossComplianceTable beam_cross_compliance(const Tool& t, const MachineStiffness& m, bool tool_only,
                                           const BeamOptions& opt) {
  // Column j of the solve is the whole deflected line under a load at station j,
  // so the displacement at station i is read off directly: exact for the beam
  // model at station pairs (spindle and clamp springs included through the chain).
  const StationSolve r = solve_stations(t, m, tool_only, opt);
  const auto n = static_cast<Eigen::Index>(r.stations_mm.size());
  Eigen::MatrixXd lat(n, n), ax(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) {
      lat(i, j) = disp(r, r.w_dof[static_cast<std::size_t>(i)], 2 * j);
      ax(i, j) = disp(r, r.u_dof[static_cast<std::size_t>(i)], 2 * j + 1);
    }
  // The structure compliance is a rigid translation of the spindle in series.
  const Compliance S = tool_only ? Compliance::Zero() : Compliance(m.structure_mm_per_N);
  return CrossComplianceTable(r.stations_mm, std::move(lat), std::move(ax), S);
}

ComplianceTable add_machine(const ComplianceTable& tool_only_table, const Tool& t,
                            const MachineStiffness& m) {
  const ComplianceTable full = beam_compliance(t, m, false);
  const ComplianceTable alone = beam_compliance(t, m, true);
  std::vector<ComplianceRow> rows = tool_only_table.rows();
  for (auto& r : rows) r.matrix_mm_per_N += full.at(r.height_mm) - alone.at(r.height_mm);
  return ComplianceTable(std::move(rows));
}

}  // namespace deflex::stiffness
