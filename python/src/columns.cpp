// The columns of points.csv (columns.hpp), named by the library's own header
// (report::kPointsCsvHeader) so that a column added there without a binding
// here fails loudly at the first run instead of going missing.
#include "columns.hpp"

#include <pybind11/numpy.h>

#include <functional>
#include <map>
#include <sstream>
#include <stdexcept>

namespace deflex::python {
namespace {

using Get = std::function<double(const report::PointRow&)>;

// The float columns by header name, from PointRow's fields (in the order
// report/recorder.cpp's write_csv writes them).
const std::map<std::string, Get>& getters() {
  using R = report::PointRow;
  static const std::map<std::string, Get> g = {
      {"x_mm", [](const R& r) { return r.tip_mm.x(); }},
      {"y_mm", [](const R& r) { return r.tip_mm.y(); }},
      {"z_mm", [](const R& r) { return r.tip_mm.z(); }},
      {"path_mm", [](const R& r) { return r.path_mm; }},
      {"ap_mm", [](const R& r) { return r.ap_mm; }},
      {"ae_mm", [](const R& r) { return r.ae_mm; }},
      {"d_eff_mm", [](const R& r) { return r.d_eff_mm; }},
      {"cwe_area_mm2", [](const R& r) { return r.cwe_area_mm2; }},
      {"mrr_mm3_per_s", [](const R& r) { return r.mrr_mm3_per_s; }},
      {"Fx_N", [](const R& r) { return r.force_N.x(); }},
      {"Fy_N", [](const R& r) { return r.force_N.y(); }},
      {"Fz_N", [](const R& r) { return r.force_N.z(); }},
      {"dx_mm", [](const R& r) { return r.delta_mm.x(); }},
      {"dy_mm", [](const R& r) { return r.delta_mm.y(); }},
      {"dz_mm", [](const R& r) { return r.delta_mm.z(); }},
      {"surface_error_mm", [](const R& r) { return r.surface_error_mm; }},
      {"surface_error_as_written_mm", [](const R& r) { return r.surface_error_as_written_mm; }},
      {"offset_mm", [](const R& r) { return r.offset_mm; }},
      {"nx", [](const R& r) { return r.normal.x(); }},
      {"ny", [](const R& r) { return r.normal.y(); }},
      {"nz", [](const R& r) { return r.normal.z(); }},
      {"part_gap_mm", [](const R& r) { return r.part_gap_mm; }},
      {"flank_min_mm", [](const R& r) { return r.flank_min_mm; }},
      {"flank_max_mm", [](const R& r) { return r.flank_max_mm; }},
      {"flank_z_min_mm", [](const R& r) { return r.flank_z_min_mm; }},
      {"flank_z_max_mm", [](const R& r) { return r.flank_z_max_mm; }},
      {"stepover_mm", [](const R& r) { return r.stepover_mm; }},
      {"cusp_height_mm", [](const R& r) { return r.cusp_height_mm; }},
      {"power_kW", [](const R& r) { return r.power_kW; }},
      {"torque_Nm", [](const R& r) { return r.torque_Nm; }},
      {"ap_limit_mm", [](const R& r) { return r.ap_limit_mm; }},
      {"workpiece_dx_mm", [](const R& r) { return r.workpiece_delta_mm.x(); }},
      {"workpiece_dy_mm", [](const R& r) { return r.workpiece_delta_mm.y(); }},
      {"workpiece_dz_mm", [](const R& r) { return r.workpiece_delta_mm.z(); }},
  };
  return g;
}

std::vector<std::string> header_names() {
  std::vector<std::string> names;
  std::istringstream in(report::kPointsCsvHeader);
  for (std::string n; std::getline(in, n, ',');) {
    while (!n.empty() && (n.back() == '\n' || n.back() == '\r')) n.pop_back();
    names.push_back(n);
  }
  return names;
}

bool is_float(const std::string& name) { return name != "line" && name != "normal_source"; }

}  // namespace

Columns::Columns() : names_(header_names()) {
  for (const std::string& n : names_) {
    if (!is_float(n)) continue;
    if (!getters().count(n))
      throw std::logic_error("points.csv column '" + n + "' has no Python binding (python/src/columns.cpp)");
    values_.emplace_back();
  }
}

void Columns::add(const report::PointRow& r) {
  lines_.push_back(r.line);
  normal_sources_.emplace_back(r.normal_source ? r.normal_source : "");
  std::size_t k = 0;
  for (const std::string& n : names_)
    if (is_float(n)) values_[k++].push_back(getters().at(n)(r));
}

py::dict Columns::to_numpy() const {
  py::dict d;
  std::size_t k = 0;
  for (const std::string& n : names_) {
    if (n == "line") {
      py::array_t<std::int64_t> a(py::ssize_t(lines_.size()));
      auto w = a.mutable_unchecked<1>();
      for (std::size_t i = 0; i < lines_.size(); ++i) w(py::ssize_t(i)) = lines_[i];
      d[n.c_str()] = a;
    } else if (n == "normal_source") {
      py::array a(py::dtype("O"), py::array::ShapeContainer{py::ssize_t(normal_sources_.size())});
      // A handful of distinct values: one str object each, shared by the rows.
      std::map<std::string, py::str> interned;
      auto** data = static_cast<PyObject**>(a.mutable_data());
      for (std::size_t i = 0; i < normal_sources_.size(); ++i) {
        auto it = interned.try_emplace(normal_sources_[i], py::str(normal_sources_[i])).first;
        Py_XDECREF(data[i]);
        data[i] = it->second.inc_ref().ptr();
      }
      d[n.c_str()] = a;
    } else {
      const std::vector<double>& v = values_[k++];
      d[n.c_str()] = py::array_t<double>(py::ssize_t(v.size()), v.data());
    }
  }
  return d;
}

}  // namespace deflex::python
