// The parts of the plausibility scan (plausibility.hpp) kept apart from
// plausibility.cpp: a finding's accumulator and message, and the checks of
// what the machine gives the cut - the spindle's rating and the stability
// limit (machine_checks.cpp).
#pragma once
#include <cstdint>
#include <map>
#include <set>
#include <string>

#include "deflex/compensate/plausibility.hpp"
#include "deflex/profile/spindle.hpp"

namespace deflex::compensate::detail {

// One finding as its points come: the worst value, its line and tool, the
// first 12 distinct lines.
struct Acc {
  Finding f;
  std::set<std::uint32_t> seen;
  bool any = false;
  void add(std::uint32_t line, double value, const std::string& tool) {
    ++f.count;
    if (!any || value > f.worst) {
      f.worst = value;
      f.line = line;
      f.tool = tool;
    }
    any = true;
    if (seen.insert(line).second && f.lines.size() < 12) f.lines.push_back(line);
  }
};


// "N points on M lines (l1, l2, ...)": the end of every finding's message.
std::string lines_text(const Finding& f);
// The finding with its message (and the lines' text) added to out.
void emit(Plausibility& out, Acc& a, const std::string& msg);

// The spindle's load against its rating: the worst point by torque over the
// S1 curve's allowance at its speed (power over the power curve is the same
// ratio: P = M w), with its figures for the message; S above max_rpm; and,
// with a feed limit, the points no feed keeps within it.
struct SpindleChecks {
  const profile::SpindleRating* rating = nullptr;  // null: none in the profile
  double feed_limit_N = 0;
  Acc load, speed, floor;
  double power_kW = 0, torque_Nm = 0, rpm = 0;  // the worst load's point
  double s6_worst = 0;                           // its load over the S6 curve
  SpindleChecks(const profile::SpindleRating* r, double limit_N) : rating(r && r->set ? r : nullptr), feed_limit_N(limit_N) {
    load.f.kind = "spindle_load";
    speed.f.kind = "spindle_speed";
    floor.f.kind = "feed_limit";
  }
  void add(const Point& p, const std::string& id);
};

// Chatter: the axial depth of cut over the zero-order stability limit at the
// point's immersion and speed (Point::ap_limit_mm), the worst by that ratio
// with its figures; and the tools whose limit is not known.
struct StabilityChecks {
  Acc chatter;
  double ap_mm = 0, limit_mm = 0, rpm = 0, ae_mm = 0;  // the worst point's
  std::map<std::string, std::uint32_t> unmodelled;  // tool -> its first cutting line
  StabilityChecks() { chatter.f.kind = "chatter"; }
  void add(const Point& p, const std::string& id) {
    if (p.ap_limit_mm < 0) unmodelled.try_emplace(id, p.line);
    if (!(p.ap_limit_mm > 0)) return;
    const double ratio = p.ap_mm / p.ap_limit_mm;
    if (!(ratio > 1)) return;
    const bool worse = !chatter.any || ratio > chatter.f.worst;
    chatter.add(p.line, ratio, id);
    if (!worse) return;
    ap_mm = p.ap_mm, limit_mm = p.ap_limit_mm, rpm = p.spindle_rpm, ae_mm = p.ae_mm;
  }
};

void spindle_findings(Plausibility& out, SpindleChecks& c);
void stability_findings(Plausibility& out, StabilityChecks& c);

}  // namespace deflex::compensate::detail
