// The least squares of the fit with Ceres, in deflex's plugin
// libdeflex_ceres.so (src/plugin/load.cpp says why a plugin): the table of
// functions its entry point deflex_ceres_fit returns
// (src/fit/ceres/run_solver.cpp). The plugin and the module are built
// together: plain C++ and Eigen types cross. Private to src/fit/.
#pragma once
#include <array>
#include <string>

#include <Eigen/Core>

#include "deflex/fit/basis.hpp"
#include "deflex/fit/model.hpp"
#include "deflex/fit/solve.hpp"

namespace deflex::fit::ceres_fit {

struct Data {
  BasisRows rows;  // matched x (kStiffnessParams + 1)
  Eigen::VectorXd measured_mm;
};

struct Run {
  std::array<double, kParams> x{};
  Eigen::MatrixXd cov;  // of the log-parameters, kParams x kParams (0 where held)
  bool covariance_ok = false;
  bool converged = true;  // nothing to solve: the start stands
  std::string message;
};

struct Api {
  // The bounded fit of the parameters `free` (the others held at x = 0) and
  // their covariance.
  Run (*run_solver)(const Data& d, const std::array<bool, kParams>& free, const FitOptions& o);
};

// The plugin's table, loaded on first use; throws Error(ErrorKind::config)
// when the plugin cannot be loaded (src/fit/solve.cpp).
const Api& api();

}  // namespace deflex::fit::ceres_fit
