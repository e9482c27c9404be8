#include "deflex/stiffness/machine.hpp"

#include <fstream>
#include <sstream>

#include "deflex/diag/diagnostics.hpp"
#include "yaml_read.hpp"

namespace deflex::stiffness {

namespace yr = yaml_read;

static Holder parse_holder(const YAML::Node& n, const std::string& file) {
  yr::require_map(n, "holder", file);
  yr::check_keys(n, {"length_mm", "nose_diameter_mm", "base_diameter_mm", "material", "name"},
                 file);
  Holder h;
  h.length_mm = yr::positive(n, "length_mm", file);
  h.nose_diameter_mm = yr::positive(n, "nose_diameter_mm", file);
  h.base_diameter_mm =
      n["base_diameter_mm"] ? yr::positive(n, "base_diameter_mm", file) : h.nose_diameter_mm;
  h.material = n["material"] ? yr::material(n["material"], file) : *material_preset("steel");
  return h;
}

// Joint springs; catalogue units N/um and N*m/rad become N/mm and N*mm/rad.
static Springs parse_springs(const YAML::Node& n, const std::string& what,
                             const std::string& file) {
  yr::require_map(n, what, file);
  yr::check_keys(n, {"radial_N_per_um", "rotational_Nm_per_rad", "axial_N_per_um"}, file);
  Springs s;
  if (n["radial_N_per_um"]) s.radial_N_per_mm = 1e3 * yr::positive(n, "radial_N_per_um", file);
  if (n["rotational_Nm_per_rad"])
    s.rotational_Nmm_per_rad = 1e3 * yr::positive(n, "rotational_Nm_per_rad", file);
  if (n["axial_N_per_um"]) s.axial_N_per_mm = 1e3 * yr::positive(n, "axial_N_per_um", file);
  return s;
}

static Eigen::Matrix3d parse_matrix(const YAML::Node& n, const std::string& file) {
  if (!n.IsSequence() || n.size() != 3) yr::fail(file, n.Mark(), "compliance_mm_per_N must be 3 rows of 3");
  Eigen::Matrix3d c;
  for (int i = 0; i < 3; ++i) {
    if (!n[i].IsSequence() || n[i].size() != 3) yr::fail(file, n[i].Mark(), "a row must have 3 numbers");
    for (int j = 0; j < 3; ++j) c(i, j) = yr::number_node(n[i][j], "compliance_mm_per_N", file);
  }
  // A passive structure stores energy: its symmetric part must be positive semi-definite.
  const Eigen::Matrix3d sym = 0.5 * (c + c.transpose());
  if (Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(sym).eigenvalues().minCoeff() < 0)
    yr::fail(file, n.Mark(), "compliance_mm_per_N must be positive semi-definite");
  return c;
}

// Stiffness per axis, N/um, as {x, y, z} or [x, y, z] -> diagonal compliance mm/N.
static Eigen::Matrix3d parse_axis_stiffness(const YAML::Node& n, const std::string& file) {
  Eigen::Vector3d k;
  if (n.IsMap()) {
    yr::check_keys(n, {"x", "y", "z"}, file);
    k << yr::positive(n, "x", file), yr::positive(n, "y", file), yr::positive(n, "z", file);
  } else if (n.IsSequence() && n.size() == 3) {
    for (int i = 0; i < 3; ++i) {
      k(i) = yr::number_node(n[i], "stiffness_N_per_um", file);
      if (k(i) <= 0) yr::fail(file, n[i].Mark(), "stiffness_N_per_um must be > 0");
    }
  } else {
    yr::fail(file, n.Mark(), "stiffness_N_per_um must be {x: .., y: .., z: ..} or [x, y, z]");
  }
  return (1.0 / (1e3 * k.array())).matrix().asDiagonal();
}

static Eigen::Matrix3d parse_structure(const YAML::Node& n, const std::string& file) {
  yr::require_map(n, "structure", file);
  yr::check_keys(n, {"compliance_mm_per_N", "stiffness_N_per_um"}, file);
  if (n["compliance_mm_per_N"] && n["stiffness_N_per_um"])
    yr::fail(file, n.Mark(), "give compliance_mm_per_N or stiffness_N_per_um, not both");
  if (n["compliance_mm_per_N"]) return parse_matrix(n["compliance_mm_per_N"], file);
  if (n["stiffness_N_per_um"]) return parse_axis_stiffness(n["stiffness_N_per_um"], file);
  yr::fail(file, n.Mark(), "structure needs compliance_mm_per_N or stiffness_N_per_um");
}

MachineStiffness parse_machine_stiffness(const YAML::Node& root, const std::string& file) {
  MachineStiffness m;
  if (!root || root.IsNull()) return m;
  yr::require_map(root, "a machine profile", file);
  if (root["holder"]) m.holder = parse_holder(root["holder"], file);
  const YAML::Node s = root["stiffness"];
  if (!s) return m;
  yr::require_map(s, "stiffness", file);
  yr::check_keys(s, {"tool_clamp", "spindle", "structure"}, file);
  if (s["tool_clamp"]) m.tool_clamp = parse_springs(s["tool_clamp"], "tool_clamp", file);
  if (s["spindle"]) m.spindle = parse_springs(s["spindle"], "spindle", file);
  if (s["structure"]) m.structure_mm_per_N = parse_structure(s["structure"], file);
  return m;
}

MachineStiffness load_machine_stiffness(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(Exit::io, path + ": error: cannot read the machine profile");
  std::ostringstream ss;
  ss << in.rdbuf();
  YAML::Node root;
  try {
    root = YAML::Load(ss.str());
  } catch (const YAML::ParserException& e) {
    yr::fail(path, e.mark, e.msg);
  }
  return parse_machine_stiffness(root, path);
}

}  // namespace deflex::stiffness
