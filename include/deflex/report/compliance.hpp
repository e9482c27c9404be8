// C(h) as a text table or as JSON (the output of `deflex stiffness`). Here, not
// in stiffness/, because it is written with the report's JSON writer.
#pragma once
#include <string>
#include <vector>

#include "deflex/report/json.hpp"
#include "deflex/stiffness/compliance.hpp"

namespace deflex::report {

// [[..],[..],[..]]: rows displacement x, y, z; columns force x, y, z; mm/N,
// 7 significant digits.
Json compliance_matrix_json(const stiffness::Compliance& c);

// The same as three text rows "  dx  ...", "  dy", "  dz" of 4-digit
// mantissas, each ending in a newline.
std::string compliance_matrix_text(const stiffness::Compliance& c);

// `v` by a printf format of one double conversion ("%.3f"), never "-0".
std::string formatted(const char* format, double v);

// {"compliance": [{"height_mm": H, "matrix_mm_per_N": [[..],[..],[..]]}, ...]}
// rows = displacement x, y, z; columns = force x, y, z.
std::string compliance_json(const std::vector<stiffness::ComplianceRow>& rows);

// A readable table: one block per height, with the lateral stiffness 1/C_xx
// and 1/C_yy in N/um. `title` lines come first.
std::string compliance_text(const std::vector<stiffness::ComplianceRow>& rows, const std::string& title);

}  // namespace deflex::report
