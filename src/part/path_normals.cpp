// Normals of the CL (tip) surface from the neighbouring tip points
// (include/deflex/part/path_normals.hpp).
#include "deflex/part/path_normals.hpp"

#include <CGAL/Fuzzy_sphere.h>
#include <CGAL/Kd_tree.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Simple_cartesian.h>

#include <Eigen/Dense>
#include <cmath>
#include <iterator>

namespace deflex::part {
namespace {
using K = CGAL::Simple_cartesian<double>;
using Traits = CGAL::Search_traits_3<K>;
using Tree = CGAL::Kd_tree<Traits>;
using Sphere = CGAL::Fuzzy_sphere<Traits>;
}  // namespace

struct PathNormals::Impl {
  PathNormalOptions o;
  Tree tree;
  std::size_t n = 0;

  // The quadratic fit over the points within r; nothing when they do not span 2D.
  std::optional<Eigen::Vector3d> fit(const Eigen::Vector3d& q, double r) const {
    std::vector<K::Point_3> near;
    tree.search(std::back_inserter(near), Sphere(K::Point_3(q.x(), q.y(), q.z()), r, 0.0));
    if (near.size() < 6) return std::nullopt;
    // Spread across the smaller principal direction of the weighted XY offsets.
    const std::size_t m = near.size();
    Eigen::VectorXd w(m);
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    double ws = 0;
    for (std::size_t i = 0; i < m; ++i) {
      const Eigen::Vector3d d(near[i].x() - q.x(), near[i].y() - q.y(), near[i].z() - q.z());
      const double t = 1.0 - d.squaredNorm() / (r * r);
      w[static_cast<Eigen::Index>(i)] = t * t + 1e-6;
      mean += w[static_cast<Eigen::Index>(i)] * d.head<2>();
      ws += w[static_cast<Eigen::Index>(i)];
    }
    mean /= ws;
    for (std::size_t i = 0; i < m; ++i) {
      const Eigen::Vector2d d = Eigen::Vector2d(near[i].x() - q.x(), near[i].y() - q.y()) - mean;
      cov += w[static_cast<Eigen::Index>(i)] * d * d.transpose();
    }
    cov /= ws;
    const double minor = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(cov).eigenvalues()[0];
    if (!(std::sqrt(std::max(minor, 0.0)) >= o.min_spread * r)) return std::nullopt;
    // z - z_q = c0 + c1 x + c2 y + c3 x^2 + c4 x y + c5 y^2 (offsets from q, scaled by r).
    Eigen::MatrixXd A(m, 6);
    Eigen::VectorXd b(m);
    for (std::size_t i = 0; i < m; ++i) {
      const double x = (near[i].x() - q.x()) / r, y = (near[i].y() - q.y()) / r;
      const double sw = std::sqrt(w[static_cast<Eigen::Index>(i)]);
      A.row(static_cast<Eigen::Index>(i)) << sw, sw * x, sw * y, sw * x * x, sw * x * y, sw * y * y;
      b[static_cast<Eigen::Index>(i)] = sw * (near[i].z() - q.z());
    }
    const Eigen::VectorXd c = A.colPivHouseholderQr().solve(b);
    if (!c.allFinite()) return std::nullopt;
    return Eigen::Vector3d(-c[1] / r, -c[2] / r, 1.0).normalized();
  }
};

PathNormals::PathNormals(std::vector<Eigen::Vector3d> tips_mm, const PathNormalOptions& o)
    : impl_(std::make_unique<Impl>()) {
  impl_->o = o;
  impl_->n = tips_mm.size();
  for (const auto& p : tips_mm) impl_->tree.insert(K::Point_3(p.x(), p.y(), p.z()));
  impl_->tree.build();  // now, not lazily on the first (threaded) query
}
PathNormals::PathNormals(PathNormals&&) noexcept = default;
PathNormals::~PathNormals() = default;

std::size_t PathNormals::points() const { return impl_->n; }

std::optional<Eigen::Vector3d> PathNormals::normal_at(const Eigen::Vector3d& tip_mm) const {
  for (double r = impl_->o.radius_mm; r <= impl_->o.max_radius_mm * (1 + 1e-9); r *= 2)
    if (auto n = impl_->fit(tip_mm, r)) return n;
  return std::nullopt;
}

}  // namespace deflex::part
