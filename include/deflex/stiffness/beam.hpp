// Timoshenko beam finite-element model of tool + holder + joints -> C(h).
#pragma once
#include <Eigen/Dense>

#include "deflex/stiffness/compliance.hpp"
#include "deflex/stiffness/machine.hpp"
#include "deflex/stiffness/tool.hpp"

namespace deflex::stiffness {

// Section properties of a beam element.
struct BeamSection {
  double EI_Nmm2 = 0;  // bending stiffness
  double EA_N = 0;     // axial stiffness
  double kGA_N = 0;    // shear stiffness (shear coefficient * G * A)
};

// Shear coefficient of a solid circular section (Cowper 1966):
// k = 6 (1 + nu) / (7 + 6 nu).
double shear_coefficient_circle(double poisson);

// Solid circular section of a material; with bore_mm > 0 a tube.
BeamSection circular_section(double diameter_mm, const Material& m, double bore_mm = 0);

// 4x4 stiffness of a 2-node Timoshenko beam element in one bending plane,
// dofs (w1, theta1, w2, theta2) in mm and rad, N/mm and N*mm/rad. Exact for a
// prismatic beam loaded at its nodes (shear parameter phi = 12 EI / (kGA L^2),
// Przemieniecki 1968 §5.6).
Eigen::Matrix4d timoshenko_element(double length_mm, const BeamSection& s);

struct BeamOptions {
  int station_steps = 0;         // table steps along the flutes; 0: every 0.5 mm
  double max_element_mm = 2.0;   // element length outside the stations
};

// C(h) for h from 0 to the top of the flutes (cut at the holder face).
// tool_only: the tool clamped rigidly at the holder face; otherwise the holder,
// the joint springs and the structure compliance of `m` are in the chain.
ComplianceTable beam_compliance(const Tool& t, const MachineStiffness& m, bool tool_only,
                                const BeamOptions& opt = {});

// C(z, z') from the same chain and stations as beam_compliance (its diagonal at
// the stations is bit for bit that table's rows): one solve per station load
// gives the deflected line, read at every station.
CrossComplianceTable beam_cross_compliance(const Tool& t, const MachineStiffness& m, bool tool_only,
                                           const BeamOptions& opt = {});

// Adds what the machine contributes to a tool-only table (e.g. from the solid
// model): C(h) + [C_beam(h) - C_beam,tool_only(h)]. Exact in series: the tool's
// own deflection relative to the holder face does not depend on how the face moves.
ComplianceTable add_machine(const ComplianceTable& tool_only_table, const Tool& t,
                            const MachineStiffness& m);

}  // namespace deflex::stiffness
