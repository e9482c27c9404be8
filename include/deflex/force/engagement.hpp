// What the force model needs to know about the cut: for each axial slice of the
// cutter (the slicing of a CutterSlices), the immersion-angle intervals in which
// an edge point of that slice is inside the stock.
//
// Immersion angle phi (rad): measured clockwise from +Y seen from above, i.e. the
// edge point of radius r sits at (x, y) = r (sin phi, cos phi) relative to the tool
// axis. With feed along +X and the spindle turning clockwise (M3) the uncut chip is
// h = f_z sin(phi) sin(kappa): the cutting side is phi in (0, pi); up-milling cuts
// on the +Y side (entry at phi = 0), down-milling on the -Y side (exit at phi = pi).
// Altintas 2012 ch. 2 uses the same convention.
#pragma once
#include <cstddef>
#include <vector>

#include "deflex/force/cutter.hpp"

namespace deflex::force {

// One engaged interval [start, end], rad. start in [0, 2 pi); start <= end <= start + 2 pi.
struct AngleInterval {
  double start = 0;
  double end = 0;
};

// Per slice (index = slice index of the CutterSlices), its engaged intervals,
// sorted and disjoint. Reuse one object per thread: clear() keeps the capacity,
// so filling it for every CL point does not allocate once warm.
struct Engagement {
  std::vector<std::vector<AngleInterval>> slices;

  void clear(std::size_t slice_count);  // resize to slice_count, empty every slice
  // Adds [start, end] (any real start; end - start clamped to 2 pi) to slice i.
  void add(std::size_t slice, double start, double end);
  bool empty() const;  // no slice engaged: an air cut
};

enum class MillingMode { up, down };

// The textbook condition: a straight cut along +X into stock bounded by a wall
// parallel to X, radial depth a_e measured from the cutting side (+Y for up-,
// -Y for down-milling), axial depth a_p above the tip, stock face above. Slice i
// is engaged where its edge point (r_mm at mid height) is in the stock on the
// front half. a_e >= D gives a full slot [0, pi] whatever the mode.
void simple_engagement(const CutterSlices& cs, double ae_mm, double ap_mm, MillingMode mode,
                       Engagement& out);

// Entry and exit immersion angles of a cylinder of radius r in that condition
// (Altintas 2012 ch. 2): up [0, acos(1 - a_e/r')], down [pi - acos(...), pi].
AngleInterval immersion_interval(double r_mm, double R0_mm, double ae_mm, MillingMode mode);

// The part of an engaged interval on the cutting side, phi in [0, pi], where
// the chip law gives a chip: an interval across phi = 0 (start near 2 pi, end
// past it) counts from 0, one beyond pi stops at pi, one wholly on the back
// half is none ({0, 0}). What the stability limit (stability/model.hpp) reads
// of an engagement.
AngleInterval cutting_side(const AngleInterval& iv);

}  // namespace deflex::force
