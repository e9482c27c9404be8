// What report.html draws, kept point by point on disk and made at the end
// (the Recorder's; include/deflex/report/recorder.hpp has Page).
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "deflex/compensate/compensate.hpp"
#include "deflex/process/cusp.hpp"
#include "deflex/report/recorder.hpp"
#include "deflex/report/spill.hpp"

namespace deflex::report {

// The values drawn along the program (kSeries in page.cpp).
inline constexpr std::size_t kSeriesCount = 16;

class PageSink {
 public:
  // `maps`: 2 (as written, then the rows') or 1 (the rows').
  // spindle (may be null): the S1 allowance drawn beside the power and torque.
  PageSink(const std::string& spill_dir, int maps, double tolerance_mm, const profile::SpindleRating* spindle = nullptr);
  // A row in material.
  void add(const compensate::Point& p, const V3& contact_mm, double path_mm, double error_mm,
           double as_written_mm, const process::CuspResult& c);
  Page finish(const ValueStats& cusp);

 private:
  // One row: what the plots, the grid and the histogram read. Errors in
  // double (their statistics), the drawing's values in float.
  struct Rec {
    double e[2];
    double path_mm;
    float contact_mm[3];
    float series[kSeriesCount];  // the order of kSeries in page.cpp
    float stepover_mm, cusp_mm;
    std::uint32_t line;
  };
  // The 20 lines whose worst row is worst (exact in one pass: a line evicted
  // with |e| = u can only come back with a larger |e|, since the smallest kept
  // only grows).
  struct Worst {
    std::uint32_t line;
    double key;
    std::array<double, 3> values;  // the maps, last first, then the cusp (unused: NaN)
  };
  void worst_add(std::uint32_t line, double key, const std::array<double, 3>& values);
  double grid_cell_mm();
  Json worst_table(const std::vector<std::pair<std::string, std::string>>& maps);

  Spill<Rec> spill_;
  int maps_;
  double tol_;
  double x0_ = HUGE_VAL, y0_ = HUGE_VAL, x1_ = -HUGE_VAL, y1_ = -HUGE_VAL;
  double max_abs_ = 0, cusp_max_ = 0;
  std::size_t steps_ = 0;
  double step_lo_ = HUGE_VAL, step_hi_ = -HUGE_VAL;
  std::vector<Worst> worst_;
  const profile::SpindleRating* spindle_ = nullptr;
};

}  // namespace deflex::report
