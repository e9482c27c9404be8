#include "deflex/stiffness/shape.hpp"

#include <algorithm>
#include <cmath>

namespace deflex::stiffness {

ToolShape tool_shape(const Tool& t) {
  ToolShape s;
  const double L = t.stickout_mm;
  const double k = t.flute_diameter_ratio;
  const double R = 0.5 * t.diameter_mm;
  const double rc = t.corner_radius_mm;
  s.length_mm = L;
  s.cap_height_mm = rc;
  s.cap_offset_mm = k * (R - rc);
  s.cap_semi_axis_mm = k * rc;
  // Sections above the cap, each cut at the holder face.
  auto push = [&](double z0, double z1, double r) {
    z0 = std::max(z0, rc);
    z1 = std::min(z1, L);
    if (z1 > z0) s.cylinders.push_back({z0, z1, r});
  };
  const double flute_top = t.flute_length_mm;
  push(0, flute_top, k * R);
  double z = flute_top;
  if (t.neck) {
    push(z, z + t.neck->length_mm, 0.5 * t.neck->diameter_mm);
    z += t.neck->length_mm;
  }
  push(z, L, 0.5 * t.shank_diameter_mm);
  return s;
}

double radius_at(const ToolShape& s, double z) {
  const double c = s.cap_height_mm;
  if (z < c) {
    const double u = (c - z) / c;
    return s.cap_offset_mm + s.cap_semi_axis_mm * std::sqrt(std::max(0.0, 1 - u * u));
  }
  for (const auto& cyl : s.cylinders)
    if (z <= cyl.z1_mm) return cyl.radius_mm;
  return s.cylinders.empty() ? 0.0 : s.cylinders.back().radius_mm;
}

}  // namespace deflex::stiffness
