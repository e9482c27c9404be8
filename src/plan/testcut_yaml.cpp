// The test cut's plan as YAML (plan/testcut.hpp): written for the user to
// read and for `deflex probe` to read back, through the project's strict
// reader (profile/yaml.hpp: every error located, every unknown key refused).
#include <cmath>
#include <ostream>
#include <tuple>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/diag/plural.hpp"
#include "deflex/plan/testcut.hpp"
#include "deflex/profile/yaml.hpp"

namespace deflex::plan {
namespace {

const char* shape_name(stock::EndShape s) {
  return s == stock::EndShape::ball ? "ball" : s == stock::EndShape::bull ? "bull" : "flat";
}

// A number as YAML: fixed decimals, no negative zero.
std::string yn(double v, int decimals = 3) {
  std::string s = fixed_decimals(v, decimals);
  if (s.starts_with('-') && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
  return s;
}
std::string seq(const Vec3& v, int decimals = 3) { return "[" + yn(v[0], decimals) + ", " + yn(v[1], decimals) + ", " + yn(v[2], decimals) + "]"; }
// A string as a YAML double-quoted scalar (a path may hold ':' or '#').
std::string quoted(const std::string& v) {
  std::string q = "\"";
  for (char c : v) q += c == '"' || c == '\\' ? std::string("\\") + c : std::string(1, c);
  return q + "\"";
}
std::string pair(double a, double b) { return "[" + yn(a) + ", " + yn(b) + "]"; }

// A flow sequence of `n` numbers under `key`.
std::vector<double> numbers(const yaml::Map& m, const char* key, std::size_t n) {
  const YAML::Node s = m.get(key);
  if (!s.IsSequence() || s.size() != n)
    m.fail(s, m.name() + "." + key + " must be a list of " + std::to_string(n) + " numbers");
  std::vector<double> v;
  for (std::size_t i = 0; i < n; ++i) v.push_back(yaml::number(s[i], m.name() + "." + key, m.file()));
  return v;
}
Vec3 vec3(const yaml::Map& m, const char* key) {
  const std::vector<double> v = numbers(m, key, 3);
  return {v[0], v[1], v[2]};
}
// [lo, hi] with lo < hi.
std::pair<double, double> range(const yaml::Map& m, const char* key) {
  const std::vector<double> v = numbers(m, key, 2);
  if (!(v[0] < v[1])) m.fail(m.get(key), m.name() + "." + key + " must be [low, high] with low < high");
  return {v[0], v[1]};
}
Vec3 unit(const yaml::Map& m, const char* key) {
  const Vec3 v = vec3(m, key);
  if (std::abs(std::hypot(v[0], v[1], v[2]) - 1) > 1e-3) m.fail(m.get(key), m.name() + "." + key + " must be a unit vector");
  return v;
}

bool valid_id(const std::string& id) {
  return !id.empty() && id.size() <= 16 && id.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_") == std::string::npos;
}

WallFeature read_feature(const YAML::Node& n, const std::string& name, const std::string& file, const TestBlock& b) {
  const yaml::Map m(n, name, file,
                    {"id", "kind", "feed_direction", "point_mm", "normal", "u_mm", "z_mm", "ae_mm", "ap_mm", "fz_mm", "mode",
                     "morelli", "lines"});
  WallFeature f;
  f.id = m.text("id");
  if (!valid_id(f.id)) m.fail("id", name + ".id must be uppercase letters, digits and underscores (at most 16), not '" + f.id + "'");
  if (m.text("kind") != "wall") m.fail("kind", name + ".kind must be wall (the only kind of feature so far)");
  if (m.text("mode") != "down") m.fail("mode", name + ".mode must be down (the test cut only mills down)");
  f.feed_direction = unit(m, "feed_direction");
  f.normal = unit(m, "normal");
  const double dot = f.feed_direction[0] * f.normal[0] + f.feed_direction[1] * f.normal[1] + f.feed_direction[2] * f.normal[2];
  if (std::abs(dot) > 1e-3) m.fail("normal", name + ".normal must be perpendicular to the feed direction");
  if (std::abs(f.normal[2]) > 1e-3) m.fail("normal", name + ".normal must be horizontal (a wall)");
  f.feed_axis = std::abs(f.feed_direction[0]) >= std::abs(f.feed_direction[1]) ? 0 : 1;
  if (std::abs(f.feed_direction[f.feed_axis]) < 1 - 1e-6 || f.feed_direction[f.feed_axis] < 0)
    m.fail("feed_direction", name + ".feed_direction must be [1, 0, 0] or [0, 1, 0]");
  f.point_mm = vec3(m, "point_mm");
  std::tie(f.u0_mm, f.u1_mm) = range(m, "u_mm");
  std::tie(f.z0_mm, f.z1_mm) = range(m, "z_mm");
  if (f.z0_mm < b.z0_mm - 1e-9 || f.z1_mm > b.z1_mm + 1e-9) m.fail("z_mm", name + ".z_mm must lie within the block's Z");
  const double lo = f.feed_axis == 0 ? b.x0_mm : b.y0_mm, hi = f.feed_axis == 0 ? b.x1_mm : b.y1_mm;
  if (f.u0_mm < lo - 1e-9 || f.u1_mm > hi + 1e-9) m.fail("u_mm", name + ".u_mm must lie within the block");
  f.ae_mm = m.number("ae_mm", yaml::Range::positive());
  f.ap_mm = m.number("ap_mm", yaml::Range::positive());
  f.fz_mm = m.number("fz_mm", yaml::Range::positive());
  f.morelli = m.text("morelli", "");
  const std::vector<double> l = numbers(m, "lines", 2);
  if (!(l[0] >= 1 && l[0] <= l[1] && l[1] < 1e9 && l[0] == std::floor(l[0]) && l[1] == std::floor(l[1])))
    m.fail("lines", name + ".lines must be [first, last] line numbers");
  f.first_line = static_cast<int>(l[0]);
  f.last_line = static_cast<int>(l[1]);
  return f;
}

}  // namespace

void write_plan_yaml(std::ostream& out, const TestCutPlan& p, const std::string& program) {
  const TestBlock& b = p.block;
  const TestCutter& t = p.tool;
  out << "# deflex test cut: what " << program << " cuts, for deflex probe (the probing program)\n"
      << "# and the fit of the machine's stiffness. Lengths in mm, work frame (G54).\n"
      << "program: " << quoted(program) << "\n"
      << "machine: " << quoted(p.machine) << "\n"
      << "material: " << quoted(p.material) << "\n"
      << "dialect: " << quoted(p.dialect) << "\n"
      << "block_mm: {x: " << pair(b.x0_mm, b.x1_mm) << ", y: " << pair(b.y0_mm, b.y1_mm) << ", z: " << pair(b.z0_mm, b.z1_mm) << "}\n"
      << "tool: {id: " << quoted(t.id) << ", number: " << p.tool_number << ", type: " << shape_name(t.type)
      << ", diameter_mm: " << yn(t.diameter_mm) << ", corner_radius_mm: " << yn(t.corner_radius_mm) << ", flutes: " << t.flutes
      << ", helix_deg: " << yn(t.helix_deg, 2) << "}\n"
      << "spindle_rpm: " << yn(p.spindle_rpm, 0) << "   # M3, clockwise\n"
      << "feed_mm_per_min: " << yn(p.feed_mm_per_min) << "   # fz x flutes x rpm\n"
      << "clearance_mm: " << yn(p.clearance_mm) << "   # rapids only this far above the block top\n"
      << "# Each feature: a wall side-milled down (climb), its intended surface the plane\n"
      << "# through point_mm with the outward normal (material to air); the probe region\n"
      << "# is steady-state cut: u_mm along the feed direction's coordinate, z_mm from\n"
      << "# the floor (plus a bull nose's corner radius) to the block top. morelli: the\n"
      << "# force shape of Morelli 2021 (single flute I/II/III, then one overlap letter per\n"
      << "# following flute). lines: the program lines from going down to leaving the cut.\n"
      << "features:\n";
  for (const WallFeature& f : p.features) {
    out << "  - id: " << f.id << "\n"
        << "    kind: wall\n"
        << "    feed_direction: " << seq(f.feed_direction, 0) << "\n"
        << "    point_mm: " << seq(f.point_mm) << "\n"
        << "    normal: " << seq(f.normal, 4) << "\n"
        << "    u_mm: " << pair(f.u0_mm, f.u1_mm) << "\n"
        << "    z_mm: " << pair(f.z0_mm, f.z1_mm) << "\n"
        << "    ae_mm: " << yn(f.ae_mm) << "\n"
        << "    ap_mm: " << yn(f.ap_mm) << "\n"
        << "    fz_mm: " << yn(f.fz_mm, 4) << "\n"
        << "    mode: down\n"
        << "    morelli: \"" << f.morelli << "\"\n"
        << "    lines: [" << f.first_line << ", " << f.last_line << "]\n";
  }
}

TestCutPlan read_plan_yaml(const std::string& text, const std::string& file) {
  const YAML::Node root = yaml::load_text(text, file);
  const yaml::Map m(root, "the test cut plan", file,
                    {"program", "machine", "material", "dialect", "block_mm", "tool", "spindle_rpm", "feed_mm_per_min",
                     "clearance_mm", "features"});
  TestCutPlan p;
  p.machine = m.text("machine");
  p.material = m.text("material");
  p.dialect = m.text("dialect");
  const yaml::Map bm = m.map("block_mm", {"x", "y", "z"});
  TestBlock& b = p.block;
  std::tie(b.x0_mm, b.x1_mm) = range(bm, "x");
  std::tie(b.y0_mm, b.y1_mm) = range(bm, "y");
  std::tie(b.z0_mm, b.z1_mm) = range(bm, "z");
  const yaml::Map tm = m.map("tool", {"id", "number", "type", "diameter_mm", "corner_radius_mm", "flutes", "helix_deg"});
  p.tool.id = tm.text("id");
  p.tool_number = static_cast<int>(tm.integer("number", 0, 99999));
  const std::string type = tm.text("type");
  if (type != "flat" && type != "bull") tm.fail("type", "tool.type must be flat or bull");
  p.tool.type = type == "flat" ? stock::EndShape::flat : stock::EndShape::bull;
  p.tool.diameter_mm = tm.number("diameter_mm", yaml::Range::positive());
  p.tool.corner_radius_mm = tm.number("corner_radius_mm", yaml::Range::between(0, p.tool.diameter_mm / 2));
  p.tool.flutes = static_cast<int>(tm.integer("flutes", 1, 20));
  p.tool.helix_deg = tm.number("helix_deg", yaml::Range::between(0, 89));
  p.spindle_rpm = m.number("spindle_rpm", yaml::Range::positive());
  p.feed_mm_per_min = m.number("feed_mm_per_min", yaml::Range::positive());
  p.clearance_mm = m.number("clearance_mm", yaml::Range::between(1, 1000));
  const YAML::Node fs = m.get("features");
  if (!fs.IsSequence() || fs.size() == 0) m.fail(fs, "features must be a list of at least one feature");
  for (std::size_t i = 0; i < fs.size(); ++i) {
    p.features.push_back(read_feature(fs[i], "features[" + std::to_string(i) + "]", file, b));
    for (std::size_t j = 0; j + 1 < p.features.size(); ++j)
      if (p.features[j].id == p.features.back().id)
        yaml::fail(file, fs[i]["id"].Mark(), "feature id '" + p.features.back().id + "' is given twice");
  }
  if (!p.features.empty()) p.fz_mm = p.features.front().fz_mm;
  return p;
}

}  // namespace deflex::plan
