// fit::match() (observe.hpp).
#include "deflex/fit/observe.hpp"

namespace deflex::fit {

Matching match(const Surface& surface, const std::vector<Observation>& obs, double reach_mm,
               const part::PartModel* part) {
  Matching m;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const Observation& o = obs[i];
    const long s = surface.nearest(o.at_mm, reach_mm);
    if (s < 0) {
      m.unmatched.push_back(i);
      continue;
    }
    const SurfaceSample& smp = surface.samples()[static_cast<std::size_t>(s)];
    double e = 0;
    if (o.error_mm) {
      e = *o.error_mm;
    } else if (part) {
      const part::Contact c = part->closest(o.at_mm);
      e = (o.at_mm - c.point_mm).dot(c.normal);
    } else {
      e = (o.at_mm - smp.at_mm).dot(smp.normal);
    }
    m.matched.push_back({i, static_cast<std::size_t>(s), e});
  }
  return m;
}

}  // namespace deflex::fit
