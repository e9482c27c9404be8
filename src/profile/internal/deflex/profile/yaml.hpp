// The one strict YAML reader of deflex: config.yaml, machine profiles (every
// section), dialects, tool and material libraries all go through it, so each
// error is a deflex::Error(ErrorKind::config) whose text starts `file:line:col: error:`,
// an unknown key is always an error (a typo never passes silently), and no
// number becomes an integer or a limit without being checked first.
//
// A header of this build only, never installed: it names yaml-cpp's types, which
// the public headers keep out. The modules that include it link yaml-cpp
// themselves (PRIVATE, CMakeLists.txt).
#pragma once
#include <initializer_list>
#include <limits>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "deflex/profile/document.hpp"

namespace deflex::yaml {

struct Document::Node {
  YAML::Node node;
};
inline Document document(const YAML::Node& n) { return Document(std::make_shared<const Document::Node>(Document::Node{n})); }
// The document's root; a null node for an empty Document.
inline YAML::Node node(const Document& d) { return d ? d.node()->node : YAML::Node(); }

std::string where(const std::string& file, const YAML::Mark& mark);  // yaml-cpp marks are 0-based
[[noreturn]] void fail(const std::string& file, const YAML::Mark& mark, const std::string& msg);

std::string read_file(const std::string& path);  // Error(ErrorKind::io) when it cannot be read
YAML::Node load_file(const std::string& path);
YAML::Node load_text(const std::string& text, const std::string& file);

// Allowed values of a number; NaN and infinities are never allowed.
struct Range {
  double lo = -std::numeric_limits<double>::max();
  double hi = std::numeric_limits<double>::max();
  bool lo_open = false;  // lo itself excluded
  static Range positive() { return {0, std::numeric_limits<double>::max(), true}; }
  static Range non_negative() { return {0, std::numeric_limits<double>::max(), false}; }
  static Range between(double lo, double hi) { return {lo, hi, false}; }
};

// Typed readers of one node; `what` names it in the message.
double number(const YAML::Node& node, const std::string& what, const std::string& file, Range r = {});
// A whole number in [lo, hi], range-checked before the cast.
long long integer(const YAML::Node& node, const std::string& what, const std::string& file, long long lo, long long hi);
std::string text(const YAML::Node& node, const std::string& what, const std::string& file);
bool boolean(const YAML::Node& node, const std::string& what, const std::string& file);

// A map section that knows its allowed keys: constructing it fails on a
// non-map and on the first unknown key
// (`file:l:c: error: unknown key 'x' in limits (expected: a, b, c)`).
// Getters without a default fail on a missing key, located at the section.
class Map {
 public:
  Map(const YAML::Node& node, std::string name, std::string file, std::initializer_list<const char*> keys);

  bool has(const char* key) const { return static_cast<bool>(node_[key]); }
  YAML::Node get(const char* key) const;  // required
  YAML::Node node() const { return node_; }
  const std::string& file() const { return file_; }
  const std::string& name() const { return name_; }
  [[noreturn]] void fail(const YAML::Node& at, const std::string& msg) const;
  [[noreturn]] void fail(const char* key, const std::string& msg) const { fail(get(key), msg); }

  double number(const char* key, Range r = {}) const;
  double number(const char* key, double dflt, Range r) const;
  long long integer(const char* key, long long lo, long long hi) const;
  long long integer(const char* key, long long dflt, long long lo, long long hi) const;
  std::string text(const char* key) const;
  std::string text(const char* key, const std::string& dflt) const;
  bool boolean(const char* key, bool dflt) const;
  // A sub-section (required); its name in messages is "<this>.<key>".
  Map map(const char* key, std::initializer_list<const char*> keys) const;

 private:
  YAML::Node node_;
  std::string name_, file_;
};

}  // namespace deflex::yaml
