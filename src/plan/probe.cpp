// The probing program of a test cut (plan/probe.hpp).
#include "deflex/plan/probe.hpp"

#include <algorithm>
#include <cmath>
#include <ostream>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/diag/plural.hpp"
#include "deflex/writer/writer.hpp"

namespace deflex::plan {
namespace {

double on_grid(double v) { return std::round(v * 1000) / 1000; }

// Fixed decimals without a negative zero (the comment's format is parsed).
std::string fixed(double v, int decimals) {
  std::string s = fixed_decimals(v, decimals);
  if (s.starts_with('-') && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
  return s;
}

Vec3 along(const Vec3& p, const Vec3& n, double d) { return {p[0] + n[0] * d, p[1] + n[1] * d, p[2] + n[2] * d}; }

// The heights of a wall's points: every step from its bottom + r + 0.1 (the
// ball clear of the floor) up to its top - 0.1, the top itself the last.
std::vector<double> heights(const WallFeature& f, double r, double step) {
  const double lo = on_grid(f.z0_mm + r + 0.1), hi = on_grid(f.z1_mm - 0.1);
  std::vector<double> z;
  for (int k = 0; lo + k * step <= hi + 1e-9; ++k) z.push_back(on_grid(lo + k * step));
  if (!z.empty() && z.back() < hi - 1e-6) z.push_back(hi);
  return z;
}

std::vector<double> positions(const WallFeature& f, int n) {
  std::vector<double> u;
  for (int k = 0; k < n; ++k) u.push_back(on_grid(n == 1 ? (f.u0_mm + f.u1_mm) / 2 : f.u0_mm + (f.u1_mm - f.u0_mm) * k / (n - 1)));
  return u;
}

// The points of one feature: up the first position, down the next (zig-zag).
std::vector<ProbePoint> feature_points(const WallFeature& f, const ProbeOptions& o, int& id) {
  const double r = o.ball_diameter_mm / 2;
  std::vector<double> z = heights(f, r, o.step_mm);
  std::vector<ProbePoint> pts;
  for (double u : positions(f, o.positions_along)) {
    for (double h : z) {
      ProbePoint p;
      p.id = ++id;
      p.feature = f.id;
      p.normal = f.normal;
      // The intended surface point: on the plane through point_mm at (u, h).
      Vec3 s = f.point_mm;
      s[f.feed_axis] = u;
      s[2] = h;
      p.surface_mm = s;
      p.start_mm = along(s, f.normal, r + o.approach_mm);
      p.end_mm = along(s, f.normal, r - o.overtravel_mm);
      for (Vec3* v : {&p.start_mm, &p.end_mm})
        for (double& c : *v) c = on_grid(c);
      pts.push_back(p);
    }
    std::reverse(z.begin(), z.end());
  }
  return pts;
}

}  // namespace

void check_probe_options(const ProbeOptions& o) {
  auto bad = [](const std::string& what) { throw Error(ErrorKind::settings, what); };
  if (!(o.ball_diameter_mm >= 0.3 && o.ball_diameter_mm <= 20)) bad("{ball_diameter_mm} must be in [0.3, 20] mm");
  if (!(o.step_mm >= 0.25 - 1e-9 && o.step_mm <= 0.5 + 1e-9)) bad("{step_mm} must be in [0.25, 0.5] mm");
  if (!(o.approach_mm >= 0.5 && o.approach_mm <= 20)) bad("{approach_mm} must be in [0.5, 20] mm");
  if (!(o.overtravel_mm > 0 && o.overtravel_mm <= 5 && o.overtravel_mm < o.ball_diameter_mm / 2 + o.approach_mm))
    bad("the overtravel must be in (0, 5] mm");
  if (!(o.probe_feed_mm_per_min > 0 && o.probe_feed_mm_per_min <= 5000)) bad("{probe_feed_mm_per_min} must be in (0, 5000] mm/min");
  if (!(o.move_feed_mm_per_min > 0 && o.move_feed_mm_per_min <= 20000)) bad("the positioning feed must be in (0, 20000] mm/min");
  if (o.probe_tool < 0 || o.probe_tool > 99999) bad("{probe_tool} must be T<n> with n in 1..99999");
  if (o.positions_along < 1 || o.positions_along > 50) bad("probe positions along a wall must be 1 to 50");
  if (!(o.probe_length_mm >= 0 && o.probe_length_mm <= 500)) bad("{probe_length_mm} must be in (0, 500] mm");
}

void check_probe_fits(const TestCutPlan& p, const ProbeOptions& o) {
  auto bad = [](const std::string& what) { throw Error(ErrorKind::settings, what); };
  const double r = o.ball_diameter_mm / 2;
  double deepest = 0;
  for (const WallFeature& f : p.features) {
    if (heights(f, r, o.step_mm).empty())
      bad(f.id + ": the wall (Z" + fixed(f.z0_mm, 3) + " to Z" + fixed(f.z1_mm, 3) + ") is too low for a ball of " +
          fixed(o.ball_diameter_mm, 3) + " mm");
    if (f.u1_mm - f.u0_mm < 0) bad(f.id + ": an empty probe region");
    deepest = std::max(deepest, p.block.z1_mm - (f.z0_mm + r + 0.1));
  }
  // The probe body must stay above the block top: the stylus reaches the
  // deepest ball centre with 1 mm to spare.
  if (o.probe_length_mm > 0 && o.probe_length_mm < deepest + 1)
    bad("{probe_length_mm}: the stylus (" + fixed(o.probe_length_mm, 3) + " mm) is too short: the deepest point is " +
        fixed(deepest, 3) + " mm below the block top, so the stylus needs at least " + fixed(deepest + 1, 3) + " mm");
}

ProbeProgram plan_probe(const TestCutPlan& p, const ProbeOptions& o) {
  check_probe_options(o);
  check_probe_fits(p, o);
  ProbeProgram pp;
  pp.plan = p;
  pp.options = o;
  pp.clear_z_mm = p.block.z1_mm + p.clearance_mm;
  int id = 0;
  for (const WallFeature& f : p.features) pp.features.push_back(feature_points(f, o, id));
  return pp;
}

std::string probe_comment(const ProbePoint& pt, double r) {
  const Vec3 &s = pt.surface_mm, &n = pt.normal;
  return "DEFLEX PROBE " + std::to_string(pt.id) + " " + pt.feature + " AT " + fixed(s[0], 3) + " " + fixed(s[1], 3) + " " +
         fixed(s[2], 3) + " N " + fixed(n[0], 4) + " " + fixed(n[1], 4) + " " + fixed(n[2], 4) + " BALL " + fixed(r, 3);
}

}  // namespace deflex::plan
