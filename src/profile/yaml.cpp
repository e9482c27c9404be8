#include "deflex/profile/yaml.hpp"

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::yaml {

std::string where(const std::string& file, const YAML::Mark& mark) {
  if (mark.is_null()) return file;
  return file + ":" + std::to_string(mark.line + 1) + ":" + std::to_string(mark.column + 1);
}

void fail(const std::string& file, const YAML::Mark& mark, const std::string& msg) {
  throw Error(Exit::config, where(file, mark) + ": error: " + msg);
}

YAML::Node load_text(const std::string& text, const std::string& file) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    fail(file, e.mark, e.msg);
  }
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(Exit::io, path + ": error: cannot read the file");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw Error(Exit::io, path + ": error: read failed");
  return ss.str();
}

YAML::Node load_file(const std::string& path) { return load_text(read_file(path), path); }

void require_map(const YAML::Node& node, const std::string& what, const std::string& file) {
  if (!node.IsMap()) fail(file, node.Mark(), what + " must be a map");
}

void check_keys(const YAML::Node& map, std::initializer_list<const char*> known,
                const std::string& file) {
  const std::set<std::string> ok(known.begin(), known.end());
  for (const auto& kv : map) {
    const std::string key = kv.first.Scalar();
    if (ok.count(key)) continue;
    std::string list;
    for (const char* k : known) list += (list.empty() ? "" : ", ") + std::string(k);
    fail(file, kv.first.Mark(), "unknown key '" + key + "' (expected one of: " + list + ")");
  }
}

double number(const YAML::Node& node, const std::string& what, const std::string& file) {
  if (!node.IsScalar()) fail(file, node.Mark(), what + " must be a number");
  double v = 0;
  try {
    v = node.as<double>();
  } catch (const YAML::Exception&) {
    fail(file, node.Mark(), what + " must be a number, not '" + node.Scalar() + "'");
  }
  if (!std::isfinite(v)) fail(file, node.Mark(), what + " must be finite");
  return v;
}

double number_at(const YAML::Node& parent, const char* key, const std::string& file,
                 const double* fallback) {
  const YAML::Node n = parent[key];
  if (!n) {
    if (fallback) return *fallback;
    fail(file, parent.Mark(), std::string("missing key '") + key + "'");
  }
  return number(n, key, file);
}

std::string text_at(const YAML::Node& parent, const char* key, const std::string& file) {
  const YAML::Node n = parent[key];
  if (!n) fail(file, parent.Mark(), std::string("missing key '") + key + "'");
  if (!n.IsScalar()) fail(file, n.Mark(), std::string(key) + " must be a string");
  return n.Scalar();
}

}  // namespace deflex::yaml
