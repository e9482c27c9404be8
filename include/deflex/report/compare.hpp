// deflex compare: several programs for the same part (strategies) simulated on
// the same stock, one row each (Bagci & Yüncüoğlu 2017,
// docs/physics.md; Fig. 15 and Table 4 compare strategies by these figures).
#pragma once
#include <string>
#include <vector>

#include "deflex/process/machining_time.hpp"
#include "deflex/report/json.hpp"
#include "deflex/report/recorder.hpp"
#include "deflex/report/stats.hpp"

namespace deflex::report {

struct CompareRow {
  std::string program;
  ErrorStats error;                 // surface error against the program itself, mm
  double peak_force_N = 0;          // largest |F| over a revolution at any point
  double mean_force_N = 0;          // mean over the points in material of the mean |F|
  double peak_deflection_mm = 0;    // largest |delta|
  double peak_mrr_mm3_per_s = 0;
  double mean_d_eff_mm = 0;         // over the points in material
  double mean_area_mm2 = 0;         // engaged area, over the points in material
  double cusp_max_mm = 0, cusp_mean_mm = 0;  // NaN-free: 0 where no cusp
  std::size_t cusp_points = 0;
  double path_mm = 0;               // cutting path length
  double time_s = 0;                // machining time, rapids included
};

// A program's row: the figures of its simulation (a Recorder's) and its machining time.
CompareRow compare_row(const std::string& program, const RunFigures& f, const process::MachiningTime& time);

// The table for a terminal (fixed columns, units in the header).
std::string compare_text(const std::vector<CompareRow>& rows, double tolerance_mm);
// One line per program; the header names the units. Fields quoted per RFC 4180 where needed.
std::string compare_csv(const std::vector<CompareRow>& rows);
Json compare_json(const std::vector<CompareRow>& rows, double tolerance_mm);
// A self-contained page: the table, each figure with a bar scaled to its
// column's largest, the best of each column marked; `provenance` as in report.html.
std::string compare_html(const std::vector<CompareRow>& rows, double tolerance_mm,
                         const std::vector<std::pair<std::string, std::string>>& provenance);

}  // namespace deflex::report
