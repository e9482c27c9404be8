// Slope patches of a ball end mill's test cut (plan/testcut.hpp): a ball
// cutting inclined planes, where its deflection depends on the inclination
// (Bagci 2017 Table 4; REFERENCE §6).
//
// Each patch chamfers the block's front top edge (y = Y0) over a segment
// along X: the plane through the line y = Y0 + w, z = Z1 descending towards
// -Y at the inclination theta, outward normal (0, -sin theta, cos theta).
// Passes run along +X with the ball tangent to the plane, from the top edge
// down the slope a stepover p apart; the wedge each pass meets lies down the
// slope, on the right of the feed: down-milling, as the walls. The width w
// keeps the wedge at most 0.8 R thick (w tan theta <= 0.8 R, at most 10 mm),
// so the ball never cuts deeper than its own end. Each pass is entered from
// the air in front of the block and left into it.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/diag/plural.hpp"
#include "testcut_slope.hpp"

namespace deflex::plan {
namespace {

double on_grid(double v) { return std::round(v * 1000) / 1000; }
double radians(double deg) { return deg * std::numbers::pi / 180; }

// Width of a patch along Y (mm): the wedge at most 0.8 R thick.
double patch_width_mm(const TestCutter& t, double slope_deg) {
  return on_grid(std::min(10.0, 0.8 * t.diameter_mm / 2 / std::tan(radians(slope_deg))));
}

WallFeature patch(const TestBlock& b, const TestCutter& t, const TestCutOptions& o, int number, double s0, double deg) {
  const double R = t.diameter_mm / 2, th = radians(deg), w = patch_width_mm(t, deg), top = b.z1_mm;
  const double s1 = on_grid(s0 + o.probe_length_mm + 2 * R), clear = top + o.clearance_mm;
  const double out = on_grid(b.y0_mm - R - o.air_mm), p = on_grid(0.1 * R);
  WallFeature f;
  f.kind = "slope";
  f.slope_deg = deg;
  f.id = "S" + std::to_string(number);
  f.feed_axis = 0;
  f.feed_direction = {1, 0, 0};
  f.normal = {0, -std::sin(th), std::cos(th)};
  f.point_mm = {on_grid((s0 + s1) / 2), b.y0_mm + w, top};
  f.u0_mm = on_grid(s0 + R);
  f.u1_mm = on_grid(s1 - R);
  f.z0_mm = on_grid(top - w * std::tan(th));
  f.z1_mm = top;
  f.ae_mm = p;
  f.ap_mm = on_grid(top - f.z0_mm);
  f.fz_mm = o.fz_mm;
  // Contact points s along the slope from the top edge, past the front face.
  const int passes = static_cast<int>(std::ceil(w / std::cos(th) / p - 1e-9)) + 1;
  auto tip = [&](int k) {
    const double s = k * p, yc = b.y0_mm + w - s * std::cos(th), zc = top - s * std::sin(th);
    return Vec3{0, on_grid(yc - R * std::sin(th)), on_grid(zc + R * std::cos(th) - R)};
  };
  f.path = {{s0, out, clear}, {s0, out, tip(0)[2]}};
  for (int k = 0; k < passes; ++k) {
    const Vec3 q = tip(k);
    f.path.push_back({s0, q[1], q[2]});   // in from the air in front of the block
    f.path.push_back({s1, q[1], q[2]});   // along the slope's strike
    f.path.push_back({s1, out, q[2]});    // out into the air
    if (k + 1 < passes) f.path.push_back({s0, out, tip(k + 1)[2]});  // back in the air, down to the next pass
  }
  f.path.push_back({s1, out, clear});
  return f;
}

}  // namespace

Vec3 smallest_slope_block_mm(const TestCutter& t, const TestCutOptions& o) {
  const double R = t.diameter_mm / 2, n = static_cast<double>(o.slopes_deg.size());
  const double seg = o.probe_length_mm + 2 * R;
  double w = 0;
  for (double deg : o.slopes_deg) w = std::max(w, patch_width_mm(t, deg));
  const double x = (o.gap_mm + R) + n * seg + (n - 1) * (2 * R + o.gap_mm) + R + o.gap_mm;
  return {std::ceil(x), std::ceil(w + o.gap_mm), std::ceil(0.8 * R + o.floor_margin_mm)};
}

void check_slopes(const TestCutter& t, const TestCutOptions& o) {
  auto bad = [](const std::string& what) { throw Error(ErrorKind::settings, what); };
  if (o.slopes_deg.empty() || o.slopes_deg.size() > 10) bad("testcut: give 1 to 10 slope inclinations");
  for (double deg : o.slopes_deg)
    if (!(deg >= 5 && deg <= 75)) bad("testcut: each slope's inclination must be in [5, 75] deg");
  if (!o.ae_mm.empty() || !o.ap_mm.empty())
    bad("testcut: " + t.id + " is a ball end mill: its slope patches take no {ae_mm} or {ap_mm} (the stepover is 0.1 R)");
}

void add_slopes(TestCutPlan& p, const TestBlock& b, const TestCutter& t, const TestCutOptions& o) {
  const double R = t.diameter_mm / 2, step = o.probe_length_mm + 2 * t.diameter_mm + o.gap_mm;
  double s = on_grid(b.x0_mm + o.gap_mm + R);
  int n = 0;
  for (double deg : o.slopes_deg) {
    p.features.push_back(patch(b, t, o, ++n, s, deg));
    s = on_grid(s + step);
  }
}

}  // namespace deflex::plan
