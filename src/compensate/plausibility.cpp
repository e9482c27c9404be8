#include "deflex/compensate/plausibility.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <limits>
#include <map>
#include <set>

namespace deflex::compensate {

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

std::string num(double v, int prec) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", prec, v);
  return b;
}

struct Acc {
  Finding f;
  std::set<std::uint32_t> seen;
  bool any = false;
  void add(const Point& p, double value, const std::string& tool) {
    ++f.count;
    if (!any || value > f.worst) {
      f.worst = value;
      f.line = p.line;
      f.tool = tool;
    }
    any = true;
    if (seen.insert(p.line).second && f.lines.size() < 12) f.lines.push_back(p.line);
  }
};

}  // namespace

Plausibility plausibility(const std::vector<interp::Motion>& motions, const std::vector<Point>& points,
                          const stiffness::ToolLibrary& tools, const Settings& s,
                          const std::vector<std::uint32_t>* capped_lines) {
  const std::set<std::uint32_t> capped =
      capped_lines ? std::set<std::uint32_t>(capped_lines->begin(), capped_lines->end()) : std::set<std::uint32_t>{};
  Acc flute, force, cap, centre, rough;
  flute.f.kind = "flute_length";
  force.f.kind = "peak_force";
  cap.f.kind = "offset_cap";
  centre.f.kind = "centre_cutting";
  rough.f.kind = "roughing";
  std::map<std::string, ForceLimit> limits;
  double force_peak = 0, force_lim = 0;  // peak_force: the worst by F / limit
  // Full-width deep slot runs (flat and bull ends): points and path length.
  std::vector<const Point*> run;
  double run_mm = 0;
  std::string run_tool;
  auto end_run = [&] {
    if (run_mm > 1.0)
      for (const Point* q : run) rough.add(*q, q->ap_mm, run_tool);
    run.clear();
    run_mm = 0;
  };
  for (const Point& p : points) {
    if (p.motion >= motions.size()) continue;
    const std::string id = tool_id(motions[p.motion], s);
    const auto it = tools.tools.find(id);
    if (it == tools.tools.end()) continue;
    const stiffness::Tool& t = it->second;
    const double D = t.diameter_mm, R = 0.5 * D;
    // 1. Above the flutes: the engaged edge reaches their top and the stock stands higher.
    if (!p.air && p.ap_mm >= t.flute_length_mm - s.slice_mm && p.stock_depth_mm > t.flute_length_mm + 0.01) {
      flute.add(p, p.stock_depth_mm, id);
      flute.f.limit = t.flute_length_mm;
    }
    // 2. Peak force over the limit (the worst by its ratio to its tool's limit).
    if (!p.air) {
      auto li = limits.find(id);
      if (li == limits.end()) li = limits.emplace(id, force_limit(t)).first;
      const double lim = li->second.N;
      if (p.peak_N > lim) {
        const bool worse = !force.any || p.peak_N / lim > force.f.worst;
        force.add(p, p.peak_N / lim, id);
        if (worse) {
          force_peak = p.peak_N;
          force_lim = lim;
        }
      }
    }
    // 3. The offset cap bites.
    if (!p.air && !p.plunge && (capped_lines ? capped.count(p.line) > 0 : s.gain * std::fabs(p.error_mm) > s.max_offset_mm)) {
      cap.add(p, std::fabs(p.error_mm), id);
      cap.f.limit = s.max_offset_mm;
    }
    // 4. A plunge into material with an end that does not cut at its centre.
    if (p.plunge && !t.centre_cutting && (!p.air || p.stock_depth_mm > 0.01)) {
      centre.add(p, std::max(p.ap_mm, p.stock_depth_mm), id);
    }
    // 5. Roughing under a finishing tool.
    if (t.type == stiffness::ToolType::ball) {
      if (!p.air && p.ap_mm > R + 1e-6) {
        // a_p stops at the top of the flutes: past them the stock tells the depth.
        rough.add(p, p.ap_mm >= t.flute_length_mm - s.slice_mm ? std::max(p.ap_mm, p.stock_depth_mm) : p.ap_mm, id);
        rough.f.limit = R;
      }
    } else {
      const bool slot = !p.air && p.ae_mm >= 0.98 * D && p.ap_mm > 0.5 * D;
      if (slot && (run.empty() || (run_tool == id && run.back()->motion + 1 >= p.motion))) {
        if (!run.empty()) run_mm += (p.tip_mm - run.back()->tip_mm).norm();
        run.push_back(&p);
        run_tool = id;
        rough.f.limit = std::max(rough.f.limit, 0.5 * D);
      } else {
        end_run();
        if (slot) {
          run.push_back(&p);
          run_tool = id;
        }
      }
    }
  }
  end_run();

  Plausibility out;
  auto lines_text = [](const Finding& f) {
    std::string l;
    for (std::size_t i = 0; i < f.lines.size(); ++i) l += (i ? ", " : "") + std::to_string(f.lines[i]);
    if (f.line_count > f.lines.size()) l += ", ...";
    return std::to_string(f.count) + " points on " + std::to_string(f.line_count) + " lines (" + l + ")";
  };
  auto emit = [&](Acc& a, const std::string& msg) {
    a.f.line_count = a.seen.size();
    a.f.message = msg + "; " + lines_text(a.f);
    out.findings.push_back(a.f);
  };
  if (flute.any) {
    const auto& t = tools.tools.at(flute.f.tool);
    flute.f.limit = t.flute_length_mm;
    emit(flute, "the cut reaches " + num(flute.f.worst, 2) + " mm above the tip of " + flute.f.tool +
                    ", whose flutes are " + num(t.flute_length_mm, 2) + " mm long: the " +
                    (t.neck ? "neck" : "shank") + " is in the cut and rubs");
  }
  if (force.any) {
    force.f.worst = force_peak;
    force.f.limit = force_lim;
    const auto& t = tools.tools.at(force.f.tool);
    const ForceLimit fl = force_limit(t);
    const std::string why = t.max_force_N ? std::string("its max_force_N")
                                          : "bending at " + fl.where + ", " + t.material.name + " " +
                                                num(t.material.allowable_bending_MPa, 0) +
                                                " MPa allowable; set max_force_N to override";
    emit(force, "predicted peak cutting force " + num(force.f.worst, 0) + " N exceeds the limit " +
                    num(force.f.limit, 0) + " N of " + force.f.tool + " (" + why + "): the tool may break");
  }
  if (cap.any && capped_lines) {
    // The cap bit at the motion ends: count those, the lines in program order.
    cap.f.count = capped_lines->size();
    cap.f.lines.clear();
    std::set<std::uint32_t> seen;
    for (std::uint32_t l : *capped_lines)
      if (seen.insert(l).second && cap.f.lines.size() < 12) cap.f.lines.push_back(l);
    cap.seen = seen;
  }
  if (cap.any)
    emit(cap, "the deflection along the surface normal reaches " + num(cap.f.worst, 4) +
                  " mm, over the offset cap max_offset_mm = " + num(s.max_offset_mm, 4) +
                  " mm: these points are compensated only up to the cap");
  if (centre.any)
    emit(centre, "plunge into the material with " + centre.f.tool +
                     ", which does not cut at its centre (centre_cutting: false): ramp or helix in, or pre-drill");
  if (rough.any) {
    const auto& t = tools.tools.at(rough.f.tool);
    const bool ball = t.type == stiffness::ToolType::ball;
    rough.f.limit = 0.5 * t.diameter_mm;
    emit(rough, std::string("a_p up to ") + num(rough.f.worst, 2) + " mm under " + rough.f.tool + " (" +
                    (ball ? "a ball end of radius " + num(rough.f.limit, 2) + " mm"
                          : "a full-width slot deeper than D/2 = " + num(rough.f.limit, 2) + " mm") +
                    "): the stock looks like a raw blank that needs roughing first");
  }
  return out;
}

}  // namespace deflex::compensate
