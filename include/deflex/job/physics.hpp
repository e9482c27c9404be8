// `deflex stiffness`, `deflex forces` and `deflex calibrate` as calls: the
// compliance C(h) of a library tool, alone or in its holder on a machine, at
// load heights along its flutes; the cutting forces over a revolution for one
// engagement; the coefficients of a material fitted to slot tests.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "deflex/force/calibration.hpp"
#include "deflex/force/material.hpp"
#include "deflex/force/mechanistic.hpp"
#include "deflex/job/settings.hpp"
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

struct ForceSettings {
  std::string tool;               // the tool's id in the library
  std::string tool_file;          // the library ("": config tool_file, else the installed one)
  MaterialSettings material;      // by name, or the coefficients ("": config material)
  double ae_mm = 0;               // radial depth of cut from the cutting side (>= D: a slot)
  double ap_mm = 0;               // axial depth of cut above the tip, at most the flute length
  double fz_mm = 0;               // feed per tooth
  bool up_milling = false;        // up-milling (cuts on +Y); else down-milling (cuts on -Y)
  int steps = 360;                // angular steps per revolution
  double dz_mm = 0.05;            // axial slice height (at least 20 slices over a_p)
};

struct ForceResult {
  std::vector<force::Vec3> force_N;   // on the tool, machine axes, one per step from angle 0
  force::ForceSummary summary;        // mean and peak |F| per axis
  double mean_torque_Nm = 0;          // on the spindle, mean over the revolution (force::mean_torque)
  // Morelli's shape code of the force curve, where it applies (a flat end
  // mill down-milling with helical flutes and K_rc > 0).
  std::optional<std::string> shape_code;
};

// Each setting checked (a settings Error) before anything is computed.
ForceResult forces(const ForceSettings& s);

struct CalibrationSettings {
  std::string file;    // the slot tests, CSV (force/calibration.hpp)
  std::string name;    // the material's name ("": the CSV's '# material:', else the file's stem)
  std::string output;  // the material entry (YAML) written here atomically ("": not written)
};

struct CalibrationResult {
  force::SlotTestData tests;
  force::SlotCalibration fit;  // the coefficients, the line fits, each test's residual
  force::MaterialEntry entry;  // for a material library: the coefficients with their source and conditions
  std::string yaml;            // the entry as a material library's YAML
};

// An output that is the input is refused before the tests are read.
CalibrationResult calibrate(const CalibrationSettings& s);

}  // namespace deflex::job
