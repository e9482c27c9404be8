#include "deflex/stiffness/report.hpp"

#include <cstdio>
#include <sstream>

namespace deflex::stiffness {

namespace {
std::string fmt(const char* f, double v) {
  char b[48];
  std::snprintf(b, sizeof b, f, v == 0 ? 0.0 : v);  // no "-0"
  return b;
}
}  // namespace

std::string compliance_json(const std::vector<ComplianceRow>& rows) {
  std::ostringstream o;
  o << "{\"compliance\": [";
  for (std::size_t k = 0; k < rows.size(); ++k) {
    o << (k ? ", " : "") << "{\"height_mm\": " << fmt("%.6g", rows[k].height_mm)
      << ", \"matrix_mm_per_N\": [";
    for (int i = 0; i < 3; ++i) {
      o << (i ? ", " : "") << "[";
      for (int j = 0; j < 3; ++j) o << (j ? ", " : "") << fmt("%.7g", rows[k].matrix_mm_per_N(i, j));
      o << "]";
    }
    o << "]}";
  }
  o << "]}\n";
  return o.str();
}

std::string compliance_text(const std::vector<ComplianceRow>& rows, const std::string& title) {
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

std::vector<ComplianceRow> sample(const ComplianceTable& c, const std::vector<double>& heights_mm) {
  std::vector<ComplianceRow> rows;
  for (double h : heights_mm) rows.push_back({h, c.at(h)});
  return rows;
}

}  // namespace deflex::stiffness
