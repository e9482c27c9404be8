// Plausibility warnings: what makes a program dangerous on the machine however
// well its deflection is compensated. Computed from the points of the program
// as written (compensate::simulate, Result::nominal) with the tool library:
//   flute_length    the cut reaches above the flutes (neck or shank in the cut):
//                   the engaged edge reaches the top of the flutes (a_p) and the
//                   stock over the tool's disc stands higher (Point::stock_depth_mm)
//   peak_force      the peak |F| over a revolution exceeds the tool's max_force_N,
//                   by default the tip force that breaks it in bending
//                   (default_force_limit)
//   offset_cap      gain |e| along the normal exceeds max_offset_mm: the mirror
//                   offset is capped there, the error stays
//   centre_cutting  a plunge (no XY travel) into material with a tool whose
//                   centre_cutting is false
//   roughing        a finishing cut on what looks like a raw blank: a ball end
//                   deeper than its radius, or another end in a full-width slot
//                   (a_e >= 0.98 D) deeper than D/2 over more than 1 mm of path,
//                   removing more than such a slot would (the cross-section
//                   across the travel, Point::section_mm2, over D x D/2). a_p
//                   counts only the band actually cut, not a wall the flank
//                   grazes (engage::Metrics::ap_mm)
//   gouge           a ball end's roughing points on a drop of more than R over
//                   less than R across followed at once by a climb of more
//                   than R, both within 2R across: no ball fits a hole that
//                   deep and narrow, so the program gouges (a drop-cutter
//                   sample off a rim), not a raw blank.
//   earlier_cut     (the stock came from earlier programs, --stock-from) a
//                   cutting move runs in air for longer than the tool's
//                   diameter with the stock a little below it (within the
//                   tool's radius): an earlier program cut below this
//                   program's surface there, and those points, in air, are
//                   neither compensated nor in the predicted error
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "deflex/compensate/compensate.hpp"

namespace deflex::compensate {

struct Finding {
  std::string kind;                  // flute_length | peak_force | offset_cap | centre_cutting | roughing | no_material | earlier_cut | gouge
                                     // | spindle_load | spindle_speed | feed_limit | chatter | stability_unchecked
  std::size_t count = 0;             // CL points
  double worst = 0, limit = 0;       // the worst value and what it is held against (mm, N, a ratio, rpm)
  std::uint32_t line = 0;            // line of the worst point
  std::string tool;                  // its tool
  std::vector<std::uint32_t> lines;  // distinct lines in program order, the first 12
  std::size_t line_count = 0;        // distinct lines in all
  std::string message;               // one sentence, without the location
};

struct Plausibility {
  std::vector<Finding> findings;
  const Finding* find(const std::string& kind) const;
};

// The largest tip force before the tool's bending stress reaches its
// material's allowable (Material::allowable_bending_MPa): F = sigma W / L, W =
// pi d^3 / 32, at the root of the flutes (d = flute_diameter_ratio D, L =
// flute_length_mm), of the neck (its diameter, L = flute + neck length) and at
// the holder face (shank diameter, L = stickout_mm); the smallest. `where`
// names the section.
struct ForceLimit {
  double N = 0;
  std::string where;
};
ForceLimit default_force_limit(const stiffness::Tool& t);
// The tool's max_force_N, else default_force_limit.
ForceLimit force_limit(const stiffness::Tool& t);

// capped_lines (compensate: Result::capped_lines, may be null): where the cap
// did bite; offset_cap then counts those and takes the worst |e| of the points
// on their lines, else it counts the points with gain |e| > max_offset_mm.
// spindle: as PlausibilityScan's.
Plausibility plausibility(const std::vector<Point>& points, const stiffness::ToolLibrary& tools, const Settings& s,
                          const std::vector<std::uint32_t>* capped_lines = nullptr, bool earlier_stock = false,
                          const profile::SpindleRating* spindle = nullptr);

// The same, point by point as a simulation produces them (program order), so
// that the points need not be kept: memory is the findings, the distinct lines
// they name, and a worst |e| per line for the offset cap, for the lines whose
// capped state is not known yet.
class PlausibilityScan {
 public:
  // earlier_stock: the stock is what earlier programs left (--stock-from).
  // spindle (may be null or not set): the points' power and torque are held against its S1 curve.
  PlausibilityScan(const stiffness::ToolLibrary& tools, const Settings& s, bool earlier_stock = false,
                   const profile::SpindleRating* spindle = nullptr);
  ~PlausibilityScan();
  void add(const Point& p);
  // compensate: the lines where the cap bit (Result::capped_lines, in program
  // order), as the mirror pass finds them. Not concurrently with add().
  void capped(const std::vector<std::uint32_t>& lines);
  // compensated: offset_cap from the capped lines given, else from the points.
  Plausibility finish(bool compensated);

 private:
  struct State;
  std::unique_ptr<State> st_;
};

}  // namespace deflex::compensate
