#include "deflex/report/stats.hpp"

#include <algorithm>
#include <cmath>

namespace deflex::report {

ErrorAccumulator::ErrorAccumulator(double tolerance_mm, bool percentiles, const std::string& spill_dir)
    : tol_(tolerance_mm), mag_(percentiles ? std::make_unique<Spill<double>>(spill_dir) : nullptr) {}
ErrorAccumulator::~ErrorAccumulator() = default;

void ErrorAccumulator::add(double v) {
  if (std::isnan(v)) return;
  const double a = std::fabs(v);
  if (mag_) mag_->push_back(a);
  ++s_.points;
  s_.max_under = std::max(s_.max_under, v);
  s_.max_over = std::min(s_.max_over, v);
  max_abs_ = std::max(max_abs_, a);
  sq_ += v * v;
  out_ += a > tol_;
}

ErrorStats ErrorAccumulator::stats() {
  ErrorStats s = s_;
  if (!s.points) return s;
  const double n = static_cast<double>(s.points);
  s.rms = std::sqrt(sq_ / n);
  s.share_out = static_cast<double>(out_) / n;
  s.max_abs = max_abs_;
  if (mag_) {
    // Nearest-rank percentiles: the smallest value with at least p of the points at or below it.
    auto rank = [&](double p) {
      const std::size_t k = static_cast<std::size_t>(std::ceil(p * n)) - 1;
      return kth_value([&](const std::function<void(double)>& f) { mag_->each(f); }, s.points, k, 0.0, max_abs_);
    };
    s.p50_abs = rank(0.50);
    s.p95_abs = rank(0.95);
    s.p99_abs = rank(0.99);
  }
  return s;
}

ErrorStats error_stats(const std::vector<double>& e, double tol) {
  ErrorAccumulator acc(tol, true);
  for (double v : e) acc.add(v);
  return acc.stats();
}

Json to_json(const ErrorStats& s) {
  return {{"max", fixed(s.max_abs, 6)},          {"rms", fixed(s.rms, 6)},
          {"p50", fixed(s.p50_abs, 6)},          {"p95", fixed(s.p95_abs, 6)},
          {"p99", fixed(s.p99_abs, 6)},          {"out_of_tolerance_share", fixed(s.share_out, 6)},
          {"max_undercut", fixed(s.max_under, 6)}, {"max_overcut", fixed(s.max_over, 6)}};
}

void ValueAccumulator::add(double x) {
  if (std::isnan(x)) return;
  ++s_.points;
  sum_ += x;
  s_.max = std::max(s_.max, x);
}

ValueStats ValueAccumulator::stats() const {
  ValueStats s = s_;
  if (s.points) s.mean = sum_ / static_cast<double>(s.points);
  return s;
}

ValueStats value_stats(const std::vector<double>& v) {
  ValueAccumulator a;
  for (double x : v) a.add(x);
  return a.stats();
}

}  // namespace deflex::report
