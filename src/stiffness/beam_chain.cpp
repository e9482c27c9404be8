// The beam model's chain (beam_chain.hpp): nodes, elements, joints, and the
// assembly of its stiffness and mass.
#include "beam_chain.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/stiffness/compliance.hpp"
#include "deflex/stiffness/shape.hpp"

namespace deflex::stiffness::chain {
namespace {

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

// The element at height z: its section and its mass per length.
struct Element {
  BeamSection section;
  BeamMass mass;
};

// kg/m^3 -> t/mm^3 (1 t = 1e3 kg, 1 m^3 = 1e9 mm^3).
constexpr double kTonnePerMm3 = 1e-12;

BeamMass circular_mass(double d, const Material& m, double bore = 0) {
  const double pi = std::numbers::pi, rho = m.density_kg_per_m3 * kTonnePerMm3;
  return {rho * pi * (d * d - bore * bore) / 4, rho * pi * (std::pow(d, 4) - std::pow(bore, 4)) / 64};
}

void append_beam(Chain& c, const std::vector<double>& z, auto element_at_mm) {
  if (c.node_z_mm.empty()) c.node_z_mm.push_back(z.front());
  for (std::size_t i = 1; i < z.size(); ++i) {
    const Element e = element_at_mm(0.5 * (z[i] + z[i - 1]));
    c.links.push_back({z[i] - z[i - 1], e.section, e.mass, std::nullopt});
    c.node_z_mm.push_back(z[i]);
  }
}

void append_joint(Chain& c, const Springs& s) {
  c.links.push_back({0, {}, {}, s});
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

// Shank and holder body bend together inside the holder: stiffnesses and masses add.
void append_holder(Chain& c, const Tool& t, const Holder& h, double max_mm) {
  const double L = t.stickout_mm, d_shank = t.shank_diameter_mm;
  if (h.nose_diameter_mm <= d_shank || h.base_diameter_mm <= d_shank)
    throw Error(ErrorKind::config, "holder diameter must exceed the shank diameter of " + t.id);
  append_beam(c, grid(L, L + h.length_mm, max_mm), [&](double z) {
    const double d = h.nose_diameter_mm + (h.base_diameter_mm - h.nose_diameter_mm) * (z - L) / h.length_mm;
    const BeamSection a = circular_section(d, h.material, d_shank);
    const BeamSection b = circular_section(d_shank, t.material);
    const BeamMass ma = circular_mass(d, h.material, d_shank), mb = circular_mass(d_shank, t.material);
    return Element{{a.EI_Nmm2 + b.EI_Nmm2, a.EA_N + b.EA_N, a.kGA_N + b.kGA_N},
                   {ma.rhoA_t_per_mm + mb.rhoA_t_per_mm, ma.rhoI_t_mm + mb.rhoI_t_mm}};
  });
}

std::optional<double> spring_of(const Springs& s, int comp) {
  return comp == W ? s.radial_N_per_mm : comp == THETA ? s.rotational_Nmm_per_rad : s.axial_N_per_mm;
}

}  // namespace

std::vector<double> station_heights(const Tool& t, const BeamOptions& opt) {
  const double top = std::min(t.flute_length_mm, t.stickout_mm);
  const int steps = opt.station_steps > 0 ? opt.station_steps
                                          : std::max(2, static_cast<int>(std::ceil(top / 0.5)));
  return station_heights_mm(top, steps);
}

Chain build_chain(const Tool& t, const MachineStiffness& m, bool tool_only, const std::vector<double>& stations,
                  double max_mm) {
  const ToolShape shape = tool_shape(t);
  Chain c;
  append_beam(c, tool_nodes(shape, stations, max_mm), [&](double z) {
    const double d = 2 * radius_at(shape, z);
    return Element{circular_section(d, t.material), circular_mass(d, t.material)};
  });
  if (tool_only) return c;
  if (m.tool_clamp) append_joint(c, *m.tool_clamp);
  if (m.holder) append_holder(c, t, *m.holder, max_mm);
  c.base = m.spindle;
  return c;
}

// Numbered from the base down so a rigid joint component shares its dof across the joint.
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

namespace {

// Adds a 4x4 element matrix on the lateral dofs of nodes i and i+1 (fixed dofs dropped).
void add_lateral(std::vector<Eigen::Triplet<double>>& trip, const std::vector<std::array<int, 3>>& d,
                 std::size_t i, const Eigen::Matrix4d& e) {
  const std::array<int, 4> dofs{d[i][W], d[i][THETA], d[i + 1][W], d[i + 1][THETA]};
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b)
      if (dofs[a] >= 0 && dofs[b] >= 0) trip.emplace_back(dofs[a], dofs[b], e(a, b));
}

}  // namespace

Eigen::SparseMatrix<double> assemble(const Chain& c, const std::vector<std::array<int, 3>>& d, int ndof) {
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
    add_lateral(trip, d, i, timoshenko_element(l.length_mm, l.section));
    add_spring(d[i][U], d[i + 1][U], l.section.EA_N / l.length_mm);
  }
  if (c.base)
    for (int k = 0; k < 3; ++k)
      if (auto s = spring_of(*c.base, k)) add_spring(d.back()[k], -1, *s);
  Eigen::SparseMatrix<double> K(ndof, ndof);
  K.setFromTriplets(trip.begin(), trip.end());
  return K;
}

Eigen::SparseMatrix<double> assemble_mass(const Chain& c, const std::vector<std::array<int, 3>>& d, int ndof) {
  std::vector<Eigen::Triplet<double>> trip;
  for (std::size_t i = 0; i < c.links.size(); ++i)
    if (!c.links[i].joint) add_lateral(trip, d, i, timoshenko_mass(c.links[i].length_mm, c.links[i].section, c.links[i].mass));
  Eigen::SparseMatrix<double> M(ndof, ndof);
  M.setFromTriplets(trip.begin(), trip.end());
  return M;
}

Eigen::Matrix4d timoshenko_mass(double L, const BeamSection& s, const BeamMass& m) {
  // Przemieniecki 1968 §11.7 (Eqs. 11.41, 11.42), the consistent mass of the
  // shear-deformable element whose shape functions give timoshenko_element
  // (same phi = 12 EI / (kGA L^2)); Friedman & Kosmatka 1993 derive the same.
  const double p = 12 * s.EI_Nmm2 / (s.kGA_N * L * L), q = 1 + p;
  const double m1 = 13.0 / 35 + 7 * p / 10 + p * p / 3, m2 = (11.0 / 210 + 11 * p / 120 + p * p / 24) * L;
  const double m3 = 9.0 / 70 + 3 * p / 10 + p * p / 6, m4 = -(13.0 / 420 + 3 * p / 40 + p * p / 24) * L;
  const double m5 = (1.0 / 105 + p / 60 + p * p / 120) * L * L, m6 = -(1.0 / 140 + p / 60 + p * p / 120) * L * L;
  Eigen::Matrix4d t;  // translational inertia, rho A
  t << m1, m2, m3, m4,  //
      m2, m5, -m4, m6,  //
      m3, -m4, m1, -m2,  //
      m4, m6, -m2, m5;
  const double r1 = 6.0 / 5, r2 = (1.0 / 10 - p / 2) * L;
  const double r3 = (2.0 / 15 + p / 6 + p * p / 3) * L * L, r4 = (-1.0 / 30 - p / 6 + p * p / 6) * L * L;
  Eigen::Matrix4d r;  // rotary inertia, rho I
  r << r1, r2, -r1, r2,  //
      r2, r3, -r2, r4,   //
      -r1, -r2, r1, -r2,  //
      r2, r4, -r2, r3;
  return m.rhoA_t_per_mm * L / (q * q) * t + m.rhoI_t_mm / (L * q * q) * r;
}

}  // namespace deflex::stiffness::chain
