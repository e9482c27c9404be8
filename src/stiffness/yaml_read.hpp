// Small YAML readers that report errors as `file:line:col: error: ...`.
// Private to src/stiffness/.
#pragma once
#include <initializer_list>
#include <string>

#include <yaml-cpp/yaml.h>

#include "deflex/stiffness/tool.hpp"

namespace deflex::stiffness::yaml_read {

// Throws Error(Exit::config) located at `mark` (yaml-cpp marks are 0-based).
[[noreturn]] void fail(const std::string& file, const YAML::Mark& mark, const std::string& msg);

// "file:line:col" of a node.
std::string where(const std::string& file, const YAML::Mark& mark);

// Fails on a key of `map` not in `known` (catches misspelt keys).
void check_keys(const YAML::Node& map, std::initializer_list<const char*> known,
                const std::string& file);

// Fails unless `node` is a map.
void require_map(const YAML::Node& node, const std::string& what, const std::string& file);

// A number; `parent` locates a missing key.
double number(const YAML::Node& parent, const char* key, const std::string& file);
// A number > 0 (or >= 0 with allow_zero).
double positive(const YAML::Node& parent, const char* key, const std::string& file,
                bool allow_zero = false);
double number_node(const YAML::Node& node, const std::string& what, const std::string& file);
int integer(const YAML::Node& parent, const char* key, const std::string& file);
std::string text(const YAML::Node& parent, const char* key, const std::string& file);

// `material:` as a preset name or {E_MPa, poisson}.
Material material(const YAML::Node& node, const std::string& file);

}  // namespace deflex::stiffness::yaml_read
