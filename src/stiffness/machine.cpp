#include "deflex/stiffness/machine.hpp"

#include "deflex/diag/diagnostics.hpp"
#include "deflex/profile/yaml.hpp"
#include "tool_yaml.hpp"

namespace deflex::stiffness {

using yaml::Map;
using yaml::Range;

static Holder parse_holder(const Map& n) {
  Holder h;
  // At most a metre, like a tool's sizes (stiffness/tool.cpp): beyond it a
  // number is a typo, and the beam mesh would count past an int.
  const Range size_mm{0, 1000, true};
  h.length_mm = n.number("length_mm", size_mm);
  h.nose_diameter_mm = n.number("nose_diameter_mm", size_mm);
  h.base_diameter_mm = n.number("base_diameter_mm", h.nose_diameter_mm, size_mm);
  h.material = n.has("material") ? parse_material(n.get("material"), n.file()) : *material_preset("steel");
  if (n.has("name")) n.text("name");
  return h;
}

// Joint springs; catalogue units N/um and N*m/rad become N/mm and N*mm/rad.
static Springs parse_springs(const Map& n) {
  Springs s;
  if (n.has("radial_N_per_um")) s.radial_N_per_mm = 1e3 * n.number("radial_N_per_um", Range::positive());
  if (n.has("rotational_Nm_per_rad"))
    s.rotational_Nmm_per_rad = 1e3 * n.number("rotational_Nm_per_rad", Range::positive());
  if (n.has("axial_N_per_um")) s.axial_N_per_mm = 1e3 * n.number("axial_N_per_um", Range::positive());
  return s;
}

static Eigen::Matrix3d parse_matrix(const YAML::Node& n, const std::string& file) {
  if (!n.IsSequence() || n.size() != 3) yaml::fail(file, n.Mark(), "compliance_mm_per_N must be 3 rows of 3");
  Eigen::Matrix3d c;
  for (std::size_t i = 0; i < 3; ++i) {
    if (!n[i].IsSequence() || n[i].size() != 3) yaml::fail(file, n[i].Mark(), "a row must have 3 numbers");
    for (std::size_t j = 0; j < 3; ++j)
      c(static_cast<int>(i), static_cast<int>(j)) = yaml::number(n[i][j], "compliance_mm_per_N", file);
  }
  // A passive structure stores energy: its symmetric part must be positive semi-definite.
  const Eigen::Matrix3d sym = 0.5 * (c + c.transpose());
  if (Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(sym).eigenvalues().minCoeff() < 0)
    yaml::fail(file, n.Mark(), "compliance_mm_per_N must be positive semi-definite");
  return c;
}

// Stiffness per axis, N/um, as {x, y, z} or [x, y, z] -> diagonal compliance mm/N.
static Eigen::Matrix3d parse_axis_stiffness(const Map& structure) {
  const YAML::Node n = structure.get("stiffness_N_per_um");
  Eigen::Vector3d k;
  if (n.IsMap()) {
    const Map m = structure.map("stiffness_N_per_um", {"x", "y", "z"});
    k << m.number("x", Range::positive()), m.number("y", Range::positive()), m.number("z", Range::positive());
  } else if (n.IsSequence() && n.size() == 3) {
    for (std::size_t i = 0; i < 3; ++i)
      k(static_cast<int>(i)) = yaml::number(n[i], "stiffness_N_per_um", structure.file(), Range::positive());
  } else {
    structure.fail(n, "stiffness_N_per_um must be {x: .., y: .., z: ..} or [x, y, z]");
  }
  return (1.0 / (1e3 * k.array())).matrix().asDiagonal();
}

static Eigen::Matrix3d parse_structure(const Map& n) {
  if (n.has("compliance_mm_per_N") && n.has("stiffness_N_per_um"))
    n.fail(n.node(), "give compliance_mm_per_N or stiffness_N_per_um, not both");
  if (n.has("compliance_mm_per_N")) return parse_matrix(n.get("compliance_mm_per_N"), n.file());
  if (n.has("stiffness_N_per_um")) return parse_axis_stiffness(n);
  n.fail(n.node(), "structure needs compliance_mm_per_N or stiffness_N_per_um");
}

static Dynamics parse_dynamics(const Map& n) {
  Dynamics d;
  if (!n.has("damping_ratio")) return d;
  // Underdamped modes only: zeta >= 1 has no resonance, zeta = 0 an infinite one.
  d.damping_ratio = n.number("damping_ratio");
  if (!(d.damping_ratio > 0 && d.damping_ratio < 1)) n.fail("damping_ratio", "damping_ratio must be in (0, 1)");
  d.damping_given = true;
  return d;
}

MachineStiffness parse_machine_stiffness(const yaml::Document& doc, const std::string& file) {
  const YAML::Node root = yaml::node(doc);
  MachineStiffness m;
  if (!root || root.IsNull()) return m;
  if (!root.IsMap()) yaml::fail(file, root.Mark(), "a machine profile must be a map");
  // The profile's other keys are deflex::profile's (load_machine checks them).
  if (root["holder"])
    m.holder = parse_holder(Map(root["holder"], "holder", file,
                                {"length_mm", "nose_diameter_mm", "base_diameter_mm", "material", "name"}));
  if (root["dynamics"]) m.dynamics = parse_dynamics(Map(root["dynamics"], "dynamics", file, {"damping_ratio"}));
  if (!root["stiffness"]) return m;
  const Map s(root["stiffness"], "stiffness", file, {"tool_clamp", "spindle", "structure"});
  const std::initializer_list<const char*> springs = {"radial_N_per_um", "rotational_Nm_per_rad", "axial_N_per_um"};
  if (s.has("tool_clamp")) m.tool_clamp = parse_springs(s.map("tool_clamp", springs));
  if (s.has("spindle")) m.spindle = parse_springs(s.map("spindle", springs));
  if (s.has("structure")) m.structure_mm_per_N = parse_structure(s.map("structure", {"compliance_mm_per_N", "stiffness_N_per_um"}));
  return m;
}

MachineStiffness load_machine_stiffness(const std::string& path) {
  return parse_machine_stiffness(yaml::document(yaml::load_file(path)), path);
}

}  // namespace deflex::stiffness
