// The lower surface of a vertical end mill, as the Z-map sees it: the tool is
// the solid above that surface (the shank is a cylinder of the same radius).
//
// Frame: d = horizontal distance from the tool axis, height measured up from the
// tool tip (the programmed point), mm.
#pragma once
#include <cmath>
#include <limits>

#include "deflex/stock/end_shape.hpp"

namespace deflex::stock {

struct ToolProfile {
  EndShape kind = EndShape::flat;
  double radius_mm = 5.0;         // R0 = D/2
  double corner_radius_mm = 0.0;  // bull nose r_c in (0, R0]; ball: R0; flat: 0
};

// Corner radius actually used by the geometry (R0 for a ball, 0 for a flat end).
inline double corner_of(const ToolProfile& t) { return corner_radius_mm(t.kind, t.radius_mm, t.corner_radius_mm); }

// Height of the lower surface above the tip at distance d from the axis;
// +inf beyond the radius. Flat end: 0; corner arc of radius r_c centred at
// (R0 - r_c, r_c): r_c - sqrt(r_c^2 - (d - (R0 - r_c))^2).
inline double profile_height(const ToolProfile& t, double d_mm) {
  if (d_mm > t.radius_mm) return std::numeric_limits<double>::infinity();
  const double rc = corner_of(t);
  const double e = d_mm - (t.radius_mm - rc);
  if (e <= 0) return 0.0;
  return rc - std::sqrt(std::max(0.0, rc * rc - e * e));
}

// Radius of the profile at height z above the tip (inverse of profile_height; R0 above r_c).
inline double profile_radius(const ToolProfile& t, double z_mm) {
  const double rc = corner_of(t);
  if (z_mm >= rc) return t.radius_mm;
  if (z_mm <= 0) return t.radius_mm - rc;
  const double c = rc - z_mm;
  return t.radius_mm - rc + std::sqrt(std::max(0.0, rc * rc - c * c));
}

}  // namespace deflex::stock
