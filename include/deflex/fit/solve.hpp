// The fit: bounded nonlinear least squares of the stiffness and coefficient
// scales (model.hpp) to the measured errors, with Ceres (Debian's
// libceres-dev), and what the cut cannot determine named, not invented.
//
// Parameters are the logarithms of the scales: a stiffness halved and one
// doubled are equally far from the start, and the intervals come out as
// factors. Residual per matched point: predicted - measured, mm.
//
// Determinacy. A parameter the measured points do not feel at all (its
// column of the Jacobian is zero: no measured surface faces the axis of a
// structure stiffness) is held at its starting value and named. The others
// join the fit one at a time, in the order a cut sees them (solve.cpp,
// joins_late()); one whose joining leaves any fitted 95 % interval wider
// than FitOptions::determined_within (as a factor) is held at its start and
// named with the parameter it trades off against (the largest |correlation|).
// A static surface error is compliance times force: from walls cut near the
// tip of one tool, the coefficients' scale, the clamp and the spindle are
// nearly each other's twins and the structure along X and Y what the walls
// show best; the fit says so rather than fitting noise.
//
// Intervals: the covariance of the log-parameters is sigma^2 (J^T J)^-1
// (ceres::Covariance), sigma^2 the residual variance (sum r^2 / (n - p)); the
// 95 % interval of a scale is exp(x +- 1.96 sigma_x). It assumes the model is
// right and the noise independent: a systematic residual (per feature, the
// fit's report) widens nothing and must be read there.
#pragma once
#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "deflex/fit/basis.hpp"
#include "deflex/fit/model.hpp"
#include "deflex/fit/observe.hpp"

namespace deflex::fit {

struct FitOptions {
  double min_scale = 0.1, max_scale = 10.0;              // bounds of each stiffness scale
  double min_coefficients = 0.3, max_coefficients = 3.0;  // bounds of the coefficients' scale
  // A fitted scale whose 95 % interval reaches beyond x (1 + this) or
  // x / (1 + this) is not determined.
  double determined_within = 0.10;
  std::array<bool, kParams> hold{};  // held at the start by the caller
};

struct ParamFit {
  bool fitted = false;
  double scale = 1, lo95 = 1, hi95 = 1;  // of the starting value; lo/hi: the 95 % interval
  bool at_bound = false;                 // the solution sits on a bound
  std::string why_held;                  // not fitted: why
};

struct FitResult {
  std::array<ParamFit, kParams> params;
  Scales scales = unit_scales();
  Eigen::MatrixXd correlation;        // kParams x kParams, fitted parameters only (NaN elsewhere)
  Eigen::VectorXd residual_before_mm;  // predicted - measured at the starting profile, per matched point
  Eigen::VectorXd residual_mm;         // the same after the fit
  double sigma_mm = 0;                 // residual standard deviation after the fit
  bool converged = true;               // the last fit accepted ended by Ceres' convergence test
  std::string message;                 // its solver's message (job::fit warns when it did not converge)
};

FitResult solve(const Basis& b, const Matching& m, const FitOptions& o = {});

// Several measured cuts of one machine fitted together (each its program's
// basis and its points), residuals in the order given. Cuts of tools that
// stick out differently weigh tool, clamp, spindle and structure
// differently: what one tool's walls cannot tell apart, two may.
struct Cut {
  const Basis* basis = nullptr;
  const Matching* matching = nullptr;
};
FitResult solve(const std::vector<Cut>& cuts, const FitOptions& o = {});

}  // namespace deflex::fit
