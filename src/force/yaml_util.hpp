// YAML helpers of the force module that report `file:line:col: error: ...` as
// deflex::Error(Exit::config). Private to src/force/.
#pragma once
#include <initializer_list>
#include <string>

#include <yaml-cpp/yaml.h>

namespace deflex::force::yaml {

std::string where(const std::string& file, const YAML::Mark& mark);  // yaml-cpp marks are 0-based
[[noreturn]] void fail(const std::string& file, const YAML::Mark& mark, const std::string& msg);

// The bytes of a file; Error(Exit::io) when it cannot be read.
std::string read_file(const std::string& path);
// Reads and parses a whole file; I/O errors are Exit::io, syntax errors Exit::config.
YAML::Node load_file(const std::string& path);
YAML::Node load_text(const std::string& text, const std::string& file);

void require_map(const YAML::Node& node, const std::string& what, const std::string& file);
// Fails on a key of `map` not in `known`, when `strict`.
void check_keys(const YAML::Node& map, std::initializer_list<const char*> known,
                const std::string& file);
double number(const YAML::Node& node, const std::string& what, const std::string& file);
// parent[key] as a number; `fallback` when absent (nullptr: the key is required).
double number_at(const YAML::Node& parent, const char* key, const std::string& file,
                 const double* fallback = nullptr);
std::string text_at(const YAML::Node& parent, const char* key, const std::string& file);

}  // namespace deflex::force::yaml
