// Timoshenko beam finite elements of the chain tip -> tool -> [tool clamp] ->
// [holder] -> [spindle springs] -> ground. The chain is axisymmetric, so one
// bending plane (dofs w, theta) serves x and y, and bar elements (dof u) give
// the axial compliance.
#include "deflex/stiffness/beam.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/stiffness/shape.hpp"

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

enum Comp { W = 0, THETA = 1, U = 2 };

// Link between chain node i and i+1: a beam element or a zero-length joint.
struct Link {
  double length_mm = 0;
  BeamSection section;
  std::optional<Springs> joint;  // set: zero-length spring joint
};

struct Chain {
  std::vector<double> node_z_mm;  // the tip side first
  std::vector<Link> links;        // links[i] joins node i and i+1
  std::optional<Springs> base;    // springs to ground at the last node; nullopt: clamped
};

// Node heights of [z0, z1] with elements no longer than max_mm, plus `extra` inside.
std::vector<double> grid(double z0, double z1, double max_mm) {
  // Range-checked before the cast: the readers bound every length, this is the
  // last line of defence for a caller that does not.
  const double count = std::ceil((z1 - z0) / max_mm - 1e-9);
  if (!(count <= 1e6)) throw Error(ErrorKind::config, "beam model: a section of " + std::to_string(z1 - z0) +
                                                     " mm needs more than 10^6 elements");
  const int n = std::max(1, static_cast<int>(count));
  std::vector<double> z;
  for (int i = 0; i <= n; ++i) z.push_back(z0 + (z1 - z0) * i / n);
  return z;
}

void sort_unique(std::vector<double>& z) {
  std::sort(z.begin(), z.end());
  z.erase(std::unique(z.begin(), z.end(), [](double a, double b) { return b - a < 1e-9; }),
          z.end());
}

void append_beam(Chain& c, const std::vector<double>& z, auto section_at_mm) {
  if (c.node_z_mm.empty()) c.node_z_mm.push_back(z.front());
  for (std::size_t i = 1; i < z.size(); ++i) {
    c.links.push_back({z[i] - z[i - 1], section_at_mm(0.5 * (z[i] + z[i - 1])), std::nullopt});
    c.node_z_mm.push_back(z[i]);
  }
}

void append_joint(Chain& c, const Springs& s) {
  c.links.push_back({0, {}, s});
  c.node_z_mm.push_back(c.node_z_mm.back());
}

// Tool nodes: stations, section changes, and a fine grid in the cap where the
// section varies (element sections are taken at the element midpoint).
std::vector<double> tool_nodes(const ToolShape& s, const std::vector<double>& stations,
                               double max_mm) {
  std::vector<double> z = stations;
  if (s.cap_height_mm > 0)
    for (double v : grid(0, s.cap_height_mm, std::min(max_mm, s.cap_height_mm / 16))) z.push_back(v);
  for (const auto& c : s.cylinders)
    for (double v : grid(c.z0_mm, c.z1_mm, max_mm)) z.push_back(v);
  z.push_back(0);
  sort_unique(z);
  return z;
}

Chain build_chain(const Tool& t, const MachineStiffness& m, bool tool_only,
                  const std::vector<double>& stations, double max_mm) {
  const ToolShape shape = tool_shape(t);
  Chain c;
  append_beam(c, tool_nodes(shape, stations, max_mm),
              [&](double z) { return circular_section(2 * radius_at(shape, z), t.material); });
  if (tool_only) return c;
  if (m.tool_clamp) append_joint(c, *m.tool_clamp);
  if (m.holder) {
    const Holder& h = *m.holder;
    const double L = t.stickout_mm, d_shank = t.shank_diameter_mm;
    if (h.nose_diameter_mm <= d_shank || h.base_diameter_mm <= d_shank)
      throw Error(ErrorKind::config, "holder diameter must exceed the shank diameter of " + t.id);
    // Shank and holder body bend together inside the holder: stiffnesses add.
    append_beam(c, grid(L, L + h.length_mm, max_mm), [&](double z) {
      const double d = h.nose_diameter_mm +
                       (h.base_diameter_mm - h.nose_diameter_mm) * (z - L) / h.length_mm;
      const BeamSection a = circular_section(d, h.material, d_shank);
      const BeamSection b = circular_section(d_shank, t.material);
      return BeamSection{a.EI_Nmm2 + b.EI_Nmm2, a.EA_N + b.EA_N, a.kGA_N + b.kGA_N};
    });
  }
  c.base = m.spindle;
  return c;
}

std::optional<double> spring_of(const Springs& s, int comp) {
  return comp == W ? s.radial_N_per_mm : comp == THETA ? s.rotational_Nmm_per_rad : s.axial_N_per_mm;
}

// Dof index of each node's (w, theta, u); -1 = fixed. Numbered from the base
// down so a rigid joint component shares its dof across the joint.
std::vector<std::array<int, 3>> number_dofs(const Chain& c, int& ndof) {
  const std::size_t n = c.node_z_mm.size();
  std::vector<std::array<int, 3>> d(n);
  ndof = 0;
  for (int k = 0; k < 3; ++k) d[n - 1][k] = (c.base && spring_of(*c.base, k)) ? ndof++ : -1;
  for (std::size_t i = n - 1; i-- > 0;) {
    const Link& l = c.links[i];
    for (int k = 0; k < 3; ++k)
      d[i][k] = (l.joint && !spring_of(*l.joint, k)) ? d[i + 1][k] : ndof++;
  }
  return d;
}

Eigen::SparseMatrix<double> assemble(const Chain& c, const std::vector<std::array<int, 3>>& d,
                                     int ndof) {
  std::vector<Eigen::Triplet<double>> trip;
  auto add = [&](int a, int b, double v) {
    if (a >= 0 && b >= 0) trip.emplace_back(a, b, v);
  };
  auto add_spring = [&](int a, int b, double k) {  // b = -1: to ground
    add(a, a, k);
    add(b, b, k);
    add(a, b, -k);
    add(b, a, -k);
  };
  for (std::size_t i = 0; i < c.links.size(); ++i) {
    const Link& l = c.links[i];
    if (l.joint) {
      for (int k = 0; k < 3; ++k)
        if (auto s = spring_of(*l.joint, k)) add_spring(d[i][k], d[i + 1][k], *s);
      continue;
    }
    const Eigen::Matrix4d kb = timoshenko_element(l.length_mm, l.section);
    const std::array<int, 4> dofs{d[i][W], d[i][THETA], d[i + 1][W], d[i + 1][THETA]};
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) add(dofs[a], dofs[b], kb(a, b));
    add_spring(d[i][U], d[i + 1][U], l.section.EA_N / l.length_mm);
  }
  if (c.base)
    for (int k = 0; k < 3; ++k)
      if (auto s = spring_of(*c.base, k)) add_spring(d.back()[k], -1, *s);
  Eigen::SparseMatrix<double> K(ndof, ndof);
  K.setFromTriplets(trip.begin(), trip.end());
  return K;
}

}  // namespace

namespace {

// The chain solved for unit lateral (column 2 s) and axial (column 2 s + 1) loads
// at each station node; x holds the displacements of every dof.
struct StationSolve {
  std::vector<double> stations_mm;
  std::vector<int> w_dof, u_dof;  // the station nodes' dofs; -1: fixed
  Eigen::MatrixXd x;
};

StationSolve solve_stations(const Tool& t, const MachineStiffness& m, bool tool_only,
                            const BeamOptions& opt) {
  const double top = std::min(t.flute_length_mm, t.stickout_mm);
  const int steps = opt.station_steps > 0 ? opt.station_steps
                                          : std::max(2, static_cast<int>(std::ceil(top / 0.5)));
  StationSolve r;
  r.stations_mm = station_heights_mm(top, steps);
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
