// Surface normals estimated from the program itself, without a part model.
//
// For a ball end of radius R the tool-tip points of a finishing program lie on
// the part surface offset by R along its normal and shifted down by R (the CL
// surface), and the CL surface's normal at a tip point is the part's normal at
// the contact point (the offset of a surface keeps its normals). So the normal
// of the part at a CL point is the normal of the surface through the
// neighbouring tip points of the same and the adjacent passes: fitted here as a
// height field z(x, y) = quadratic, by weighted least squares (weights
// (1 - (d/r)^2)^2) over the tip points within r of the query, r growing from
// radius_mm (doubling, up to max_radius_mm) until the points determine the
// slope (PathNormalOptions): one pass alone is a line and gives no slope
// across it, two rows of points do not determine a quadratic across them, so
// the first and last passes of a raster need the two passes beside them on
// their one side. Exact for planes,
// second order for curved surfaces. Neighbours are found through CGAL's
// kd-tree.
#pragma once
#include <Eigen/Core>
#include <memory>
#include <optional>
#include <vector>

namespace deflex::part {

struct PathNormalOptions {
  double radius_mm = 1.0;       // first search radius
  double max_radius_mm = 8.0;   // no neighbours across the pass within it: no estimate
  // The fit must pin the slope down: its standard error (from the scatter of
  // the points about the fit, at least the rounding of a program's 3
  // decimals, 0.001 / sqrt(12) mm) under max_slope_error_rad (a 0.1 mm
  // deflection then moves the error by 0.2 um), and the points must lie on a
  // smooth surface (scatter under max_residual_mm: not across a wall or a
  // gouge). Else the radius grows; at max_radius_mm there is no estimate.
  double max_slope_error_rad = 0.002;
  double digit_noise_mm = 0.001 / 3.4641016151377544;
  double max_residual_mm = 0.005;
};

class PathNormals {
 public:
  explicit PathNormals(std::vector<Eigen::Vector3d> tips_mm, const PathNormalOptions& o = {});
  PathNormals(PathNormals&&) noexcept;
  ~PathNormals();
  // The upward unit normal of the tip surface at tip_mm (one of the points or
  // near them); nothing when the neighbours do not span a surface. Thread-safe.
  std::optional<Eigen::Vector3d> normal_at(const Eigen::Vector3d& tip_mm) const;
  std::size_t points() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace deflex::part
