// The one JSON writer of deflex: every JSON document a command prints or
// writes (check, diff, stiffness, forces, summary.json) is built as an
// nlohmann::ordered_json, so strings are escaped by the library and fields
// keep the order they were added in. Shared field names: "file" for a program
// or library path, "line" and "col" for 1-based positions, "_mm"/"_N" units.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::report {

using Json = nlohmann::ordered_json;

// `v` rounded to `decimals` places (no -0): JSON numbers carry the precision
// the text output does, not binary noise like 0.30000000000000004.
double fixed(double v, int decimals);
// `v` rounded to `digits` significant digits (as printf's %.<digits>g).
double significant(double v, int digits);
// [x, y, z], each rounded to `decimals` places.
Json xyz(double x, double y, double z, int decimals);

// {file, line, col, severity, message}; line and col are 0 when unknown.
Json to_json(const Diagnostic& d);
Json to_json(const std::vector<Diagnostic>& all);

// One line and a newline (stdout); invalid UTF-8 in a string (a file name in
// another encoding) is replaced, never an exception.
std::string line(const Json& j);
// Indented, for files a person opens (summary.json).
std::string document(const Json& j);

}  // namespace deflex::report
