// Roughing over a target surface (plan/roughing.hpp).
#include "deflex/plan/roughing.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/writer/writer.hpp"

namespace deflex::plan {
namespace {

constexpr double kNone = -std::numeric_limits<double>::infinity();
// Most floor samples of one plan (lines x samples per line): 800 MB of doubles.
constexpr double kMaxSamples = 1e8;

// Points evenly spaced from a to b, at most `step` apart (both ends included).
std::vector<double> even(double a, double b, double step) {
  const int n = std::max(1, static_cast<int>(std::ceil((b - a) / step - 1e-9)));
  std::vector<double> v(n + 1);
  for (int k = 0; k <= n; ++k) v[k] = a + (b - a) * k / n;
  return v;
}

// Keeps the points of a line whose removal would bring the move below the
// floor or more than `tol` above it: the move from the last kept point to a
// candidate must pass on or above every dropped point and within tol of it.
// Each dropped point bounds the slope of that move from both sides, so the
// slopes still allowed are an interval narrowed point by point: one pass, O(n)
// (Douglas-Peucker would not keep the one-sided bound).
std::vector<Point> merge(const std::vector<Point>& pts, double tol) {
  if (pts.size() < 3) return pts;
  constexpr double inf = std::numeric_limits<double>::infinity();
  std::vector<Point> out{pts[0]};
  std::size_t anchor = 0;
  double lo = -inf, hi = inf;  // slopes dz/dx from the anchor the points dropped so far allow
  for (std::size_t k = 1; k < pts.size(); ++k) {
    const Point& a = pts[anchor];
    const double dx = pts[k][0] - a[0];
    const double slope = (pts[k][2] - a[2]) / dx;
    if (k > anchor + 1 && !(slope >= lo && slope <= hi)) {
      anchor = k - 1;  // the move to k would cut into the floor or leave too much: keep k - 1
      out.push_back(pts[anchor]);
      lo = -inf;
      hi = inf;
    }
    // Point k as a dropped point of a later move from the anchor: the move's
    // height over it within [z_k - 1e-9, z_k + tol].
    const Point& b = pts[anchor];
    const double d = pts[k][0] - b[0];
    if (k > anchor) {
      const double s1 = (pts[k][2] - 1e-9 - b[2]) / d, s2 = (pts[k][2] + tol - b[2]) / d;
      lo = std::max(lo, std::min(s1, s2));
      hi = std::min(hi, std::max(s1, s2));
    }
  }
  out.push_back(pts.back());
  return out;
}

// Floor heights at the samples of every line, lines in parallel.
std::vector<double> floor_samples(const stock::ZMap& target, const RoughingOptions& o, const std::vector<double>& ys,
                                  const std::vector<double>& xs) {
  const stock::ToolProfile g = grown(o.tool, o.allowance_mm);
  std::vector<double> h(ys.size() * xs.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, ys.size()), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t j = r.begin(); j != r.end(); ++j)
      for (std::size_t k = 0; k < xs.size(); ++k) {
        const double d = drop_height(target, g, xs[k], ys[j]);
        h[j * xs.size() + k] = d == kNone ? kNone : d + o.allowance_mm;
      }
  });
  return h;
}

}  // namespace

void check_options(const RoughingOptions& o) {
  auto bad = [](const std::string& what) { throw Error(ErrorKind::settings, what); };
  if (!(o.tool.radius_mm > 0)) bad("the roughing tool has no diameter");
  if (!(o.allowance_mm >= 0 && o.allowance_mm <= 50)) bad("the allowance must be between 0 and 50 mm");
  if (!(o.stepdown_mm >= 0 && o.stepdown_mm <= 100)) bad("the stepdown must be between 0 (one level) and 100 mm");
  if (!(o.stepover_mm > 0 && o.stepover_mm <= 2 * o.tool.radius_mm))
    bad("the stepover must be > 0 and at most the tool diameter (" + std::to_string(2 * o.tool.radius_mm) + " mm)");
  if (!(o.sample_mm >= 0.01 && o.sample_mm <= o.tool.radius_mm)) bad("the sample spacing must be between 0.01 mm and the tool radius");
  if (!(o.spindle_rpm > 0 && o.spindle_rpm <= 1e6)) bad("the spindle speed must be > 0 rpm");
  if (!(o.feed_mm_per_min > 0 && o.feed_mm_per_min <= 1e6)) bad("the feed must be > 0 mm/min");
}

stock::ToolProfile grown(const stock::ToolProfile& tool, double a_mm) {
  stock::ToolProfile g = tool;
  g.radius_mm = tool.radius_mm + a_mm;
  if (tool.kind == stock::EndShape::flat && a_mm > 0) {
    g.kind = stock::EndShape::bull;
    g.corner_radius_mm = a_mm;
  } else if (tool.kind == stock::EndShape::bull) {
    g.corner_radius_mm = tool.corner_radius_mm + a_mm;
  }
  return g;
}

double drop_height(const stock::ZMap& z, const stock::ToolProfile& tool, double x_mm, double y_mm) {
  const double R = tool.radius_mm, flat = R - stock::corner_of(tool);
  const int j0 = std::max(0, z.iy(y_mm - R)), j1 = std::min(z.grid().ny - 1, z.iy(y_mm + R));
  double best = kNone;
  for (int j = j0; j <= j1; ++j) {
    const double dy = z.cy(j) - y_mm, w2 = R * R - dy * dy;
    if (w2 < 0) continue;
    const double w = std::sqrt(w2), wf2 = flat * flat - dy * dy;
    const int i0 = std::max(0, z.ix(x_mm - w)), i1 = std::min(z.grid().nx - 1, z.ix(x_mm + w));
    for (int i = i0; i <= i1; ++i) {
      const float c = z.at(i, j);
      if (c == stock::no_material || c <= best) continue;  // the profile only lowers it
      const double dx = z.cx(i) - x_mm, d2 = dx * dx + dy * dy;
      if (d2 > R * R) continue;
      const double lift = d2 <= wf2 ? 0.0 : stock::profile_height(tool, std::sqrt(d2));
      best = std::max(best, c - lift);
    }
  }
  return best;
}

RoughingPlan plan_roughing(const stock::ZMap& target, double stock_top_mm, const RoughingOptions& o) {
  check_options(o);
  const stock::GridSpec& g = target.grid();
  const double margin = o.tool.radius_mm + o.allowance_mm + 1.0;  // line ends: the grown tool clear of the grid
  RoughingPlan p;
  p.top_mm = stock_top_mm;
  p.x_start_mm = g.x0_mm - margin;
  p.x_end_mm = g.x0_mm + g.nx * g.cell_mm + margin;
  // The raster's size before anything is allocated: a tiny stepover or sample
  // over a large stock would be a run away, not a roughing.
  const double lines = std::ceil(g.ny * g.cell_mm / o.stepover_mm) + 1,
               samples = std::ceil((p.x_end_mm - p.x_start_mm) / o.sample_mm) + 1;
  if (!(lines * samples <= kMaxSamples))
    throw Error(ErrorKind::settings, "the raster would have " + std::to_string(static_cast<long long>(lines * samples)) +
                                 " floor samples (at most " + std::to_string(static_cast<long long>(kMaxSamples)) +
                                 "): raise the stepover or the sample spacing");
  p.line_y_mm = even(g.y0_mm, g.y0_mm + g.ny * g.cell_mm, o.stepover_mm);
  const std::vector<double> xs = even(p.x_start_mm, p.x_end_mm, o.sample_mm);
  const std::vector<double> h = floor_samples(target, o, p.line_y_mm, xs);
  // The lowest floor where the cutter can touch the stock: beside an edge its
  // centre stands outside while its end still reaches the edge cells; further
  // out it cuts air at any height.
  p.floor_min_mm = std::numeric_limits<double>::infinity();
  const double reach_lo = g.x0_mm - o.tool.radius_mm, reach_hi = g.x0_mm + g.nx * g.cell_mm + o.tool.radius_mm;
  for (std::size_t k = 0; k < h.size(); ++k) {
    const double x = xs[k % xs.size()];
    if (h[k] != kNone && x > reach_lo && x < reach_hi) p.floor_min_mm = std::min(p.floor_min_mm, h[k]);
  }
  if (!(p.floor_min_mm < stock_top_mm - 1e-6))
    throw Error(ErrorKind::settings, "nothing to rough: the target lies within the allowance of the stock top everywhere");
  const double depth = stock_top_mm - p.floor_min_mm;
  const int levels = o.stepdown_mm > 0 ? std::max(1, static_cast<int>(std::ceil(depth / o.stepdown_mm - 1e-9))) : 1;
  for (int k = 1; k <= levels; ++k) p.levels_mm.push_back(k == levels ? p.floor_min_mm : stock_top_mm - depth * k / levels);
  for (double level : p.levels_mm) {
    std::vector<Point> pass;
    for (std::size_t j = 0; j < p.line_y_mm.size(); ++j) {
      std::vector<Point> line(xs.size());
      for (std::size_t k = 0; k < xs.size(); ++k) {
        const std::size_t kk = j % 2 ? xs.size() - 1 - k : k;  // zig-zag
        line[k] = {xs[kk], p.line_y_mm[j], std::max(level, h[j * xs.size() + kk])};
      }
      const std::vector<Point> m = merge(line, o.merge_tol_mm);
      pass.insert(pass.end(), m.begin(), m.end());  // the step to the next line runs outside the stock
    }
    p.passes.push_back(std::move(pass));
  }
  return p;
}

void write_roughing(std::ostream& out, const RoughingPlan& p, const RoughingOptions& o, const profile::Dialect& d,
                    const std::vector<std::string>& header) {
  auto num = [&](double v) { return writer::format_number(v, false, d); };
  const std::string t = std::to_string(o.tool_number);
  const double clear = p.top_mm + o.clearance_mm;
  out << "%\n";
  for (const std::string& c : header) out << writer::format_comment(c, d) << "\n";
  out << "G21 G90 G17 G40 G49 G80\nT" << t << " M6\nG54 G0 X" << num(p.x_start_mm) << " Y" << num(p.line_y_mm.front())
      << " S" << static_cast<long>(std::lround(o.spindle_rpm)) << " M3\nG43 H" << t << " Z" << num(clear) << "\n";
  for (std::size_t k = 0; k < p.passes.size(); ++k) {
    const std::vector<Point>& pass = p.passes[k];
    out << writer::format_comment("level " + std::to_string(k + 1) + " of " + std::to_string(p.passes.size()) +
                                      ": Z" + num(p.levels_mm[k]) + " or the floor above it",
                                  d)
        << "\n";
    if (k) out << "G0 X" << num(pass[0][0]) << " Y" << num(pass[0][1]) << "\n";
    out << "G1 Z" << num(pass[0][2]) << " F" << num(o.feed_mm_per_min) << "\n";
    std::string last[3] = {num(pass[0][0]), num(pass[0][1]), num(pass[0][2])};
    for (std::size_t i = 1; i < pass.size(); ++i) {
      std::string block;
      for (int a = 0; a < 3; ++a) {
        const std::string v = num(pass[i][a]);
        if (v != last[a]) block += std::string(block.empty() ? "" : " ") + "XYZ"[a] + v;
        last[a] = v;
      }
      if (!block.empty()) out << block << "\n";
    }
    out << "G0 Z" << num(clear) << "\n";
  }
  out << "M5\nM30\n%\n";
}

}  // namespace deflex::plan
