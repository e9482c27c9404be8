#include "deflex/interp/travel.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "deflex/interp/arc.hpp"

namespace deflex::interp {
namespace {

// Extends the box by the arc's extreme points at the quadrant angles it sweeps.
void arc_box(const Motion& m, Vec3& lo, Vec3& hi) {
  const Arc arc = arc_of(m);
  const PlaneAxes p = plane_axes(arc.plane);
  const double r = arc_radius_mm(arc), t0 = arc_start_angle(arc), sweep = arc_angle(arc);
  constexpr double two_pi = 2 * std::numbers::pi;
  for (int q = 0; q < 4; ++q) {
    const double ang = q * two_pi / 4;
    double d = arc.cw ? t0 - ang : ang - t0;
    d = std::fmod(std::fmod(d, two_pi) + two_pi, two_pi);
    if (d <= sweep) {
      const double pa = arc.center_mm[p.a] + r * std::cos(ang), pb = arc.center_mm[p.b] + r * std::sin(ang);
      lo[p.a] = std::min(lo[p.a], pa);
      hi[p.a] = std::max(hi[p.a], pa);
      lo[p.b] = std::min(lo[p.b], pb);
      hi[p.b] = std::max(hi[p.b], pb);
    }
  }
}

}  // namespace

bool check_travel(const Motion& m, const profile::Travel& t, const SourceText& src, Diagnostics& d) {
  if (!t.set) return true;
  static const char axes[] = {'X', 'Y', 'Z'};
  Vec3 lo = m.end_mm, hi = m.end_mm;
  for (int i = 0; i < 3; ++i) {
    lo[i] = std::min(lo[i], m.start_mm[i]);
    hi[i] = std::max(hi[i], m.start_mm[i]);
  }
  if (is_arc(m)) arc_box(m, lo, hi);
  bool inside = true;
  for (int i = 0; i < 3; ++i) {
    const double mn = lo[i] + m.work_offset_mm[i], mx = hi[i] + m.work_offset_mm[i];
    const double eps = 1e-9;
    if (mn < t.min_mm[i] - eps || mx > t.max_mm[i] + eps) {
      char buf[200];
      std::snprintf(buf, sizeof buf, "%c travels to %.4f mm (machine), outside the limit [%.4f, %.4f] of the machine profile",
                    axes[i], mn < t.min_mm[i] - eps ? mn : mx, t.min_mm[i], t.max_mm[i]);
      d.report(Severity::error, src, m.line, 1, buf);
      inside = false;
    }
  }
  return inside;
}

}  // namespace deflex::interp
