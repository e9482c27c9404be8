// Fusion 360 JSON and LinuxCNC .tbl tool libraries to deflex YAML
// (include/deflex/stiffness/tool_import.hpp). JSON by nlohmann-json, YAML
// written by yaml-cpp's emitter (quoting and escaping are theirs).
#include "deflex/stiffness/tool_import.hpp"

#include "deflex/stock/end_shape.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/diag/plural.hpp"
#include "deflex/profile/yaml.hpp"

namespace deflex::stiffness {
namespace {

// One tool as written to the YAML; `note` holds the comment of each key that
// took a default.
struct Entry {
  int number = 0;
  std::string description, material = "carbide";
  stock::EndShape type = stock::EndShape::flat;
  double d_mm = 0, corner_mm = 0, helix_deg = 30, flute_mm = 0, stickout_mm = 0;
  std::optional<double> shank_mm;
  int flutes = 2;
  std::map<std::string, std::string> note;
};

// A number as YAML reads it back: 6 significant digits, written as a plain scalar.
std::string number_text(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

std::string to_yaml(const std::vector<Entry>& tools, const std::string& header, const std::vector<std::string>& skipped) {
  YAML::Emitter out;
  out << YAML::Comment(header);
  for (const std::string& s : skipped) out << YAML::Newline << YAML::Comment("skipped: " + s);
  out << YAML::BeginMap << YAML::Key << "tools" << YAML::Value << YAML::BeginMap;
  for (const Entry& e : tools) {
    out << YAML::Key << "T" + std::to_string(e.number) << YAML::Value << YAML::BeginMap;
    auto key = [&](const char* k, const auto& v) {
      out << YAML::Key << k << YAML::Value << v;
      if (const auto it = e.note.find(k); it != e.note.end()) out << YAML::Comment(it->second);
    };
    if (!e.description.empty()) key("description", e.description);
    key("type", to_string(e.type));
    key("diameter_mm", number_text(e.d_mm));
    if (e.type == stock::EndShape::bull) key("corner_radius_mm", number_text(e.corner_mm));
    key("flutes", e.flutes);
    key("helix_deg", number_text(e.helix_deg));
    key("flute_length_mm", number_text(e.flute_mm));
    key("stickout_mm", number_text(e.stickout_mm));
    if (e.shank_mm) key("shank_diameter_mm", number_text(*e.shank_mm));
    key("material", e.material);
    out << YAML::EndMap;
  }
  out << YAML::EndMap << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

[[noreturn]] void fail(const std::string& where, const std::string& msg) {
  throw Error(ErrorKind::config, where + ": error: " + msg);
}

// --- Fusion 360 ----------------------------------------------------------------

using Json = nlohmann::json;

// "line:col" (1-based) of byte offset `at` of `text`, by SourceText's line index.
std::string position(const std::string& file, const std::string& text, std::size_t at) {
  const SourceText src(file, text);
  const auto off = static_cast<std::uint32_t>(std::min(at, text.size()));
  const std::uint32_t line = src.line_of(off);
  if (line == 0) return "1:1";  // an empty file has no lines
  return std::to_string(line) + ":" + std::to_string(off - src.line_begin(line) + 1);
}

bool is_json(const std::string& path) { return path.ends_with(".json") || path.ends_with(".JSON"); }

struct FusionTool {
  const Json& j;
  std::string where;  // "file: data[3] (T5 'Ball D10')"
  double scale;       // to mm

  const Json* geometry(const char* k) const {
    const auto g = j.find("geometry");
    if (g == j.end() || !g->is_object()) return nullptr;
    const auto it = g->find(k);
    return it == g->end() || it->is_null() ? nullptr : &*it;
  }
  std::optional<double> length(const char* k) const {
    const Json* v = geometry(k);
    if (!v) return std::nullopt;
    if (!v->is_number() || !std::isfinite(v->get<double>()) || v->get<double>() < 0)
      fail(where, std::string("geometry.") + k + " must be a number >= 0 (" + v->dump() + ")");
    return v->get<double>() * scale;
  }
};

// The string at key `k` of object `o`, `def` where absent, "" where not a string.
std::string text_of(const Json& o, const char* k, const std::string& def) {
  if (!o.is_object()) return def;
  const auto it = o.find(k);
  if (it == o.end() || it->is_null()) return def;
  return it->is_string() ? it->get<std::string>() : "";
}

const std::map<std::string, stock::EndShape>& fusion_types() {
  static const std::map<std::string, stock::EndShape> m = {{"flat end mill", stock::EndShape::flat},
                                                            {"ball end mill", stock::EndShape::ball},
                                                            {"bull nose end mill", stock::EndShape::bull}};
  return m;
}

}  // namespace

bool is_foreign_tool_library(const std::string& path) {
  return is_json(path) || path.ends_with(".tbl") || path.ends_with(".TBL");
}

namespace {
ImportedLibrary fusion_tools(const Json& root, const std::string& file);
}  // namespace

ImportedLibrary import_fusion_json(const std::string& text, const std::string& file) {
  Json root;
  try {
    root = Json::parse(text);
  } catch (const Json::parse_error& e) {
    fail(file + ":" + position(file, text, e.byte ? e.byte - 1 : 0), std::string("not valid JSON: ") + e.what());
  } catch (const Json::exception& e) {
    // A number beyond a double (4e333) is an out_of_range error, without a position
    // (libFuzzer's find: it escaped as an internal error).
    fail(file, std::string("not valid JSON: ") + e.what());
  }
  if (!root.is_object() || !root.contains("data") || !root["data"].is_array())
    fail(file, "a Fusion 360 tool library is a JSON object with a \"data\" array of tools");
  try {
    return fusion_tools(root, file);
  } catch (const Json::exception& e) {  // a value of an unexpected JSON type the checks above let through
    fail(file, std::string("unexpected JSON value: ") + e.what());
  }
}

namespace {

// The tool number of a Fusion tool (post-process.number, 1..99999), or 0.
int fusion_number(const Json& t) {
  if (const auto pp = t.is_object() ? t.find("post-process") : t.end(); t.is_object() && pp != t.end() && pp->is_object())
    if (const auto n = pp->find("number"); n != pp->end() && n->is_number_integer() && n->get<long long>() >= 1 &&
                                           n->get<long long>() <= 99999)
      return static_cast<int>(n->get<long long>());
  return 0;
}

// One end mill's entry from its geometry (Fusion 360's keys: DC diameter, RE
// corner radius, NOF flutes, LCF flute length, LB length below the holder,
// SFDM shank diameter, BMC material); defaults noted where the library is silent.
Entry fusion_entry(const FusionTool& ft, int number, const std::string& desc, stock::EndShape type) {
  Entry e;
  e.number = number;
  e.description = desc;
  e.type = type;
  const auto dc = ft.length("DC");
  if (!dc || *dc <= 0) fail(ft.where, "geometry.DC (the cutting diameter) is missing or 0");
  e.d_mm = *dc;
  if (e.type == stock::EndShape::bull) {
    const auto re = ft.length("RE");
    if (!re || *re <= 0 || *re > e.d_mm / 2)
      fail(ft.where, "a bull nose needs geometry.RE (the corner radius) in (0, DC/2]");
    e.corner_mm = *re;
  }
  if (const Json* nof = ft.geometry("NOF")) {
    if (!nof->is_number() || nof->get<double>() < 1 || nof->get<double>() > 100 || std::floor(nof->get<double>()) != nof->get<double>())
      fail(ft.where, "geometry.NOF must be a whole number of flutes, 1..100 (" + nof->dump() + ")");
    e.flutes = nof->get<int>();
  } else {
    e.note["flutes"] = "default: the library gives no NOF";
  }
  e.note["helix_deg"] = "default: a Fusion library gives no helix angle; set the vendor's";
  if (const auto lcf = ft.length("LCF"); lcf && *lcf > 0) e.flute_mm = *lcf;
  else { e.flute_mm = 2 * e.d_mm; e.note["flute_length_mm"] = "default 2 D: the library gives no LCF"; }
  if (const auto lb = ft.length("LB"); lb && *lb > 0) e.stickout_mm = *lb;
  else { e.stickout_mm = e.flute_mm + e.d_mm; e.note["stickout_mm"] = "default LCF + D: the library gives no LB (length below the holder)"; }
  if (const auto sf = ft.length("SFDM"); sf && *sf > 0) e.shank_mm = *sf;
  // What deflex's reader requires of every tool, said here of the source.
  const double corner = stock::corner_radius_mm(e.type, e.d_mm / 2, e.corner_mm);
  for (const auto& [k, v] : {std::pair("DC", e.d_mm), std::pair("LCF", e.flute_mm), std::pair("LB", e.stickout_mm),
                             std::pair("SFDM", e.shank_mm.value_or(1.0))})
    if (!(v <= 1000)) fail(ft.where, std::string("geometry.") + k + " is " + number_text(v) + " mm: more than 1000 mm");
  if (e.flute_mm < corner) fail(ft.where, "geometry.LCF (flute length) must reach past the corner radius");
  if (e.stickout_mm <= corner) fail(ft.where, "geometry.LB (length below the holder) must exceed the corner radius");
  const Json* bmc = ft.geometry("BMC");
  const std::string m = bmc && bmc->is_string() ? bmc->get<std::string>() : "";
  if (m == "carbide" || m == "hss") e.material = m;
  else e.note["material"] = "default: the library says " + (m.empty() ? std::string("nothing") : "'" + m + "'");
  return e;
}

ImportedLibrary fusion_tools(const Json& root, const std::string& file) {
  ImportedLibrary out;
  out.format = "Fusion 360 JSON";
  std::vector<Entry> tools;
  std::map<int, std::string> taken;
  const Json& data = root["data"];
  for (std::size_t i = 0; i < data.size(); ++i) {
    const Json& t = data[i];
    const std::string desc = text_of(t, "description", "");
    const std::string type = text_of(t, "type", "?");
    const int number = fusion_number(t);
    const std::string name = "data[" + std::to_string(i) + "] '" + desc + "' (" + type + ")";
    if (!t.is_object()) fail(file, "data[" + std::to_string(i) + "] is not a tool object");
    const auto kind = fusion_types().find(type);
    if (kind == fusion_types().end()) {
      out.skipped.push_back(name + ": not a flat, ball or bull-nose end mill");
      continue;
    }
    if (!number) {
      out.skipped.push_back(name + ": no tool number (post-process.number)");
      continue;
    }
    if (const auto it = taken.find(number); it != taken.end()) {
      out.skipped.push_back(name + ": T" + std::to_string(number) + " is already " + it->second);
      continue;
    }
    const std::string unit = text_of(t, "unit", "millimeters");
    if (unit != "millimeters" && unit != "inches")
      fail(file + ": " + name, "unit must be \"millimeters\" or \"inches\" (" + unit + ")");
    const FusionTool ft{t, file + ": " + name + " T" + std::to_string(number), unit == "inches" ? 25.4 : 1.0};
    tools.push_back(fusion_entry(ft, number, desc, kind->second));
    taken[number] = "'" + desc + "'";
  }
  out.tools = static_cast<int>(tools.size());
  out.yaml = to_yaml(tools,
                     "Imported by deflex from " + file + " (Fusion 360 JSON): " + std::to_string(tools.size()) +
                         " tools, " + std::to_string(out.skipped.size()) + " skipped. Lengths in mm.",
                     out.skipped);
  return out;
}

}  // namespace

ImportedLibrary import_linuxcnc_tbl(const std::string& text, const std::string& file) {
  ImportedLibrary out;
  out.format = "LinuxCNC tool table";
  std::vector<Entry> tools;
  std::set<int> taken;
  std::istringstream in(text);
  std::string line;
  for (int ln = 1; std::getline(in, line); ++ln) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::string comment;
    if (const auto semi = line.find(';'); semi != std::string::npos) {
      comment = line.substr(semi + 1);
      line.resize(semi);
      while (!comment.empty() && comment.front() == ' ') comment.erase(comment.begin());
    }
    std::optional<int> t;
    std::optional<double> d;
    std::size_t pos = 0;
    while (pos < line.size()) {
      if (line[pos] == ' ' || line[pos] == '\t') { ++pos; continue; }
      const std::string at = file + ":" + std::to_string(ln) + ":" + std::to_string(pos + 1);
      const char letter = static_cast<char>(std::toupper(static_cast<unsigned char>(line[pos])));
      if (std::string("TPXYZABCUVWDIJQ").find(letter) == std::string::npos)
        fail(at, std::string("'") + line[pos] + "' is not a word of a LinuxCNC tool table (T P X..W D I J Q)");
      std::size_t end = pos + 1;
      while (end < line.size() && line[end] != ' ' && line[end] != '\t') ++end;
      const std::string num = line.substr(pos + 1, end - pos - 1);
      char* stop = nullptr;
      const double v = std::strtod(num.c_str(), &stop);
      if (num.empty() || *stop || !std::isfinite(v)) fail(at, "'" + line.substr(pos, end - pos) + "' needs a number");
      if (letter == 'T') {
        if (v < 1 || v > 99999 || std::floor(v) != v) fail(at, "T must be a tool number 1..99999");
        t = static_cast<int>(v);
      }
      if (letter == 'D') {
        // At most 200 mm: the default stick-out of 4 D stays within a tool's 1000 mm.
        if (!(v > 0 && v <= 200)) fail(at, "D must be a diameter in (0, 200] mm");
        d = v;
      }
      pos = end;
    }
    if (!t && !d) continue;  // a blank or comment line
    const std::string at = file + ":" + std::to_string(ln) + ":1";
    if (!t) fail(at, "a tool line needs T");
    if (!d) {
      out.skipped.push_back("T" + std::to_string(*t) + " (line " + std::to_string(ln) + "): no diameter D");
      continue;
    }
    if (!taken.insert(*t).second) fail(at, "T" + std::to_string(*t) + " is listed twice");
    Entry e;
    e.number = *t;
    e.description = comment;
    e.d_mm = *d;
    e.flute_mm = 3 * e.d_mm;
    e.stickout_mm = 4 * e.d_mm;
    e.note["type"] = "default: a tool table gives no type; set ball or bull (with corner_radius_mm) where it is one";
    e.note["flutes"] = "default: a tool table gives no flutes";
    e.note["helix_deg"] = "default: a tool table gives no helix angle";
    e.note["flute_length_mm"] = "default 3 D: a tool table gives no flute length";
    e.note["stickout_mm"] = "default 4 D: a tool table gives no stick-out; measure it";
    e.note["material"] = "default";
    tools.push_back(e);
  }
  out.tools = static_cast<int>(tools.size());
  out.yaml = to_yaml(tools,
                     "Imported by deflex from " + file + " (LinuxCNC tool table, diameters in mm): " +
                         plural(tools.size(), "tool") + ", " + std::to_string(out.skipped.size()) +
                         " skipped. Check every default below.",
                     out.skipped);
  return out;
}

ImportedLibrary import_tool_library(const std::string& path) {
  const std::string text = yaml::read_file(path);
  return is_json(path) ? import_fusion_json(text, path) : import_linuxcnc_tbl(text, path);
}

}  // namespace deflex::stiffness
