// The material library (samples/materials.yaml): cutting-force coefficient sets,
// each with the model form it was identified for and its source.
//
// File format:
//   materials:
//     NAME:
//       aliases: [OTHER, ...]          # optional
//       model: mechanistic | smaoui_krta
//       # mechanistic (Altintas): K_tc_N_per_mm2, K_rc_N_per_mm2 required;
//       #   K_ac_N_per_mm2, K_te_N_per_mm, K_re_N_per_mm, K_ae_N_per_mm default 0
//       # smaoui_krta (Smaoui 2011 Eq. 2): K_T_N_per_mm2, K_R_N_per_mm2, K_A_N_per_mm2
//       source: "where the numbers come from"   # required
//       conditions: "tool and cutting conditions of the identification"  # optional
//       notes: "..."                             # optional
//       elastic: {E_MPa: 71700, poisson: 0.33}   # optional: the workpiece's
//       #   elastic constants (stiffness/workpiece.hpp), as a tool library
//       #   writes a tool's material; E > 0, -1 < poisson < 0.5
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "deflex/force/coefficients.hpp"

namespace deflex::force {

// Isotropic elastic constants of a work material, for the workpiece's own
// compliance (stiffness/workpiece.hpp).
struct ElasticConstants {
  double E_MPa = 0;
  double poisson = 0;
};

struct MaterialEntry {
  std::string name;
  std::vector<std::string> aliases;
  ModelForm form = ModelForm::mechanistic;
  Coefficients k;  // as used by the model (smaoui_krta mapped by from_smaoui)
  std::string source;
  std::string conditions;
  std::string notes;
  std::optional<ElasticConstants> elastic;  // none: the entry has no `elastic:`
  std::string location;  // "file:line:col" of the entry, for messages
};

struct MaterialLibrary {
  std::string file;
  std::vector<MaterialEntry> entries;
};

// Throws Error(ErrorKind::io) when unreadable, Error(ErrorKind::config,
// "file:line:col: error: ...") on any YAML or value error.
MaterialLibrary load_material_library(const std::string& path);
MaterialLibrary parse_material_library(const std::string& yaml_text, const std::string& file);

// By name or alias, ignoring case and the characters " -_". Throws
// Error(ErrorKind::settings) naming the known materials when absent.
const MaterialEntry& find_material(const MaterialLibrary& lib, const std::string& name);

// One entry as YAML text (with the `materials:` header), readable by the loader.
std::string to_yaml(const MaterialEntry& m);

}  // namespace deflex::force
