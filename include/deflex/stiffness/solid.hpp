// Solid model: the tool as an OpenCASCADE solid, meshed with quadratic
// tetrahedra by gmsh, solved by our own linear-elastic FEM (Eigen) -> C(h).
#pragma once
#include <cstddef>
#include <optional>
#include <string>

#include "deflex/stiffness/compliance.hpp"
#include "deflex/stiffness/machine.hpp"
#include "deflex/stiffness/tool.hpp"

namespace deflex::stiffness {

struct SolidOptions {
  double mesh_size_mm = 0;     // largest element edge; 0: default_mesh_size_mm(tool)
  double patch_radius_mm = 0;  // load patch radius; 0: default_patch_radius_mm(tool)
  int station_steps = 8;       // load stations along the flutes
  // Cache folder; nullopt: default_cache_dir(); empty string: no cache.
  std::optional<std::string> cache_dir;
};

struct SolidInfo {
  std::size_t nodes = 0;
  std::size_t elements = 0;  // 10-node tetrahedra
  std::size_t dofs = 0;      // free degrees of freedom
  double seconds = 0;        // wall time of this call
  bool from_cache = false;
  std::string cache_file;    // empty: not cached
};

// Default element size: a fifth of the fluted diameter (quadratic tets carry
// the linear bending stress exactly, so a few elements across suffice; see the
// mesh convergence test).
double default_mesh_size_mm(const Tool& t);
// Default load patch radius: a quarter of the fluted radius.
double default_patch_radius_mm(const Tool& t);

// $DEFLEX_CACHE_DIR, else $XDG_CACHE_HOME/deflex, else ~/.cache/deflex.
std::string default_cache_dir();

// C(h) of the tool clamped rigidly at the holder face (every node at or above
// z = stickout_mm is fixed), for h from 0 to the top of the flutes. Built from
// the tool's parameters, or from tool.step_file when set (axis +z; its lowest
// point is moved to z = 0). Throws Error(ErrorKind::io) for an unreadable STEP file,
// Error(ErrorKind::internal) when meshing or solving fails.
ComplianceTable solid_tool_compliance(const Tool& t, const SolidOptions& opt = {},
                                      SolidInfo* info = nullptr);

// Writes the tool's parametric solid (the body the solid model meshes) as a
// STEP file, e.g. to check it in a CAD viewer. Throws Error(ErrorKind::io).
void write_tool_step(const Tool& t, const std::string& step_path);

// The same with the holder, joints and machine structure of `m` in series (the
// machine part from the beam model, see add_machine), unless tool_only.
ComplianceTable solid_compliance(const Tool& t, const MachineStiffness& m, bool tool_only,
                                 const SolidOptions& opt = {}, SolidInfo* info = nullptr);

}  // namespace deflex::stiffness
