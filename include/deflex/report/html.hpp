// report.html: one self-contained page (opens offline) a process engineer can
// show: provenance, the summary as written -> compensated, the machined surface
// in 3D coloured by the surface error (three.js), top views with ticks and a
// colour bar, plots along the program (dygraphs), a histogram and the worst
// lines with their source text (issue 12 item 1).
//
// The numbers are those of the PointTable and summary.json; only the drawing is
// decimated: the maps on a grid of at most 300 x 300 cells, the plots to at
// most 4000 buckets that each keep the value of largest magnitude of every
// series, so no peak is lost. The libraries (Debian's libjs-three and
// libjs-dygraphs) are compiled into deflex (cmake/embed_report.cmake).
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/report/json.hpp"
#include "deflex/report/points.hpp"

namespace deflex::report {

// A grid of the top view: per cell the design surface's height and, per map,
// the value of largest magnitude among the points in it (NaN: none).
struct Grid {
  double x0_mm = 0, y0_mm = 0, cell_mm = 1;
  int nx = 1, ny = 1;
  std::vector<double> z_mm;
  std::vector<std::vector<double>> values;
};

// `xyz` the points' positions, `values` per map one value per point (NaN:
// not drawn). The cell is the larger of extent / max_cells and `min_cell_mm`
// (the step-over, so neighbouring passes leave no empty stripe between them);
// twice, an empty cell enclosed by filled ones (two opposite, or five of its
// eight neighbours) takes their largest value and mean height.
Grid make_grid(const std::vector<Eigen::Vector3d>& xyz, const std::vector<const std::vector<double>*>& values,
               double min_cell_mm, int max_cells = 300);

// Where the cutter touches the design surface at each point: the tip moved by
// the cutter's profile against the normal (ball: centre - R n; bull nose and
// flat: the corner circle's point facing n).
std::vector<Eigen::Vector3d> contact_points(const PointTable& t, const std::vector<interp::Motion>& motions,
                                            const compensate::Physics& ph, const compensate::Settings& s);

struct HtmlInput {
  std::string title;
  std::vector<std::pair<std::string, std::string>> provenance;  // label, value
  Json summary;                         // as written to summary.json
  const PointTable* table = nullptr;
  std::vector<Eigen::Vector3d> contact_mm;  // per point of the table
  const SourceText* source = nullptr;   // the program, for the worst lines' text
  double tolerance_mm = 0.01;
  std::vector<std::vector<std::string>> facts;  // {label, text, summary key}: rows under the summary
};

// The page's text.
std::string report_html(const HtmlInput& in);

// The SHA-256 of `bytes`, as 64 hex digits (OpenSSL).
std::string sha256_hex(const std::string& bytes);

}  // namespace deflex::report
