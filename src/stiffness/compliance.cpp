#include "deflex/stiffness/compliance.hpp"

#include <algorithm>
#include <stdexcept>

namespace deflex::stiffness {

ComplianceTable::ComplianceTable(std::vector<ComplianceRow> rows) : rows_(std::move(rows)) {
  std::sort(rows_.begin(), rows_.end(),
            [](const auto& a, const auto& b) { return a.height_mm < b.height_mm; });
  for (std::size_t i = 1; i < rows_.size(); ++i)
    if (!(rows_[i].height_mm > rows_[i - 1].height_mm))
      throw std::invalid_argument("ComplianceTable: duplicate station height");
}

// Slope at station i: derivative of the parabola through i and its neighbours
// (exact for a quadratic C(h)).
static Compliance slope_at(const std::vector<ComplianceRow>& r, std::size_t i) {
  const std::size_t n = r.size();
  if (n == 2) return (r[1].matrix_mm_per_N - r[0].matrix_mm_per_N) / (r[1].height_mm - r[0].height_mm);
  const std::size_t a = i == 0 ? 0 : (i == n - 1 ? n - 3 : i - 1);
  const double x0 = r[a].height_mm, x1 = r[a + 1].height_mm, x2 = r[a + 2].height_mm;
  const Compliance d01 = (r[a + 1].matrix_mm_per_N - r[a].matrix_mm_per_N) / (x1 - x0);
  const Compliance d12 = (r[a + 2].matrix_mm_per_N - r[a + 1].matrix_mm_per_N) / (x2 - x1);
  const Compliance f012 = (d12 - d01) / (x2 - x0);
  const double x = r[i].height_mm;
  // Newton form p(x) = f0 + d01 (x - x0) + f012 (x - x0)(x - x1).
  return d01 + f012 * ((x - x0) + (x - x1));
}

Compliance ComplianceTable::at(double h) const {
  if (rows_.empty()) throw std::logic_error("ComplianceTable::at on an empty table");
  if (rows_.size() == 1 || h <= rows_.front().height_mm) return rows_.front().matrix_mm_per_N;
  if (h >= rows_.back().height_mm) return rows_.back().matrix_mm_per_N;
  const auto it = std::upper_bound(rows_.begin(), rows_.end(), h,
                                   [](double v, const ComplianceRow& r) { return v < r.height_mm; });
  const std::size_t i = static_cast<std::size_t>(it - rows_.begin()) - 1;
  const double x0 = rows_[i].height_mm, dx = rows_[i + 1].height_mm - x0;
  const double t = (h - x0) / dx;
  // Cubic Hermite basis.
  const double h00 = (1 + 2 * t) * (1 - t) * (1 - t), h10 = t * (1 - t) * (1 - t);
  const double h01 = t * t * (3 - 2 * t), h11 = t * t * (t - 1);
  return h00 * rows_[i].matrix_mm_per_N + h10 * dx * slope_at(rows_, i) +
         h01 * rows_[i + 1].matrix_mm_per_N + h11 * dx * slope_at(rows_, i + 1);
}

Eigen::Vector3d deflection_mm(const ComplianceTable& c, double height_mm,
                              const Eigen::Vector3d& force_N) {
  return c.at(height_mm) * force_N;
}

std::vector<double> station_heights_mm(double top_mm, int steps) {
  steps = std::max(steps, 1);
  std::vector<double> h(static_cast<std::size_t>(steps) + 1);
  for (int i = 0; i <= steps; ++i) h[static_cast<std::size_t>(i)] = top_mm * i / steps;
  return h;
}

}  // namespace deflex::stiffness
