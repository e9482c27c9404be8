#include "deflex/report/compliance.hpp"

#include <cstdio>
#include <sstream>

#include "deflex/report/json.hpp"

namespace deflex::report {

namespace {
std::string fmt(const char* f, double v) {
  char b[48];
  std::snprintf(b, sizeof b, f, v == 0 ? 0.0 : v);  // no "-0"
  return b;
}
}  // namespace

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
    o << "\nh = " << fmt("%.3f", r.height_mm) << " mm    k_x = " << fmt("%.2f", 1e-3 / c(0, 0))
      << " N/um, k_y = " << fmt("%.2f", 1e-3 / c(1, 1)) << " N/um\n";
    const char* axis[3] = {"  dx", "  dy", "  dz"};
    for (int i = 0; i < 3; ++i) {
      o << axis[i];
      for (int j = 0; j < 3; ++j) o << "  " << fmt("% .4e", c(i, j));
      o << "\n";
    }
  }
  return o.str();
}

}  // namespace deflex::report
