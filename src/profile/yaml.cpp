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
  throw Error(ErrorKind::config, where(file, mark) + ": error: " + msg);
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
  if (!in) throw Error(ErrorKind::io, path + ": error: cannot read the file");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw Error(ErrorKind::io, path + ": error: read failed");
  return ss.str();
}

YAML::Node load_file(const std::string& path) { return load_text(read_file(path), path); }

namespace {

// A node's mark; an undefined (zombie) node has none and yaml-cpp would throw.
YAML::Mark mark_of(const YAML::Node& n) { return n.IsDefined() ? n.Mark() : YAML::Mark::null_mark(); }

std::string fmt(double v) {
  std::ostringstream o;
  o << v;
  return o.str();
}

std::string range_text(const Range& r) {
  const double big = std::numeric_limits<double>::max();
  if (r.hi == big) return std::string(r.lo_open ? "> " : ">= ") + fmt(r.lo);
  if (r.lo == -big) return "<= " + fmt(r.hi);
  return std::string("in ") + (r.lo_open ? "(" : "[") + fmt(r.lo) + ", " + fmt(r.hi) + "]";
}

}  // namespace

double number(const YAML::Node& node, const std::string& what, const std::string& file, Range r) {
  if (!node.IsScalar()) fail(file, mark_of(node), what + " must be a number");
  double v = 0;
  try {
    v = node.as<double>();
  } catch (const YAML::Exception&) {
    fail(file, node.Mark(), what + " must be a number, not '" + node.Scalar() + "'");
  }
  // .nan and .inf parse as numbers; a NaN limit would switch its check off.
  if (!std::isfinite(v)) fail(file, node.Mark(), what + " must be finite, not '" + node.Scalar() + "'");
  const bool below = r.lo_open ? !(v > r.lo) : v < r.lo;
  if (below || v > r.hi) fail(file, node.Mark(), what + " must be " + range_text(r));
  return v;
}

long long integer(const YAML::Node& node, const std::string& what, const std::string& file, long long lo,
                  long long hi) {
  const double v = number(node, what, file);
  if (v != std::floor(v)) fail(file, node.Mark(), what + " must be a whole number");
  // Compared as doubles before the cast: a cast of an out-of-range double is undefined.
  if (v < static_cast<double>(lo) || v > static_cast<double>(hi))
    fail(file, node.Mark(), what + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return static_cast<long long>(v);
}

std::string text(const YAML::Node& node, const std::string& what, const std::string& file) {
  if (!node.IsScalar()) fail(file, mark_of(node), what + " must be a string");
  return node.Scalar();
}

bool boolean(const YAML::Node& node, const std::string& what, const std::string& file) {
  bool b = false;
  if (!node.IsScalar() || !YAML::convert<bool>::decode(node, b))
    fail(file, mark_of(node), what + " must be true or false");
  return b;
}

Map::Map(const YAML::Node& node, std::string name, std::string file, std::initializer_list<const char*> keys)
    : node_(node), name_(std::move(name)), file_(std::move(file)) {
  if (!node_.IsDefined() || !node_.IsMap()) yaml::fail(file_, mark_of(node_), name_ + " must be a map");
  const std::set<std::string> ok(keys.begin(), keys.end());
  for (const auto& kv : node_) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : "?";
    if (ok.count(key)) continue;
    std::string list;
    for (const char* k : keys) list += (list.empty() ? "" : ", ") + std::string(k);
    yaml::fail(file_, kv.first.Mark(), "unknown key '" + key + "' in " + name_ + " (expected: " + list + ")");
  }
}

void Map::fail(const YAML::Node& at, const std::string& msg) const {
  yaml::fail(file_, at.IsDefined() ? at.Mark() : node_.Mark(), msg);
}

YAML::Node Map::get(const char* key) const {
  const YAML::Node n = node_[key];
  if (!n) yaml::fail(file_, node_.Mark(), std::string("missing key '") + key + "' in " + name_);
  return n;
}

double Map::number(const char* key, Range r) const { return yaml::number(get(key), key, file_, r); }
double Map::number(const char* key, double dflt, Range r) const { return has(key) ? number(key, r) : dflt; }
long long Map::integer(const char* key, long long lo, long long hi) const {
  return yaml::integer(get(key), key, file_, lo, hi);
}
long long Map::integer(const char* key, long long dflt, long long lo, long long hi) const {
  return has(key) ? integer(key, lo, hi) : dflt;
}
std::string Map::text(const char* key) const { return yaml::text(get(key), key, file_); }
std::string Map::text(const char* key, const std::string& dflt) const { return has(key) ? text(key) : dflt; }
bool Map::boolean(const char* key, bool dflt) const { return has(key) ? yaml::boolean(get(key), key, file_) : dflt; }
Map Map::map(const char* key, std::initializer_list<const char*> keys) const {
  // A document ("machine profile") names its sections by their key alone.
  const bool document = name_.find(' ') != std::string::npos;
  return Map(get(key), document ? std::string(key) : name_ + "." + key, file_, keys);
}

}  // namespace deflex::yaml
