// Settings named in the library's messages. The library writes a setting as
// {keyword}, in the vocabulary of the job's settings (job::Settings, job
// files, Python's deflex.Job: tolerance_mm, feed_limit_N, ...); each front end
// shows it by its own name when the text leaves the library: the command line
// as its flag (--tolerance), Python as the keyword. So one message reads
// right whether it came from `deflex compensate` or from `deflex.Job`.
#pragma once
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace deflex {

// Every keyword a message may name. Only these are replaced, so braces in a
// file name or a program's comment are never taken for a setting.
std::span<const std::string_view> setting_keywords();

// A front end's name for a keyword. An empty function names it by the keyword.
using SettingNames = std::function<std::string(std::string_view keyword)>;

// `text` with each {keyword} of the vocabulary replaced by its name.
std::string name_settings(std::string_view text, const SettingNames& names);

// The keywords `text` names as {keyword}, in order, each once.
std::vector<std::string> settings_named(std::string_view text);

}  // namespace deflex
