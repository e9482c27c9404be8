// The plausibility checks of what the machine gives the cut: the spindle's
// power and torque against its rating, and the stability limit (chatter)
// (plausibility_parts.hpp).
#include <string>

#include "deflex/diag/plural.hpp"
#include "internal.hpp"
#include "plausibility_parts.hpp"

namespace deflex::compensate::detail {

void SpindleChecks::add(const Point& p, const std::string& id) {
  if (feed_limit_N > 0 && p.feed_share < detail::min_feed_share) floor.add(p.line, p.feed_share, id);
  if (!rating || !(p.spindle_rpm > 0)) return;
  if (p.spindle_rpm > rating->max_rpm) {
    speed.add(p.line, p.spindle_rpm, id);
    speed.f.limit = rating->max_rpm;
  }
  const double ratio = p.torque_Nm / rating->s1.allowed_torque_Nm(p.spindle_rpm);
  if (!(ratio > 1)) return;
  const bool worse = !load.any || ratio > load.f.worst;
  load.add(p.line, ratio, id);
  if (!worse) return;
  power_kW = p.power_kW;
  torque_Nm = p.torque_Nm;
  rpm = p.spindle_rpm;
  s6_worst = rating->s6 ? p.torque_Nm / rating->s6->allowed_torque_Nm(p.spindle_rpm) : 0;
}

// Chatter: how far over the limit, where, and how to find a stable speed.
void stability_findings(Plausibility& out, StabilityChecks& c) {
  if (c.chatter.any) {
    c.chatter.f.limit = 1;
    emit(out, c.chatter, "the cut is " + fixed_decimals(c.ap_mm, 2) + " mm deep (a_p) at " + fixed_decimals(c.rpm, 0) +
                             " rpm where the stability limit of " + c.chatter.f.tool + " is " +
                             fixed_decimals(c.limit_mm, 2) + " mm (zero-order lobes of its tip's modes): it chatters, "
                             "and a chattering cut leaves marks no compensation removes; take a smaller depth or move S "
                             "to a stable pocket (`deflex stability --tool " + c.chatter.f.tool + " --ae " +
                             fixed_decimals(c.ae_mm, 2) + " --ap " + fixed_decimals(c.ap_mm, 2) +
                             "` with the run's machine and material draws its lobes)");
  }
  for (const auto& [id, line] : c.unmodelled) {
    Finding f;
    f.kind = "stability_unchecked";
    f.tool = id;
    f.line = line;
    f.lines = {line};
    f.line_count = 1;
    f.message = "the stability limit (chatter) of " + id + " is not checked: its material or its holder's has no "
                "density_kg_per_m3, which the tip's modes need (add it to the {E_MPa, poisson} material of the tool library or "
                "of the machine profile's holder)";
    out.findings.push_back(f);
  }
}

// The spindle's findings: how much and how often the cut asks more than the
// S1 rating gives, S above the spindle's top speed, and the points the feed
// limit cannot bring within its limits.
void spindle_findings(Plausibility& out, SpindleChecks& c) {
  if (c.load.any) {
    const profile::SpindleRating& r = *c.rating;
    c.load.f.limit = 1;
    std::string s6;
    if (r.s6)
      s6 = c.s6_worst > 1 ? "; above its S6 rating too (" + fixed_decimals(r.s6->allowed_power_kW(c.rpm), 1) + " kW)"
                          : "; within its S6 rating (" + fixed_decimals(r.s6->allowed_power_kW(c.rpm), 1) +
                                " kW), which it gives only for short spells";
    const std::string remedy = c.feed_limit_N > 0 ? "{feed_limit_N} lowers the feed of these blocks to keep within it"
                                                  : "lower the feed or the depth of cut ({feed_limit_N} keeps the feed within it)";
    emit(out, c.load, "the cut asks the spindle for up to " + fixed_decimals(c.power_kW, 2) + " kW and " +
                          fixed_decimals(c.torque_Nm, 1) + " N m at " + fixed_decimals(c.rpm, 0) + " rpm, " +
                          fixed_decimals(100 * (c.load.f.worst - 1), 0) + " % over its continuous (S1) rating there, " +
                          fixed_decimals(r.s1.allowed_power_kW(c.rpm), 2) + " kW and " +
                          fixed_decimals(r.s1.allowed_torque_Nm(c.rpm), 1) + " N m" + (r.source.empty() ? "" : " (" + r.source + ")") +
                          s6 + ": the spindle slows or overheats; " + remedy);
  }
  if (c.speed.any)
    emit(out, c.speed, "S" + fixed_decimals(c.speed.f.worst, 0) + " is above the spindle's top speed, max_rpm " +
                           fixed_decimals(c.speed.f.limit, 0) + ": the control clamps or refuses it, and the cut runs at another speed than simulated");
  if (c.floor.any) {
    c.floor.f.limit = detail::min_feed_share;
    emit(out, c.floor, "even at a tenth of the feed the peak force or the torque stays above the limits of {feed_limit_N} (the edge forces, "
                       "which do not shrink with the feed, reach them alone): the feed of these blocks is lowered tenfold, the most "
                       "deflex lowers it, and the limit is still exceeded; take a smaller depth or width of cut");
  }
}

}  // namespace deflex::compensate::detail
