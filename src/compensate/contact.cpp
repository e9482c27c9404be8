// compensate::contact_point() and flank_point() (contact.hpp).
#include "deflex/compensate/contact.hpp"

#include "deflex/stock/end_shape.hpp"

namespace deflex::compensate {

namespace {

// The horizontal unit direction of n (zero for a floor's normal).
V3 horizontal(const V3& n) {
  const V3 h(n.x(), n.y(), 0.0);
  return h.norm() > 1e-9 ? V3(h.normalized()) : V3(V3::Zero());
}

}  // namespace

V3 contact_point(const Point& p, const stiffness::Tool& t) {
  const double R = t.diameter_mm / 2;
  const double r = stock::corner_radius_mm(t.type, R, t.corner_radius_mm);
  // The corner circle's centre nearest the surface lies R - r from the axis
  // on the material's side, i.e. against the normal's horizontal part.
  return p.tip_mm + V3(0, 0, r) - (R - r) * horizontal(p.normal) - r * p.normal;
}

V3 flank_point(const Point& p, const stiffness::Tool& t, double z_mm) {
  return p.tip_mm + V3(0, 0, z_mm) - (t.diameter_mm / 2) * horizontal(p.normal);
}

}  // namespace deflex::compensate
