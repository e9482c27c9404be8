// detail::read_observations() (internal.hpp): the measure module's forms as
// the fit's observations.
#include "deflex/measure/measured.hpp"
#include "internal.hpp"

namespace deflex::job::detail {

std::vector<fit::Observation> read_observations(const Settings& s) {
  if (!(s.measured_reach_mm > 0 && s.measured_reach_mm <= 10))
    throw Error(ErrorKind::settings, "{measured_reach_mm} must be above 0 and at most 10 mm");
  const measure::Measured m = measure::read_measured(s.measured, s.probe_program);
  std::vector<fit::Observation> obs;
  for (const measure::Sample& p : m.samples)
    obs.push_back({p.p_mm, p.p_mm, std::nullopt, "", s.measured + (p.line ? ":" + std::to_string(p.line) : "")});
  // A probe log: the intended point finds the prediction, the error is the log's.
  for (const measure::MeasuredPoint& p : m.points)
    obs.push_back({p.intended_mm, p.surface_mm, p.error_mm, p.feature, s.measured + ":" + std::to_string(p.line)});
  return obs;
}

}  // namespace deflex::job::detail
