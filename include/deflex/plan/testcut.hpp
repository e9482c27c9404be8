// A calibration test cut: straight side-milled walls on a block, each at one
// radial depth a_e and one axial depth a_p, down-milling with the spindle
// clockwise (M3), so the surface error each leaves can be probed on the
// machine and the machine's stiffness fitted to it (REFERENCE §7: paper 003
// measured its walls this way with the spindle's touch probe).
//
// Geometry (work frame, block [X0,X1] x [Y0,Y1] x [Z0,Z1]):
//  - walls fed along +X on the back face (y = Y1): material at -Y, the wall's
//    outward normal +Y; the material is on the right of the feed, which is
//    down (climb) milling for a clockwise spindle, and the side deflex's
//    engagement calls down-milling (engage::Metrics::up_share on +Y' = left);
//  - walls fed along +Y on the left face (x = X0): material at +X, normal -X,
//    again on the right of the feed.
// Each feature is its own straight segment along its face: the tool goes down
// in air beside the block, feeds in to the radial depth, cuts along the face
// and leaves into air; segments are `gap_mm` apart beyond the cutter's reach,
// and the corner X0/Y1 is kept free, so no cut touches another feature's
// wall. The wall is steady-state from one tool radius after the entry to one
// tool radius before the exit: that is the probe region.
//
// Axial depths are chosen against the axial pitch between flutes,
// p = pi D / (N tan(helix)) (Morelli 2021 Eq. 3: the swept angle k_b a_p
// reaches the tooth pitch 2 pi / N at a_p = p): below it, at small a_e, one
// flute at a time generates the wall (Morelli's single-flute case); above it
// the flutes overlap. Each feature records Morelli's shape code
// (force/morelli.hpp) for its a_e, a_p.
#pragma once
#include <array>
#include <iosfwd>
#include <string>
#include <vector>

#include "deflex/profile/profile.hpp"
#include "deflex/stock/end_shape.hpp"

namespace deflex::plan {

using Vec3 = std::array<double, 3>;  // mm or a unit vector, work frame

struct TestBlock {
  double x0_mm = 0, y0_mm = 0, z0_mm = 0, x1_mm = 0, y1_mm = 0, z1_mm = 0;  // x0 < x1 ...
};

// The end mill of a test cut (from the tool library).
struct TestCutter {
  std::string id;  // T<n>
  stock::EndShape type = stock::EndShape::flat;
  double diameter_mm = 0, corner_radius_mm = 0;
  int flutes = 2;
  double helix_deg = 30;
  double flute_length_mm = 0;  // 0: unknown (a_p then at most 1.5 D)
};

struct TestCutOptions {
  int tool_number = 1;                            // its T and H words
  double spindle_rpm = 6000;
  double fz_mm = 0.05;                            // feed per tooth; the feed is fz N n
  std::vector<double> ae_fractions{0.1, 0.25, 0.5};  // a_e / D of the walls
  std::vector<double> ap_pitches{0.4, 1.25};      // a_p / axial pitch (single flute, overlap)
  double probe_length_mm = 6;                     // steady-state wall along the feed, mm
  double gap_mm = 3;                              // between the reach of neighbouring cuts
  double air_mm = 2;                              // the cutter this far from the block when it goes down
  double clearance_mm = 5;                        // rapids this far above the block top
  double floor_margin_mm = 2;                     // material left under the deepest floor
  double Ktc_N_per_mm2 = 752.9, Krc_N_per_mm2 = 200.5;  // for Morelli's classification only
};

struct WallFeature {
  std::string id;                // WX1, WY2 ...: W, the feed axis, a number
  int feed_axis = 0;             // 0: fed along +X (back face), 1: along +Y (left face)
  Vec3 feed_direction{1, 0, 0};
  Vec3 point_mm{};               // a point of the intended wall plane
  Vec3 normal{0, 1, 0};          // outward unit normal, material to air
  double u0_mm = 0, u1_mm = 0;   // probe region along the feed axis coordinate
  double z0_mm = 0, z1_mm = 0;   // the wall: floor (plus a bull nose's corner) to block top
  double ae_mm = 0, ap_mm = 0, fz_mm = 0;
  std::string morelli;           // Morelli's shape code, e.g. "IIM" ("" when it does not apply)
  std::vector<Vec3> path;        // tool tip: above in air, down, in, along, out, up
  int first_line = 0, last_line = 0;  // program lines from going down to leaving (write_testcut)
};

struct TestCutPlan {
  TestBlock block;
  std::string machine, material, dialect;
  TestCutter tool;
  int tool_number = 1;
  double spindle_rpm = 0, feed_mm_per_min = 0, fz_mm = 0, clearance_mm = 5;
  std::vector<WallFeature> features;
};

// The axial pitch between flutes, pi D / (N tan(helix)), mm.
double axial_pitch_mm(const TestCutter& t);

// The smallest block (lengths along X, Y, Z, mm) the features of `t`, `o` fit.
Vec3 smallest_block_mm(const TestCutter& t, const TestCutOptions& o);

// Throws Error(settings) naming the option out of range, the cutter that is
// not a flat or bull-nose end mill (slope patches for a ball are not
// implemented), or the block that is too small (naming the smallest that fits).
void check_testcut(const TestBlock& b, const TestCutter& t, const TestCutOptions& o);

// The features and their tool paths (check_testcut first).
TestCutPlan plan_testcut(const TestBlock& b, const TestCutter& t, const TestCutOptions& o);

// The program for dialect `d` (mm, absolute): header comments, tool change,
// spindle M3, each feature entered from air; ends with M30. Sets each
// feature's first_line / last_line.
void write_testcut(std::ostream& out, TestCutPlan& p, const profile::Dialect& d, const std::vector<std::string>& header);

// The plan as commented YAML (testcut.yaml), and read back: every value
// checked, errors `file:line:col: error: ...` (Error(config)).
void write_plan_yaml(std::ostream& out, const TestCutPlan& p, const std::string& program);
TestCutPlan read_plan_yaml(const std::string& text, const std::string& file);

}  // namespace deflex::plan
