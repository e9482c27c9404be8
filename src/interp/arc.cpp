#include "deflex/interp/arc.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::interp {

Arc arc_of(const Motion& m) {
  Arc a;
  a.start_mm = m.start_mm;
  a.end_mm = m.end_mm;
  a.center_mm = m.center_mm;
  a.plane = m.plane;
  a.cw = m.kind == MotionKind::arc_cw;
  return a;
}

double arc_radius_mm(const Arc& a) {
  const PlaneAxes p = plane_axes(a.plane);
  return std::hypot(a.start_mm[p.a] - a.center_mm[p.a], a.start_mm[p.b] - a.center_mm[p.b]);
}

double arc_start_angle(const Arc& a) {
  const PlaneAxes p = plane_axes(a.plane);
  return std::atan2(a.start_mm[p.b] - a.center_mm[p.b], a.start_mm[p.a] - a.center_mm[p.a]);
}

double arc_angle(const Arc& a) {
  const PlaneAxes p = plane_axes(a.plane);
  const double t0 = arc_start_angle(a);
  const double t1 = std::atan2(a.end_mm[p.b] - a.center_mm[p.b], a.end_mm[p.a] - a.center_mm[p.a]);
  constexpr double two_pi = 2 * std::numbers::pi;
  double d = a.cw ? t0 - t1 : t1 - t0;
  d -= two_pi * std::floor(d / two_pi);
  // Same start and end angle: a full circle (the interpreter only emits those on purpose).
  if (d < 1e-9) d = two_pi;
  return d;
}

double arc_length_mm(const Arc& a) {
  const PlaneAxes p = plane_axes(a.plane);
  return std::hypot(arc_radius_mm(a) * arc_angle(a), a.end_mm[p.n] - a.start_mm[p.n]);
}

Vec3 arc_point(const Arc& a, double u) {
  if (u <= 0) return a.start_mm;
  if (u >= 1) return a.end_mm;
  const PlaneAxes p = plane_axes(a.plane);
  const double t = arc_start_angle(a) + (a.cw ? -1 : 1) * arc_angle(a) * u;
  const double r = arc_radius_mm(a);
  Vec3 q{};
  q[p.a] = a.center_mm[p.a] + r * std::cos(t);
  q[p.b] = a.center_mm[p.b] + r * std::sin(t);
  q[p.n] = a.start_mm[p.n] + (a.end_mm[p.n] - a.start_mm[p.n]) * u;
  return q;
}

Vec3 arc_tangent(const Arc& a, double u) {
  const PlaneAxes p = plane_axes(a.plane);
  const double ang = arc_angle(a);
  const double sgn = a.cw ? -1 : 1;
  const double t = arc_start_angle(a) + sgn * ang * u;
  const double r = arc_radius_mm(a);
  Vec3 v{};
  // d/du of the point: r * ang * sgn * (-sin t, cos t), rise along the normal.
  v[p.a] = -r * ang * sgn * std::sin(t);
  v[p.b] = r * ang * sgn * std::cos(t);
  v[p.n] = a.end_mm[p.n] - a.start_mm[p.n];
  const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (l > 0)
    for (double& c : v) c /= l;
  return v;
}

int arc_chord_count(const Arc& a, double chord_tol_mm) {
  if (!(chord_tol_mm > 0)) throw Error(ErrorKind::internal, "arc_chord_count: tolerance must be > 0");
  const double r = arc_radius_mm(a);
  if (r <= chord_tol_mm) return std::max(1, static_cast<int>(std::ceil(arc_angle(a) / (std::numbers::pi / 2))));
  const double dmax = 2 * std::acos(1 - chord_tol_mm / r);
  return std::max(1, static_cast<int>(std::ceil(arc_angle(a) / dmax - 1e-9)));
}

std::vector<Vec3> arc_polyline(const Arc& a, int chords) {
  chords = std::max(1, chords);
  std::vector<Vec3> pts(static_cast<std::size_t>(chords) + 1);
  for (int k = 0; k <= chords; ++k) pts[static_cast<std::size_t>(k)] = arc_point(a, static_cast<double>(k) / chords);
  return pts;
}

}  // namespace deflex::interp
