// The fit's bounded least squares and covariance with Ceres, in deflex's
// plugin libdeflex_ceres.so (src/fit/ceres_api.hpp).
#include <cmath>
#include <vector>

#include <ceres/ceres.h>

#include "../ceres_api.hpp"

namespace deflex::fit::ceres_fit {

namespace {

// One matched point: the basis errors of its sample and its measured error.
struct PointResidual {
  std::array<double, kStiffnessParams + 1> b;
  double measured_mm;
  template <class T>
  bool operator()(const T* const c, const T* const s, const T* const x, const T* const y, const T* const z,
                  const T* const k, T* r) const {
    const T inverse[kStiffnessParams] = {ceres::exp(-c[0]), ceres::exp(-s[0]), ceres::exp(-x[0]), ceres::exp(-y[0]),
                                         ceres::exp(-z[0])};
    r[0] = scaled_error(b.data(), inverse, ceres::exp(k[0])) - measured_mm;
    return true;
  }
};

Run run_solver(const Data& d, const std::array<bool, kParams>& free, const FitOptions& o) {
  Run run;
  ceres::Problem problem;
  for (Eigen::Index i = 0; i < d.rows.rows(); ++i) {
    PointResidual f;
    for (int k = 0; k <= kStiffnessParams; ++k) f.b[k] = d.rows(i, k);
    f.measured_mm = d.measured_mm(i);
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PointResidual, 1, 1, 1, 1, 1, 1, 1>(new PointResidual(f)),
                             nullptr, &run.x[0], &run.x[1], &run.x[2], &run.x[3], &run.x[4], &run.x[5]);
  }
  for (int k = 0; k < kParams; ++k) {
    const bool coef = k == kParams - 1;
    problem.SetParameterLowerBound(&run.x[k], 0, std::log(coef ? o.min_coefficients : o.min_scale));
    problem.SetParameterUpperBound(&run.x[k], 0, std::log(coef ? o.max_coefficients : o.max_scale));
    if (!free[k]) problem.SetParameterBlockConstant(&run.x[k]);
  }
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = 200;
  so.function_tolerance = 1e-12;
  so.parameter_tolerance = 1e-10;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary sum;
  ceres::Solve(so, &problem, &sum);
  run.converged = sum.termination_type == ceres::CONVERGENCE;
  run.message = sum.message;

  ceres::Covariance::Options co;
  co.algorithm_type = ceres::DENSE_SVD;
  // No direction dropped: one the data leave nearly free must show as a huge
  // variance (dropping it would report a tight interval); an exactly free one
  // makes Compute() fail, and solve() then holds the least felt parameter.
  co.null_space_rank = 0;
  ceres::Covariance cov(co);
  std::vector<std::pair<const double*, const double*>> blocks;
  for (int a = 0; a < kParams; ++a)
    for (int b = a; b < kParams; ++b)
      if (free[a] && free[b]) blocks.emplace_back(&run.x[a], &run.x[b]);
  run.cov = Eigen::MatrixXd::Zero(kParams, kParams);
  if (!blocks.empty() && cov.Compute(blocks, &problem)) {
    run.covariance_ok = true;
    for (int a = 0; a < kParams; ++a)
      for (int b = a; b < kParams; ++b)
        if (free[a] && free[b]) {
          double v = 0;
          cov.GetCovarianceBlock(&run.x[a], &run.x[b], &v);
          run.cov(a, b) = run.cov(b, a) = v;
        }
  }
  return run;
}

}  // namespace

}  // namespace deflex::fit::ceres_fit

extern "C" __attribute__((visibility("default"))) const void* deflex_ceres_fit() {
  static const deflex::fit::ceres_fit::Api api{&deflex::fit::ceres_fit::run_solver};
  return &api;
}
