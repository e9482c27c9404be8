// A tolerant reader of the cutting geometry in a tool library
// (`tools: {ID: {type, diameter_mm, corner_radius_mm, flutes, helix_deg,
// flute_length_mm, ...}}`, samples/tools.yaml). Keys the force model does not
// need (stickout, holder, material of the tool...) are ignored.
#pragma once
#include <string>

#include "deflex/force/cutter.hpp"

namespace deflex::force {

// Throws Error(Exit::io) when unreadable, Error(Exit::config,
// "file:line:col: error: ...") on a YAML or value error in that tool's entry,
// Error(Exit::usage) naming the known tools when `id` is absent.
Cutter read_cutter(const std::string& path, const std::string& id);
Cutter parse_cutter(const std::string& yaml_text, const std::string& file, const std::string& id);

}  // namespace deflex::force
