// Statistics of the surface error over the CL points in material: the
// figures of the summary line, summary.json and report.html.
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "deflex/report/json.hpp"
#include "deflex/report/spill.hpp"

namespace deflex::report {

struct ErrorStats {
  std::size_t points = 0;
  double max_abs = 0, rms = 0, share_out = 0;
  double max_under = 0;   // largest e (material left), >= 0
  double max_over = 0;    // smallest e (dug in), <= 0
  double p50_abs = 0, p95_abs = 0, p99_abs = 0;  // percentiles of |e| (nearest rank)
};

// NaN values are not points in material and are skipped.
ErrorStats error_stats(const std::vector<double>& e_mm, double tolerance_mm);

// The same one value at a time, as a simulation produces them. Percentiles
// need every |e|: with `percentiles` they go to a Spill in `spill_dir` ("":
// the temporary folder), so memory stays constant; without, nothing is kept
// and they stay 0.
class ErrorAccumulator {
 public:
  ErrorAccumulator(double tolerance_mm, bool percentiles, const std::string& spill_dir = "");
  ~ErrorAccumulator();
  void add(double e_mm);
  ErrorStats stats();

 private:
  double tol_;
  ErrorStats s_;
  double sq_ = 0, max_abs_ = 0;
  std::size_t out_ = 0;
  std::unique_ptr<Spill<double>> mag_;
};
Json to_json(const ErrorStats& s);

// The statistics of a per-point quantity that may be missing (NaN): cusp heights.
struct ValueStats {
  std::size_t points = 0;
  double max = 0, mean = 0;
};
ValueStats value_stats(const std::vector<double>& v);
// The same one value at a time.
class ValueAccumulator {
 public:
  void add(double v);
  ValueStats stats() const;

 private:
  ValueStats s_;
  double sum_ = 0;
};

}  // namespace deflex::report
