#include "deflex/profile/profile.hpp"
#include "deflex/profile/search.hpp"

#include <filesystem>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/profile/yaml.hpp"
#include "sections.hpp"

namespace deflex::embedded {
const std::vector<std::pair<std::string_view, std::string_view>>& dialect_files();
}

namespace deflex::profile {
namespace fs = std::filesystem;

namespace {

using yaml::Map;
using yaml::Range;

template <typename E>
E get_enum(const Map& n, const char* key, std::initializer_list<std::pair<const char*, E>> values, E dflt) {
  if (!n.has(key)) return dflt;
  std::string v = n.text(key), list;
  for (auto& [name, e] : values) {
    if (v == name) return e;
    list += std::string(list.empty() ? "" : ", ") + name;
  }
  n.fail(key, std::string("'") + key + "' must be one of: " + list);
}

std::array<double, 3> get_xyz(const YAML::Node& v, const std::string& what, const std::string& file) {
  if (!v.IsSequence() || v.size() != 3) yaml::fail(file, v.Mark(), what + ": expected [x, y, z] in mm");
  std::array<double, 3> a{};
  for (std::size_t i = 0; i < 3; ++i) a[i] = yaml::number(v[i], what, file);
  return a;
}

void read_numbers(const Map& n, Dialect& d) {
  d.lii_mm = n.number("least_input_increment_mm", d.lii_mm, Range::positive());
  d.lii_inch = n.number("least_input_increment_inch", d.lii_inch, Range::positive());
  d.decimals_mm = static_cast<int>(n.integer("decimals_mm", d.decimals_mm, 0, 9));
  d.decimals_inch = static_cast<int>(n.integer("decimals_inch", d.decimals_inch, 0, 9));
  d.max_line_length = static_cast<int>(n.integer("max_line_length", d.max_line_length, 0, 1000000));
  d.arc_radius_tolerance_mm = n.number("arc_radius_tolerance_mm", d.arc_radius_tolerance_mm, Range::positive());
  d.peck_retract_mm = n.number("peck_retract_mm", d.peck_retract_mm, Range::non_negative());
}

}  // namespace

Dialect parse_dialect(const YAML::Node& node, const std::string& file) {
  const Map n(node, "dialect", file,
              {"name", "decimal_point_rule", "least_input_increment_mm", "least_input_increment_inch",
               "decimals_mm", "decimals_inch", "trailing_zeros", "leading_zero", "max_line_length",
               "n_numbers_for_inserted_blocks", "comment_style", "arc_radius_tolerance_mm",
               "cycle_repeat_word", "peck_retract_mm", "fine_boring_shift",
               "cycle_positions_before_raise", "extended_work_offsets", "cutter_comp_corner",
               "cutter_comp_startup"});
  Dialect d;
  d.name = n.text("name");
  d.decimal_rule = get_enum<DecimalRule>(n, "decimal_point_rule",
      {{"least_input_increment", DecimalRule::least_input_increment}, {"calculator", DecimalRule::calculator}},
      d.decimal_rule);
  read_numbers(n, d);
  d.trailing_zeros = n.boolean("trailing_zeros", d.trailing_zeros);
  d.leading_zero = n.boolean("leading_zero", d.leading_zero);
  d.n_policy = get_enum<NPolicy>(n, "n_numbers_for_inserted_blocks",
      {{"none", NPolicy::none}, {"increment", NPolicy::increment}, {"required", NPolicy::required}}, d.n_policy);
  d.comment_style = get_enum<CommentStyle>(n, "comment_style",
      {{"paren", CommentStyle::paren}, {"semicolon", CommentStyle::semicolon}}, d.comment_style);
  if (n.has("cycle_repeat_word")) {
    std::string w = n.text("cycle_repeat_word");
    if (w != "K" && w != "L") n.fail("cycle_repeat_word", "'cycle_repeat_word' must be K or L");
    d.cycle_repeat_word = w[0];
  }
  if (n.has("fine_boring_shift")) {
    d.fine_boring_shift = n.text("fine_boring_shift");
    const std::string& f = d.fine_boring_shift;
    if (!f.empty() && !(f.size() == 2 && (f[0] == '+' || f[0] == '-') && (f[1] == 'X' || f[1] == 'Y')))
      n.fail("fine_boring_shift", "'fine_boring_shift' must be +X, -X, +Y, -Y or empty");
  }
  d.cycle_positions_before_raise = n.boolean("cycle_positions_before_raise", d.cycle_positions_before_raise);
  d.extended_offsets = get_enum<ExtendedOffsets>(n, "extended_work_offsets",
      {{"none", ExtendedOffsets::none}, {"g54_1", ExtendedOffsets::g54_1}, {"g154", ExtendedOffsets::g154},
       {"g59_x", ExtendedOffsets::g59_x}}, d.extended_offsets);
  d.comp_corner = get_enum<Dialect::CompCorner>(n, "cutter_comp_corner",
      {{"arc", Dialect::CompCorner::arc}, {"intersection", Dialect::CompCorner::intersection}}, d.comp_corner);
  d.comp_startup = get_enum<Dialect::CompStartup>(n, "cutter_comp_startup",
      {{"offset_line", Dialect::CompStartup::offset_line},
       {"perpendicular_next", Dialect::CompStartup::perpendicular_next}}, d.comp_startup);
  return d;
}

std::vector<std::string> dialect_names() {
  std::vector<std::string> v;
  for (auto& [name, text] : embedded::dialect_files()) v.emplace_back(name);
  return v;
}

Dialect load_dialect(const std::string& name_or_path) {
  bool is_path = name_or_path.find('/') != std::string::npos ||
                 (name_or_path.size() > 5 && name_or_path.ends_with(".yaml"));
  if (is_path) return parse_dialect(yaml::load_file(name_or_path), name_or_path);
  for (auto& [name, text] : embedded::dialect_files()) {
    if (name == name_or_path) {
      std::string file = "postproc/" + std::string(name) + ".yaml";
      return parse_dialect(yaml::load_text(std::string(text), file), file);
    }
  }
  std::string list;
  for (auto& n : dialect_names()) list += (list.empty() ? "" : ", ") + n;
  throw Error(ErrorKind::settings, "unknown dialect '" + name_or_path + "' (built in: " + list + "; or give a .yaml file)");
}

namespace {

void read_travel(const Map& t, Travel& travel) {
  const char* axes[] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i) {
    if (!t.has(axes[i])) continue;
    const YAML::Node a = t.get(axes[i]);
    const std::string what = std::string("travel_mm.") + axes[i];
    if (!a.IsSequence() || a.size() != 2) t.fail(a, what + " must be [min, max] in mm");
    travel.min_mm[i] = yaml::number(a[0], what, t.file());
    travel.max_mm[i] = yaml::number(a[1], what, t.file());
    if (travel.min_mm[i] > travel.max_mm[i]) t.fail(a, "travel minimum above maximum");
    travel.set = true;
  }
}

void read_work_offsets(const Map& n, MachineProfile& m) {
  const YAML::Node w = n.get("work_offsets_mm");
  if (!w.IsMap()) n.fail(w, "work_offsets_mm must map G54..G59 / G54.1P1.. to [x, y, z]");
  for (auto it = w.begin(); it != w.end(); ++it) {
    std::string k = yaml::text(it->first, "a work offset name", n.file());
    for (char& c : k) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    m.work_offsets_mm[k] = get_xyz(it->second, "work_offsets_mm." + k, n.file());
  }
}

void read_reference_points(const Map& n, MachineProfile& m) {
  const YAML::Node r = n.get("reference_points_mm");
  if (!r.IsMap()) n.fail(r, "reference_points_mm must map 1..4 to [x, y, z] (machine coordinates)");
  for (auto it = r.begin(); it != r.end(); ++it) {
    const int k = static_cast<int>(yaml::integer(it->first, "reference point number", n.file(), 1, 4));
    m.reference_points_mm[k] = get_xyz(it->second, "reference_points_mm", n.file());
  }
}

// tool_offsets: {D: {radius_mm: R, wear_mm: W}} or {D: R}.
void read_tool_offsets(const Map& n, MachineProfile& m) {
  const YAML::Node t = n.get("tool_offsets");
  if (!t.IsMap()) n.fail(t, "tool_offsets must map D register numbers to {radius_mm: .., wear_mm: ..}");
  for (auto it = t.begin(); it != t.end(); ++it) {
    const int k = static_cast<int>(yaml::integer(it->first, "a D register number", n.file(), 1, 9999));
    MachineProfile::ToolOffset o;
    if (it->second.IsMap()) {
      const Map e(it->second, "tool_offsets entry", n.file(), {"radius_mm", "wear_mm"});
      o.radius_mm = e.number("radius_mm", Range::non_negative());
      o.wear_mm = e.number("wear_mm", 0.0, Range{});
    } else {
      o.radius_mm = yaml::number(it->second, "tool_offsets radius", n.file(), Range::non_negative());
    }
    m.tool_offsets[k] = o;
  }
}

}  // namespace

MachineProfile load_machine(const std::string& name_or_path) {
  std::string file = name_or_path;
  if (name_or_path.find('/') == std::string::npos && !name_or_path.ends_with(".yaml")) {
    file = find_machine(name_or_path);
    if (file.empty()) {
      std::string where;
      for (const std::string& d : machine_folders()) where += (where.empty() ? "" : ", ") + d;
      throw Error(ErrorKind::config, "machine profile '" + name_or_path + "' not found (looked for " + name_or_path +
                                    ".yaml in " + where + ")");
    }
  }
  const YAML::Node root = yaml::load_file(file);
  // holder:, stiffness: and dynamics: are read (with their own key checks) by deflex::stiffness.
  const Map n(root, "machine profile", file, {"name", "dialect", "travel_mm", "work_offsets_mm",
                                              "reference_points_mm", "max_offset_mm", "axis_limits", "holder",
                                              "stiffness", "dynamics", "tool_offsets", "force_scale",
                                              "spindle"});
  MachineProfile m;
  m.file = file;
  m.root = yaml::document(root);
  m.name = n.text("name", fs::path(file).stem().string());
  m.dialect = n.text("dialect", m.dialect);
  if (n.has("travel_mm")) read_travel(n.map("travel_mm", {"x", "y", "z"}), m.travel);
  if (n.has("work_offsets_mm")) read_work_offsets(n, m);
  if (n.has("reference_points_mm")) read_reference_points(n, m);
  if (n.has("tool_offsets")) read_tool_offsets(n, m);
  m.max_offset_mm = n.number("max_offset_mm", m.max_offset_mm, Range::positive());
  m.force_scale = n.number("force_scale", m.force_scale, Range::between(0.1, 10));
  if (n.has("axis_limits")) m.axis_limits = parse_axis_limits(n.get("axis_limits"), file);
  if (n.has("spindle")) m.spindle = parse_spindle(n.get("spindle"), file);
  load_dialect(m.dialect);  // an unknown dialect is a profile error, found early
  return m;
}

Config load_config(const std::string& path) {
  const std::string file = find_config(path);
  Config c;
  if (file.empty()) return c;
  const YAML::Node root = yaml::load_file(file);
  if (root.IsNull()) return c;
  // Every key is type-checked here, so a bad value is found before any command runs.
  const Map n(root, "config", file, {"machine", "dialect", "max_errors", "tool_file", "tool", "material",
                                     "material_file", "stock", "part", "part_gap_mm", "tolerance_mm", "gain"});
  for (const char* k : {"tool_file", "tool", "material", "material_file", "stock", "part"})
    if (n.has(k)) n.text(k);
  n.number("part_gap_mm", 0, Range::non_negative());
  n.number("tolerance_mm", 0, Range::non_negative());
  n.number("gain", 0, Range::between(0, 2));
  c.file = file;
  c.root = yaml::document(root);
  c.machine = n.text("machine", c.machine);
  c.dialect = n.text("dialect", c.dialect);
  c.max_errors = static_cast<int>(n.integer("max_errors", c.max_errors, 0, 1000000));
  return c;
}

}  // namespace deflex::profile
