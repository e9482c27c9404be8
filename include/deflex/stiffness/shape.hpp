// The tool body as a solid of revolution of its equivalent radius profile, shared
// by the beam and the solid model so the two describe the same body.
// Frame: tool axis +z, tip at z = 0, holder face at z = length_mm.
#pragma once
#include <vector>

#include "deflex/stiffness/tool.hpp"

namespace deflex::stiffness {

struct Cylinder {
  double z0_mm = 0;
  double z1_mm = 0;
  double radius_mm = 0;
};

// End cap from z = 0 to cap_height_mm (ball or bull corner), then cylinders.
// Cap radius: r(z) = cap_offset_mm + cap_semi_axis_mm * sqrt(1 - ((c - z)/c)^2),
// c = cap_height_mm: a quarter ellipse (a circle when unfluted) around the
// corner centre. A flat end has no cap.
struct ToolShape {
  double cap_height_mm = 0;
  double cap_offset_mm = 0;     // radius of the flat centre of the end face
  double cap_semi_axis_mm = 0;  // radial semi-axis of the corner
  std::vector<Cylinder> cylinders;  // contiguous, from cap_height_mm to length_mm
  double length_mm = 0;
};

// The fluted part (cap included) is a solid of flute_diameter_ratio * D (docs/physics.md,
// 'Flutes': flutes behave like a cylinder of about 0.75-0.85 D); above it the neck,
// then the shank, cut at the holder face.
ToolShape tool_shape(const Tool& t);

// Radius of the shape at height z (0 <= z <= length_mm).
double radius_at(const ToolShape& s, double z_mm);

}  // namespace deflex::stiffness
