#include "deflex/interp/travel.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace deflex::interp {
namespace {

// Extends the box by the arc's extreme points at the quadrant angles it sweeps.
void arc_box(const Motion& m, Vec3& lo, Vec3& hi) {
  int a = 0, b = 1;
  if (m.plane == 18) { a = 2; b = 0; }
  if (m.plane == 19) { a = 1; b = 2; }
  double r = std::hypot(m.start_mm[a] - m.center_mm[a], m.start_mm[b] - m.center_mm[b]);
  double t0 = std::atan2(m.start_mm[b] - m.center_mm[b], m.start_mm[a] - m.center_mm[a]);
  double t1 = std::atan2(m.end_mm[b] - m.center_mm[b], m.end_mm[a] - m.center_mm[a]);
  bool ccw = m.kind == MotionKind::arc_ccw;
  double sweep = ccw ? t1 - t0 : t0 - t1;
  const double two_pi = 2 * 3.14159265358979323846;
  while (sweep <= 1e-12) sweep += two_pi;
  for (int q = 0; q < 4; ++q) {
    double ang = q * two_pi / 4;
    double d = ccw ? ang - t0 : t0 - ang;
    d = std::fmod(std::fmod(d, two_pi) + two_pi, two_pi);
    if (d <= sweep) {
      double pa = m.center_mm[a] + r * std::cos(ang), pb = m.center_mm[b] + r * std::sin(ang);
      lo[a] = std::min(lo[a], pa); hi[a] = std::max(hi[a], pa);
      lo[b] = std::min(lo[b], pb); hi[b] = std::max(hi[b], pb);
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
  if (m.kind == MotionKind::arc_cw || m.kind == MotionKind::arc_ccw) arc_box(m, lo, hi);
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
