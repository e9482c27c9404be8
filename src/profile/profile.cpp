#include "deflex/profile/profile.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/profile/yaml.hpp"

namespace deflex::embedded {
const std::vector<std::pair<std::string_view, std::string_view>>& dialect_files();
}

namespace deflex::profile {
namespace fs = std::filesystem;

[[noreturn]] void yaml_error(const std::string& file, const YAML::Mark& mark, const std::string& msg) {
  deflex::yaml::fail(file, mark, msg);
}

YAML::Node load_yaml_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(Exit::config, path + ": error: cannot open: " + std::strerror(errno));
  std::stringstream ss;
  ss << in.rdbuf();
  try {
    return YAML::Load(ss.str());
  } catch (const YAML::Exception& e) {
    yaml_error(path, e.mark, e.msg);
  }
}

double get_number(const YAML::Node& n, const std::string& file, const std::string& key) {
  const YAML::Node v = n[key];
  try {
    return v.as<double>();
  } catch (const YAML::Exception&) {
    yaml_error(file, v.Mark(), "'" + key + "' must be a number");
  }
}

// A whole number in [lo, hi]; checked as a double before the conversion, which
// would be undefined behaviour out of int's range.
static int get_int(const YAML::Node& n, const std::string& file, const std::string& key, int lo, int hi) {
  const double v = get_number(n, file, key);
  if (!(v >= lo && v <= hi) || v != std::floor(v))
    yaml_error(file, n[key].Mark(),
               "'" + key + "' must be a whole number from " + std::to_string(lo) + " to " + std::to_string(hi));
  return static_cast<int>(v);
}

std::string get_string(const YAML::Node& n, const std::string& file, const std::string& key) {
  const YAML::Node v = n[key];
  // IsDefined first: a missing key is an invalid node, on which IsScalar() throws.
  if (!v.IsDefined()) yaml_error(file, n.Mark(), "missing key '" + key + "'");
  if (!v.IsScalar()) yaml_error(file, v.Mark(), "'" + key + "' must be a text");
  return v.as<std::string>();
}

namespace {

void check_keys(const YAML::Node& n, const std::string& file, std::initializer_list<const char*> known) {
  deflex::yaml::require_map(n, "this section", file);
  deflex::yaml::check_keys(n, known, file);
}

template <typename E>
E get_enum(const YAML::Node& n, const std::string& file, const std::string& key,
           std::initializer_list<std::pair<const char*, E>> values, E dflt) {
  if (!n[key]) return dflt;
  std::string v = get_string(n, file, key), list;
  for (auto& [name, e] : values) {
    if (v == name) return e;
    list += std::string(list.empty() ? "" : ", ") + name;
  }
  yaml_error(file, n[key].Mark(), "'" + key + "' must be one of: " + list);
}

std::array<double, 3> get_xyz(const YAML::Node& v, const std::string& file) {
  if (!v.IsSequence() || v.size() != 3) yaml_error(file, v.Mark(), "expected [x, y, z] in mm");
  std::array<double, 3> a{};
  for (int i = 0; i < 3; ++i) {
    try {
      a[i] = v[i].as<double>();
    } catch (const YAML::Exception&) {
      yaml_error(file, v[i].Mark(), "expected a number (mm)");
    }
  }
  return a;
}

}  // namespace

Dialect parse_dialect(const YAML::Node& n, const std::string& file) {
  check_keys(n, file, {"name", "decimal_point_rule", "least_input_increment_mm", "least_input_increment_inch",
                       "decimals_mm", "decimals_inch", "trailing_zeros", "leading_zero", "max_line_length",
                       "n_numbers_for_inserted_blocks", "comment_style", "arc_radius_tolerance_mm",
                       "cycle_repeat_word", "peck_retract_mm", "fine_boring_shift",
                       "cycle_positions_before_raise", "extended_work_offsets"});
  Dialect d;
  d.name = get_string(n, file, "name");
  d.decimal_rule = get_enum<DecimalRule>(n, file, "decimal_point_rule",
      {{"least_input_increment", DecimalRule::least_input_increment}, {"calculator", DecimalRule::calculator}},
      d.decimal_rule);
  auto num = [&](const char* k, double dflt) { return n[k] ? get_number(n, file, k) : dflt; };
  auto flag = [&](const char* k, bool dflt) {
    if (!n[k]) return dflt;
    try { return n[k].as<bool>(); } catch (const YAML::Exception&) { yaml_error(file, n[k].Mark(), std::string("'") + k + "' must be true or false"); }
  };
  d.lii_mm = num("least_input_increment_mm", d.lii_mm);
  d.lii_inch = num("least_input_increment_inch", d.lii_inch);
  auto whole = [&](const char* k, int lo, int hi, int dflt) { return n[k] ? get_int(n, file, k, lo, hi) : dflt; };
  d.decimals_mm = whole("decimals_mm", 0, 9, d.decimals_mm);
  d.decimals_inch = whole("decimals_inch", 0, 9, d.decimals_inch);
  d.trailing_zeros = flag("trailing_zeros", d.trailing_zeros);
  d.leading_zero = flag("leading_zero", d.leading_zero);
  d.max_line_length = whole("max_line_length", 0, 1 << 30, d.max_line_length);
  d.n_policy = get_enum<NPolicy>(n, file, "n_numbers_for_inserted_blocks",
      {{"none", NPolicy::none}, {"increment", NPolicy::increment}}, d.n_policy);
  d.comment_style = get_enum<CommentStyle>(n, file, "comment_style",
      {{"paren", CommentStyle::paren}, {"semicolon", CommentStyle::semicolon}}, d.comment_style);
  d.arc_radius_tolerance_mm = num("arc_radius_tolerance_mm", d.arc_radius_tolerance_mm);
  if (n["cycle_repeat_word"]) {
    std::string w = get_string(n, file, "cycle_repeat_word");
    if (w != "K" && w != "L") yaml_error(file, n["cycle_repeat_word"].Mark(), "'cycle_repeat_word' must be K or L");
    d.cycle_repeat_word = w[0];
  }
  d.peck_retract_mm = num("peck_retract_mm", d.peck_retract_mm);
  if (n["fine_boring_shift"]) {
    d.fine_boring_shift = get_string(n, file, "fine_boring_shift");
    const std::string& f = d.fine_boring_shift;
    if (!f.empty() && !(f.size() == 2 && (f[0] == '+' || f[0] == '-') && (f[1] == 'X' || f[1] == 'Y')))
      yaml_error(file, n["fine_boring_shift"].Mark(), "'fine_boring_shift' must be +X, -X, +Y, -Y or empty");
  }
  d.cycle_positions_before_raise = flag("cycle_positions_before_raise", d.cycle_positions_before_raise);
  d.extended_offsets = get_enum<ExtendedOffsets>(n, file, "extended_work_offsets",
      {{"none", ExtendedOffsets::none}, {"g54_1", ExtendedOffsets::g54_1}, {"g154", ExtendedOffsets::g154},
       {"g59_x", ExtendedOffsets::g59_x}}, d.extended_offsets);
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
  if (is_path) return parse_dialect(load_yaml_file(name_or_path), name_or_path);
  for (auto& [name, text] : embedded::dialect_files()) {
    if (name == name_or_path) {
      std::string file = "postproc/" + std::string(name) + ".yaml";
      try {
        return parse_dialect(YAML::Load(std::string(text)), file);
      } catch (const YAML::Exception& e) {
        yaml_error(file, e.mark, e.msg);
      }
    }
  }
  std::string list;
  for (auto& n : dialect_names()) list += (list.empty() ? "" : ", ") + n;
  throw Error(Exit::usage, "unknown dialect '" + name_or_path + "' (built in: " + list + "; or give a .yaml file)");
}

namespace {

std::string find_named(const std::string& dir, const std::string& name) {
  for (const std::string& base : {std::string("."), std::string(DEFLEX_SOURCE_DIR)}) {
    fs::path p = fs::path(base) / dir / (name + ".yaml");
    if (fs::exists(p)) return p.string();
  }
  return {};
}

}  // namespace

MachineProfile load_machine(const std::string& name_or_path) {
  std::string file = name_or_path;
  if (name_or_path.find('/') == std::string::npos && !name_or_path.ends_with(".yaml")) {
    file = find_named("samples/machines", name_or_path);
    if (file.empty())
      throw Error(Exit::config, "machine profile '" + name_or_path +
                                    "' not found (looked for samples/machines/" + name_or_path + ".yaml)");
  }
  YAML::Node n = load_yaml_file(file);
  check_keys(n, file, {"name", "dialect", "travel_mm", "work_offsets_mm", "reference_points_mm",
                       "max_offset_mm", "holder", "stiffness", "spindle", "limits"});
  MachineProfile m;
  m.file = file;
  m.root = n;
  m.name = n["name"] ? get_string(n, file, "name") : fs::path(file).stem().string();
  if (n["dialect"]) m.dialect = get_string(n, file, "dialect");
  if (const YAML::Node t = n["travel_mm"]) {
    check_keys(t, file, {"x", "y", "z"});
    const char* axes[] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i) {
      const YAML::Node a = t[axes[i]];
      if (!a) continue;
      if (!a.IsSequence() || a.size() != 2) yaml_error(file, a.Mark(), std::string("travel_mm.") + axes[i] + " must be [min, max] in mm");
      try {
        m.travel.min_mm[i] = a[0].as<double>();
        m.travel.max_mm[i] = a[1].as<double>();
      } catch (const YAML::Exception&) {
        yaml_error(file, a.Mark(), "travel limits must be numbers (mm)");
      }
      if (m.travel.min_mm[i] > m.travel.max_mm[i]) yaml_error(file, a.Mark(), "travel minimum above maximum");
      m.travel.set = true;
    }
  }
  if (const YAML::Node w = n["work_offsets_mm"]) {
    if (!w.IsMap()) yaml_error(file, w.Mark(), "work_offsets_mm must map G54..G59 / G54.1P1.. to [x, y, z]");
    for (auto it = w.begin(); it != w.end(); ++it) {
      std::string k = it->first.as<std::string>();
      for (char& c : k) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      m.work_offsets_mm[k] = get_xyz(it->second, file);
    }
  }
  if (const YAML::Node r = n["reference_points_mm"]) {
    if (!r.IsMap()) yaml_error(file, r.Mark(), "reference_points_mm must map 1..4 to [x, y, z] (machine coordinates)");
    for (auto it = r.begin(); it != r.end(); ++it) {
      int k = 0;
      try { k = it->first.as<int>(); } catch (const YAML::Exception&) { k = 0; }
      if (k < 1 || k > 4) yaml_error(file, it->first.Mark(), "reference point number must be 1..4");
      m.reference_points_mm[k] = get_xyz(it->second, file);
    }
  }
  if (n["max_offset_mm"]) m.max_offset_mm = get_number(n, file, "max_offset_mm");
  load_dialect(m.dialect);  // an unknown dialect is a profile error, found early
  return m;
}

Config load_config(const std::string& path) {
  std::string file = path;
  if (file.empty()) {
    for (const std::string& base : {std::string("."), std::string(DEFLEX_SOURCE_DIR)})
      if (fs::exists(fs::path(base) / "config.yaml")) { file = (fs::path(base) / "config.yaml").string(); break; }
  }
  Config c;
  if (file.empty()) return c;
  YAML::Node n = load_yaml_file(file);
  if (n.IsNull()) return c;
  check_keys(n, file, {"machine", "dialect", "max_errors", "tool_file", "tool", "material", "material_file",
                       "stock", "tolerance_mm", "gain", "compensate", "report"});
  c.file = file;
  c.root = n;
  if (n["machine"]) c.machine = get_string(n, file, "machine");
  if (n["dialect"]) c.dialect = get_string(n, file, "dialect");
  if (n["max_errors"]) c.max_errors = get_int(n, file, "max_errors", 0, 1 << 30);
  return c;
}

}  // namespace deflex::profile
