#include "deflex/stiffness/workpiece_field.hpp"

#include <Eigen/Dense>
#include <algorithm>
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

namespace {
const double kSameFace = std::cos(WorkpieceField::kSameFaceDeg * 3.14159265358979323846 / 180);
}  // namespace

std::vector<Compliance> compliances(const WorkpieceModel& model, const std::vector<V3>& points_mm,
                                    SolvedCompliances* solved, const std::function<void(double)>& progress) {
  auto key = [](const V3& p) { return std::make_tuple(p.x(), p.y(), p.z()); };
  std::vector<V3> todo;
  for (const V3& p : points_mm)
    if (!solved || !solved->count(key(p))) todo.push_back(p);
  SolvedCompliances local;
  SolvedCompliances& into = solved ? *solved : local;
  // In chunks of a few batches, for the progress.
  const std::size_t chunk = 4 * WorkpieceModel::kBatchPoints;
  for (std::size_t b = 0; b < todo.size(); b += chunk) {
    const std::vector<V3> some(todo.begin() + static_cast<std::ptrdiff_t>(b),
                               todo.begin() + static_cast<std::ptrdiff_t>(std::min(todo.size(), b + chunk)));
    for (const PointCompliance& pc : model.compliance_at(some)) into[key(pc.point_mm)] = pc.matrix_mm_per_N;
    if (progress) progress(double(std::min(todo.size(), b + chunk)) / todo.size());
  }
  std::vector<Compliance> c;
  for (const V3& p : points_mm) c.push_back(into.at(key(p)));
  return c;
}

WorkpieceField::WorkpieceField(const WorkpieceModel& model, const std::vector<V3>& points_mm,
                               const std::vector<V3>& normals, double spacing_mm,
                               const std::function<void(double)>& progress, SolvedCompliances* solved)
    : h_(spacing_mm) {
  if (!(spacing_mm > 0)) throw Error(ErrorKind::settings, "workpiece field: the node spacing must be > 0 mm");
  if (normals.size() != points_mm.size()) throw Error(ErrorKind::internal, "workpiece field: a normal per point");
  for (std::size_t i = 0; i < points_mm.size(); ++i) {
    std::vector<std::size_t>& cell = cells_[key(points_mm[i])];
    const bool face_has_one = std::any_of(cell.begin(), cell.end(), [&](std::size_t n) { return normal_[n].dot(normals[i]) >= kSameFace; });
    if (face_has_one) continue;
    cell.push_back(node_mm_.size());
    node_mm_.push_back(points_mm[i]);
    normal_.push_back(normals[i]);
  }
  c_ = compliances(model, node_mm_, solved, progress);
}

void WorkpieceField::near_nodes(const V3& p, const V3& normal, std::vector<std::size_t>& near) const {
  const double r = 2 * h_;
  const auto i0 = static_cast<std::int64_t>(std::floor(p.x() / h_)), j0 = static_cast<std::int64_t>(std::floor(p.y() / h_)),
             k0 = static_cast<std::int64_t>(std::floor(p.z() / h_));
  near.clear();
  for (std::int64_t i = i0 - 2; i <= i0 + 2; ++i)
    for (std::int64_t j = j0 - 2; j <= j0 + 2; ++j)
      for (std::int64_t k = k0 - 2; k <= k0 + 2; ++k) {
        const auto it = cells_.find(key(i, j, k));
        if (it == cells_.end()) continue;
        for (std::size_t n : it->second)
          if ((node_mm_[n] - p).norm() <= r && normal_[n].dot(normal) >= kSameFace) near.push_back(n);
      }
}

double WorkpieceField::node_distance_mm(const V3& p, const V3& normal) const {
  thread_local std::vector<std::size_t> near;
  near_nodes(p, normal, near);
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t n : near) d = std::min(d, (node_mm_[n] - p).norm());
  return d;
}

Compliance WorkpieceField::at(const V3& p, const V3& normal, bool* covered) const {
  if (node_mm_.empty()) throw Error(ErrorKind::internal, "workpiece field: no nodes");
  const double r = 2 * h_;
  thread_local std::vector<std::size_t> near;
  near_nodes(p, normal, near);
  if (covered) *covered = !near.empty();
  std::size_t best = 0;
  double best_d = std::numeric_limits<double>::infinity();
  for (std::size_t n : near)
    if ((node_mm_[n] - p).norm() < best_d) best_d = (node_mm_[n] - p).norm(), best = n;
  if (near.size() < 4) {
    // Far from every node of the face: its nearest, else the nearest of all.
    for (int pass = 0; pass < 2 && near.empty() && best_d == std::numeric_limits<double>::infinity(); ++pass)
      for (std::size_t n = 0; n < node_mm_.size(); ++n)
        if ((pass == 1 || normal_[n].dot(normal) >= kSameFace) && (node_mm_[n] - p).norm() < best_d)
          best_d = (node_mm_[n] - p).norm(), best = n;
    return c_[best];
  }
  if (best_d < 1e-9 * h_) return c_[best];
  // Weighted least squares of C = a + b . (x - p) over the nodes near, each
  // of the nine entries alike, the slopes b held toward zero by a ridge of a
  // hundredth of the weights: nodes on a surface leave the normal's slope
  // undetermined, and nodes along a narrow face (the top of a thin wall) its
  // slope across nearly so, which unheld would extrapolate without bound.
  const auto m = static_cast<Eigen::Index>(near.size());
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(m + 3, 4), B = Eigen::MatrixXd::Zero(m + 3, 9);
  double w2 = 0;
  for (Eigen::Index q = 0; q < m; ++q) {
    const std::size_t n = near[static_cast<std::size_t>(q)];
    const V3 d = node_mm_[n] - p;
    const double w = std::pow(1 - std::min(1.0, d.norm() / r), 2) + 1e-12;  // smooth, 0 at the radius
    A(q, 0) = w;
    A.block<1, 3>(q, 1) = w * d.transpose() / h_;
    B.row(q) = w * Eigen::Map<const Eigen::Matrix<double, 1, 9>>(c_[n].data());
    w2 += w * w;
  }
  for (int k = 0; k < 3; ++k) A(m + k, 1 + k) = std::sqrt(0.01 * w2);
  const Eigen::MatrixXd x = A.completeOrthogonalDecomposition().solve(B);
  Compliance c;
  Eigen::Map<Eigen::Matrix<double, 1, 9>>(c.data()) = x.row(0);
  return c;
}

double WorkpieceField::largest_entry_mm_per_N() const {
  double m = 0;
  for (const Compliance& c : c_) m = std::max(m, c.cwiseAbs().maxCoeff());
  return m;
}

}  // namespace deflex::stiffness
