#include "deflex/force/tool.hpp"

namespace deflex::force {

Cutter cutter_of(const stiffness::Tool& t) {
  Cutter c;
  c.type = t.type;
  c.diameter_mm = t.diameter_mm;
  c.corner_radius_mm = c.type == stock::EndShape::bull ? t.corner_radius_mm : 0.0;
  c.flutes = t.flutes;
  c.helix_deg = t.helix_deg;
  c.flute_length_mm = t.flute_length_mm;
  validate(c);
  return c;
}

}  // namespace deflex::force
