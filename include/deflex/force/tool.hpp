// The cutting part of a tool-library entry (stiffness::Tool, read by
// stiffness::load_tool_library) as the force model sees it.
#pragma once
#include "deflex/force/cutter.hpp"
#include "deflex/stiffness/tool.hpp"

namespace deflex::force {

// Type, D, corner radius (bull nose only), flutes, helix and flute length;
// validated (throws Error(ErrorKind::config) when the geometry cannot cut).
Cutter cutter_of(const stiffness::Tool& t);

}  // namespace deflex::force
