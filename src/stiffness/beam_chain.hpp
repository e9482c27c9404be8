// The chain of the beam model, shared by the static solve (beam.cpp) and the
// modal one (modes.cpp): tip -> tool -> [tool clamp] -> [holder] -> [spindle
// springs] -> ground, its dof numbering and its assembled matrices. The chain
// is axisymmetric, so one bending plane (dofs w, theta) serves x and y, and bar
// elements (dof u) give the axial compliance.
#pragma once
#include <array>
#include <optional>
#include <vector>

#include <Eigen/Sparse>

#include "deflex/stiffness/beam.hpp"

namespace deflex::stiffness::chain {

enum Comp { W = 0, THETA = 1, U = 2 };

// Mass per length of an element, in the units that go with N and mm (1 N =
// 1 t mm/s^2): rhoA_t_per_mm translational, rhoI_t_mm rotary (rho * second
// moment of area, one bending plane). 0 where the material has no density.
struct BeamMass {
  double rhoA_t_per_mm = 0;
  double rhoI_t_mm = 0;
};

// Link between chain node i and i+1: a beam element or a zero-length joint.
struct Link {
  double length_mm = 0;
  BeamSection section;
  BeamMass mass;
  std::optional<Springs> joint;  // set: zero-length spring joint
};

struct Chain {
  std::vector<double> node_z_mm;  // the tip side first
  std::vector<Link> links;        // links[i] joins node i and i+1
  std::optional<Springs> base;    // springs to ground at the last node; nullopt: clamped
};

// The heights of beam_compliance's table rows (and of the nodes it loads).
std::vector<double> station_heights(const Tool& t, const BeamOptions& opt);

Chain build_chain(const Tool& t, const MachineStiffness& m, bool tool_only, const std::vector<double>& stations,
                  double max_mm);

// Dof index of each node's (w, theta, u); -1 = fixed. A rigid joint component
// shares its dof across the joint.
std::vector<std::array<int, 3>> number_dofs(const Chain& c, int& ndof);

// ndof x ndof stiffness, N/mm, N/rad, N mm/rad (lateral and axial dofs, uncoupled).
Eigen::SparseMatrix<double> assemble(const Chain& c, const std::vector<std::array<int, 3>>& d, int ndof);

// ndof x ndof consistent mass of the lateral dofs, t and t mm^2 (axial dofs:
// zero rows). Joints are massless.
Eigen::SparseMatrix<double> assemble_mass(const Chain& c, const std::vector<std::array<int, 3>>& d, int ndof);

// 4x4 consistent mass of a Timoshenko element with rotary inertia, dofs (w1,
// theta1, w2, theta2) as timoshenko_element's, t and t mm^2.
Eigen::Matrix4d timoshenko_mass(double length_mm, const BeamSection& s, const BeamMass& m);

}  // namespace deflex::stiffness::chain
