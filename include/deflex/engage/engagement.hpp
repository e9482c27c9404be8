// Cutter-workpiece engagement at one CL point, from the stock as cut so far.
//
// Frames. World = the work frame of the program (mm, Z up). At each CL point the
// FEED frame has X' along the XY direction of travel, Y' = Z x X' (90 deg
// counter-clockwise from X'), Z' = Z; it is the frame of deflex::force: the edge
// point of slice i at immersion phi sits at tip + z_i Z' + r_i (sin phi X' + cos phi Y'),
// phi measured clockwise from +Y' seen from above (force/engagement.hpp).
//
// Method. Each slice circle of a force::CutterSlices is sampled at N angles
// phi_j = (j + 1/2) 2 pi / N; a sample is engaged when its edge point is in
// material: below the Z-map height of its cell, above the stock base, and outside
// every swept volume not yet committed to the Z-map (StockView::pending), which
// includes the current move up to just before this CL point. That last test is
// what makes an edge point "in front material": points on the back of the tool lie
// inside the tool's own earlier positions and are excluded exactly (not to a cell),
// which is why no explicit front-half rule is needed and why ramps and arcs are
// handled as well as lines. Every in/out transition is refined by bisection.
// evaluate() settles most of those tests without making them (arcs of samples
// above every Z-map cell they could read, pending sweeps out of reach of a slice
// or a point; src/engage/probe.hpp), with the results of making them all,
// evaluate_reference(), bit for bit.
//
// Plunges and ramps. The feed frame takes the XY direction of travel; a pure
// plunge (no XY travel) keeps the previous move's XY direction (+X at the start).
// The engagement is geometric, so a descending ramp or plunge engages the lower
// part of a ball / corner on the whole circle and a flat bottom reports
// bottom_area_mm2 (the slices of deflex::force carry no end-face edge). The
// force model's chip law h = f_z sin(phi) sin(kappa) assumes horizontal feed: for
// |ramp_angle| beyond a few degrees its forces are an approximation, and for a
// plunge (Metrics::plunge) they are not meaningful; the caller should flag those.
#pragma once
#include <array>
#include <span>
#include <vector>

#include "deflex/force/cutter.hpp"
#include "deflex/force/engagement.hpp"
#include "deflex/stock/sweep.hpp"
#include "deflex/stock/zmap.hpp"

namespace deflex::engage {

using Point3 = stock::Point3;

struct Options {
  int angle_samples = 72;  // N per slice circle (5 deg); transitions are refined below
  int refine_steps = 6;    // bisections per transition: 5 deg / 2^6 = 0.08 deg
  int bottom_rings = 6;    // radial rings sampling a flat bottom (ramps, plunges)
};

// Feed per tooth and spindle speed: feed speed v_f = f_z n_t N (Bagci Eq. 1).
struct Process {
  double fz_mm = 0.05;
  double spindle_rpm = 10000;
};

// The stock as cut so far: the Z-map, minus the swept volumes not yet committed
// to it (oldest first) and the current move up to just before the CL point.
struct StockView {
  const stock::ZMap* zmap = nullptr;
  std::span<const stock::LineSweep> pending;
  const stock::LineSweep* current = nullptr;
};

struct CLPoint {
  Point3 tip_mm{};           // tool tip (programmed point), world
  Point3 dir{1, 0, 0};       // unit direction of travel (3D)
  double feed_x = 1, feed_y = 0;  // unit XY feed direction X' (see Plunges above)
};

struct Metrics {
  bool air_cut = true;           // nothing engaged
  bool plunge = false;           // no XY travel
  double ramp_angle = 0;         // rad, travel above the horizontal (< 0: descending)
  // Axial depth of cut: height above the tip where the flank leaves the material
  // it cuts (the highest engaged slice, refined by bisection), not counting a
  // band above where the engaged edge only grazes a wall (material less than a
  // Z-map cell deep inside the envelope: the tool's own earlier cut; the force
  // and the area still count it). 0 when only a flat bottom cuts.
  double ap_mm = 0;
  double ae_mm = 0;              // radial width: extent of the engaged edge points along Y'
  double cwe_area_mm2 = 0;       // engaged area of the tool envelope (flanks + flat bottom)
  double bottom_area_mm2 = 0;    // engaged flat bottom (only when descending)
  double d_eff_mm = 0;           // Bagci Eq. 2: 2 r(a_p); ball 2 sqrt(a_p (D - a_p)) for a_p < D/2
  double mrr_mm3_per_s = 0;      // Bagci Eq. 1, at the Process feed
  double section_mm2 = 0;        // removed cross-section across the travel: mrr_mm3_per_s / feed (mm/s)
  double up_share = 0;           // share of the horizontal removal on the up-milling (+Y') side
};

// Precomputed tables for one cutter and option set; evaluate() is const and thread-safe.
class Engager {
 public:
  Engager(const force::CutterSlices& cs, const Options& o = {});

  // Fills `out` (one entry per slice of cs) and returns the per-point quantities.
  Metrics evaluate(const StockView& stock, const CLPoint& p, const Process& proc,
                   force::Engagement& out) const;
  // The same by the definition, point by point: every test against the Z-map and
  // every pending sweep near the tool, no shortcut. evaluate() skips only tests
  // whose outcome it has proved, so both give identical results (the tests
  // compare them bit for bit); this one is several times slower.
  Metrics evaluate_reference(const StockView& stock, const CLPoint& p, const Process& proc,
                             force::Engagement& out) const;

  const force::CutterSlices& slices() const { return cs_; }
  const stock::ToolProfile& tool() const { return tool_; }

 private:
  force::CutterSlices cs_;
  Options o_;
  stock::ToolProfile tool_;
  std::vector<double> sin_, cos_;  // of the sample angles
  // sin and cos of the refinement midpoints: refine_nodes_ per transition (empty
  // when refine_steps is 0 or large); r dz integrated over each slice's band.
  std::vector<std::array<double, 2>> refine_sc_;
  int refine_nodes_ = 0;
  std::vector<double> band_rdz_;

  // The method, with the in-material tests answered by a Probe (engagement.cpp).
  template <class Probe>
  Metrics evaluate_with(const StockView& stock, const CLPoint& p, const Process& proc,
                        force::Engagement& out) const;
  // a_p: the top of the band where the radial depth of cut exceeds depth_mm
  // (engagement.cpp), at most the envelope's top.
  template <class Probe>
  double cut_top(const Probe& probe, const CLPoint& p, const stock::LineSweep* current, const force::Engagement& out,
                 std::size_t top_slice, double envelope_top_mm, double depth_mm) const;
};

// The Z-map's view of a cutter's lower surface.
stock::ToolProfile tool_profile(const force::Cutter& c);

}  // namespace deflex::engage
