// Output of `deflex stiffness`: C(h) as a text table or as JSON.
#pragma once
#include <string>
#include <vector>

#include "deflex/stiffness/compliance.hpp"

namespace deflex::stiffness {

// {"compliance": [{"height_mm": H, "matrix_mm_per_N": [[..],[..],[..]]}, ...]}
// rows = displacement x, y, z; columns = force x, y, z.
std::string compliance_json(const std::vector<ComplianceRow>& rows);

// A readable table: one block per height, with the lateral stiffness 1/C_xx
// and 1/C_yy in N/um. `title` lines come first.
std::string compliance_text(const std::vector<ComplianceRow>& rows, const std::string& title);

// C(h) at each height.
std::vector<ComplianceRow> sample(const ComplianceTable& c, const std::vector<double>& heights_mm);

}  // namespace deflex::stiffness
