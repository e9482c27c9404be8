// Engager::evaluate skips in-material tests whose outcome it has proved (slices
// and arcs above the Z-map, sweeps out of reach, tabulated refinement angles);
// evaluate_reference tests every point against the Z-map and every near pending
// sweep. Over realistic views of a stock being cut, both must give the same
// Metrics and engagement intervals, bit for bit.
#include <doctest/doctest.h>

#include "../support.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "deflex/engage/engagement.hpp"
#include "deflex/engage/path.hpp"
#include "deflex/force/cutter.hpp"
#include "deflex/force/engagement.hpp"
#include "deflex/stock/build.hpp"
#include "deflex/stock/sweep.hpp"

using namespace deflex;
using namespace deflex::engage;

namespace {

interp::Motion g1(stock::Point3 a, stock::Point3 b) { return test::linear_motion(a, b, 1000); }

bool same(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

bool same(const Metrics& a, const Metrics& b) {
  return a.air_cut == b.air_cut && a.plunge == b.plunge && same(a.ramp_angle, b.ramp_angle) && same(a.ap_mm, b.ap_mm) &&
         same(a.ae_mm, b.ae_mm) && same(a.cwe_area_mm2, b.cwe_area_mm2) && same(a.bottom_area_mm2, b.bottom_area_mm2) &&
         same(a.d_eff_mm, b.d_eff_mm) && same(a.mrr_mm3_per_s, b.mrr_mm3_per_s) && same(a.up_share, b.up_share);
}

bool same(const force::Engagement& a, const force::Engagement& b) {
  if (a.slices.size() != b.slices.size()) return false;
  for (std::size_t i = 0; i < a.slices.size(); ++i) {
    if (a.slices[i].size() != b.slices[i].size()) return false;
    for (std::size_t k = 0; k < a.slices[i].size(); ++k)
      if (!same(a.slices[i][k].start, b.slices[i][k].start) || !same(a.slices[i][k].end, b.slices[i][k].end))
        return false;
  }
  return true;
}

// A 40 x 24 mm block (0.1 mm cells: tiles of 6.4 mm) whose top is a wave below
// z = 0 for x < 27, with a through-hole (no material) and a wall step; the tiles
// beyond stay uniform. The paths below run off the grid at both ends.
stock::ZMap wavy_block() {
  stock::ZMap z = stock::zmap_from_box(stock::parse_box("box:0,0,-20,40,24,0"), 0.1);
  const stock::GridSpec& g = z.grid();
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const double x = z.cx(i), y = z.cy(j);
      if (x >= 27) continue;
      float h = static_cast<float>(-0.8 + 0.7 * std::sin(x / 3.1) * std::cos(y / 4.3));
      if (x > 20 && y < 6) h -= 2.5f;  // a step with a vertical wall
      if (std::hypot(x - 12, y - 15) < 1.5) h = stock::no_material;
      z.set(i, j, h);
    }
  return z;
}

// Zig-zag passes along X (or Y when `along_y`) of short G1 moves following a
// wave, entering by a descending ramp and with one plunge: a CAM-like finishing path.
std::vector<interp::Motion> raster(double depth, double step, int passes, bool along_y) {
  std::vector<interp::Motion> ms;
  auto pt = [&](double u, double v, double zz) {
    return along_y ? stock::Point3{v, u, zz} : stock::Point3{u, v, zz};
  };
  const double u0 = -4, u1 = along_y ? 28 : 44, seg = 0.5;
  auto zf = [&](double u) { return depth + 0.4 * std::sin(u / 2.3); };
  stock::Point3 p = pt(u0, 3, 2);
  auto to = [&](const stock::Point3& q) {
    ms.push_back(g1(p, q));
    p = q;
  };
  to(pt(u0 + 6, 3, zf(u0 + 6)));  // ramp down, about -20 deg
  double u = u0 + 6;
  for (int k = 0; k < passes; ++k) {
    const double v = 3 + k * step;
    if (k > 0) to(pt(u, v, zf(u)));
    const bool fwd = k % 2 == 0;
    const double end = fwd ? u1 : u0;
    while (fwd ? u < end : u > end) {
      u = fwd ? std::min(end, u + seg) : std::max(end, u - seg);
      to(pt(u, v, zf(u)));
      if (k == 1 && std::fabs(u - 15) < 0.45) {  // a plunge and back up, mid-pass
        const stock::Point3 top = p;
        to({top[0], top[1], top[2] - 0.6});
        to(top);
      }
    }
  }
  return ms;
}

struct Tally {
  int samples = 0, engaged = 0, partial = 0, bottom = 0;
  std::size_t max_pending = 0;
};

// Runs the motions as the Simulator does (the stock as cut so far: the Z-map
// plus the sweeps of the last keep_mm of path, and the current move up to
// just before the sample) and compares both evaluations at every CL sample.
void compare_on(stock::ZMap& z, const force::CutterSlices& cs, const Options& opt,
                const std::vector<interp::Motion>& ms, Tally& t) {
  const Engager eng(cs, opt);
  const stock::ToolProfile& tool = eng.tool();
  const double keep_mm = 2 * cs.cutter.diameter_mm + 4 * z.grid().cell_mm;
  const std::vector<CLSample> samples = cl_samples(ms, PathOptions{});
  std::vector<stock::LineSweep> pending;
  std::vector<double> pending_end;  // path length at each one's end
  double s = 0;
  std::size_t next_motion = 0;
  const Process proc{0.08, 9000};
  force::Engagement fast, ref;
  for (const CLSample& c : samples) {
    for (; next_motion < c.motion; ++next_motion) {  // the motions before this one are done
      const interp::Motion& m = ms[next_motion];
      pending.emplace_back(tool, m.start_mm, m.end_mm);
      s += std::hypot(m.end_mm[0] - m.start_mm[0], m.end_mm[1] - m.start_mm[1], m.end_mm[2] - m.start_mm[2]);
      pending_end.push_back(s);
      while (!pending.empty() && s - pending_end.front() > keep_mm) {
        stock::sweep_line(z, pending.front());
        pending.erase(pending.begin());
        pending_end.erase(pending_end.begin());
      }
    }
    const interp::Motion& m = ms[c.motion];
    const stock::Point3 a = m.start_mm, b = c.point.tip_mm;
    const double l = std::hypot(b[0] - a[0], b[1] - a[1], b[2] - a[2]), f = l <= 1e-4 ? 0 : (l - 1e-4) / l;
    const stock::LineSweep current(tool, a, {a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])});
    const StockView view{&z, pending, &current};
    const Metrics mf = eng.evaluate(view, c.point, proc, fast);
    const Metrics mr = eng.evaluate_reference(view, c.point, proc, ref);
    CAPTURE(c.motion);
    CAPTURE(c.index);
    REQUIRE(same(mf, mr));
    REQUIRE(same(fast, ref));
    ++t.samples;
    t.engaged += !mr.air_cut;
    t.bottom += mr.bottom_area_mm2 > 0;
    t.max_pending = std::max(t.max_pending, pending.size());
    for (const auto& sl : ref.slices)
      if (!sl.empty() && (sl.size() > 1 || sl[0].end - sl[0].start < 6)) {
        ++t.partial;
        break;
      }
  }
}

force::Cutter cutter(stock::EndShape type, double D, double rc = 0) {
  force::Cutter c;
  c.type = type;
  c.diameter_mm = D;
  c.corner_radius_mm = rc;
  c.flutes = 2;
  c.helix_deg = 30;
  c.flute_length_mm = 8;
  return c;
}

}  // namespace

TEST_SUITE("engage") {

TEST_CASE("evaluate equals evaluate_reference bit for bit: ball, flat and bull rasters with ramps on a wavy Z-map") {
  Tally t;
  stock::ZMap z = wavy_block();
  // Ball D6 along X, step-over 0.7 mm (the default options: tabulated refinement).
  compare_on(z, force::make_slices(cutter(stock::EndShape::ball, 6), 0.2, 8), {}, raster(-1.2, 0.7, 3, false), t);
  // Flat D5 along Y on the stock the ball left (flat bottom on the ramps and
  // the plunge); 9 bisections: the refinement angles computed as they come.
  Options o;
  o.refine_steps = 9;
  compare_on(z, force::make_slices(cutter(stock::EndShape::flat, 5), 0.25, 8), o, raster(-1.6, 1.5, 2, true), t);
  // Bull nose D8 r1.5 along X, 40 samples a turn, again on the stock as cut.
  o = {};
  o.angle_samples = 40;
  o.refine_steps = 4;
  compare_on(z, force::make_slices(cutter(stock::EndShape::bull, 8, 1.5), 0.2, 8), o, raster(-2.1, 1.2, 3, false), t);
  MESSAGE(t.samples, " CL samples: ", t.engaged, " engaged, ", t.partial, " with partial slices, ", t.bottom,
          " with a flat bottom cutting; up to ", t.max_pending, " pending sweeps");
  // The views are the demanding kind: mostly engaged, transitions to refine,
  // flat-bottom cuts, dozens of pending sweeps.
  CHECK(t.samples > 500);
  CHECK(t.engaged > t.samples / 2);
  CHECK(t.partial > t.samples / 2);
  CHECK(t.bottom > 5);
  CHECK(t.max_pending >= 20);
}

}  // TEST_SUITE
