#include "deflex/force/tool_reader.hpp"

#include <cmath>

#include "deflex/diag/diagnostics.hpp"
#include "yaml_util.hpp"

namespace deflex::force {

Cutter parse_cutter(const std::string& yaml_text, const std::string& file, const std::string& id) {
  const YAML::Node root = yaml::load_text(yaml_text, file);
  if (!root.IsMap() || !root["tools"]) yaml::fail(file, root.Mark(), "expected a map with a 'tools:' key");
  const YAML::Node tools = root["tools"];
  yaml::require_map(tools, "tools", file);
  const YAML::Node t = tools[id];
  if (!t) {
    std::string known;
    for (const auto& kv : tools) known += (known.empty() ? "" : ", ") + kv.first.Scalar();
    throw Error(Exit::usage, "unknown tool '" + id + "' in " + file + " (known: " + known + ")");
  }
  yaml::require_map(t, "tool '" + id + "'", file);

  Cutter c;
  const std::string type = yaml::text_at(t, "type", file);
  if (type == "flat" || type == "square") c.type = CutterType::flat;
  else if (type == "ball" || type == "ball_nose") c.type = CutterType::ball;
  else if (type == "bull" || type == "bull_nose" || type == "bullnose" || type == "torus")
    c.type = CutterType::bull;
  else
    yaml::fail(file, t["type"].Mark(), "unknown tool type '" + type + "' (expected ball, flat or bull)");

  c.diameter_mm = yaml::number_at(t, "diameter_mm", file);
  const double zero = 0, helix = 30;
  c.corner_radius_mm = yaml::number_at(t, "corner_radius_mm", file, &zero);
  const YAML::Node fl = t["flutes"];
  if (!fl) yaml::fail(file, t.Mark(), "missing key 'flutes'");
  const double nf = yaml::number(fl, "flutes", file);
  if (nf != std::floor(nf) || nf < 1) yaml::fail(file, fl.Mark(), "flutes must be a whole number >= 1");
  c.flutes = static_cast<int>(nf);
  c.helix_deg = yaml::number_at(t, "helix_deg", file, &helix);
  const double two_d = 2 * c.diameter_mm;
  c.flute_length_mm = yaml::number_at(t, "flute_length_mm", file, &two_d);
  try {
    validate(c);
  } catch (const Error& e) {
    yaml::fail(file, t.Mark(), "tool '" + id + "': " + e.what());
  }
  return c;
}

Cutter read_cutter(const std::string& path, const std::string& id) {
  return parse_cutter(yaml::read_file(path), path, id);
}

}  // namespace deflex::force
