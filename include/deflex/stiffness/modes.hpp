// The lateral modes of the beam model's chain (beam.hpp: tip -> tool -> [tool
// clamp] -> [holder] -> [spindle springs] -> ground) as the tool tip sees them:
// what the stability lobes (deflex/stability/) build the tip's frequency
// response from.
//
// K phi = omega^2 M phi, with K the static model's stiffness and M the
// consistent mass of each Timoshenko element, translational (rho A) and rotary
// (rho I) inertia (Przemieniecki 1968 §11.7; Friedman & Kosmatka 1993). Joint
// springs are massless; their fixed and rigid components are as in the static
// model. The machine structure compliance of the profile (stiffness.structure)
// is NOT in the modal model: it is a massless spring in series, with no
// frequency of its own; a measured FRF (stability/frf.hpp) carries the
// structure's modes where they matter.
//
// The chain is axisymmetric: the same modes serve x and y.
#pragma once
#include <vector>

#include "deflex/stiffness/beam.hpp"
#include "deflex/stiffness/machine.hpp"
#include "deflex/stiffness/tool.hpp"

namespace deflex::stiffness {

// One mode seen at the tool tip, in one lateral direction. stiffness_N_per_mm
// is the modal stiffness at the tip, k_r = omega_r^2 / phi_r(tip)^2 for the
// mass-normalised mode shape phi_r, so that the tip's direct FRF is
//   H(omega) = sum_r 1 / (k_r (1 - (omega/omega_r)^2 + 2 i zeta_r omega/omega_r))   mm/N
// and H(0) = sum_r 1/k_r is the static tip compliance.
struct Mode {
  double frequency_Hz = 0;
  double damping_ratio = 0;
  double stiffness_N_per_mm = 0;
};

// The `count` lowest lateral modes of the chain (count <= 0: all of them),
// frequency ascending, each with the profile's dynamics.damping_ratio. A mode
// with no motion at the tip (none in a cantilever chain) is left out. Mesh as
// beam_compliance's (the same nodes), so the sum of 1/k_r over all modes equals
// beam_compliance's C(0) without the structure compliance.
// tool_only: the tool clamped rigidly at the holder face.
// Throws Error(ErrorKind::config) when the tool's or the holder's material has
// no density (a custom material without density_kg_per_m3).
std::vector<Mode> tip_modes(const Tool& t, const MachineStiffness& m, bool tool_only, int count,
                            const BeamOptions& opt = {});

}  // namespace deflex::stiffness
