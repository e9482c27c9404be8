// The solid models' sparse Cholesky by CHOLMOD (SuiteSparse), in deflex's
// plugin libdeflex_cholmod.so (src/plugin/load.cpp says why a plugin: the
// program starts without SuiteSparse, BLAS and LAPACK, which only a solid
// model needs): the table of functions its entry point deflex_cholmod_stiffness
// returns (src/stiffness/cholmod/factor.cpp). Built where SuiteSparse is found
// (DEFLEX_HAVE_CHOLMOD); Eigen's SimplicialLDLT else. Private to src/stiffness/.
#pragma once
#include <Eigen/Sparse>

namespace deflex::stiffness::cholmod {

struct Factor;  // the plugin's factorisation, opaque here

struct Api {
  // The supernodal LL^T of the symmetric matrix whose upper triangle is
  // `upper`; null when it is not positive definite or too large to factorise.
  Factor* (*factorise)(const Eigen::SparseMatrix<double>& upper);
  // A^-1 b. Thread-safe.
  Eigen::MatrixXd (*solve)(Factor* f, const Eigen::MatrixXd& b);
  void (*release)(Factor* f);
};

// The plugin's table, loaded on first use; throws Error(ErrorKind::config)
// when the plugin cannot be loaded (src/stiffness/solid_fem.cpp).
const Api& api();

}  // namespace deflex::stiffness::cholmod
