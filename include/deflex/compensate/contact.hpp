// Where a CL point's cutter touches the surface it generates: what the
// report draws and where a measured point is matched with its prediction.
#pragma once
#include "deflex/compensate/compensate.hpp"
#include "deflex/stiffness/tool.hpp"

namespace deflex::compensate {

// The contact of the cutter with the surface whose outward normal (from the
// material towards the tool) is p.normal: the corner circle's point facing
// the material, moved back by the corner radius along the normal (ball:
// centre - R n; flat on a floor: the tip; flat on a wall: R from the axis
// towards the wall).
V3 contact_point(const Point& p, const stiffness::Tool& t);

// A flank cut's wall point at height z_mm above the tip (force::FlankPoint):
// R from the axis towards the wall, along the horizontal part of p.normal.
V3 flank_point(const Point& p, const stiffness::Tool& t, double z_mm);

}  // namespace deflex::compensate
