#include "yaml_read.hpp"

#include <cmath>
#include <set>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/profile/yaml.hpp"

namespace deflex::stiffness::yaml_read {

std::string where(const std::string& file, const YAML::Mark& mark) { return deflex::yaml::where(file, mark); }

void fail(const std::string& file, const YAML::Mark& mark, const std::string& msg) { deflex::yaml::fail(file, mark, msg); }

void require_map(const YAML::Node& node, const std::string& what, const std::string& file) {
  deflex::yaml::require_map(node, what, file);
}

void check_keys(const YAML::Node& map, std::initializer_list<const char*> known, const std::string& file) {
  deflex::yaml::check_keys(map, known, file);
}

double number_node(const YAML::Node& node, const std::string& what, const std::string& file) {
  return deflex::yaml::number(node, what, file);
}

static YAML::Node required(const YAML::Node& parent, const char* key, const std::string& file) {
  const YAML::Node n = parent[key];
  if (!n) fail(file, parent.Mark(), std::string("missing key '") + key + "'");
  return n;
}

double number(const YAML::Node& parent, const char* key, const std::string& file) {
  return number_node(required(parent, key, file), key, file);
}

double positive(const YAML::Node& parent, const char* key, const std::string& file,
                bool allow_zero) {
  const YAML::Node n = required(parent, key, file);
  const double v = number_node(n, key, file);
  if (v < 0 || (!allow_zero && v == 0))
    fail(file, n.Mark(), std::string(key) + " must be " + (allow_zero ? ">= 0" : "> 0"));
  return v;
}

int integer(const YAML::Node& parent, const char* key, const std::string& file) {
  const YAML::Node n = required(parent, key, file);
  const double v = number_node(n, key, file);
  if (v != std::floor(v)) fail(file, n.Mark(), std::string(key) + " must be an integer");
  return static_cast<int>(v);
}

std::string text(const YAML::Node& parent, const char* key, const std::string& file) {
  const YAML::Node n = required(parent, key, file);
  if (!n.IsScalar()) fail(file, n.Mark(), std::string(key) + " must be a string");
  return n.Scalar();
}

Material material(const YAML::Node& node, const std::string& file) {
  if (node.IsScalar()) {
    if (auto m = material_preset(node.Scalar())) return *m;
    fail(file, node.Mark(),
         "unknown material '" + node.Scalar() + "' (presets: carbide, hss, steel; or {E_MPa, poisson})");
  }
  if (!node.IsMap()) fail(file, node.Mark(), "material must be a preset name or {E_MPa, poisson}");
  check_keys(node, {"E_MPa", "poisson"}, file);
  Material m;
  m.name = "custom";
  m.E_MPa = positive(node, "E_MPa", file);
  const YAML::Node nu = required(node, "poisson", file);
  m.poisson = number_node(nu, "poisson", file);
  // Isotropic elasticity needs -1 < nu < 0.5 for a positive-definite material.
  if (!(m.poisson > -1.0 && m.poisson < 0.5)) fail(file, nu.Mark(), "poisson must be in (-1, 0.5)");
  return m;
}

}  // namespace deflex::stiffness::yaml_read
