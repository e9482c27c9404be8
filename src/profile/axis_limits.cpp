#include "deflex/profile/axis_limits.hpp"

#include "sections.hpp"

namespace deflex::profile {

namespace {

using yaml::Map;
using yaml::Range;

// {x: .., y: .., z: ..} (all three) or one number for every axis; each > 0.
// A zero limit would make a move along that axis take forever: the profile
// is wrong, not the program.
std::array<double, 3> per_axis(const Map& s, const char* key) {
  const YAML::Node n = s.get(key);
  const std::string what = s.name() + "." + key;
  if (n.IsScalar()) {
    const double v = yaml::number(n, what, s.file(), Range::positive());
    return {v, v, v};
  }
  if (!n.IsMap()) s.fail(n, what + " must be {x: .., y: .., z: ..} or one number for all axes");
  const Map m(n, what, s.file(), {"x", "y", "z"});
  std::array<double, 3> v{};
  const char* axes[] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i) v[i] = yaml::number(m.get(axes[i]), what + "." + axes[i], s.file(), Range::positive());
  return v;
}

}  // namespace

AxisLimits parse_axis_limits(const YAML::Node& section, const std::string& file) {
  const Map s(section, "axis_limits", file,
              {"max_feed_mm_per_min", "rapid_mm_per_min", "acceleration_mm_per_s2", "corner_tolerance_mm"});
  AxisLimits a;
  a.set = true;
  if (s.has("max_feed_mm_per_min")) a.max_feed_mm_per_min = per_axis(s, "max_feed_mm_per_min");
  if (s.has("rapid_mm_per_min")) a.rapid_mm_per_min = per_axis(s, "rapid_mm_per_min");
  if (s.has("acceleration_mm_per_s2")) a.acceleration_mm_per_s2 = per_axis(s, "acceleration_mm_per_s2");
  // > 0: a zero tolerance is exact stop at every corner, which a control does
  // with G61, not with a profile setting; it would also make every corner of a
  // finely segmented curve a full stop.
  a.corner_tolerance_mm = s.number("corner_tolerance_mm", a.corner_tolerance_mm, Range::positive());
  return a;
}

}  // namespace deflex::profile
