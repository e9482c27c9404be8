// The samples' tool library, machine (mill3) and a material of theirs, as a
// compensate::Physics for tests that simulate on a stock of their own.
#pragma once
#include <string>

#include "deflex/compensate/compensate.hpp"
#include "deflex/force/material.hpp"

namespace deflex::test {

inline compensate::Physics sample_physics(const std::string& material) {
  compensate::Physics ph;
  ph.tools = stiffness::load_tool_library("samples/tools.yaml");
  ph.machine = stiffness::load_machine_stiffness("samples/machines/mill3.yaml");
  ph.k = force::find_material(force::load_material_library("samples/materials.yaml"), material).k;
  return ph;
}

}  // namespace deflex::test
