// What the machine adds to the tool's own compliance: the holder, the
// tool/holder and holder/spindle interfaces, and the machine structure.
//
// Machine profile schema (samples/machines/*.yaml; other keys belong to the
// profile module and are ignored here). Every key is optional; a missing spring
// component is rigid; a missing section adds nothing.
//
//   holder:                      # tool holder body, as beam elements
//     length_mm: 60              # holder face (nose) to spindle gauge line
//     nose_diameter_mm: 32       # outer diameter at the holder face
//     base_diameter_mm: 44       # outer diameter at the gauge line (linear taper between)
//     material: steel            # preset (carbide, hss, steel) or {E_MPa: .., poisson: ..,
//                                #   density_kg_per_m3: ..} (the density for the modal model)
//   stiffness:
//     tool_clamp:                # tool/holder joint at the holder face (collet, shrink fit)
//       radial_N_per_um: 300
//       rotational_Nm_per_rad: 1.5e5
//       axial_N_per_um: 500
//     spindle:                   # holder/spindle interface + spindle, to ground at the gauge line
//       radial_N_per_um: 150
//       rotational_Nm_per_rad: 8.0e5
//       axial_N_per_um: 400
//     structure:                 # measured machine compliance at the tool, in series (one of):
//       compliance_mm_per_N: [[2e-5, 0, 0], [0, 2e-5, 0], [0, 0, 1e-5]]
//       stiffness_N_per_um: {x: 50, y: 50, z: 100}
//   dynamics:                    # the modal model of the tool tip (stiffness/modes.hpp)
//     damping_ratio: 0.03        # modal damping ratio of every tool-tip mode, 0 < zeta < 1
//
// Inside the holder the tool shank and the holder body bend together: their
// bending stiffnesses add (an ideal shrink fit); a compliant collet is the
// tool_clamp spring.
#pragma once
#include <optional>
#include <string>

#include <Eigen/Dense>

#include "deflex/profile/document.hpp"
#include "deflex/stiffness/tool.hpp"

namespace deflex::stiffness {

// Holder body, from the holder face (tool side) to the gauge line.
struct Holder {
  double length_mm = 0;
  double nose_diameter_mm = 0;
  double base_diameter_mm = 0;
  Material material;
};

// A joint's springs; std::nullopt = rigid in that direction. Lateral springs act
// alike in x and y (axisymmetric joint).
struct Springs {
  std::optional<double> radial_N_per_mm;
  std::optional<double> rotational_Nmm_per_rad;
  std::optional<double> axial_N_per_mm;
  bool any() const { return radial_N_per_mm || rotational_Nmm_per_rad || axial_N_per_mm; }
};

// The `dynamics:` section. Tap tests of tool-holder-spindle assemblies give
// modal damping ratios of about 0.02-0.05 for the tool-tip modes (Schmitz &
// Smith, Machining Dynamics, 2nd ed. 2019; Altintas 2012 ch. 3): 0.03 stands
// in the middle when the profile gives none.
struct Dynamics {
  double damping_ratio = 0.03;
  bool damping_given = false;  // the profile gave it (else the default above)
};

struct MachineStiffness {
  std::optional<Holder> holder;
  std::optional<Springs> tool_clamp;  // nullopt: rigid joint
  std::optional<Springs> spindle;     // nullopt: holder clamped rigidly at the gauge line
  // 3x3, machine axes, mm/N (rows displacement x,y,z; cols force x,y,z); zero = rigid.
  Eigen::Matrix3d structure_mm_per_N = Eigen::Matrix3d::Zero();
  Dynamics dynamics;
};

// Reads the `holder:`, `stiffness:` and `dynamics:` sections of a machine profile's root map.
// Throws Error(ErrorKind::config, "file:line:col: error: ...").
MachineStiffness parse_machine_stiffness(const yaml::Document& profile_root, const std::string& file);
// Reads a machine profile file (ErrorKind::io if unreadable).
MachineStiffness load_machine_stiffness(const std::string& path);

}  // namespace deflex::stiffness
