// What the engaged intervals of a slice contribute to the per-point
// quantities of engage::Metrics: the engaged area, the removal rate (Bagci
// Eq. 1) and the radial extent (engagement.cpp).
#pragma once
#include <limits>

#include "deflex/force/cutter.hpp"
#include "deflex/stock/sweep.hpp"

namespace deflex::engage {

struct Accum {
  double cwe = 0, mrr_h = 0, mrr_v = 0, up = 0, down = 0;
  double y_hi = -std::numeric_limits<double>::infinity();
  double y_lo = std::numeric_limits<double>::infinity();
};

// Integral of the profile radius from the tip to height z, mm^2 (exact: the
// corner arc integrates to circular-segment areas).
double radius_integral(const stock::ToolProfile& t, double z);

// Interval [a, b] (rad) of slice s, whose band of height h carries int r dz = rdz.
void accumulate(const force::Slice& s, double a, double b, double h, double rdz, double dz, Accum& acc);

}  // namespace deflex::engage
