// A top view (X-Y, work frame, mm) of the predicted surface error, as SVG: each
// cell of a raster coloured by the error of largest magnitude that falls in it
// (red: material left / undercut, blue: overcut, white: inside the tolerance).
#pragma once
#include <string>
#include <vector>

namespace deflex::compensate {

struct PlotPoint {
  double x_mm, y_mm, error_mm;
};

// `scale_mm`: the error shown at full colour (e.g. the largest of the plots to
// compare, so two maps share one scale).
std::string error_map_svg(const std::vector<PlotPoint>& pts, double tolerance_mm, double scale_mm,
                          const std::string& title);

}  // namespace deflex::compensate
