// Roughing and semi-finishing programs over a target surface: what
// a shop ran before the finishing program, when the shop has only the
// finishing program. deflex needs the stock the finishing tool meets; a box
// makes bear.nc a 17 mm deep cut under a finishing ball. The target is the
// Z-map the finishing program leaves in the blank; the generated program
// leaves `allowance_mm` over it, measured along the surface normal, as a
// CAM system's roughing would.
//
// Strategy: Z-level raster. Lines along X, `stepover_mm` apart in Y, zig-zag;
// levels `stepdown_mm` apart (at most) from the stock top down to the lowest
// floor; on every level the tip runs at max(level, floor(x, y)), so the last
// level follows the floor everywhere. The floor is the drop-cutter height of
// the tool grown by the allowance (the Minkowski sum of the cutter and a ball
// of radius a: a flat end R becomes a bull nose R + a with corner a, a bull
// nose r a bull nose r + a, a ball R a ball R + a), lowered back by a: the
// lowest tip height at which no point of the cutter comes nearer than a to
// the target. Lines start and end outside the stock, so every plunge is in air.
//
// Accuracy: the floor is exact against the target's cell centres; between
// centres and between samples along a line the target may rise by the slope
// times half a cell or half a sample, which the allowance absorbs. Points are
// merged only where the straight move stays above the floor (never into the
// allowance). What a raster leaves over the allowance: a flat end on a slope
// s along the lines, s (R - sqrt(R^2 - p^2/4)) midway between lines p apart;
// on a slope across the lines, terraces up to s p; a ball end at a small
// stepover (a semi-finishing pass), scallops of p^2 / 8R on the flat
// (tests/plan/test_roughing.cpp checks the first and the last).
// The program cuts air where an earlier level already went: it is a sweep of
// the stock, not an optimised roughing strategy.
#pragma once
#include <array>
#include <ostream>
#include <string>
#include <vector>

#include "deflex/profile/profile.hpp"
#include "deflex/stock/tool.hpp"
#include "deflex/stock/zmap.hpp"

namespace deflex::plan {

struct RoughingOptions {
  stock::ToolProfile tool;      // the cutter of the generated program
  int tool_number = 1;          // its T and H words
  double allowance_mm = 0.5;    // left over the target along the surface normal
  double stepdown_mm = 5.0;     // largest depth of one level; 0: one level on the floor (semi-finishing)
  double stepover_mm = 4.0;     // distance between raster lines, mm (Y)
  double sample_mm = 0.25;      // distance between floor samples along a line, mm (X)
  double clearance_mm = 5.0;    // rapids this far above the stock top
  double merge_tol_mm = 0.002;  // a point is dropped when the move past it stays within this above the floor
  double spindle_rpm = 8000, feed_mm_per_min = 1500;
};

using Point = std::array<double, 3>;  // tip X, Y, Z, mm (work frame)

struct RoughingPlan {
  double top_mm = 0;                 // stock top the levels start from
  double floor_min_mm = 0;           // lowest floor over the stock
  double x_start_mm = 0, x_end_mm = 0;  // line ends (outside the stock)
  std::vector<double> line_y_mm;     // raster lines
  std::vector<double> levels_mm;     // from the top down; the last one is floor_min_mm
  std::vector<std::vector<Point>> passes;  // one zig-zag polyline per level, starting at (x_start, line 0)
};

// Lowest tip height of `tool` at (x, y) with no cell centre of `z` above its
// lower surface; no_material when the tool's disc misses every material cell.
double drop_height(const stock::ZMap& z, const stock::ToolProfile& tool, double x_mm, double y_mm);
// The cutter grown by a ball of radius a (Minkowski sum), tip lowered by a.
stock::ToolProfile grown(const stock::ToolProfile& tool, double a_mm);

// Throws Error(usage) naming the option out of range.
void check_options(const RoughingOptions& o);

// Plans the roughing of `target` (the surface the finishing leaves) from a
// stock whose top is `stock_top_mm`. Throws Error(usage) when there is nothing
// to rough (the target lies within the allowance of the top everywhere).
RoughingPlan plan_roughing(const stock::ZMap& target, double stock_top_mm, const RoughingOptions& o);

// The plan as a program for the dialect `d` (mm, absolute): header comments,
// tool change, spindle, each level entered in air; ends with M30.
void write_roughing(std::ostream& out, const RoughingPlan& p, const RoughingOptions& o, const profile::Dialect& d,
                    const std::vector<std::string>& header);

}  // namespace deflex::plan
