#include "deflex/report/stats.hpp"

#include <algorithm>
#include <cmath>

namespace deflex::report {

ErrorStats error_stats(const std::vector<double>& e, double tol) {
  ErrorStats s;
  std::vector<double> mag;
  mag.reserve(e.size());
  double sq = 0;
  std::size_t out = 0;
  for (double v : e) {
    if (std::isnan(v)) continue;
    mag.push_back(std::fabs(v));
    s.max_under = std::max(s.max_under, v);
    s.max_over = std::min(s.max_over, v);
    sq += v * v;
    out += std::fabs(v) > tol;
  }
  s.points = mag.size();
  if (mag.empty()) return s;
  const double n = static_cast<double>(mag.size());
  s.rms = std::sqrt(sq / n);
  s.share_out = static_cast<double>(out) / n;
  // Nearest-rank percentiles: the smallest value with at least p of the points at or below it.
  auto rank = [&](double p) {
    const std::size_t k = static_cast<std::size_t>(std::ceil(p * n)) - 1;
    std::nth_element(mag.begin(), mag.begin() + static_cast<std::ptrdiff_t>(k), mag.end());
    return mag[k];
  };
  s.p50_abs = rank(0.50);
  s.p95_abs = rank(0.95);
  s.p99_abs = rank(0.99);
  s.max_abs = *std::max_element(mag.begin(), mag.end());
  return s;
}

Json to_json(const ErrorStats& s) {
  return {{"max", fixed(s.max_abs, 6)},          {"rms", fixed(s.rms, 6)},
          {"p50", fixed(s.p50_abs, 6)},          {"p95", fixed(s.p95_abs, 6)},
          {"p99", fixed(s.p99_abs, 6)},          {"out_of_tolerance_share", fixed(s.share_out, 6)},
          {"max_undercut", fixed(s.max_under, 6)}, {"max_overcut", fixed(s.max_over, 6)}};
}

ValueStats value_stats(const std::vector<double>& v) {
  ValueStats s;
  double sum = 0;
  for (double x : v) {
    if (std::isnan(x)) continue;
    ++s.points;
    sum += x;
    s.max = std::max(s.max, x);
  }
  if (s.points) s.mean = sum / static_cast<double>(s.points);
  return s;
}

}  // namespace deflex::report
