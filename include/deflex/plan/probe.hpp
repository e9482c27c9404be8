// The on-machine probing program of a test cut's walls (plan/testcut.hpp):
// points over each feature's probe region, each approached along the wall's
// intended outward normal N. With r the stylus ball's radius and P the
// intended surface point, the ball centre goes to P + N (r + approach), the
// protected probing move runs along -N to P + N r - N overtravel (it stops
// on contact), then back to the start. Heights every `step_mm` from the
// wall's bottom + r + 0.1 to its top - 0.1 (paper 003 probed every 0.25 mm
// along the axial depth; REFERENCE §7).
//
// The programmed point is the ball centre: the probe's tool length offset
// must be set to the ball centre. Below the block top + clearance every move
// is a feed (G1) or a probing move, never a rapid; the ball stays in the air
// the test cut left (the removed strip of its own feature, or outside the
// block), so no move enters the material.
//
// Dialects: LinuxCNC writes G38.2 (an error if the probe does not trip) and
// logs every trip point to the file of (PROBEOPEN ...) ... (PROBECLOSE)
// (LinuxCNC G-code manual, "Comments: probe logging"; one line of 9 axes per
// probe). The ISO dialects write G31, the skip function (Fanuc 15i-MA
// programming manual, "Skip function G31": one-shot, the skip position in
// #5061..#5063, work coordinates), and DPRNT of that position to the output
// opened by POPEN and closed by PCLOS (custom macro B's external output).
// Before each probing move a comment another reader parses, byte for byte:
//   (DEFLEX PROBE 12 WX1 AT 10.000 5.000 -2.250 N 0.0000 1.0000 0.0000 BALL 1.000)
#pragma once
#include <iosfwd>
#include <string>
#include <vector>

#include "deflex/plan/testcut.hpp"
#include "deflex/profile/profile.hpp"

namespace deflex::plan {

struct ProbeOptions {
  double ball_diameter_mm = 2;
  double probe_length_mm = 0;        // stylus: ball centre to the probe body (0: not given, not checked)
  int probe_tool = 0;                // T/H number of the probe (0: none: the probe is in the spindle already)
  double step_mm = 0.5;              // between heights, 0.25 .. 0.5
  double approach_mm = 2;            // start of each probing move, off the intended surface
  double overtravel_mm = 1;          // how far past the intended surface the probing move may go
  double probe_feed_mm_per_min = 100;
  double move_feed_mm_per_min = 1000;  // positioning below the clearance plane
  int positions_along = 3;           // probe positions along each wall's probe region
  std::string results_file = "probe_results.txt";  // LinuxCNC's PROBEOPEN file
};

struct ProbePoint {
  int id = 0;              // 1..n in program order
  std::string feature;     // the feature's id
  Vec3 surface_mm{};       // intended surface point
  Vec3 normal{};           // outward unit normal
  Vec3 start_mm{}, end_mm{};  // ball centre: start and programmed end of the probing move
};

struct ProbeProgram {
  TestCutPlan plan;
  ProbeOptions options;
  double clear_z_mm = 0;   // rapids at or above this
  std::vector<std::vector<ProbePoint>> features;  // the points of each feature, in program order
};

// Throws Error(settings) naming the option out of range (before any plan is read).
void check_probe_options(const ProbeOptions& o);
// Throws Error(settings) on a wall too low for the ball, or a stylus too
// short for the deepest point.
void check_probe_fits(const TestCutPlan& p, const ProbeOptions& o);

ProbeProgram plan_probe(const TestCutPlan& p, const ProbeOptions& o);

// The DEFLEX PROBE comment's text (without the parentheses).
std::string probe_comment(const ProbePoint& pt, double ball_radius_mm);

// The program for dialect `d`; linuxcnc: G38.2 and PROBEOPEN, any other: G31
// and DPRNT.
void write_probe(std::ostream& out, const ProbeProgram& p, const profile::Dialect& d, const std::vector<std::string>& header);

}  // namespace deflex::plan
