// fit::solve() (solve.hpp); its least squares in the Ceres plugin
// (ceres_api.hpp).
#include "deflex/fit/solve.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "ceres_api.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "deflex_plugin.hpp"

namespace deflex::fit {

const ceres_fit::Api& ceres_fit::api() {
  static const Api& a = plugin::api<Api>("deflex_ceres", "deflex_ceres_fit", "Ceres: the machine fit");
  return a;
}

namespace {

using ceres_fit::Data;
using ceres_fit::Run;

constexpr double kZ95 = 1.959963984540054;

// The matched points of every cut, one row each, in the order given.
Data data_of(const std::vector<Cut>& cuts) {
  std::size_t n = 0;
  for (const Cut& c : cuts) n += c.matching->matched.size();
  Data d{BasisRows(static_cast<Eigen::Index>(n), kStiffnessParams + 1), Eigen::VectorXd(static_cast<Eigen::Index>(n))};
  Eigen::Index r = 0;
  for (const Cut& c : cuts)
    for (const Matched& m : c.matching->matched) {
      d.rows.row(r) = c.basis->errors_mm.row(static_cast<Eigen::Index>(m.sample));
      d.measured_mm(r++) = m.measured_error_mm;
    }
  return d;
}

Eigen::VectorXd residuals(const Data& d, const std::array<double, kParams>& x) {
  double inverse[kStiffnessParams];
  for (int k = 0; k < kStiffnessParams; ++k) inverse[k] = std::exp(-x[k]);
  Eigen::VectorXd r(d.rows.rows());
  for (Eigen::Index i = 0; i < d.rows.rows(); ++i)
    r(i) = scaled_error(d.rows.row(i).data(), inverse, std::exp(x[kParams - 1])) - d.measured_mm(i);
  return r;
}

// The Jacobian's column of each parameter at the start (x = 0): how much the
// measured points feel it.
std::array<double, kParams> sensitivities(const Data& d) {
  std::array<double, kParams> n{};
  for (int k = 0; k < kStiffnessParams; ++k) n[k] = d.rows.col(1 + k).norm();
  n[kParams - 1] = d.rows.rowwise().sum().norm();
  return n;
}

// The order in which parameters join the fit (solve()): first what a cut
// sees directly, the structure's stiffness along X and Y (a wall facing an
// axis shows that axis' compliance times its force), then the coefficients'
// scale (separable from the compliance only where the tool's own bending,
// known from its model, shapes the error differently from the machine's),
// the clamp (an isotropic spring: to a wall, mostly a share of X and Y
// alike), Z, and the spindle last (the machine builder's figure; from walls
// of one tool it is the clamp's twin).
int joins_late(Param p) {
  switch (p) {
    case Param::structure_x:
    case Param::structure_y: return 0;
    case Param::coefficients: return 1;
    case Param::clamp: return 2;
    case Param::structure_z: return 3;
    case Param::spindle: return 4;
  }
  return 5;
}

std::string factor(double f) {
  std::ostringstream s;
  s.precision(3);
  s << "x" << f;
  return s.str();
}

}  // namespace

FitResult solve(const Basis& b, const Matching& m, const FitOptions& o) { return solve({{&b, &m}}, o); }

FitResult solve(const std::vector<Cut>& cuts, const FitOptions& o) {
  const Data d = data_of(cuts);
  FitResult res;
  const auto n = static_cast<std::size_t>(d.rows.rows());
  // One machine: every cut's basis has the same components.
  const std::array<bool, kParams>& present = cuts.front().basis->present;
  std::array<bool, kParams> free{};
  const std::array<double, kParams> sens = sensitivities(d);
  const double top = *std::max_element(sens.begin(), sens.end());
  for (int k = 0; k < kParams; ++k) {
    ParamFit& p = res.params[k];
    if (!present[k]) p.why_held = "the starting profile has it rigid: there is nothing to scale";
    else if (o.hold[k]) p.why_held = "held at the profile's value as asked";
    else if (!(sens[k] > 1e-3 * top)) p.why_held = "the measured points do not feel it";
    else free[k] = true;
  }
  std::array<double, kParams> zero{};
  res.residual_before_mm = residuals(d, zero);

  // Forward selection: the parameters join the fit one at a time in the
  // order of joins_late() (most felt first within a rank); one
  // whose joining leaves any fitted interval wider than the limit is held at
  // its start and named with what it trades off against. Never running a fit
  // that is already degenerate keeps the intervals meaningful.
  std::array<int, kParams> order{};
  for (int k = 0; k < kParams; ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const int ra = joins_late(Param(a)), rb = joins_late(Param(b));
    return ra != rb ? ra < rb : sens[a] > sens[b];
  });
  std::array<bool, kParams> in{};
  Run run;  // nothing free yet: the starting profile, x = 0
  run.cov = Eigen::MatrixXd::Zero(kParams, kParams);
  double var = residuals(d, run.x).squaredNorm() / static_cast<double>(n);
  for (int k : order) {
    if (!free[k]) continue;
    std::array<bool, kParams> trial = in;
    trial[k] = true;
    const int ntrial = static_cast<int>(std::count(trial.begin(), trial.end(), true));
    if (static_cast<int>(n) <= ntrial) {
      res.params[k].why_held = "too few measured points with a prediction to fit it as well";
      continue;
    }
    Run t = ceres_fit::api().run_solver(d, trial, o);
    const double tvar = residuals(d, t.x).squaredNorm() / static_cast<double>(static_cast<int>(n) - ntrial);
    int worst = -1;
    double worst_half = 0;
    for (int j = 0; j < kParams; ++j) {
      if (!trial[j]) continue;
      const double half = t.covariance_ok ? kZ95 * std::sqrt(std::max(0.0, tvar * t.cov(j, j)))
                                          : std::numeric_limits<double>::infinity();
      if (worst < 0 || half > worst_half) worst_half = half, worst = j;
    }
    if (std::exp(worst_half) <= 1 + o.determined_within) {
      in = trial, run = t, var = tvar;
      continue;
    }
    // Held: named with the fitted parameter it trades off against.
    int partner = -1;
    double corr = 0;
    for (int j = 0; j < kParams; ++j) {
      if (j == k || !trial[j] || !t.covariance_ok) continue;
      const double c = t.cov(k, j) / std::sqrt(t.cov(k, k) * t.cov(j, j));
      if (std::abs(c) > std::abs(corr)) corr = c, partner = j;
    }
    std::ostringstream why;
    const std::string whose = worst == k ? std::string("its") : "the " + std::string(name(Param(worst))) + "'s";
    if (std::isfinite(worst_half) && worst_half < std::log(100.0))
      why << "the cut cannot determine it (fitted too, " << whose << " 95 % interval would be "
          << factor(std::exp(-worst_half)) << " to " << factor(std::exp(worst_half)) << ")";
    else if (std::isfinite(worst_half))
      why << "the cut cannot determine it (fitted too, " << whose << " 95 % interval would be wider than x0.01 to x100)";
    else
      why << "the cut cannot determine it: the measured points leave it free together with the others";
    if (partner >= 0) {
      why.precision(2);
      why << "; it trades off against the " << name(Param(partner)) << " (correlation " << corr << ")";
    }
    res.params[k].why_held = why.str();
  }
  free = in;
  res.sigma_mm = std::sqrt(var);
  res.residual_mm = residuals(d, run.x);

  res.converged = run.converged;
  res.message = run.message;
  res.correlation = Eigen::MatrixXd::Constant(kParams, kParams, std::numeric_limits<double>::quiet_NaN());
  for (int k = 0; k < kParams; ++k) {
    ParamFit& p = res.params[k];
    res.scales[k] = std::exp(run.x[k]);
    if (!free[k]) continue;
    p.fitted = true;
    p.scale = res.scales[k];
    const double half = kZ95 * std::sqrt(std::max(0.0, var * run.cov(k, k)));
    p.lo95 = std::exp(run.x[k] - half);
    p.hi95 = std::exp(run.x[k] + half);
    const bool coef = k == kParams - 1;
    const double lo = std::log(coef ? o.min_coefficients : o.min_scale), hi = std::log(coef ? o.max_coefficients : o.max_scale);
    p.at_bound = run.x[k] <= lo + 1e-6 || run.x[k] >= hi - 1e-6;
    for (int j = 0; j < kParams; ++j)
      if (free[j]) res.correlation(k, j) = run.cov(k, j) / std::sqrt(run.cov(k, k) * run.cov(j, j));
  }
  return res;
}

}  // namespace deflex::fit
