// What a report says about each CL point, gathered as the simulations produce
// the points: points.csv and flank_profile.csv are written
// row by row, the figures of summary.json accumulate, and what report.html
// draws goes to a Spill on disk, read back once at the end. Memory does not
// grow with the program.
//
// Sign convention, everywhere in deflex: the surface error e is measured along
// the outward normal n of the design surface, e = (landing point - intended
// point) . n; e > 0 the tool stood off the surface (material left, undercut),
// e < 0 it dug in (overcut). Offsets are along n likewise.
//
// The rows are the points reported: the compensated program's (compensate),
// or the simulated program's (simulate, compare). A compensation's row also
// shows the program as written at the same place: the sample of the same
// original move nearest to the row's design point (the compensated program
// holds inserted blocks the program as written does not have), whose error and
// cusp it takes. The cusp is that of the program as written (compensate) or of
// the points themselves, from process::CuspStream's window.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <deque>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <ostream>
#include <string>
#include <vector>

#include "deflex/compensate/compensate.hpp"
#include "deflex/process/cusp.hpp"
#include "deflex/report/json.hpp"
#include "deflex/report/stats.hpp"
#include "deflex/stiffness/tool.hpp"

namespace deflex::report {

using V3 = Eigen::Vector3d;

constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

// The offset commanded at a CL sample: between the offsets of the motion's
// start (the motion before) and its end, by the sample's position along it.
inline V3 offset_at(const compensate::Point& p, const std::vector<V3>& offsets) {
  if (offsets.empty()) return V3::Zero();
  const V3 end = offsets[p.motion], start = p.motion ? offsets[p.motion - 1] : V3(V3::Zero());
  const double u = p.count ? static_cast<double>(p.index) / p.count : 1.0;
  return start + u * (end - start);
}

// One row of points.csv: a reported CL point, in mm, N, mm^3/s (NaN: empty
// in the CSV, e.g. a cusp with no neighbouring pass). The CSV writes these
// values with a fixed number of decimals; a row sink gets them unrounded.
struct PointRow {
  std::uint32_t line = 0;
  V3 tip_mm = V3::Zero();
  double path_mm = 0, ap_mm = 0, ae_mm = 0, d_eff_mm = 0, cwe_area_mm2 = 0, mrr_mm3_per_s = 0;
  V3 force_N = V3::Zero(), delta_mm = V3::Zero();
  double surface_error_mm = 0, surface_error_as_written_mm = 0, offset_mm = 0;
  V3 normal = V3::UnitZ();
  const char* normal_source = "";
  double part_gap_mm = kNone;
  double flank_min_mm = kNone, flank_max_mm = kNone, flank_z_min_mm = kNone, flank_z_max_mm = kNone;
  double stepover_mm = kNone, cusp_height_mm = kNone;
  double power_kW = 0, torque_Nm = 0;  // the spindle's load (compensate::Point)
  double ap_limit_mm = kNone;          // the stability limit (compensate::Point; none where not checked)
  // The workpiece's displacement at the contact (compensate::Point; none
  // without a workpiece model: a rigid part).
  V3 workpiece_delta_mm = V3::Constant(kNone);
};
// The header of points.csv: its columns, in the order of PointRow's values.
extern const char* const kPointsCsvHeader;

struct RecorderOptions {
  double tolerance_mm = 0.01;
  // compensate: as_written() gives the program as written beside the points.
  bool as_written = false;
  bool workpiece = false;              // a workpiece model is in the run: its columns are filled
  std::ostream* points_csv = nullptr;  // null: no points.csv
  std::ostream* flank_csv = nullptr;   // null: no flank_profile.csv (the rows as written)
  std::function<void(const PointRow&)> rows;  // each points.csv row as it comes (null: none)
  bool page = false;                   // keep what report.html draws
  bool percentiles = false;            // ErrorStats' p50, p95, p99
  // The cusp and, in a compensation, the sample as written of each row (the
  // rows wait for them). false: the figures only (no cusp, no flank rows;
  // points.csv's as-written and cusp columns stay empty).
  bool cusp = true;
  std::string spill_dir;               // where they are kept ("": the temporary folder)
  // The tool of a point's T number (null: unknown): cusp (ball ends) and contact points.
  std::function<const stiffness::Tool*(int t_number)> tool_of;
  std::size_t cusp_block = process::kCuspBlock;
  // The machine's spindle rating (null or not set: none): report.html draws its
  // S1 allowance beside the power and torque.
  const profile::SpindleRating* spindle = nullptr;
};

// The figures of a run over its CL points in material (not in air, not plunging).
struct RunFigures {
  ErrorStats error;             // the rows against the design
  ErrorStats error_as_written;  // compensate: the program as written; else the rows'
  ValueStats cusp;              // the rows' cusp heights (ball ends with a neighbouring pass)
  double peak_force_N = 0, mean_force_N = 0, peak_deflection_mm = 0, peak_mrr_mm3_per_s = 0;
  double peak_power_kW = 0, peak_torque_Nm = 0;  // the spindle's (mean over a revolution)
  // The stability limit (chatter): the largest a_p over it, the rows above
  // it (ratio > 1) and the rows it was checked at.
  double worst_ap_over_limit = 0;
  std::size_t above_limit = 0, stability_checked = 0;
  double mean_d_eff_mm = 0, mean_area_mm2 = 0;
  bool flank_rows = false;      // flank_profile.csv got a row
  // The rows outside the tolerance on motions deflex never moves, per reason
  // (interp::Fixed): how many, and the line of the first.
  struct LeftAlone {
    std::size_t points = 0;
    std::uint32_t first_line = 0;
    double largest_mm = 0;  // the largest |error| among them
  };
  std::map<interp::Fixed, LeftAlone> left_alone;
  // With a workpiece model (RecorderOptions::workpiece): the deflection
  // along the normal split into the workpiece's share (-delta_w . n) and the
  // tool's (the rest), each's largest magnitude (signed) and its line.
  struct Share {
    double largest_mm = 0;
    std::uint32_t line = 0;
  };
  Share workpiece_share, tool_share;
};

// A grid of the top view: per cell the design surface's height and, per map,
// the value of largest magnitude among the points in it (NaN: none).
struct Grid {
  double x0_mm = 0, y0_mm = 0, cell_mm = 1;
  int nx = 1, ny = 1;
  std::vector<double> z_mm;
  std::vector<std::vector<double>> values;
};

// What report.html draws, decimated: the maps on a grid of at most 300 x 300
// cells, the plots to at most 4000 buckets that each keep the value of largest
// magnitude of every series (no peak is lost), the 20 worst lines.
struct Page {
  std::vector<std::pair<std::string, std::string>> maps;  // key, title: as written (compensate), then the rows'
  double scale_mm = 0;  // the colour scale: the largest |e| of the maps, at least twice the tolerance
  Grid grid;            // values: the maps, then the cusp height
  double cusp_max_mm = 0;
  ValueStats cusp;
  Json series, histogram, worst;  // worst: rows with "line", "values"; "text" filled by the caller
};

class Recorder {
 public:
  explicit Recorder(RecorderOptions o);
  ~Recorder();
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  // compensate: a point of the program as written, in program order.
  void as_written(const compensate::Point& p);
  // A point reported, in program order, with the offset commanded at it
  // (Point::motion counts the reported program's motions); `original`: the
  // motion of the program as written it lies on (compensate; else unused).
  void point(const compensate::Point& p, const V3& offset, std::size_t original);
  // After the last point: the rows still waiting are written.
  RunFigures finish();
  // After finish(), with RecorderOptions::page.
  Page page();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::mutex mutex_;  // the two streams may come from two threads
};

// The grid of a set of points: `xyz` their positions, `values` per map one
// value per point (NaN: not drawn). The cell is the larger of extent /
// max_cells and `min_cell_mm` (the step-over, so neighbouring passes leave no
// empty stripe between them); twice, an empty cell enclosed by filled ones (two
// opposite, or five of its eight neighbours) takes their largest value and
// mean height.
Grid make_grid(const std::vector<Eigen::Vector3d>& xyz, const std::vector<const std::vector<double>*>& values,
               double min_cell_mm, int max_cells = 300);

// The same point by point: the extent first (a pass over the points), then add().
class GridBuilder {
 public:
  GridBuilder(double x0_mm, double y0_mm, double x1_mm, double y1_mm, std::size_t maps, double min_cell_mm,
              int max_cells = 300);
  void add(const Eigen::Vector3d& xyz, const double* values);
  Grid finish();

 private:
  Grid g_;
  std::vector<double> zsum_, zn_;
  bool empty_;
};

}  // namespace deflex::report
