// Linear-elastic FEM on 10-node tetrahedra: assembly, clamp, patch loads, solve.
#include <algorithm>
#include <cmath>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include "deflex/diag/diagnostics.hpp"
#include "solid_internal.hpp"
#ifdef DEFLEX_HAVE_CHOLMOD
#include "cholmod_api.hpp"
#include "deflex_plugin.hpp"
#endif

#ifdef DEFLEX_HAVE_CHOLMOD
namespace deflex::stiffness {
const cholmod::Api& cholmod::api() {
  static const Api& a = plugin::api<Api>("deflex_cholmod", "deflex_cholmod_stiffness", "CHOLMOD: the solid models' factorisation");
  return a;
}

}  // namespace deflex::stiffness
#endif

namespace deflex::stiffness::solid {

namespace {

using Grad = Eigen::Matrix<double, 10, 3>;  // dN_a / d(xi, eta, zeta) or d(x, y, z)
using Vec10 = Eigen::Matrix<double, 10, 1>;

// Reference tet: corners (0,0,0) (1,0,0) (0,1,0) (0,0,1); barycentric
// L = (1 - xi - eta - zeta, xi, eta, zeta). Corner N = L (2L - 1), edge N = 4 Li Lj.
Vec10 shape(const Eigen::Vector3d& p) {
  const std::array<double, 4> L{1 - p.sum(), p(0), p(1), p(2)};
  Vec10 n;
  for (int c = 0; c < 4; ++c) n(c) = L[c] * (2 * L[c] - 1);
  for (int e = 0; e < 6; ++e) n(4 + e) = 4 * L[kEdges[e][0]] * L[kEdges[e][1]];
  return n;
}

Grad shape_grad_ref(const Eigen::Vector3d& p) {
  const std::array<double, 4> L{1 - p.sum(), p(0), p(1), p(2)};
  // dL_c / dxi_k
  const double dL[4][3] = {{-1, -1, -1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  Grad g = Grad::Zero();
  for (int c = 0; c < 4; ++c)
    for (int k = 0; k < 3; ++k) g(c, k) = (4 * L[c] - 1) * dL[c][k];
  for (int e = 0; e < 6; ++e) {
    const int i = kEdges[e][0], j = kEdges[e][1];
    for (int k = 0; k < 3; ++k) g(4 + e, k) = 4 * (L[j] * dL[i][k] + L[i] * dL[j][k]);
  }
  return g;
}

// 4-point Gauss rule, degree 2 (exact for the stiffness of a straight-sided
// quadratic tet); weights sum to the reference volume 1/6.
struct QuadPoint {
  Eigen::Vector3d p;
  double w;
};
const std::array<QuadPoint, 4>& gauss4() {
  static const std::array<QuadPoint, 4> q = [] {
    const double a = 0.5854101966249685, b = 0.1381966011250105;
    return std::array<QuadPoint, 4>{{{{b, b, b}, 1.0 / 24},
                                     {{a, b, b}, 1.0 / 24},
                                     {{b, a, b}, 1.0 / 24},
                                     {{b, b, a}, 1.0 / 24}}};
  }();
  return q;
}

using Coords = Eigen::Matrix<double, 10, 3>;  // node coordinates of one element

Coords element_coords(const TetMesh& m, std::size_t e) {
  Coords x;
  for (int a = 0; a < 10; ++a) x.row(a) = m.node_mm[m.tet[e][a]].transpose();
  return x;
}

// 30x30 element stiffness, dofs (node a, component i) -> 3a + i. Block
// K_ab,ij = int lambda g_a,i g_b,j + mu g_a,j g_b,i + mu delta_ij g_a.g_b.
Eigen::Matrix<double, 30, 30> element_stiffness(const Coords& x, double lambda, double mu) {
  Eigen::Matrix<double, 30, 30> k = Eigen::Matrix<double, 30, 30>::Zero();
  for (const auto& q : gauss4()) {
    const Grad gr = shape_grad_ref(q.p);
    const Eigen::Matrix3d J = x.transpose() * gr;  // J_ij = d x_i / d xi_j
    const double det = J.determinant();
    if (!(det > 0)) throw Error(ErrorKind::internal, "solid mesh has an inverted quadratic tetrahedron");
    const Grad g = gr * J.inverse();  // rows: grad_x N_a
    const double w = q.w * det;
    for (int a = 0; a < 10; ++a)
      for (int b = 0; b < 10; ++b) {
        const double dot = g.row(a).dot(g.row(b));
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            k(3 * a + i, 3 * b + j) += w * (lambda * g(a, i) * g(b, j) + mu * g(a, j) * g(b, i) +
                                             (i == j ? mu * dot : 0.0));
      }
  }
  return k;
}

// Upper triangle of K in compressed columns, built from the node graph so no
// triplet list of the whole mesh is needed.
class UpperAssembler {
 public:
  UpperAssembler(const TetMesh& m, const std::vector<int>& free_index, int nfree)
      : adj_(static_cast<std::size_t>(nfree)) {
    for (const auto& t : m.tet)
      for (int a : t)
        for (int b : t) {
          const int fa = free_index[a], fb = free_index[b];
          if (fa >= 0 && fb >= 0 && fa <= fb) adj_[fb].push_back(fa);
        }
    for (auto& v : adj_) {
      std::sort(v.begin(), v.end());
      v.erase(std::unique(v.begin(), v.end()), v.end());
    }
    const int n = 3 * nfree;
    K_.resize(n, n);
    std::vector<int> outer(static_cast<std::size_t>(n) + 1, 0);
    for (int c = 0; c < nfree; ++c)
      for (int k = 0; k < 3; ++k)
        outer[3 * c + k + 1] = outer[3 * c + k] + 3 * static_cast<int>(adj_[c].size() - 1) + k + 1;
    K_.resizeNonZeros(outer.back());
    std::copy(outer.begin(), outer.end(), K_.outerIndexPtr());
    int* inner = K_.innerIndexPtr();
    for (int c = 0; c < nfree; ++c)
      for (int k = 0; k < 3; ++k) {
        int p = outer[3 * c + k];
        for (int r : adj_[c])
          for (int i = 0; i < 3 && 3 * r + i <= 3 * c + k; ++i) inner[p++] = 3 * r + i;
      }
    std::fill(K_.valuePtr(), K_.valuePtr() + K_.nonZeros(), 0.0);
  }

  // Adds block (row node fa, column node fb), fa <= fb.
  void add_block(int fa, int fb, const Eigen::Matrix3d& blk) {
    const auto& col = adj_[fb];
    const int pos = static_cast<int>(std::lower_bound(col.begin(), col.end(), fa) - col.begin());
    for (int k = 0; k < 3; ++k) {
      double* v = K_.valuePtr() + K_.outerIndexPtr()[3 * fb + k] + 3 * pos;
      for (int i = 0; i < 3 && (fa < fb || i <= k); ++i) v[i] += blk(i, k);
    }
  }
  Eigen::SparseMatrix<double>& matrix() { return K_; }

 private:
  std::vector<std::vector<int>> adj_;
  Eigen::SparseMatrix<double> K_;
};

// Integrates over a reference (sub-)tet by splitting it into 8 children
// `levels` times and using the 4-point rule on each: the load patch is smooth
// but narrower than an element, so the element rule alone would miss it.
template <class F>
void integrate_subdivided(const std::array<Eigen::Vector3d, 4>& v, int levels, const F& f) {
  if (levels == 0) {
    const double vol = std::abs((v[1] - v[0]).cross(v[2] - v[0]).dot(v[3] - v[0])) / 6;
    for (const auto& q : gauss4()) {
      const double l1 = q.p(0), l2 = q.p(1), l3 = q.p(2);
      f(v[0] * (1 - l1 - l2 - l3) + v[1] * l1 + v[2] * l2 + v[3] * l3, q.w * 6 * vol);
    }
    return;
  }
  const auto m = [&](int i, int j) { return Eigen::Vector3d(0.5 * (v[i] + v[j])); };
  const Eigen::Vector3d m01 = m(0, 1), m02 = m(0, 2), m03 = m(0, 3), m12 = m(1, 2),
                        m13 = m(1, 3), m23 = m(2, 3);
  const std::array<std::array<Eigen::Vector3d, 4>, 8> kids{{{v[0], m01, m02, m03},
                                                             {m01, v[1], m12, m13},
                                                             {m02, m12, v[2], m23},
                                                             {m03, m13, m23, v[3]},
                                                             {m01, m02, m03, m13},
                                                             {m01, m02, m12, m13},
                                                             {m02, m03, m13, m23},
                                                             {m02, m12, m13, m23}}};
  for (const auto& k : kids) integrate_subdivided(k, levels - 1, f);
}

bool valid(const Coords& x) {
  for (const auto& q : gauss4())
    if (!((x.transpose() * shape_grad_ref(q.p)).determinant() > 0)) return false;
  return true;
}

}  // namespace

std::size_t straighten_inverted(TetMesh& m) {
  std::size_t straightened = 0;
  for (int round = 0; round < 4; ++round) {
    std::size_t now = 0;
    for (std::size_t e = 0; e < m.tet.size(); ++e) {
      if (valid(element_coords(m, e))) continue;
      const auto& t = m.tet[e];
      for (int k = 0; k < 6; ++k) m.node_mm[t[4 + k]] = 0.5 * (m.node_mm[t[kEdges[k][0]]] + m.node_mm[t[kEdges[k][1]]]);
      ++now;
    }
    straightened += now;
    if (now == 0) break;
  }
  return straightened;
}

Patch patch_weights(const TetMesh& m, const Eigen::Vector3d& c, double r) {
  std::vector<double> w(m.node_mm.size(), 0.0);
  double total = 0;
  Eigen::Vector3d xsum = Eigen::Vector3d::Zero();
  const std::array<Eigen::Vector3d, 4> ref{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                                           Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 0, 1)};
  for (std::size_t e = 0; e < m.tet.size(); ++e) {
    const Coords x = element_coords(m, e);
    const Eigen::Vector3d lo = x.colwise().minCoeff().transpose(), hi = x.colwise().maxCoeff().transpose();
    if ((c.cwiseMax(lo).cwiseMin(hi) - c).norm() >= r) continue;
    // Children no larger than the patch radius: at least two levels, more
    // where an element is over four radii across (a small patch on a coarse
    // mesh would fall between the quadrature points).
    const int levels = std::clamp(static_cast<int>(std::ceil(std::log2((hi - lo).norm() / r))), 2, 5);
    integrate_subdivided(ref, levels, [&](const Eigen::Vector3d& p, double wq) {
      const Vec10 n = shape(p);
      const Eigen::Vector3d xp = x.transpose() * n;
      const double d2 = (xp - c).squaredNorm() / (r * r);
      if (d2 >= 1) return;
      const double phi = (1 - d2) * (1 - d2);
      const double dv = wq * (x.transpose() * shape_grad_ref(p)).determinant();
      for (int a = 0; a < 10; ++a) w[m.tet[e][a]] += n(a) * phi * dv;
      total += phi * dv;
      xsum += xp * phi * dv;
    });
  }
  if (!(total > 0)) throw Error(ErrorKind::internal, "load patch lies outside the solid");
  Patch p;
  p.centroid_mm = xsum / total;
  for (std::size_t a = 0; a < w.size(); ++a)
    if (w[a] != 0) p.weight.emplace_back(static_cast<int>(a), w[a] / total);
  return p;
}

#ifdef DEFLEX_HAVE_CHOLMOD
struct ElasticSolver::Factor {
  std::unique_ptr<cholmod::Factor, void (*)(cholmod::Factor*)> f;
  explicit Factor(const Eigen::SparseMatrix<double>& upper)
      : f(cholmod::api().factorise(upper), cholmod::api().release) {}
  bool ok() const { return f != nullptr; }
  Eigen::MatrixXd solve(const Eigen::MatrixXd& b) const { return cholmod::api().solve(f.get(), b); }
};
#else
struct ElasticSolver::Factor {
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Upper> ldlt;
  explicit Factor(const Eigen::SparseMatrix<double>& upper) : ldlt(upper) {}
  bool ok() const { return ldlt.info() == Eigen::Success; }
  Eigen::MatrixXd solve(const Eigen::MatrixXd& b) const { return ldlt.solve(b); }
};
#endif

ElasticSolver::ElasticSolver(const TetMesh& mesh, const Material& mat, const std::vector<char>& fixed)
    : free_index_(mesh.node_mm.size(), -1) {
  for (std::size_t a = 0; a < mesh.node_mm.size(); ++a)
    if (!fixed[a]) free_index_[a] = nfree_++;
  const double E = mat.E_MPa, nu = mat.poisson;
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  UpperAssembler asm_(mesh, free_index_, nfree_);
  for (std::size_t e = 0; e < mesh.tet.size(); ++e) {
    const auto ke = element_stiffness(element_coords(mesh, e), lambda, mu);
    for (int a = 0; a < 10; ++a)
      for (int b = 0; b < 10; ++b) {
        const int fa = free_index_[mesh.tet[e][a]], fb = free_index_[mesh.tet[e][b]];
        if (fa >= 0 && fb >= 0 && fa <= fb) asm_.add_block(fa, fb, ke.block<3, 3>(3 * a, 3 * b));
      }
  }
  factor_ = std::make_shared<Factor>(asm_.matrix());
  if (nfree_ == 0 || !factor_->ok())
    throw Error(ErrorKind::internal, "the solid's stiffness matrix of " + std::to_string(3 * nfree_) +
                                         " dofs could not be factorised (singular: is the solid held?)");
}

Eigen::MatrixXd ElasticSolver::solve(const Patch& load) const { return solve(std::vector<Patch>{load}); }

Eigen::MatrixXd ElasticSolver::solve(const std::vector<Patch>& loads) const {
  const auto n = static_cast<Eigen::Index>(loads.size());
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(3 * static_cast<Eigen::Index>(nfree_), 3 * n);
  for (Eigen::Index k = 0; k < n; ++k)
    for (const auto& [a, w] : loads[static_cast<std::size_t>(k)].weight)
      if (free_index_[a] >= 0)
        for (int d = 0; d < 3; ++d) rhs(3 * free_index_[a] + d, 3 * k + d) = w;
  return factor_->solve(rhs);
}

Compliance ElasticSolver::read(const Patch& at, const Eigen::Ref<const Eigen::MatrixXd>& u) const {
  Compliance c = Compliance::Zero();
  for (const auto& [a, w] : at.weight)
    if (free_index_[a] >= 0) c += w * u.middleRows(3 * free_index_[a], 3);
  return c;
}

FemStats solve_stations(const TetMesh& mesh, const Material& mat, double clamp_z_mm,
                        double patch_radius_mm, std::vector<Station>& stations) {
  // Rigid clamp: every node at or above the holder face is fixed.
  std::vector<char> fixed(mesh.node_mm.size(), 0);
  const double tol = 1e-6 * std::max(1.0, clamp_z_mm);
  for (std::size_t a = 0; a < mesh.node_mm.size(); ++a) fixed[a] = mesh.node_mm[a](2) >= clamp_z_mm - tol;
  const ElasticSolver fem(mesh, mat, fixed);
  for (auto& s : stations) {
    const Patch p = patch_weights(mesh, Eigen::Vector3d(0, 0, s.centre_z_mm), patch_radius_mm);
    s.height_mm = p.centroid_mm(2);
    s.c = fem.compliance(p);
  }
  return {fem.dofs()};
}

}  // namespace deflex::stiffness::solid
