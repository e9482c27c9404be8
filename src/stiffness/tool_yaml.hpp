// Readers of the tool library's entries from their YAML nodes, shared by the
// .cpp files of deflex::stiffness (a holder has a material too).
#pragma once
#include <string>

#include "deflex/profile/yaml.hpp"
#include "deflex/stiffness/tool.hpp"

namespace deflex::stiffness {

// `material:` as a preset name or {E_MPa, poisson[, density_kg_per_m3]} (tools
// and holders).
Material parse_material(const YAML::Node& node, const std::string& file);
// One tool entry (a YAML map).
Tool parse_tool(const YAML::Node& node, const std::string& id, const std::string& file);

}  // namespace deflex::stiffness
