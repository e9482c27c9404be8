#include "deflex/report/compliance.hpp"

#include <cstdio>
#include <sstream>

#include "deflex/report/json.hpp"

namespace deflex::report {

std::string formatted(const char* format, double v) {
  char b[64];
  std::snprintf(b, sizeof b, format, v == 0 ? 0.0 : v);  // no "-0"
  return b;
}

std::string compliance_matrix_text(const stiffness::Compliance& c) {
  std::string o;
  const char* axis[3] = {"  dx", "  dy", "  dz"};
  for (int i = 0; i < 3; ++i) {
    o += axis[i];
    for (int j = 0; j < 3; ++j) o += "  " + formatted("% .4e", c(i, j));
    o += "\n";
  }
  return o;
}

Json compliance_matrix_json(const stiffness::Compliance& c) {
  Json m = Json::array();
  for (int i = 0; i < 3; ++i) {
    Json row = Json::array();
    for (int j = 0; j < 3; ++j) row.push_back(significant(c(i, j), 7));
    m.push_back(row);
  }
  return m;
}

std::string compliance_json(const std::vector<stiffness::ComplianceRow>& rows) {
  Json list = Json::array();
  for (const auto& r : rows) {
    list.push_back({{"height_mm", significant(r.height_mm, 6)}, {"matrix_mm_per_N", compliance_matrix_json(r.matrix_mm_per_N)}});
  }
  return line({{"compliance", list}});
}

std::string compliance_text(const std::vector<stiffness::ComplianceRow>& rows, const std::string& title) {
  std::ostringstream o;
  o << title;
  o << "C(h): compliance at height h above the tip, on the tool axis, machine axes, mm/N\n"
       "      rows: displacement x, y, z; columns: force Fx, Fy, Fz\n";
  for (const auto& r : rows) {
    const auto& c = r.matrix_mm_per_N;
    o << "\nh = " << formatted("%.3f", r.height_mm) << " mm    k_x = " << formatted("%.2f", 1e-3 / c(0, 0))
      << " N/um, k_y = " << formatted("%.2f", 1e-3 / c(1, 1)) << " N/um\n"
      << compliance_matrix_text(c);
  }
  return o.str();
}

}  // namespace deflex::report
