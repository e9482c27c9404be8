#include "deflex/stiffness/tool.hpp"
#include "deflex/stiffness/tool_import.hpp"

#include <cmath>
#include <filesystem>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/profile/yaml.hpp"
#include "tool_yaml.hpp"

namespace deflex::stiffness {

std::optional<Material> material_preset(const std::string& name) {
  if (name == "carbide") return Material{"carbide", 600000.0, 0.22, 1000.0, 14500.0};
  if (name == "hss") return Material{"hss", 220000.0, 0.28, 1500.0, 8150.0};
  if (name == "steel") return Material{"steel", 210000.0, 0.30, 800.0, 7850.0};
  return std::nullopt;
}

using yaml::Map;
using yaml::Range;

Material parse_material(const YAML::Node& node, const std::string& file) {
  if (node.IsScalar()) {
    if (auto m = material_preset(node.Scalar())) return *m;
    yaml::fail(file, node.Mark(),
               "unknown material '" + node.Scalar() + "' (presets: carbide, hss, steel; or {E_MPa, poisson, density_kg_per_m3})");
  }
  if (!node.IsMap()) yaml::fail(file, node.Mark(), "material must be a preset name or {E_MPa, poisson[, density_kg_per_m3]}");
  const Map n(node, "material", file, {"E_MPa", "poisson", "density_kg_per_m3"});
  Material m;
  m.name = "custom";
  m.E_MPa = n.number("E_MPa", Range::positive());
  const double nu = n.number("poisson");
  // Isotropic elasticity needs -1 < nu < 0.5 for a positive-definite material.
  if (!(nu > -1.0 && nu < 0.5)) n.fail("poisson", "poisson must be in (-1, 0.5)");
  m.poisson = nu;
  // From 500 kg/m^3 (below any metal or ceramic a tool or holder is made of)
  // to 25,000 (past osmium, 22,590, the densest element): outside it the
  // number is a unit slip, such as g/cm^3 (7.85 for steel) written as kg/m^3.
  if (n.has("density_kg_per_m3")) m.density_kg_per_m3 = n.number("density_kg_per_m3", Range::between(500, 25000));
  return m;
}

static stock::EndShape parse_type(const Map& tool) {
  const std::string s = tool.text("type");
  if (const auto shape = stock::parse_end_shape(s)) return *shape;
  tool.fail("type", "type must be ball, flat or bull, not '" + s + "'");
}

// Lengths and diameters of a cutting tool: positive and at most a metre. A
// larger number is a typo or hostile input, and the beam model would mesh it
// into more elements than an int counts (libFuzzer found a 5e103 mm stick-out:
// tests/stiffness/data/fuzz_stickout_overflow.yaml).
static Range size_mm() { return {0, 1000, true}; }

// Corner radius by type: a ball's is D/2, a flat's 0, a bull's from the file.
static double parse_corner(const Map& tool, stock::EndShape type, double d_mm) {
  if (type == stock::EndShape::bull) {
    const double rc = tool.number("corner_radius_mm", size_mm());
    if (rc > 0.5 * d_mm) tool.fail("corner_radius_mm", "corner_radius_mm must be <= diameter_mm / 2");
    return rc;
  }
  const double expected = stock::corner_radius_mm(type, 0.5 * d_mm, 0.0);
  if (tool.has("corner_radius_mm") && std::abs(tool.number("corner_radius_mm") - expected) > 1e-9)
    tool.fail("corner_radius_mm", std::string("corner_radius_mm of a ") + to_string(type) + " tool must be " +
                                      (type == stock::EndShape::ball ? "diameter_mm / 2" : "0") + " (or left out)");
  return expected;
}

// The lengths along the tool, each checked against the corner it must clear.
static void parse_lengths(const Map& n, Tool& t) {
  t.flute_length_mm = n.number("flute_length_mm", size_mm());
  if (t.flute_length_mm < t.corner_radius_mm)
    n.fail("flute_length_mm", "flute_length_mm must reach past the corner radius");
  t.stickout_mm = n.number("stickout_mm", size_mm());
  if (t.stickout_mm <= t.corner_radius_mm) n.fail("stickout_mm", "stickout_mm must exceed the corner radius");
  if (n.has("neck")) {
    const Map neck = n.map("neck", {"diameter_mm", "length_mm"});
    t.neck = Neck{neck.number("diameter_mm", size_mm()), neck.number("length_mm", size_mm())};
  }
}

Tool parse_tool(const YAML::Node& node, const std::string& id, const std::string& file) {
  const Map n(node, "tool '" + id + "'", file,
              {"type", "diameter_mm", "corner_radius_mm", "flutes", "helix_deg", "flute_length_mm",
               "stickout_mm", "shank_diameter_mm", "flute_diameter_ratio", "material", "step_file", "frf_file", "neck",
               "description", "max_force_N", "centre_cutting"});
  Tool t;
  t.id = id;
  t.source = yaml::where(file, node.Mark());
  t.type = parse_type(n);
  t.diameter_mm = n.number("diameter_mm", size_mm());
  t.corner_radius_mm = parse_corner(n, t.type, t.diameter_mm);
  t.flutes = static_cast<int>(n.integer("flutes", t.flutes, 1, 100));
  t.helix_deg = n.number("helix_deg", t.helix_deg, Range::non_negative());
  if (t.helix_deg >= 90) n.fail("helix_deg", "helix_deg must be in [0, 90)");
  parse_lengths(n, t);
  t.shank_diameter_mm = n.number("shank_diameter_mm", t.diameter_mm, size_mm());
  t.flute_diameter_ratio = n.number("flute_diameter_ratio", t.flute_diameter_ratio, {0, 1, true});
  t.material = parse_material(n.get("material"), file);
  if (n.has("max_force_N")) t.max_force_N = n.number("max_force_N", Range::positive());
  t.centre_cutting = n.boolean("centre_cutting", true);
  if (n.has("step_file")) {
    std::filesystem::path p = n.text("step_file");
    if (p.is_relative()) p = std::filesystem::path(file).parent_path() / p;
    t.step_file = p.lexically_normal().string();
  }
  if (n.has("frf_file")) {
    std::filesystem::path p = n.text("frf_file");
    if (p.is_relative()) p = std::filesystem::path(file).parent_path() / p;
    t.frf_file = p.lexically_normal().string();
  }
  if (n.has("description")) n.text("description");
  return t;
}

ToolLibrary parse_tool_library(const std::string& yaml_text, const std::string& file) {
  const YAML::Node root = yaml::load_text(yaml_text, file);
  if (!root.IsMap() || !root["tools"])
    yaml::fail(file, root.Mark(), "a tool library is a map with a 'tools:' key");
  const Map lib_map(root, "tool library", file, {"tools"});
  const YAML::Node tools = lib_map.get("tools");
  if (!tools.IsMap()) yaml::fail(file, tools.Mark(), "tools must be a map");
  ToolLibrary lib;
  lib.file = file;
  for (const auto& kv : tools) {
    const auto id = yaml::text(kv.first, "a tool id", file);
    lib.tools.emplace(id, parse_tool(kv.second, id, file));
  }
  return lib;
}

ToolLibrary load_tool_library(const std::string& path) {
  if (!is_foreign_tool_library(path)) return parse_tool_library(yaml::read_file(path), path);
  // A Fusion 360 or LinuxCNC library goes through its YAML, so one reader
  // checks every library; what that reader refuses is named as such.
  const ImportedLibrary imp = import_tool_library(path);
  try {
    return parse_tool_library(imp.yaml, path);
  } catch (const Error& e) {
    throw Error(e.kind(), std::string(e.what()) + " (in the YAML deflex made of this " + imp.format +
                              "; `deflex tools import " + path + "` shows it)");
  }
}

const Tool& find_tool(const ToolLibrary& lib, const std::string& id) {
  const auto it = lib.tools.find(id);
  if (it != lib.tools.end()) return it->second;
  std::string known;
  for (const auto& kv : lib.tools) known += (known.empty() ? "" : ", ") + kv.first;
  throw Error(ErrorKind::settings, lib.file + ": error: no tool '" + id + "' (tools: " + known + ")");
}

}  // namespace deflex::stiffness
