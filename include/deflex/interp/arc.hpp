// Geometry of the circular and helical arcs the interpreter emits (G2/G3 in
// G17/G18/G19): the one implementation the material removal (stock), the
// engagement path (engage), compensation, machining time (process) and the
// travel check (interp) all use. It lives here, beside interp::Motion, because
// every one of those modules already depends on interp and interp depends on
// none of them.
//
// Frame: work frame, mm, points are tool-tip positions; angles in radians.
#pragma once
#include <vector>

#include "deflex/interp/motion.hpp"

namespace deflex::interp {

// The axes of an arc plane: angles are measured from axis a toward axis b, n is
// the normal (the helix axis). G17: X, Y, Z; G18: Z, X, Y; G19: Y, Z, X (the
// right-handed order of the RS274/NGC interpreter, NISTIR 6556, G2/G3).
struct PlaneAxes {
  int a, b, n;
};
constexpr PlaneAxes plane_axes(int plane) {
  if (plane == 18) return {2, 0, 1};
  if (plane == 19) return {1, 2, 0};
  return {0, 1, 2};
}

inline bool is_arc(const Motion& m) { return m.kind == MotionKind::arc_cw || m.kind == MotionKind::arc_ccw; }

// A circular or helical arc as the interpreter gives it: plane 17, 18 or 19; cw
// seen from the positive normal axis; the centre's normal coordinate equals the
// start's; end == start (in the plane) is a full circle.
struct Arc {
  Vec3 start_mm{}, end_mm{}, center_mm{};
  int plane = 17;
  bool cw = true;
};
Arc arc_of(const Motion& m);  // requires an arc motion

double arc_radius_mm(const Arc& a);
double arc_start_angle(const Arc& a);         // of the start about the centre, from axis a toward b, rad
double arc_angle(const Arc& a);               // swept angle, rad, in (0, 2 pi]
double arc_length_mm(const Arc& a);           // including the helical rise
Vec3 arc_point(const Arc& a, double u);       // u in [0, 1]; exact at both ends
Vec3 arc_tangent(const Arc& a, double u);     // unit, direction of travel
// Chords so that the sagitta r (1 - cos(dtheta / 2)) <= chord_tol_mm.
int arc_chord_count(const Arc& a, double chord_tol_mm);
std::vector<Vec3> arc_polyline(const Arc& a, int chords);

}  // namespace deflex::interp
