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

// {"compliance": [{"height_mm": H, "matrix_mm_per_N": [[..],[..],[..]]}, ...]}
// rows = displacement x, y, z; columns = force x, y, z.
std::string compliance_json(const std::vector<stiffness::ComplianceRow>& rows);

// A readable table: one block per height, with the lateral stiffness 1/C_xx
// and 1/C_yy in N/um. `title` lines come first.
std::string compliance_text(const std::vector<stiffness::ComplianceRow>& rows, const std::string& title);

}  // namespace deflex::report
