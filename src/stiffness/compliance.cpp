#include "deflex/stiffness/compliance.hpp"

#include <algorithm>
#include <array>
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

CrossComplianceTable::CrossComplianceTable(std::vector<double> heights_mm,
                                           Eigen::MatrixXd lateral_mm_per_N,
                                           Eigen::MatrixXd axial_mm_per_N,
                                           const Compliance& structure_mm_per_N)
    : h_(std::move(heights_mm)),
      lateral_(std::move(lateral_mm_per_N)),
      axial_(std::move(axial_mm_per_N)),
      structure_(structure_mm_per_N) {
  const auto n = static_cast<Eigen::Index>(h_.size());
  if (lateral_.rows() != n || lateral_.cols() != n || axial_.rows() != n || axial_.cols() != n)
    throw std::invalid_argument("CrossComplianceTable: matrices must be stations x stations");
  for (std::size_t i = 1; i < h_.size(); ++i)
    if (!(h_[i] > h_[i - 1]))
      throw std::invalid_argument("CrossComplianceTable: heights must ascend strictly");
}

namespace {

// Interpolation weights at h: value(h) = sum w_k f(idx_k), the cubic Hermite of
// ComplianceTable::at written as a linear map of the station values (its
// finite-difference slopes are themselves linear in them).
struct Weights {
  std::array<std::size_t, 8> idx{};
  std::array<double, 8> w{};
  int n = 0;
  void add(std::size_t i, double v) {
    idx[static_cast<std::size_t>(n)] = i;
    w[static_cast<std::size_t>(n++)] = v;
  }
};

// Adds scale * (slope at station i) as weights (slope_at above, in Lagrange form).
void add_slope(const std::vector<double>& x, std::size_t i, double scale, Weights& out) {
  const std::size_t n = x.size();
  if (n == 2) {
    const double d = 1 / (x[1] - x[0]);
    out.add(0, -scale * d);
    out.add(1, scale * d);
    return;
  }
  const std::size_t a = i == 0 ? 0 : (i == n - 1 ? n - 3 : i - 1);
  const double x0 = x[a], x1 = x[a + 1], x2 = x[a + 2];
  const double q = ((x[i] - x0) + (x[i] - x1)) / (x2 - x0);  // slope = (1-q) d01 + q d12
  out.add(a, -scale * (1 - q) / (x1 - x0));
  out.add(a + 1, scale * ((1 - q) / (x1 - x0) - q / (x2 - x1)));
  out.add(a + 2, scale * q / (x2 - x1));
}

Weights hermite_weights(const std::vector<double>& x, double h) {
  Weights wt;
  if (x.size() == 1 || h <= x.front()) {
    wt.add(0, 1);
    return wt;
  }
  if (h >= x.back()) {
    wt.add(x.size() - 1, 1);
    return wt;
  }
  const std::size_t i =
      static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), h) - x.begin()) - 1;
  const double dx = x[i + 1] - x[i], t = (h - x[i]) / dx;
  wt.add(i, (1 + 2 * t) * (1 - t) * (1 - t));
  wt.add(i + 1, t * t * (3 - 2 * t));
  add_slope(x, i, dx * t * (1 - t) * (1 - t), wt);
  add_slope(x, i + 1, dx * t * t * (t - 1), wt);
  return wt;
}

}  // namespace

Compliance CrossComplianceTable::at(double z_mm, double zp_mm) const {
  if (h_.empty()) throw std::logic_error("CrossComplianceTable::at on an empty table");
  const Weights a = hermite_weights(h_, z_mm), b = hermite_weights(h_, zp_mm);
  double lat = 0, ax = 0;
  for (int p = 0; p < a.n; ++p)
    for (int q = 0; q < b.n; ++q) {
      const double w = a.w[static_cast<std::size_t>(p)] * b.w[static_cast<std::size_t>(q)];
      const auto i = static_cast<Eigen::Index>(a.idx[static_cast<std::size_t>(p)]);
      const auto j = static_cast<Eigen::Index>(b.idx[static_cast<std::size_t>(q)]);
      lat += w * lateral_(i, j);
      ax += w * axial_(i, j);
    }
  Compliance c = Eigen::Vector3d(lat, lat, ax).asDiagonal();
  return c + structure_;
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

std::vector<ComplianceRow> sample(const ComplianceTable& c, const std::vector<double>& heights_mm) {
  std::vector<ComplianceRow> rows;
  for (double h : heights_mm) rows.push_back({h, c.at(h)});
  return rows;
}

}  // namespace deflex::stiffness
