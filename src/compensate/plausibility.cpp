#include "deflex/compensate/plausibility.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <limits>
#include <map>
#include <set>

#include "deflex/diag/plural.hpp"
#include "internal.hpp"
#include "plausibility_parts.hpp"

namespace deflex::compensate {

using detail::Acc;
using detail::SpindleChecks;
using detail::StabilityChecks;

const Finding* Plausibility::find(const std::string& kind) const {
  for (const Finding& f : findings)
    if (f.kind == kind) return &f;
  return nullptr;
}

ForceLimit default_force_limit(const stiffness::Tool& t) {
  const double sigma = t.material.allowable_bending_MPa;
  ForceLimit best{std::numeric_limits<double>::infinity(), ""};
  auto section = [&](double d, double L, const char* where) {
    if (!(d > 0) || !(L > 0)) return;
    const double W = std::numbers::pi * d * d * d / 32.0;
    const double F = sigma * W / L;
    if (F < best.N) best = {F, where};
  };
  const double top = std::min(t.flute_length_mm, t.stickout_mm);
  section(t.flute_diameter_ratio * t.diameter_mm, top, "the root of the flutes");
  if (t.neck) section(t.neck->diameter_mm, std::min(top + t.neck->length_mm, t.stickout_mm), "the root of the neck");
  section(t.shank_diameter_mm > 0 ? t.shank_diameter_mm : t.diameter_mm, t.stickout_mm, "the holder face");
  return best;
}

ForceLimit force_limit(const stiffness::Tool& t) {
  if (t.max_force_N) return {*t.max_force_N, "max_force_N"};
  return default_force_limit(t);
}

namespace {

// A point of a full-width slot run (kept until the run is judged).
struct RunPoint {
  std::uint32_t line = 0, motion = 0;
  V3 tip_mm = V3::Zero();
  double ap_mm = 0;
};

// earlier_cut: runs of cutting points in air with the stock a little below
// (more than the tolerance, within the tool's radius: a pass meant to cut,
// not an approach), counted in constant memory: the points of the runs longer
// than the tool's diameter, the first run's line and tool, the largest gap,
// the first 12 lines and a count of line changes (lines come in program order).
struct AirRuns {
  std::size_t points = 0, cutting = 0, line_count = 0;
  std::vector<std::uint32_t> lines;
  std::uint32_t first_line = 0;
  double gap_mm = 0;
  std::string tool;
  // The open run.
  std::size_t run_points = 0, run_line_count = 0;
  std::vector<std::uint32_t> run_lines;
  double run_mm = 0, run_gap_mm = 0, run_min_mm = 0;
  std::uint32_t run_motion = 0, run_line = 0;
  V3 last = V3::Zero();
  std::string run_tool;

  void add(const Point& p, const std::string& id, double tolerance_mm, double D) {
    ++cutting;
    const bool air = p.air && !p.plunge && p.stock_gap_mm > tolerance_mm && p.stock_gap_mm <= 0.5 * D;
    if (!air || (run_points && (id != run_tool || run_motion + 1 < p.motion))) end();
    if (!air) return;
    if (run_points) {
      run_mm += (p.tip_mm - last).norm();
    } else {
      run_tool = id;
      run_min_mm = D;
    }
    ++run_points;
    last = p.tip_mm;
    run_motion = p.motion;
    run_gap_mm = std::max(run_gap_mm, p.stock_gap_mm);
    if (run_lines.empty() || p.line != run_line) {
      ++run_line_count;
      if (run_lines.size() < 12) run_lines.push_back(p.line);
      run_line = p.line;
    }
  }
  void end() {
    if (run_points && run_mm >= run_min_mm) {
      if (!points) {
        first_line = run_lines.front();
        tool = run_tool;
      }
      points += run_points;
      gap_mm = std::max(gap_mm, run_gap_mm);
      line_count += run_line_count;
      for (std::uint32_t l : run_lines)
        if (lines.size() < 12 && (lines.empty() || lines.back() != l)) lines.push_back(l);
    }
    run_points = run_line_count = 0;
    run_lines.clear();
    run_mm = run_gap_mm = 0;
  }
};

}  // namespace

struct PlausibilityScan::State {
  const stiffness::ToolLibrary& tools;
  const Settings& s;
  Acc flute, force, cap, centre, rough, gouge;
  SpindleChecks spindle;
  StabilityChecks stability;
  // A ball end's roughing points wait for the end of their motion, and those
  // of a steep drop (more than R down over less than R across) for the end of
  // the next one. A drop and a climb back of more than R each within 2R
  // across is a dip no ball of radius R can make on any surface (a hole it
  // fits into is at least as wide as the dip is deep): a drop-cutter sample
  // that fell off a rim, the program gouging the part, not a raw blank. A
  // steep drop alone is a wall in a raster. The drop of the worst dip.
  std::vector<RunPoint> held, dip;
  std::string held_tool;
  std::uint32_t held_motion = 0, end_motion = 0, end_line = 0, dip_line = 0;
  bool start_known = false, end_known = false;
  V3 start = V3::Zero(), end = V3::Zero();
  double dip_dz_mm = 0, dip_xy_mm = 0;
  double gouge_dz_mm = 0, gouge_xy_mm = 0;
  std::uint32_t gouge_line = 0;
  bool earlier_stock = false;
  AirRuns earlier;
  // Cutting points in air or plunging (counted: a set of their lines would
  // grow with the program), the first one's line, and whether any was in material.
  std::size_t air_points = 0;
  std::uint32_t first_air_line = 0;
  std::string first_air_tool;
  bool material = false;
  std::map<std::string, ForceLimit> limits;
  double force_peak = 0, force_lim = 0;  // peak_force: the worst by F / limit
  // Full-width deep slot runs (flat and bull ends): points and path length.
  std::vector<RunPoint> run;
  double run_mm = 0;
  std::string run_tool;
  // For the cap with the capped lines (known as the mirror pass goes): the
  // worst |e| and its tool per line of the points that are neither in air nor
  // plunges, for lines from `base` on (line_worst_mm[l - base]); the lines
  // before it are settled. Lines come in program order, except under
  // subprogram calls (a program read whole, settled at the end).
  std::vector<double> line_worst_mm;
  std::vector<std::uint16_t> line_tool;  // index into tool_names
  std::uint32_t base = 0, last_line = 0;
  std::vector<std::uint32_t> pending;    // capped lines not folded yet
  Acc capped;                            // offset_cap from the capped lines
  std::uint32_t capped_line_count = 0;
  std::vector<std::string> tool_names;
  std::uint16_t tool_index(const std::string& id) {
    for (std::size_t k = 0; k < tool_names.size(); ++k)
      if (tool_names[k] == id) return static_cast<std::uint16_t>(k);
    tool_names.push_back(id);
    return static_cast<std::uint16_t>(tool_names.size() - 1);
  }

  State(const stiffness::ToolLibrary& t, const Settings& st, bool e, const profile::SpindleRating* sp)
      : tools(t), s(st), spindle(sp, st.feed_limit_N), earlier_stock(e) {
    flute.f.kind = "flute_length";
    force.f.kind = "peak_force";
    cap.f.kind = "offset_cap";
    centre.f.kind = "centre_cutting";
    rough.f.kind = "roughing";
    gouge.f.kind = "gouge";
  }
  void end_run() {
    if (run_mm > 1.0)
      for (const RunPoint& q : run) rough.add(q.line, q.ap_mm, run_tool);
    run.clear();
    run_mm = 0;
  }
  void add(const Point& p);
  void check_flutes(const Point& p, const stiffness::Tool& t, const std::string& id);
  void check_force(const Point& p, const stiffness::Tool& t, const std::string& id);
  void check_cap(const Point& p, const std::string& id);
  void check_ball_depth(const Point& p, const stiffness::Tool& t, const std::string& id);
  void check_slot(const Point& p, const stiffness::Tool& t, const std::string& id);
  void fold(bool all);
  void motion_step(const Point& p);
  void judge_held(bool at_end, double R);
};

// The capped lines whose points are all in (every line before the last
// point's, or all at the end) go into `capped`: counted, the first 12 distinct
// kept, the worst |e| of the points on them (the earliest line on a tie).
// The per-line worsts before the lowest line still pending are then dropped.
void PlausibilityScan::State::fold(bool all) {
  std::size_t k = 0;
  for (; k < pending.size() && (all || pending[k] < last_line); ++k) {
    const std::uint32_t l = pending[k];
    ++capped.f.count;
    if (capped.seen.insert(l).second && capped.f.lines.size() < 12) capped.f.lines.push_back(l);
    if (l < base || l - base >= line_worst_mm.size() || line_worst_mm[l - base] < 0) continue;
    const double w = line_worst_mm[l - base];
    if (!capped.any || w > capped.f.worst || (w == capped.f.worst && l < capped.f.line)) {
      capped.f.worst = w;
      capped.f.line = l;
      capped.f.tool = tool_names[line_tool[l - base]];
      capped.any = true;
    }
  }
  pending.erase(pending.begin(), pending.begin() + static_cast<std::ptrdiff_t>(k));
  // Only in program order may the settled lines be dropped.
  const std::uint32_t keep_from = std::min(pending.empty() ? last_line : pending.front(), last_line);
  if (!all && keep_from > base && std::is_sorted(pending.begin(), pending.end())) {
    const std::size_t drop = std::min<std::size_t>(keep_from - base, line_worst_mm.size());
    line_worst_mm.erase(line_worst_mm.begin(), line_worst_mm.begin() + static_cast<std::ptrdiff_t>(drop));
    line_tool.erase(line_tool.begin(), line_tool.begin() + static_cast<std::ptrdiff_t>(drop));
    base += static_cast<std::uint32_t>(drop);
  }
}

// The motion's start: the end of the motion before it, when that one cut too.
void PlausibilityScan::State::motion_step(const Point& p) {
  if (p.motion == held_motion) return;
  held_motion = p.motion;
  start_known = end_known && end_motion + 1 == p.motion;
  start = end;
}

// At the end of a motion (at_end) or when it was left without one.
void PlausibilityScan::State::judge_held(bool at_end, double R) {
  const std::string& id = held_tool;
  const V3 d = end - start;
  const double xy = std::hypot(d.x(), d.y());
  const bool known = at_end && start_known && xy < R;
  auto to = [&](Acc& a, std::vector<RunPoint>& pts, double value) {
    for (const RunPoint& q : pts) a.add(q.line, value < 0 ? q.ap_mm : value, id);
    pts.clear();
  };
  if (!dip.empty() || dip_line) {
    if (known && d.z() > R && dip_xy_mm + xy < 2 * R) {
      if (!gouge.any || -dip_dz_mm > gouge.f.worst) {
        gouge_dz_mm = dip_dz_mm;
        gouge_xy_mm = dip_xy_mm;
        gouge_line = dip_line;
      }
      gouge.f.limit = R;
      to(gouge, dip, -dip_dz_mm);
      to(gouge, held, -dip_dz_mm);
      dip_line = 0;
      return;
    }
    to(rough, dip, -1);
    dip_line = 0;
  }
  if (known && d.z() < -R) {
    dip.swap(held);
    dip_dz_mm = d.z();
    dip_xy_mm = xy;
    dip_line = end_line;
    return;
  }
  to(rough, held, -1);
}

void PlausibilityScan::State::add(const Point& p) {
  const std::string id = tool_id(p.tool, s);
  const auto it = tools.tools.find(id);
  if (it == tools.tools.end()) return;
  const stiffness::Tool& t = it->second;
  if (!(p.air || p.plunge)) {
    material = true;
  } else if (!air_points++) {
    first_air_line = p.line;
    first_air_tool = id;
  }
  check_flutes(p, t, id);
  if (!p.air) check_force(p, t, id);
  if (!p.air && !p.plunge) spindle.add(p, id);
  if (!p.air && !p.plunge) stability.add(p, id);
  if (!p.air && !p.plunge) check_cap(p, id);
  // 4. A plunge into material with an end that does not cut at its centre.
  if (p.plunge && !t.centre_cutting && (!p.air || p.stock_depth_mm > 0.01)) {
    centre.add(p.line, std::max(p.ap_mm, p.stock_depth_mm), id);
  }
  // Air over the stock earlier programs cut below this program's surface.
  if (earlier_stock) earlier.add(p, id, s.tolerance_mm, t.diameter_mm);
  // 5. Roughing under a finishing tool. A ball end deeper than its radius (a_p
  // counts no graze, engage::Metrics); not by its cross-section: a raster on a
  // raw blank removes a strip one step-over wide, less than a ball slot R deep
  // would, at every pass but the first. Another end in a full-width slot
  // deeper than D/2 that also removes what such a slot would (D x D/2).
  // Not on a move the gouge check finds cutting into the part: the program
  // gouges there, as that check says, and the stock is not to blame.
  if (p.fixed == interp::Fixed::gouge) return;
  if (t.type == stock::EndShape::ball) check_ball_depth(p, t, id);
  else check_slot(p, t, id);
}

// 1. Above the flutes: the engaged edge reaches their top and the stock stands higher.
void PlausibilityScan::State::check_flutes(const Point& p, const stiffness::Tool& t, const std::string& id) {
  if (!p.air && p.ap_mm >= t.flute_length_mm - s.slice_mm && p.stock_depth_mm > t.flute_length_mm + 0.01) {
    flute.add(p.line, p.stock_depth_mm, id);
    flute.f.limit = t.flute_length_mm;
  }
}

// 2. Peak force over the limit (the worst by its ratio to its tool's limit).
void PlausibilityScan::State::check_force(const Point& p, const stiffness::Tool& t, const std::string& id) {
  auto li = limits.find(id);
  if (li == limits.end()) li = limits.emplace(id, force_limit(t)).first;
  const double lim = li->second.N;
  if (p.peak_N > lim) {
    const bool worse = !force.any || p.peak_N / lim > force.f.worst;
    force.add(p.line, p.peak_N / lim, id);
    if (worse) {
      force_peak = p.peak_N;
      force_lim = lim;
    }
  }
}

// 3. The offset cap bites (by the nominal error; finish() redoes it with the
// capped lines, from the worst |e| per line kept here).
void PlausibilityScan::State::check_cap(const Point& p, const std::string& id) {
  if (s.gain * std::fabs(p.error_mm) > s.max_offset_mm) {
    cap.add(p.line, std::fabs(p.error_mm), id);
    cap.f.limit = s.max_offset_mm;
  }
  last_line = std::max(last_line, p.line);
  if (p.line >= base) {
    const std::size_t k = p.line - base;
    if (k >= line_worst_mm.size()) {
      line_worst_mm.resize(k + 1, -1.0);
      line_tool.resize(k + 1);
    }
    if (std::fabs(p.error_mm) > line_worst_mm[k]) {
      line_worst_mm[k] = std::fabs(p.error_mm);
      line_tool[k] = tool_index(id);
    }
  }
}

// 5. for a ball end: its points deeper than R wait for the end of their motion (judge_held).
void PlausibilityScan::State::check_ball_depth(const Point& p, const stiffness::Tool& t, const std::string& id) {
  const double R = 0.5 * t.diameter_mm;
  if (p.motion != held_motion && !held.empty()) judge_held(false, R);  // a motion without its end
  motion_step(p);
  if (!p.air && p.ap_mm > R + 1e-6) {
    // a_p stops at the top of the flutes: past them the stock tells the depth.
    held_tool = id;
    held.push_back({p.line, p.motion, p.tip_mm,
                    p.ap_mm >= t.flute_length_mm - s.slice_mm ? std::max(p.ap_mm, p.stock_depth_mm) : p.ap_mm});
    rough.f.limit = R;
  }
  if (p.index == p.count) {
    end = p.tip_mm;
    end_line = p.line;
    end_known = true;
    end_motion = p.motion;
    judge_held(true, R);
  }
}

// 5. for other ends: runs of full-width slot points deeper than D/2 (end_run).
void PlausibilityScan::State::check_slot(const Point& p, const stiffness::Tool& t, const std::string& id) {
  const double D = t.diameter_mm;
  const bool slot = !p.air && p.ae_mm >= 0.98 * D && p.ap_mm > 0.5 * D && p.section_mm2 > 0.5 * D * D;
  const RunPoint q{p.line, p.motion, p.tip_mm, p.ap_mm};
  if (slot && (run.empty() || (run_tool == id && run.back().motion + 1 >= p.motion))) {
    if (!run.empty()) run_mm += (p.tip_mm - run.back().tip_mm).norm();
    run.push_back(q);
    run_tool = id;
    rough.f.limit = std::max(rough.f.limit, 0.5 * D);
  } else {
    end_run();
    if (slot) {
      run.push_back(q);
      run_tool = id;
    }
  }
}

PlausibilityScan::PlausibilityScan(const stiffness::ToolLibrary& tools, const Settings& s, bool earlier_stock,
                                   const profile::SpindleRating* spindle)
    : st_(std::make_unique<State>(tools, s, earlier_stock, spindle)) {}
PlausibilityScan::~PlausibilityScan() = default;
void PlausibilityScan::add(const Point& p) { st_->add(p); }
void PlausibilityScan::capped(const std::vector<std::uint32_t>& lines) {
  st_->pending.insert(st_->pending.end(), lines.begin(), lines.end());
  st_->fold(false);
}

namespace detail {

// "N points on M lines (l1, l2, ...)": the end of every finding's message.
std::string lines_text(const Finding& f) {
  std::string l;
  for (std::size_t i = 0; i < f.lines.size(); ++i) l += (i ? ", " : "") + std::to_string(f.lines[i]);
  if (f.line_count > f.lines.size()) l += ", ...";
  return plural(f.count, "point") + " on " + plural(f.line_count, "line") + " (" + l + ")";
}

void emit(Plausibility& out, Acc& a, const std::string& msg) {
  a.f.line_count = a.seen.size();
  a.f.message = msg + "; " + lines_text(a.f);
  out.findings.push_back(a.f);
}

}  // namespace detail

using detail::emit;
using detail::lines_text;

namespace {

void flute_finding(Plausibility& out, Acc& flute, const stiffness::ToolLibrary& tools) {
  const auto& t = tools.tools.at(flute.f.tool);
  flute.f.limit = t.flute_length_mm;
  emit(out, flute, "the cut reaches " + fixed_decimals(flute.f.worst, 2) + " mm above the tip of " + flute.f.tool +
                       ", whose flutes are " + fixed_decimals(t.flute_length_mm, 2) + " mm long: the " +
                       (t.neck ? "neck" : "shank") + " is in the cut and rubs");
}

// The worst point by its ratio to its tool's limit, told in newtons.
void force_finding(Plausibility& out, Acc& force, double peak_N, double limit_N, const stiffness::ToolLibrary& tools) {
  force.f.worst = peak_N;
  force.f.limit = limit_N;
  const auto& t = tools.tools.at(force.f.tool);
  const ForceLimit fl = force_limit(t);
  const std::string why = t.max_force_N ? std::string("its max_force_N")
                                        : "bending at " + fl.where + ", " + t.material.name + " " +
                                              fixed_decimals(t.material.allowable_bending_MPa, 0) +
                                              " MPa allowable; set max_force_N to override";
  emit(out, force, "predicted peak cutting force " + fixed_decimals(force.f.worst, 0) + " N exceeds the limit " +
                       fixed_decimals(force.f.limit, 0) + " N of " + force.f.tool + " (" + why + "): the tool may break");
}

void cap_finding(Plausibility& out, Acc& cap, const Settings& s, bool compensated) {
  const std::string limit = "the offset cap max_offset_mm = " + fixed_decimals(s.max_offset_mm, 4) + " mm";
  // On a compensated line the error as programmed may lie under the cap
  // while the offset needed does not: moving the tool into the material
  // deepens the cut and the deflection grows with it.
  const std::string what =
      cap.f.worst > s.max_offset_mm
          ? "the deflection along the surface normal reaches " + fixed_decimals(cap.f.worst, 4) + " mm, over " + limit
          : "the offset these points need exceeds " + limit + " (their deflection along the normal, " +
                fixed_decimals(cap.f.worst, 4) + " mm as programmed, grows as the offset deepens the cut)";
  emit(out, cap, what + (compensated ? ": these points are compensated only up to the cap"
                                     : ": compensate would correct these points only up to the cap"));
}

void rough_finding(Plausibility& out, Acc& rough, const stiffness::ToolLibrary& tools) {
  const auto& t = tools.tools.at(rough.f.tool);
  const bool ball = t.type == stock::EndShape::ball;
  rough.f.limit = 0.5 * t.diameter_mm;
  emit(out, rough, std::string("a_p up to ") + fixed_decimals(rough.f.worst, 2) + " mm under " + rough.f.tool + " (" +
                       (ball ? "a ball end of radius " + fixed_decimals(rough.f.limit, 2) + " mm"
                             : "a full-width slot deeper than D/2 = " + fixed_decimals(rough.f.limit, 2) + " mm") +
                       "): the stock looks like a raw blank that needs roughing first");
}

// The worst dip: its drop `dz_mm` (< 0) over `xy_mm` across at `line`.
void gouge_finding(Plausibility& out, Acc& g, double dz_mm, double xy_mm, std::uint32_t line) {
  g.f.line = line;
  emit(out, g, "the program plunges " + fixed_decimals(-dz_mm, 2) + " mm in one " + fixed_decimals(xy_mm, 2) + " mm step at line " +
                   std::to_string(line) + " and climbs back at once under " + g.f.tool + " (a ball end of radius " +
                   fixed_decimals(g.f.limit, 2) + " mm, which fits no hole that deep and narrow): a gouge in the CAM program?");
}

void earlier_finding(Plausibility& out, const AirRuns& e, const Settings& s) {
  Finding f;
  f.kind = "earlier_cut";
  f.count = e.points;
  f.worst = e.gap_mm;
  f.limit = s.tolerance_mm;
  f.line = e.first_line;
  f.tool = e.tool;
  f.lines = e.lines;
  f.line_count = e.line_count;
  const double share = 100.0 * static_cast<double>(e.points) / static_cast<double>(e.cutting);
  f.message = fixed_decimals(share, 0) + "% of the cutting points (" + std::to_string(e.points) + " of " +
              std::to_string(e.cutting) + ") run in air from here, the stock the earlier programs ({stock_from}) left up to " +
              fixed_decimals(e.gap_mm, 3) + " mm below the tool: they cut below this program's surface there, and those points are "
              "neither compensated nor in the predicted error; " + lines_text(f);
  out.findings.push_back(f);
}

void no_material_finding(Plausibility& out, std::size_t air_points, std::uint32_t first_line, const std::string& tool) {
  Finding f;
  f.kind = "no_material";
  f.count = air_points;
  f.line = first_line;
  f.tool = tool;
  f.message = "none of the " + std::to_string(f.count) +
              " cutting points is in the stock: each cuts air or plunges, so nothing is compensated and the "
              "error figures say nothing; check {stock} (and {stock_from})";
  out.findings.push_back(f);
}

}  // namespace

Plausibility PlausibilityScan::finish(bool compensated) {
  State& z = *st_;
  z.end_run();
  z.judge_held(false, 0);
  z.judge_held(false, 0);  // a drop left waiting
  z.earlier.end();
  z.fold(true);
  Acc cap = compensated ? z.capped : z.cap;
  cap.f.kind = "offset_cap";
  if (compensated) cap.f.limit = z.s.max_offset_mm;
  Plausibility out;
  if (z.flute.any) flute_finding(out, z.flute, z.tools);
  if (z.force.any) force_finding(out, z.force, z.force_peak, z.force_lim, z.tools);
  if (cap.any) cap_finding(out, cap, z.s, compensated);
  if (z.centre.any)
    emit(out, z.centre, "plunge into the material with " + z.centre.f.tool +
                            ", which does not cut at its centre (centre_cutting: false): ramp or helix in, or pre-drill");
  if (z.rough.any) rough_finding(out, z.rough, z.tools);
  if (z.gouge.any) gouge_finding(out, z.gouge, z.gouge_dz_mm, z.gouge_xy_mm, z.gouge_line);
  if (z.earlier.points) earlier_finding(out, z.earlier, z.s);
  spindle_findings(out, z.spindle);
  stability_findings(out, z.stability);
  if (!z.material && z.air_points) no_material_finding(out, z.air_points, z.first_air_line, z.first_air_tool);
  return out;
}

Plausibility plausibility(const std::vector<Point>& points, const stiffness::ToolLibrary& tools, const Settings& s,
                          const std::vector<std::uint32_t>* capped_lines, bool earlier_stock,
                          const profile::SpindleRating* spindle) {
  PlausibilityScan scan(tools, s, earlier_stock, spindle);
  for (const Point& p : points) scan.add(p);
  if (capped_lines) scan.capped(*capped_lines);
  return scan.finish(capped_lines != nullptr);
}

}  // namespace deflex::compensate
