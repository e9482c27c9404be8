// The tool library: end mills described by their parameters (samples/tools.yaml).
// Frame: the tool axis is +z, the tip at z = 0, the holder face at z = stickout_mm.
#pragma once
#include <map>
#include <optional>
#include <string>

#include "deflex/stock/end_shape.hpp"

namespace deflex::stiffness {

// Linear-elastic isotropic material.
struct Material {
  std::string name;  // preset name, or "custom"
  double E_MPa = 0;
  double poisson = 0;
  // Allowable bending stress for the plausibility check of the peak force
  // (compensate/plausibility.hpp), MPa. See material_preset().
  double allowable_bending_MPa = 1000;
  // Mass density, kg/m^3, for the modal model (stiffness/modes.hpp); 0 =
  // unknown (a custom material without `density_kg_per_m3:`), which the static
  // models never need.
  double density_kg_per_m3 = 0;
};

// Presets for `material: carbide|hss|steel`. Typical handbook values: cemented
// carbide (WC-Co, 10% Co) 600 GPa, M2 high-speed steel 220 GPa, tool steel 210 GPa.
// Allowable bending stress (rupture strength / safety 2): carbide 1000 MPa
// (transverse rupture strength of micro-grain WC-Co end-mill grades ~2000-4000
// MPa, ISO 3327; the low end taken), M2 HSS at 63-65 HRC 1500 MPa (bend
// strength ~3000-4000 MPa), tool steel 800 MPa (tensile ~1600 MPa hardened);
// a custom {E_MPa, poisson} material: 1000 MPa.
// Density: WC-10%Co 14,500 kg/m^3 (ASM Handbook vol. 2, "Cemented carbides":
// 14.3-14.6 g/cm^3 at 10 % Co), M2 HSS 8,150 kg/m^3 (ASM Handbook vol. 1,
// "Wrought tool steels": M2 8.16 g/cm^3), steel 7,850 kg/m^3 (the usual
// figure of carbon and low-alloy steels, ASM Handbook vol. 1). A custom
// material gives `density_kg_per_m3:` beside E_MPa and poisson, or has none (0).
std::optional<Material> material_preset(const std::string& name);

// A reduced-diameter neck between the flutes and the shank (long-reach tools).
struct Neck {
  double diameter_mm = 0;
  double length_mm = 0;  // from the end of the flutes towards the shank
};

struct Tool {
  std::string id;
  stock::EndShape type = stock::EndShape::flat;
  double diameter_mm = 0;
  double corner_radius_mm = 0;  // bull: corner; ball: diameter/2; flat: 0
  int flutes = 2;
  double helix_deg = 30;
  double flute_length_mm = 0;         // from the tip
  double stickout_mm = 0;             // holder face to tip
  double shank_diameter_mm = 0;       // defaults to diameter_mm
  double flute_diameter_ratio = 0.8;  // equivalent solid diameter of the fluted part / D
  Material material;
  std::optional<Neck> neck;
  // Plausibility (compensate/plausibility.hpp): the largest peak |F| allowed
  // (none: from the bending strength at the stick-out), and whether the end
  // cuts at its centre (may plunge straight down).
  std::optional<double> max_force_N;
  bool centre_cutting = true;
  std::string step_file;  // vendor model, resolved against the library's folder; empty: none
  // The tool tip's measured FRF (a tap test's CSV, stability/frf.hpp), resolved
  // the same way: the stability check along a program uses it instead of the
  // modal model. Empty: none.
  std::string frf_file;
  std::string source;     // "file:line:col" of the tool's entry, for messages
};

struct ToolLibrary {
  std::string file;
  std::map<std::string, Tool> tools;
};

// Reads a tool library. Throws Error(ErrorKind::io) when the file cannot be read and
// Error(ErrorKind::config, "file:line:col: error: ...") for any YAML or value error.
ToolLibrary load_tool_library(const std::string& path);
// The same from YAML text (`file` names it in messages; relative step_file
// paths are resolved against the folder of `file`).
ToolLibrary parse_tool_library(const std::string& yaml_text, const std::string& file);

// Throws Error(ErrorKind::settings) naming the known tools when `id` is missing.
const Tool& find_tool(const ToolLibrary& lib, const std::string& id);

}  // namespace deflex::stiffness
