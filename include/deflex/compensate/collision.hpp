// The parts of the tool assembly that do not cut - the neck, the shank and the
// holder - against the stock: where one of them would run into material the
// flutes have not removed (a deep cavity under a short stick-out).
//
// The assembly is axisymmetric about the spindle axis, in heights above the
// tool tip: the neck from the top of the flutes, then the shank up to the
// stick-out (the holder face), then the holder's taper from its nose diameter
// to its base diameter over its length (the machine profile's `holder:`).
// Whatever lies higher (the spindle nose) is not modelled.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "deflex/compensate/compensate.hpp"
#include "deflex/stiffness/machine.hpp"
#include "deflex/stiffness/tool.hpp"
#include "deflex/stock/zmap.hpp"

namespace deflex::compensate {

const char* to_string(AssemblyPart p);  // AssemblyPart: compensate.hpp

// A frustum of the assembly: radius r0 at height z0 above the tip, r1 at z1.
struct Frustum {
  AssemblyPart part;
  double z0_mm, z1_mm, r0_mm, r1_mm;
};

struct Assembly {
  std::vector<Frustum> frusta;  // bottom up
};
// The tool's non-cutting parts and the holder (none: the tool's alone).
Assembly assembly_of(const stiffness::Tool& t, const std::optional<stiffness::Holder>& holder);

// The deepest interference of the assembly with the stock when the tip is at
// tip_mm: how far material stands above the lowest point of a part at its
// distance from the axis (mm, > 0), and which part. depth 0: clear.
struct Interference {
  double depth_mm = 0;
  AssemblyPart part = AssemblyPart::shank;
};
Interference interference(const stock::ZMap& z, const V3& tip_mm, const Assembly& a);

}  // namespace deflex::compensate
