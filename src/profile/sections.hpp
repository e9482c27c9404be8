// Readers of the sections of a machine profile and of a dialect from their YAML
// nodes, shared by the .cpp files of deflex::profile.
#pragma once
#include <string>

#include "deflex/profile/axis_limits.hpp"
#include "deflex/profile/profile.hpp"
#include "deflex/profile/spindle.hpp"
#include "deflex/profile/yaml.hpp"

namespace deflex::profile {

// Reads the `axis_limits:` section (the node of that key). Throws
// Error(ErrorKind::config, "file:line:col: error: ...") on an unknown key, a
// missing axis, a value that is not a finite number > 0.
AxisLimits parse_axis_limits(const YAML::Node& section, const std::string& file);

// Reads the `spindle:` section (profile/spindle.hpp), the same way.
SpindleRating parse_spindle(const YAML::Node& section, const std::string& file);

Dialect parse_dialect(const YAML::Node& node, const std::string& file);

}  // namespace deflex::profile
