// YAML reading shared by every library file deflex loads (config, machine
// profiles, dialects, tool and material libraries): each error is a
// deflex::Error(Exit::config) whose text starts `file:line:col: error:`.
#pragma once
#include <initializer_list>
#include <string>

#include <yaml-cpp/yaml.h>

namespace deflex::yaml {

std::string where(const std::string& file, const YAML::Mark& mark);  // yaml-cpp marks are 0-based
[[noreturn]] void fail(const std::string& file, const YAML::Mark& mark, const std::string& msg);

std::string read_file(const std::string& path);  // Error(Exit::io) when it cannot be read
YAML::Node load_file(const std::string& path);
YAML::Node load_text(const std::string& text, const std::string& file);

void require_map(const YAML::Node& node, const std::string& what, const std::string& file);
// Unknown keys are errors: a typo in a library must not pass silently.
void check_keys(const YAML::Node& map, std::initializer_list<const char*> known, const std::string& file);
double number(const YAML::Node& node, const std::string& what, const std::string& file);  // finite
double number_at(const YAML::Node& parent, const char* key, const std::string& file,
                 const double* fallback = nullptr);
std::string text_at(const YAML::Node& parent, const char* key, const std::string& file);

}  // namespace deflex::yaml
