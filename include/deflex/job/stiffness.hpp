// `deflex stiffness` as a call: the compliance C(h) of a library tool, alone
// or in its holder on a machine, at load heights along its flutes.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "deflex/stiffness/compliance.hpp"
#include "deflex/stiffness/solid.hpp"
#include "deflex/stiffness/tool.hpp"

namespace deflex::job {

struct ComplianceSettings {
  std::string tool;                 // the tool's id in the library (T<n>)
  std::string tool_file;            // the library ("": config tool_file, else the installed one)
  std::string machine;              // a profile file or name ("": the tool clamped rigidly at the holder face)
  std::vector<double> heights_mm;   // load heights above the tip (empty: 7 evenly along the flutes)
  bool tool_only = false;           // leave holder, spindle and machine out
  std::string method = "beam";      // beam (Timoshenko elements) or solid (gmsh + FEM)
  double mesh_mm = 0;               // solid: element size (0: D_flute / 5)
  bool cache = true;                // solid: read and write the geometry cache
};

struct ComplianceResult {
  stiffness::Tool tool;
  bool tool_only = true;
  std::string machine_file;                 // the profile used ("" when tool only)
  std::vector<stiffness::ComplianceRow> rows;
  std::optional<stiffness::SolidInfo> solid;  // the solid model's mesh and time
};

// Each setting checked before anything is computed (a settings Error: a
// height off the flutes, an unknown method, a negative mesh size).
ComplianceResult compliance(const ComplianceSettings& s);

}  // namespace deflex::job
