// Material removal by the swept envelope of a vertical end mill.
//
// Lines (G0/G1, including ramps and plunges) are exact: per cell centre the
// Z-map takes the minimum over the whole segment of the tool's lower surface
// height. The tool solid is convex and moves along a line, so that height is a
// convex function of the position along the segment and its minimum has a closed
// form for a ball (the sphere's centre sweeps a capsule) and a flat end (a
// linear function on an interval); for a bull nose it is found by bisection on
// the derivative to 1e-12 of the segment (numerically exact).
//
// Arcs and helices are swept as a polyline of chords whose sagitta is at most
// chord_tol_mm (the chords lie inside the arc, so the cut surface is off the
// exact one by at most that tolerance, toward the arc centre).
//
// Frame: work frame, mm; points are tool-tip positions (the programmed point).
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>
#include <span>

#include "deflex/interp/arc.hpp"
#include "deflex/stock/tool.hpp"
#include "deflex/stock/zmap.hpp"

namespace deflex::stock {

using Point3 = std::array<double, 3>;  // x, y, z mm

// The swept volume of one tool moving on a straight line from tip a to tip b.
class LineSweep {
 public:
  LineSweep(const ToolProfile& tool, const Point3& a_mm, const Point3& b_mm);

  // Lowest height of the tool's lower surface over the segment at (x, y); +inf
  // where the footprint does not reach. Anything above it is inside the swept tool.
  double lower_height(double x_mm, double y_mm) const;

  // Footprint (segment (+) disc of radius R0 in XY) bounding box, mm.
  double x_min() const { return xmin_; }
  double x_max() const { return xmax_; }
  double y_min() const { return ymin_; }
  double y_max() const { return ymax_; }
  // X range of the footprint on the line y = y_mm; false if it misses. With
  // start_cut (the tool at `a` is already in the Z-map) only the cells the move
  // can lower below the tool at `a` are kept. The lower surface over a cell is a
  // convex function f(s) of the travel s, so the move lowers the cell only where
  // f'(0) = m - g'(d0) par / d0 < 0 (m the slope, g the profile, d0 the distance
  // to `a`, par the coordinate along the move). A horizontal or rising move: only
  // cells ahead of the start's normal line (par > 0). A descending ball: only
  // par > -|m| R (g'(d)/d >= 1/R); a bull nose: that band with |m| r1 / g'(r1)
  // instead of |m| R, plus the disc of radius r1 = R - r_c / 2 about `a`; a flat
  // end lowers its whole footprint. A retract (rising plunge) removes nothing.
  bool row_range(double y_mm, double& x0_mm, double& x1_mm, bool start_cut = false) const;
  // row_range on n rows at once: ok[k] = row_range(y_mm[k], x0_mm[k], x1_mm[k],
  // start_cut), the same operations (4 rows per step with AVX2), so the same doubles.
  void row_ranges(const double* y_mm, int n, double* x0_mm, double* x1_mm, unsigned char* ok,
                  bool start_cut = false) const;
  // Hand-off to the next move of a chain: narrows [x0_mm, x1_mm] (e.g. this move's
  // row_range) on the line y = y_mm to the cells this move may leave out when
  // `next` starts at b() and is swept after it with start_cut (sweep_lines), one
  // interval; false if none. Those cells are in next's row_range(y, .., true), this
  // move cannot lower them below the tool at b, and next lowers them below it by a
  // margin far above the rounding of the row kernels, so next's height is <= this
  // move's (as floats) and leaving them out changes no cell (see handoff.cpp). Leaves
  // out nothing for plunges, other tools, very short or very steep moves and a
  // flat end that next does not lower.
  bool end_handoff(const LineSweep& next, double y_mm, double& x0_mm, double& x1_mm) const;

  // A lower bound of the lower surface anywhere on the line y = y_mm: the
  // segment's lowest tip plus the profile at the row's least distance in Y to
  // the segment (every point of the row is at least that far from the axis).
  double row_floor(double y_mm) const {
    const double lo = std::min(a_[1], b_[1]), hi = std::max(a_[1], b_[1]);
    const double dy = y_mm < lo ? lo - y_mm : y_mm > hi ? y_mm - hi : 0.0;
    return std::min(a_[2], b_[2]) + profile_height(tool_, dy);
  }

  // A lower bound of the lower surface over the cells of the line y = y_mm with
  // x in [x0_mm, x1_mm]: row_floor with the distance in X to the segment's X
  // range as well (the segment lies in its bounding box, so every point of the
  // span is at least that far from the axis). +inf where the tool cannot reach.
  double span_floor(double y_mm, double x0_mm, double x1_mm) const {
    const double ylo = std::min(a_[1], b_[1]), yhi = std::max(a_[1], b_[1]);
    const double dy = y_mm < ylo ? ylo - y_mm : y_mm > yhi ? y_mm - yhi : 0.0;
    const double xlo = std::min(a_[0], b_[0]), xhi = std::max(a_[0], b_[0]);
    const double dx = x1_mm < xlo ? xlo - x1_mm : x0_mm > xhi ? x0_mm - xhi : 0.0;
    return std::min(a_[2], b_[2]) + profile_height(tool_, std::sqrt(dx * dx + dy * dy));
  }

  const Point3& a() const { return a_; }
  const Point3& b() const { return b_; }
  const ToolProfile& tool() const { return tool_; }
  double dir_x() const { return ex_; }       // unit XY direction of travel (+X for a plunge)
  double dir_y() const { return ey_; }
  double xy_length() const { return len_; }  // 0 for a plunge
  double slope() const { return slope_; }    // dz per mm of XY travel (0 for a plunge)

  // Heights of the swept lower surface at the centres of n consecutive cells of
  // one Z-map row: x_k = gx0 + (i0 + k + 0.5) cell, k in [0, n), at y; +inf where
  // the footprint does not reach. Equal to lower_height within rounding (1e-12 mm);
  // ball and flat ends are evaluated 4 cells at a time (AVX2, when the CPU has it,
  // with results identical to the scalar path).
  void row_heights(double y_mm, double gx0_mm, double cell_mm, int i0, int n, float* out) const;

 private:
  ToolProfile tool_;
  Point3 a_, b_;
  double ex_ = 1, ey_ = 0;  // unit XY direction (when len_ > 0)
  double len_ = 0;          // XY length, mm
  double slope_ = 0;        // dz per mm of XY travel
  double ball_k_ = 0;       // slope / sqrt(1 + slope^2): ball's contact offset per unit half-chord
  double xmin_, xmax_, ymin_, ymax_;
};

// Removes the swept volume of a line from the stock; returns the removed volume, mm^3.
double sweep_line(ZMap& z, const ToolProfile& tool, const Point3& a_mm, const Point3& b_mm);
double sweep_line(ZMap& z, const LineSweep& s, bool start_cut = false);
// The straightforward sweep (every cell of the footprint, lower_height per cell,
// no start_cut shortcut): the reference the fast paths are tested against.
double sweep_line_reference(ZMap& z, const LineSweep& s);

// Consecutive sweeps in order (each one's start is the previous one's end when
// chained; the first one's start is cut already when first_start_cut). Bands of
// tile rows are cut in parallel (TBB), each band applying the sweeps in order, so
// the result equals sweeping them one by one (sweep_line with start_cut when
// chained), bit for bit: a move followed by a chained one skips the cells of its
// end_handoff, which the next move lowers further anyway.
double sweep_lines(ZMap& z, std::span<const LineSweep> s, bool first_start_cut);

// The work of every sweep this process has done so far, on all threads: the
// moves swept and the Z-map cells whose height under a move was computed (and
// lowered where the move reaches below it). A measure of a simulation's work
// independent of the machine: `deflex -v` prints it, bench/ divides it by the
// wall time (cells updated per second).
struct SweepWork {
  std::uint64_t moves = 0, cells = 0;
};
SweepWork sweep_work();

// Consecutive points joined by lines.
double sweep_polyline(ZMap& z, const ToolProfile& tool, std::span<const Point3> pts_mm);

// An arc or helix (interp/arc.hpp) as the chords of arc_chord_count(a, chord_tol_mm).
double sweep_arc(ZMap& z, const ToolProfile& tool, const interp::Arc& a, double chord_tol_mm);

}  // namespace deflex::stock
