// The lower envelope of the lobes as a table over speed (lobes.hpp).
#include <algorithm>
#include <cmath>
#include <limits>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/stability/lobes.hpp"

namespace deflex::stability {
namespace {

// Lowers table[j] to the segment p-q at every table speed the segment spans.
void lower_to_segment(std::vector<double>& table, double rpm_min, double step, const LobePoint& p,
                      const LobePoint& q) {
  const double lo = std::min(p.rpm, q.rpm), hi = std::max(p.rpm, q.rpm);
  const auto last = static_cast<double>(table.size() - 1);
  const double j0 = std::max(0.0, std::ceil((lo - rpm_min) / step)), j1 = std::min(last, std::floor((hi - rpm_min) / step));
  for (double j = j0; j <= j1; ++j) {
    const double rpm = rpm_min + j * step;
    const double t = hi > lo ? (rpm - p.rpm) / (q.rpm - p.rpm) : 0;
    double& a = table[static_cast<std::size_t>(j)];
    a = std::min(a, p.ap_limit_mm + t * (q.ap_limit_mm - p.ap_limit_mm));
  }
}

}  // namespace

StabilityLimit::StabilityLimit(const Lobes& lobes, double rpm_min, double rpm_max, int steps)
    : rpm_min_(rpm_min), rpm_max_(rpm_max), ap_min_mm_(lobes.ap_min_mm) {
  if (!(rpm_min > 0 && rpm_max > rpm_min) || !std::isfinite(rpm_max) || steps < 1 || steps > 10'000'000)
    throw Error(ErrorKind::settings, "a stability table needs 0 < rpm_min < rpm_max and 1 to 10^7 steps");
  step_rpm_ = (rpm_max - rpm_min) / steps;
  ap_mm_.assign(static_cast<std::size_t>(steps) + 1, std::numeric_limits<double>::infinity());
  for (const Lobe& l : lobes.lobes)
    for (std::size_t i = 1; i < l.points.size(); ++i) lower_to_segment(ap_mm_, rpm_min, step_rpm_, l.points[i - 1], l.points[i]);
  for (double& a : ap_mm_) a = std::isfinite(a) ? a : ap_min_mm_;
}

double StabilityLimit::ap_limit_mm(double rpm) const {
  if (!(rpm >= rpm_min_ && rpm <= rpm_max_)) return ap_min_mm_;
  const double x = (rpm - rpm_min_) / step_rpm_;
  const auto j = std::min(static_cast<std::size_t>(x), ap_mm_.size() - 2);
  const double t = x - static_cast<double>(j);
  return (1 - t) * ap_mm_[j] + t * ap_mm_[j + 1];
}

}  // namespace deflex::stability
