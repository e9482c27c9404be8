// CHOLMOD's supernodal Cholesky for the solid models, in deflex's plugin
// libdeflex_cholmod.so (src/stiffness/cholmod_api.hpp), through Eigen's
// CholmodSupport.
#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>
#include <memory>
#include <mutex>

#include "../cholmod_api.hpp"

namespace deflex::stiffness::cholmod {

struct Factor {
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper> llt;
  std::mutex solving;  // CHOLMOD's solve writes to its common workspace
};

namespace {

Factor* factorise(const Eigen::SparseMatrix<double>& a) {
  auto f = std::make_unique<Factor>();
  f->llt.cholmod().print = 0;  // CHOLMOD prints its errors on stdout, deflex's output
  f->llt.analyzePattern(a);
  // A failed analysis (too large) leaves no factor for factorize() to fill.
  if (f->llt.cholmod().status != CHOLMOD_OK) return nullptr;
  f->llt.factorize(a);
  if (f->llt.info() != Eigen::Success || f->llt.cholmod().status != CHOLMOD_OK) return nullptr;
  return f.release();
}

Eigen::MatrixXd solve(Factor* f, const Eigen::MatrixXd& b) {
  const std::lock_guard<std::mutex> lock(f->solving);
  return f->llt.solve(b);
}

void release(Factor* f) { delete f; }

}  // namespace

}  // namespace deflex::stiffness::cholmod

extern "C" __attribute__((visibility("default"))) const void* deflex_cholmod_stiffness() {
  using namespace deflex::stiffness::cholmod;
  static const Api api{&factorise, &solve, &release};
  return &api;
}
