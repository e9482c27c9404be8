#include "deflex/stiffness/workpiece_field.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <limits>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::stiffness {

using V3 = Eigen::Vector3d;

namespace {
// Cell indices within +-2^20 cells of the origin pack into one key.
constexpr std::int64_t kSpan = std::int64_t{1} << 21;
}  // namespace

WorkpieceField::Key WorkpieceField::key(std::int64_t i, std::int64_t j, std::int64_t k) const {
  return ((i + kSpan / 2) * kSpan + (j + kSpan / 2)) * kSpan + (k + kSpan / 2);
}

WorkpieceField::Key WorkpieceField::key(const V3& p) const {
  return key(static_cast<std::int64_t>(std::floor(p.x() / h_)), static_cast<std::int64_t>(std::floor(p.y() / h_)),
             static_cast<std::int64_t>(std::floor(p.z() / h_)));
}

WorkpieceField::WorkpieceField(const WorkpieceModel& model, const std::vector<V3>& points_mm, double spacing_mm)
    : h_(spacing_mm) {
  if (!(spacing_mm > 0)) throw Error(ErrorKind::settings, "workpiece field: the node spacing must be > 0 mm");
  for (const V3& p : points_mm) {
    std::vector<std::size_t>& cell = cells_[key(p)];
    if (!cell.empty()) continue;
    cell.push_back(node_mm_.size());
    node_mm_.push_back(p);
  }
  for (const PointCompliance& pc : model.compliance_at(node_mm_)) c_.push_back(pc.matrix_mm_per_N);
}

Compliance WorkpieceField::at(const V3& p) const {
  if (node_mm_.empty()) throw Error(ErrorKind::internal, "workpiece field: no nodes");
  const double r = 2 * h_;
  const auto i0 = static_cast<std::int64_t>(std::floor(p.x() / h_)), j0 = static_cast<std::int64_t>(std::floor(p.y() / h_)),
             k0 = static_cast<std::int64_t>(std::floor(p.z() / h_));
  thread_local std::vector<std::size_t> near;
  near.clear();
  for (std::int64_t i = i0 - 2; i <= i0 + 2; ++i)
    for (std::int64_t j = j0 - 2; j <= j0 + 2; ++j)
      for (std::int64_t k = k0 - 2; k <= k0 + 2; ++k) {
        const auto it = cells_.find(key(i, j, k));
        if (it == cells_.end()) continue;
        for (std::size_t n : it->second)
          if ((node_mm_[n] - p).norm() <= r) near.push_back(n);
      }
  std::size_t best = 0;
  double best_d = std::numeric_limits<double>::infinity();
  for (std::size_t n : near)
    if ((node_mm_[n] - p).norm() < best_d) best_d = (node_mm_[n] - p).norm(), best = n;
  if (near.size() < 4) {
    if (near.empty())  // far from every node: the nearest of all
      for (std::size_t n = 0; n < node_mm_.size(); ++n)
        if ((node_mm_[n] - p).norm() < best_d) best_d = (node_mm_[n] - p).norm(), best = n;
    return c_[best];
  }
  if (best_d < 1e-9 * h_) return c_[best];
  // Weighted least squares of C = a + b . (x - p) over the nodes near, each
  // of the nine entries alike; nodes on a surface leave the normal's slope
  // undetermined, which the minimum-norm solution sets to zero.
  const auto m = static_cast<Eigen::Index>(near.size());
  Eigen::MatrixXd A(m, 4), B(m, 9);
  for (Eigen::Index q = 0; q < m; ++q) {
    const std::size_t n = near[static_cast<std::size_t>(q)];
    const V3 d = node_mm_[n] - p;
    const double w = std::pow(1 - std::min(1.0, d.norm() / r), 2) + 1e-12;  // smooth, 0 at the radius
    A(q, 0) = w;
    A.block<1, 3>(q, 1) = w * d.transpose() / h_;
    B.row(q) = w * Eigen::Map<const Eigen::Matrix<double, 1, 9>>(c_[n].data());
  }
  const Eigen::MatrixXd x = A.completeOrthogonalDecomposition().solve(B);
  Compliance c;
  Eigen::Map<Eigen::Matrix<double, 1, 9>>(c.data()) = x.row(0);
  return c;
}

}  // namespace deflex::stiffness
