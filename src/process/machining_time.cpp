#include "deflex/process/machining_time.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/interp/arc.hpp"

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
  const auto [pa, pb, pn] = interp::plane_axes(m.plane);
  const interp::Arc a = interp::arc_of(m);
  Shape s;
  const double r_mm = interp::arc_radius_mm(a);
  const double planar_mm = r_mm * interp::arc_angle(a);
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
  s.u_start = interp::arc_tangent(a, 0);
  s.u_end = interp::arc_tangent(a, 1);
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

// One motion in the look-ahead. v_in_mm_per_s: first the junction limit at its
// start, after the backward pass the largest entry speed that can still stop
// by the program end.
struct Segment {
  double length_mm = 0;
  double vmax_mm_per_s = 0;
  double accel_mm_per_s2 = 0;
  double v_in_mm_per_s = 0;
};

void add_time(TimeTotals& t, bool rapid, double s, double mm) {
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

// The clock keeps the motions whose entry speed may still fall (the
// look-ahead) and settles them in batches: within the window the backward
// pass runs as if the path went on at full speed after it; a motion's entry
// speed is final once the braking room from it to the window's end, 2 a L
// summed, is at least its square (no later stop can lower it then).
struct MachiningClock::Entry {
  Segment g;
  bool rapid = false;
  int tool = 0;
  std::size_t index = 0;
};

MachiningClock::MachiningClock(const profile::AxisLimits& k, std::vector<double>* motion_s)
    : k_(k), motion_s_(motion_s) {}
MachiningClock::~MachiningClock() = default;

// Shapes and junction limits. A junction is at rest at the program start,
// next to a rapid (exact stop on G0 <-> G1/G2/G3) and at a tool change;
// between cutting motions it is the blend's corner speed, capped by both
// cruise speeds.
void MachiningClock::add(const Motion& m, double feed_mm_per_min) {
  const double f = std::isnan(feed_mm_per_min) ? m.feed_mm_per_min : feed_mm_per_min;
  if (!is_rapid(m) && (!(f > 0) || !std::isfinite(f)))
    throw Error(ErrorKind::internal, "machining_time: the motion of line " + std::to_string(m.line) +
                                    " has no positive feed (" + std::to_string(f) + " mm/min)");
  const double feed = is_rapid(m) ? kInf : f / 60;
  const Shape s = interp::is_arc(m) ? arc_shape(m, feed, k_) : line_shape(m, feed, k_);
  Entry e;
  e.rapid = is_rapid(m);
  e.tool = m.tool;
  e.index = count_++;
  if (motion_s_) motion_s_->push_back(0.0);
  if (s.length_mm < kMinLength_mm) {
    e.g.v_in_mm_per_s = kInf;  // transparent: entry = exit
  } else {
    e.g.length_mm = s.length_mm;
    e.g.vmax_mm_per_s = s.vmax_mm_per_s;
    e.g.accel_mm_per_s2 = s.accel_mm_per_s2;
    if (have_prev_ && !prev_rapid_ && !is_rapid(m) && prev_tool_ == m.tool) {
      const double a_corner = corner_accel(prev_shape_.u_end, s.u_start, k_.acceleration_mm_per_s2);
      const double v_corner = corner_speed_mm_per_s(prev_shape_.u_end, s.u_start, a_corner, k_.corner_tolerance_mm);
      e.g.v_in_mm_per_s = std::min({v_corner, prev_shape_.vmax_mm_per_s, s.vmax_mm_per_s});
    }
    have_prev_ = true;
    prev_rapid_ = is_rapid(m);
    prev_tool_ = m.tool;
    prev_shape_ = {s.u_end, s.vmax_mm_per_s};
  }
  window_.push_back(e);
  if (window_.size() >= settled_size_ + kBatch) settle(false);
}

// Backward pass over the window: each entry speed must let the motion slow
// down to the next entry speed (0 at the program end) within its length; then
// the forward pass over what is final: each motion leaves at what it can reach
// from its entry, capped by the next entry speed; its time follows from both.
void MachiningClock::settle(bool end) {
  const std::size_t n = window_.size();
  std::vector<double> v_in(n);
  double exit = end ? 0 : kInf, room = 0;  // room: 2 a L from the motion to the window's end
  std::size_t final_count = end ? n : 0;
  for (std::size_t i = n; i-- > 0;) {
    const Segment& g = window_[i].g;
    if (g.length_mm > 0) {
      v_in[i] = std::min(g.v_in_mm_per_s, std::sqrt(exit * exit + 2 * g.accel_mm_per_s2 * g.length_mm));
      room += 2 * g.accel_mm_per_s2 * g.length_mm;
    } else {
      v_in[i] = exit;
    }
    exit = v_in[i];
    if (!end && !final_count && v_in[i] * v_in[i] <= room) final_count = i + 1;
  }
  // A motion's time needs the next one's entry: the last final one waits.
  const std::size_t done = end ? n : (final_count ? final_count - 1 : 0);
  for (std::size_t i = 0; i < done; ++i) {
    const Entry& e = window_[i];
    const Segment& g = e.g;
    if (!(g.length_mm > 0)) continue;
    const double v0 = std::min(v_, v_in[i]);
    const double next = i + 1 < n ? v_in[i + 1] : 0.0;
    const double v1 = std::min(next, std::sqrt(v0 * v0 + 2 * g.accel_mm_per_s2 * g.length_mm));
    const double t = segment_time_s(g.length_mm, v0, v1, g.vmax_mm_per_s, g.accel_mm_per_s2);
    v_ = v1;
    if (motion_s_) (*motion_s_)[e.index] = t;
    add_time(r_.program, e.rapid, t, g.length_mm);
    if (!per_tool_ || e.tool != tool_) {
      tool_ = e.tool;
      per_tool_ = &r_.per_tool[tool_];
    }
    add_time(*per_tool_, e.rapid, t, g.length_mm);
  }
  window_.erase(window_.begin(), window_.begin() + static_cast<std::ptrdiff_t>(done));
  settled_size_ = window_.size();
}

MachiningTime MachiningClock::finish() {
  settle(true);
  return r_;
}

MachiningTime machining_time(const std::vector<Motion>& ms, const profile::AxisLimits& k,
                             const std::vector<double>& feeds) {
  if (!feeds.empty() && feeds.size() != ms.size())
    throw Error(ErrorKind::internal, "machining_time: " + std::to_string(feeds.size()) + " feeds for " +
                                    std::to_string(ms.size()) + " motions");
  std::vector<double> motion_s;
  motion_s.reserve(ms.size());
  MachiningClock clock(k, &motion_s);
  for (std::size_t i = 0; i < ms.size(); ++i) clock.add(ms[i], feeds.empty() ? NAN : feeds[i]);
  MachiningTime r = clock.finish();
  r.motion_s = std::move(motion_s);
  return r;
}

}  // namespace deflex::process
