// Normals of the CL (tip) surface from the neighbouring tip points
// (include/deflex/part/path_normals.hpp).
#include "deflex/part/path_normals.hpp"

#include <CGAL/Fuzzy_sphere.h>
#include <CGAL/Kd_tree.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Simple_cartesian.h>

#include <Eigen/Dense>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <mutex>
#include <unordered_map>

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
  // The normals already fitted, by the query's bits: a compensation asks at
  // the same design tip again and again (the program as written, then each
  // trial of the mirror pass at a point it leaves alone), and a fit is a
  // pure function of the query, so the answer is the one a new fit gives.
  struct Bits {
    std::size_t operator()(const std::array<std::uint64_t, 3>& k) const {
      std::size_t h = 0;
      for (std::uint64_t v : k) h = (h ^ std::hash<std::uint64_t>{}(v)) * 0x100000001b3ull;
      return h;
    }
  };
  mutable std::mutex memo_mutex;
  mutable std::unordered_map<std::array<std::uint64_t, 3>, std::optional<Eigen::Vector3d>, Bits> memo;

  // The quadratic fit over the points within r; nothing when they do not span 2D.
  std::optional<Eigen::Vector3d> fit(const Eigen::Vector3d& q, double r) const {
    // Kept per thread: a fresh vector per fit cost its growth by doubling
    // (several allocations) for every CL point and every radius tried.
    thread_local std::vector<K::Point_3> near;
    near.clear();
    tree.search(std::back_inserter(near), Sphere(K::Point_3(q.x(), q.y(), q.z()), r, 0.0));
    if (near.size() < 6) return std::nullopt;
    const std::size_t m = near.size();
    Eigen::VectorXd w(m);
    for (std::size_t i = 0; i < m; ++i) {
      const Eigen::Vector3d d(near[i].x() - q.x(), near[i].y() - q.y(), near[i].z() - q.z());
      const double t = 1.0 - d.squaredNorm() / (r * r);
      w[static_cast<Eigen::Index>(i)] = t * t + 1e-6;
    }
    // z - z_q = c0 + c1 x + c2 y + c3 x^2 + c4 x y + c5 y^2 (offsets from q, scaled by r).
    Eigen::MatrixXd A(m, 6);
    Eigen::VectorXd b(m);
    for (std::size_t i = 0; i < m; ++i) {
      const double x = (near[i].x() - q.x()) / r, y = (near[i].y() - q.y()) / r;
      const double sw = std::sqrt(w[static_cast<Eigen::Index>(i)]);
      A.row(static_cast<Eigen::Index>(i)) << sw, sw * x, sw * y, sw * x * x, sw * x * y, sw * y * y;
      b[static_cast<Eigen::Index>(i)] = sw * (near[i].z() - q.z());
    }
    return determined_normal(A, b, r);
  }

  // The slope of the least-squares fit and how well the points pin it down:
  // through the eigen-decomposition of the normal equations N = A'A, so a
  // term the points cannot tell from another (two rows of points across the
  // feed: y^2 is s y on them) shows as a vanishing eigenvalue, not as an
  // arbitrary split between the two (which tilted edge-pass normals by tens of
  // degrees). The slope's standard error, from the residual scatter (at least
  // the rounding of the program's digits), must stay under max_slope_error_rad;
  // else the points do not determine the normal at this radius.
  std::optional<Eigen::Vector3d> determined_normal(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, double r) const {
    const Eigen::Index m = A.rows();
    const Eigen::Matrix<double, 6, 6> N = A.transpose() * A;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> es(N);
    const Eigen::Matrix<double, 6, 1> lambda = es.eigenvalues();
    if (!(lambda[0] > 1e-12 * lambda[5])) return std::nullopt;
    const Eigen::Matrix<double, 6, 6>& V = es.eigenvectors();
    const Eigen::Matrix<double, 6, 1> c = V * ((V.transpose() * (A.transpose() * b)).array() / lambda.array()).matrix();
    if (!c.allFinite()) return std::nullopt;
    const Eigen::VectorXd res = A * c - b;
    // Weighted residual variance: A and b carry sqrt(w), weights <= 1.
    const double scatter_mm2 = m > 6 ? res.squaredNorm() / static_cast<double>(m - 6) : 0.0;
    if (std::sqrt(scatter_mm2) > o.max_residual_mm) return std::nullopt;
    const double s2 = std::max(scatter_mm2, o.digit_noise_mm * o.digit_noise_mm);
    double var_slope = 0;  // of c1 and c2, in (mm per r)^2
    for (int k = 1; k <= 2; ++k)
      for (int j = 0; j < 6; ++j) var_slope += s2 * V(k, j) * V(k, j) / lambda[j];
    if (std::sqrt(var_slope) / r > o.max_slope_error_rad) return std::nullopt;
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
  const std::array<std::uint64_t, 3> key{std::bit_cast<std::uint64_t>(tip_mm.x()), std::bit_cast<std::uint64_t>(tip_mm.y()),
                                         std::bit_cast<std::uint64_t>(tip_mm.z())};
  {
    std::lock_guard<std::mutex> lock(impl_->memo_mutex);
    auto it = impl_->memo.find(key);
    if (it != impl_->memo.end()) return it->second;
  }
  std::optional<Eigen::Vector3d> n;
  for (double r = impl_->o.radius_mm; r <= impl_->o.max_radius_mm * (1 + 1e-9) && !n; r *= 2) n = impl_->fit(tip_mm, r);
  std::lock_guard<std::mutex> lock(impl_->memo_mutex);
  impl_->memo.emplace(key, n);
  return n;
}

}  // namespace deflex::part
