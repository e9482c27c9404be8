#include "deflex/stiffness/tool.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "deflex/diag/diagnostics.hpp"
#include "yaml_read.hpp"

namespace deflex::stiffness {

namespace yr = yaml_read;

std::optional<Material> material_preset(const std::string& name) {
  if (name == "carbide") return Material{"carbide", 600000.0, 0.22};
  if (name == "hss") return Material{"hss", 220000.0, 0.28};
  if (name == "steel") return Material{"steel", 210000.0, 0.30};
  return std::nullopt;
}

std::string to_string(ToolType t) {
  switch (t) {
    case ToolType::ball: return "ball";
    case ToolType::flat: return "flat";
    case ToolType::bull: return "bull";
  }
  return "?";
}

static ToolType parse_type(const YAML::Node& tool, const std::string& file) {
  const std::string s = yr::text(tool, "type", file);
  if (s == "ball") return ToolType::ball;
  if (s == "flat") return ToolType::flat;
  if (s == "bull") return ToolType::bull;
  yr::fail(file, tool["type"].Mark(), "type must be ball, flat or bull, not '" + s + "'");
}

static double optional_positive(const YAML::Node& tool, const char* key, double fallback,
                                const std::string& file) {
  return tool[key] ? yr::positive(tool, key, file) : fallback;
}

static Neck parse_neck(const YAML::Node& n, const std::string& file) {
  yr::require_map(n, "neck", file);
  yr::check_keys(n, {"diameter_mm", "length_mm"}, file);
  return Neck{yr::positive(n, "diameter_mm", file), yr::positive(n, "length_mm", file)};
}

// Corner radius by type: a ball's is D/2, a flat's 0, a bull's from the file.
static double parse_corner(const YAML::Node& tool, ToolType type, double d_mm,
                           const std::string& file) {
  const YAML::Node n = tool["corner_radius_mm"];
  if (type == ToolType::bull) {
    const double rc = yr::positive(tool, "corner_radius_mm", file);
    if (rc > 0.5 * d_mm) yr::fail(file, n.Mark(), "corner_radius_mm must be <= diameter_mm / 2");
    return rc;
  }
  const double expected = type == ToolType::ball ? 0.5 * d_mm : 0.0;
  if (n && std::abs(yr::number_node(n, "corner_radius_mm", file) - expected) > 1e-9)
    yr::fail(file, n.Mark(),
             "corner_radius_mm of a " + to_string(type) + " tool must be " +
                 (type == ToolType::ball ? "diameter_mm / 2" : "0") + " (or left out)");
  return expected;
}

Tool parse_tool(const YAML::Node& node, const std::string& id, const std::string& file) {
  yr::require_map(node, "tool '" + id + "'", file);
  yr::check_keys(node,
                 {"type", "diameter_mm", "corner_radius_mm", "flutes", "helix_deg",
                  "flute_length_mm", "stickout_mm", "shank_diameter_mm", "flute_diameter_ratio",
                  "material", "step_file", "neck", "description"},
                 file);
  Tool t;
  t.id = id;
  t.source = yr::where(file, node.Mark());
  t.type = parse_type(node, file);
  t.diameter_mm = yr::positive(node, "diameter_mm", file);
  t.corner_radius_mm = parse_corner(node, t.type, t.diameter_mm, file);
  if (node["flutes"]) {
    t.flutes = yr::integer(node, "flutes", file);
    if (t.flutes < 1) yr::fail(file, node["flutes"].Mark(), "flutes must be >= 1");
  }
  if (node["helix_deg"]) {
    t.helix_deg = yr::number(node, "helix_deg", file);
    if (t.helix_deg < 0 || t.helix_deg >= 90)
      yr::fail(file, node["helix_deg"].Mark(), "helix_deg must be in [0, 90)");
  }
  t.flute_length_mm = yr::positive(node, "flute_length_mm", file);
  if (t.flute_length_mm < t.corner_radius_mm)
    yr::fail(file, node["flute_length_mm"].Mark(),
             "flute_length_mm must reach past the corner radius");
  t.stickout_mm = yr::positive(node, "stickout_mm", file);
  if (t.stickout_mm <= t.corner_radius_mm)
    yr::fail(file, node["stickout_mm"].Mark(), "stickout_mm must exceed the corner radius");
  t.shank_diameter_mm = optional_positive(node, "shank_diameter_mm", t.diameter_mm, file);
  if (node["flute_diameter_ratio"]) {
    t.flute_diameter_ratio = yr::positive(node, "flute_diameter_ratio", file);
    if (t.flute_diameter_ratio > 1.0)
      yr::fail(file, node["flute_diameter_ratio"].Mark(), "flute_diameter_ratio must be <= 1");
  }
  if (!node["material"]) yr::fail(file, node.Mark(), "missing key 'material'");
  t.material = yr::material(node["material"], file);
  if (node["neck"]) t.neck = parse_neck(node["neck"], file);
  if (node["step_file"]) {
    std::filesystem::path p = yr::text(node, "step_file", file);
    if (p.is_relative()) p = std::filesystem::path(file).parent_path() / p;
    t.step_file = p.lexically_normal().string();
  }
  return t;
}

ToolLibrary parse_tool_library(const std::string& yaml_text, const std::string& file) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    yr::fail(file, e.mark, e.msg);
  }
  if (!root.IsMap() || !root["tools"])
    yr::fail(file, root.Mark(), "a tool library is a map with a 'tools:' key");
  yr::check_keys(root, {"tools"}, file);
  const YAML::Node tools = root["tools"];
  yr::require_map(tools, "tools", file);
  ToolLibrary lib;
  lib.file = file;
  for (const auto& kv : tools) {
    const auto id = kv.first.as<std::string>();
    lib.tools.emplace(id, parse_tool(kv.second, id, file));
  }
  return lib;
}

ToolLibrary load_tool_library(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(Exit::io, path + ": error: cannot read the tool library");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_tool_library(ss.str(), path);
}

const Tool& find_tool(const ToolLibrary& lib, const std::string& id) {
  const auto it = lib.tools.find(id);
  if (it != lib.tools.end()) return it->second;
  std::string known;
  for (const auto& kv : lib.tools) known += (known.empty() ? "" : ", ") + kv.first;
  throw Error(Exit::usage, lib.file + ": error: no tool '" + id + "' (tools: " + known + ")");
}

}  // namespace deflex::stiffness
