#include "deflex/process/machining_time.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/stock/sweep.hpp"

namespace deflex::process {

namespace {

using interp::Motion;
using interp::MotionKind;
using interp::Vec3;

constexpr double kInf = std::numeric_limits<double>::infinity();
// Shorter motions take no time and leave the junction to their neighbours (a
// control drops a zero-length block); 1 nm is far below any least increment.
constexpr double kMinLength_mm = 1e-6;
// A direction component below this is no motion of that axis (rounding of a
// unit vector built from coordinates of 1e-4 mm resolution).
constexpr double kNoAxis = 1e-12;

bool is_rapid(const Motion& m) { return m.kind == MotionKind::rapid; }
bool is_arc(const Motion& m) { return m.kind == MotionKind::arc_cw || m.kind == MotionKind::arc_ccw; }

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// What the look-ahead needs of one motion.
struct Shape {
  double length_mm = 0;
  double vmax_mm_per_s = 0;    // cruise: programmed feed, axis limits, centripetal limit
  double accel_mm_per_s2 = 0;  // along the path
  Vec3 u_start{}, u_end{};     // unit tangents at both ends
};

std::array<double, 3> per_s(const std::array<double, 3>& per_min) {
  return {per_min[0] / 60, per_min[1] / 60, per_min[2] / 60};
}

Shape line_shape(const Motion& m, double feed_mm_per_s, const profile::AxisLimits& k) {
  Shape s;
  Vec3 d{m.end_mm[0] - m.start_mm[0], m.end_mm[1] - m.start_mm[1], m.end_mm[2] - m.start_mm[2]};
  s.length_mm = std::sqrt(dot(d, d));
  if (s.length_mm < kMinLength_mm) return s;
  for (double& c : d) c /= s.length_mm;
  s.u_start = s.u_end = d;
  s.accel_mm_per_s2 = along(k.acceleration_mm_per_s2, d);
  s.vmax_mm_per_s = is_rapid(m) ? along(per_s(k.rapid_mm_per_min), d)
                                : std::min(feed_mm_per_s, along(per_s(k.max_feed_mm_per_min), d));
  return s;
}

// Arcs and helices. The tangent turns through the plane, so the plane axes'
// limits are taken at their smallest (the direction where the slowest axis
// does all the work) rather than projected; the helical rise is projected.
// kp, kn: in-plane and normal shares of the path speed.
Shape arc_shape(const Motion& m, double feed_mm_per_s, const profile::AxisLimits& k) {
  const int pa = m.plane == 18 ? 2 : m.plane == 19 ? 1 : 0;
  const int pb = m.plane == 18 ? 0 : m.plane == 19 ? 2 : 1;
  const int pn = 3 - pa - pb;
  stock::Arc a;
  a.start_mm = m.start_mm;
  a.end_mm = m.end_mm;
  a.centre_mm = m.center_mm;
  a.plane = m.plane;
  a.cw = m.kind == MotionKind::arc_cw;
  Shape s;
  const double r_mm = stock::arc_radius_mm(a);
  const double planar_mm = r_mm * stock::arc_angle(a);
  const double rise_mm = m.end_mm[pn] - m.start_mm[pn];
  s.length_mm = std::hypot(planar_mm, rise_mm);
  if (s.length_mm < kMinLength_mm || r_mm < kMinLength_mm) return line_shape(m, feed_mm_per_s, k);
  const double kp = planar_mm / s.length_mm, kn = std::fabs(rise_mm) / s.length_mm;
  const double a_plane = std::min(k.acceleration_mm_per_s2[pa], k.acceleration_mm_per_s2[pb]);
  const double vf_plane = std::min(k.max_feed_mm_per_min[pa], k.max_feed_mm_per_min[pb]) / 60;
  // Centripetal: the in-plane speed kp v on radius r needs (kp v)^2 / r <= a_plane.
  const double v_centripetal = std::sqrt(a_plane * r_mm) / kp;
  s.vmax_mm_per_s = std::min({feed_mm_per_s, vf_plane / kp, v_centripetal});
  s.accel_mm_per_s2 = a_plane / kp;
  if (kn > kNoAxis) {
    s.vmax_mm_per_s = std::min(s.vmax_mm_per_s, k.max_feed_mm_per_min[pn] / 60 / kn);
    s.accel_mm_per_s2 = std::min(s.accel_mm_per_s2, k.acceleration_mm_per_s2[pn] / kn);
  }
  s.u_start = stock::arc_tangent(a, 0);
  s.u_end = stock::arc_tangent(a, 1);
  return s;
}

// The centripetal acceleration of a corner blend lies in the plane of the two
// legs, so only the axes they move take it; of those the slowest bounds it
// (conservative where the blend's direction would let two axes share it).
double corner_accel(const Vec3& u_in, const Vec3& u_out, const std::array<double, 3>& accel) {
  double a = kInf;
  for (int i = 0; i < 3; ++i)
    if (std::fabs(u_in[i]) > kNoAxis || std::fabs(u_out[i]) > kNoAxis) a = std::min(a, accel[i]);
  return a;
}

double feed_of(const std::vector<Motion>& ms, const std::vector<double>& feeds, std::size_t i) {
  const double f = feeds.empty() ? ms[i].feed_mm_per_min : feeds[i];
  if (!(f > 0) || !std::isfinite(f))
    throw Error(Exit::internal, "machining_time: the motion of line " + std::to_string(ms[i].line) +
                                    " has no positive feed (" + std::to_string(f) + " mm/min)");
  return f / 60;
}

// One motion in the look-ahead. v_in_mm_per_s: first the junction limit at its
// start, after the backward pass the largest entry speed that can still stop
// by the program end.
struct Segment {
  double length_mm = 0;
  double vmax_mm_per_s = 0;
  double accel_mm_per_s2 = 0;
  double v_in_mm_per_s = 0;
};

// Shapes and junction limits. A junction is at rest at the program start,
// next to a rapid (exact stop on G0 <-> G1/G2/G3) and at a tool change;
// between cutting motions it is the blend's corner speed, capped by both
// cruise speeds.
std::vector<Segment> build(const std::vector<Motion>& ms, const std::vector<double>& feeds,
                           const profile::AxisLimits& k) {
  std::vector<Segment> seg(ms.size());
  const Motion* prev = nullptr;  // last motion that has a length
  Shape prev_shape;
  for (std::size_t i = 0; i < ms.size(); ++i) {
    const Motion& m = ms[i];
    const double feed = is_rapid(m) ? kInf : feed_of(ms, feeds, i);
    const Shape s = is_arc(m) ? arc_shape(m, feed, k) : line_shape(m, feed, k);
    Segment& g = seg[i];
    if (s.length_mm < kMinLength_mm) {
      g.v_in_mm_per_s = kInf;  // transparent: entry = exit
      continue;
    }
    g.length_mm = s.length_mm;
    g.vmax_mm_per_s = s.vmax_mm_per_s;
    g.accel_mm_per_s2 = s.accel_mm_per_s2;
    if (prev && !is_rapid(*prev) && !is_rapid(m) && prev->tool == m.tool) {
      const double a_corner = corner_accel(prev_shape.u_end, s.u_start, k.acceleration_mm_per_s2);
      const double v_corner = corner_speed_mm_per_s(prev_shape.u_end, s.u_start, a_corner, k.corner_tolerance_mm);
      g.v_in_mm_per_s = std::min({v_corner, prev_shape.vmax_mm_per_s, s.vmax_mm_per_s});
    }
    prev = &m;
    prev_shape = s;
  }
  return seg;
}

// Backward pass: each entry speed must let the motion slow down to the next
// entry speed (0 at the program end) within its length.
void backward(std::vector<Segment>& seg) {
  double exit = 0;
  for (std::size_t i = seg.size(); i-- > 0;) {
    Segment& g = seg[i];
    if (g.length_mm > 0)
      g.v_in_mm_per_s = std::min(g.v_in_mm_per_s, std::sqrt(exit * exit + 2 * g.accel_mm_per_s2 * g.length_mm));
    else
      g.v_in_mm_per_s = exit;
    exit = g.v_in_mm_per_s;
  }
}

void add(TimeTotals& t, bool rapid, double s, double mm) {
  t.total_s += s;
  (rapid ? t.rapid_s : t.cutting_s) += s;
  (rapid ? t.rapid_mm : t.cutting_mm) += mm;
}

}  // namespace

double along(const std::array<double, 3>& limit, const Vec3& u) {
  double v = kInf;
  for (int i = 0; i < 3; ++i)
    if (std::fabs(u[i]) > kNoAxis) v = std::min(v, limit[i] / std::fabs(u[i]));
  return v;
}

double segment_time_s(double length_mm, double v0, double v1, double vmax, double a) {
  if (!(length_mm > 0)) return 0;
  // Peak of the triangle that accelerates from v0 and brakes to v1 over the
  // whole length: v^2 - v0^2 + v^2 - v1^2 = 2 a L. Rounding may put it a hair
  // under v0 or v1 when one ramp takes the whole length.
  const double peak = std::max({std::sqrt(a * length_mm + 0.5 * (v0 * v0 + v1 * v1)), v0, v1});
  if (peak <= vmax) return (2 * peak - v0 - v1) / a;
  const double ramps_mm = (2 * vmax * vmax - v0 * v0 - v1 * v1) / (2 * a);
  return (2 * vmax - v0 - v1) / a + (length_mm - ramps_mm) / vmax;
}

double corner_speed_mm_per_s(const Vec3& u_in, const Vec3& u_out, double a, double tolerance_mm) {
  // t: the angle between the legs at the corner (180 degrees = straight on).
  const double cos_t = -dot(u_in, u_out);
  if (cos_t <= -1 + 1e-12) return kInf;
  if (cos_t >= 1 - 1e-12) return 0;
  // The blend circle tangent to both legs whose midpoint lies tolerance_mm
  // from the corner: its centre is R / sin(t/2) from the corner, so
  // R / sin(t/2) - R = tol (Grbl's junction deviation model).
  const double sin_half = std::sqrt(0.5 * (1 - cos_t));
  const double radius_mm = tolerance_mm * sin_half / (1 - sin_half);
  return std::sqrt(a * radius_mm);
}

MachiningTime machining_time(const std::vector<Motion>& ms, const profile::AxisLimits& k,
                             const std::vector<double>& feeds) {
  if (!feeds.empty() && feeds.size() != ms.size())
    throw Error(Exit::internal, "machining_time: " + std::to_string(feeds.size()) + " feeds for " +
                                    std::to_string(ms.size()) + " motions");
  std::vector<Segment> seg = build(ms, feeds, k);
  backward(seg);
  MachiningTime r;
  r.motion_s.assign(ms.size(), 0.0);
  // Forward pass: each motion leaves at what it can reach from its entry,
  // capped by the next entry speed; its time follows from both.
  double v = 0;
  int tool = 0;
  TimeTotals* per_tool = nullptr;
  for (std::size_t i = 0; i < ms.size(); ++i) {
    const Segment& g = seg[i];
    if (!(g.length_mm > 0)) continue;
    const double v0 = std::min(v, g.v_in_mm_per_s);
    const double next = i + 1 < ms.size() ? seg[i + 1].v_in_mm_per_s : 0.0;
    const double v1 = std::min(next, std::sqrt(v0 * v0 + 2 * g.accel_mm_per_s2 * g.length_mm));
    const double t = segment_time_s(g.length_mm, v0, v1, g.vmax_mm_per_s, g.accel_mm_per_s2);
    v = v1;
    r.motion_s[i] = t;
    const bool rapid = is_rapid(ms[i]);
    add(r.program, rapid, t, g.length_mm);
    if (!per_tool || ms[i].tool != tool) {
      tool = ms[i].tool;
      per_tool = &r.per_tool[tool];
    }
    add(*per_tool, rapid, t, g.length_mm);
  }
  return r;
}

}  // namespace deflex::process
