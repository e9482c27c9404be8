// Deflection simulation and mirror compensation over a whole program.
//
// Per cutting CL point (engage::Simulator: the stock as cut so far):
//   engagement -> mean cutting force over a revolution (force::revolution_forces,
//   feed frame -> machine axes) -> deflection delta = C(h) F of tool + holder +
//   spindle + machine (stiffness::ComplianceTable), h the height along the
//   flutes where the engaged edge length is centred -> surface error
//   e = delta . n, n the outward normal of the surface being generated.
//
// Surface normal n: from the part model where one is given, else (ball ends)
// fitted through the neighbouring CL points, else the rule of the tool and the
// travel (compensate/normals.hpp). The offset acts along it in 3D.
// e > 0: the tool stands off the surface (material left); e < 0: it digs in.
//
// Flank cuts (a flat or bull-nose end cutting with its flank, flank_cut() of
// normals.hpp): the wall at height z is generated when the edge at z passes the
// generating angle (exit in down-milling, entry in up-milling), so e(z) is
// predicted from the force distribution of that instant and the cross
// compliance C(z, z') (force/flank.hpp, Morelli 2021) over the engaged slices,
// along the same normal n. The point's error is then the mid-range
// (min + max) / 2 of e(z): the mirror drives it to zero, which is the offset
// along n minimising the largest |e(z)| over the flank (a 3-axis offset cannot
// straighten a tapered wall). delta (mean force at h) stays for the report.
//
// Mirror method (Smaoui 2011 §4): P_comp = P_nom - gain e(P_comp) n. The
// engagement at a CL point depends only on the path before it, so the fixed
// point of the whole program is found in one pass in program order: at each
// motion end, with the motions before it already cut at their compensated
// positions, the offset along n is solved by secant steps (one engagement
// evaluation each, nothing cut) until the next mirror step would change it by
// no more than 1% of the tolerance, or max_iterations; then the motion is cut
// there. The same fixed point as re-simulating the whole program per mirror
// iteration, at the cost of about one simulation plus an evaluation or two per
// compensated point. A point whose error at the programmed position (in the
// stock the compensated motions before it leave) is within the tolerance stays.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "deflex/compensate/normals.hpp"
#include "deflex/compensate/workpiece.hpp"
#include "deflex/force/coefficients.hpp"
#include "deflex/force/flank.hpp"
#include "deflex/interp/motion.hpp"
#include "deflex/profile/spindle.hpp"
#include "deflex/stiffness/machine.hpp"
#include "deflex/stiffness/tool.hpp"
#include "deflex/stock/zmap.hpp"

namespace deflex::compensate {

using V3 = Eigen::Vector3d;

struct Settings {
  double tolerance_mm = 0.01;   // |e| within it: the point stays as programmed
  double gain = 1.0;            // mirror gain
  int max_iterations = 8;       // mirror updates per point at most
  double max_offset_mm = 0.1;   // cap of |offset| (machine profile)
  // The written numbers' rounding, mm (per axis, half the dialect's last
  // decimal; inch programs round coarser): the mirror caps the offset this
  // much below max_offset_mm per axis, so the cap holds on the coordinates
  // as written (writer::rounding_mm).
  double rounding_mm = 0, rounding_inch_mm = 0;
  double max_step_mm = 0.02;    // largest change of offset from one point to the next
  double cl_spacing_mm = 0.5;   // CL samples along long moves and arcs
  double slice_mm = 0.2;        // axial slice height of the force model
  int force_steps = 90;         // angular steps per revolution
  int threads = 0;              // 0: all cores
  int max_splits_per_move = 32;  // points inserted into one move at most
  double chord_tol_mm = 0.001;  // sagitta of the chords of a linearised arc
  double feed_limit_N = 0;      // > 0: lower F where the peak force would exceed it
  std::string tool_override;    // use this tool whatever the T words say
  double part_reach_mm = 1.0;   // a part contact farther than this is not the surface being cut
  bool flank_profiles = false;  // simulate(): keep each flank point's e(z) in Point::flank_profile (reports)
  // simulate(): the sweep through the stock and the assembly check alone
  // (Point::collision_mm; no engagement, forces or normals): `deflex check --stock`.
  bool geometry_only = false;
};

// What does not change with the path: tools, machine, material, stock.
struct Physics {
  stiffness::ToolLibrary tools;
  stiffness::MachineStiffness machine;
  bool tool_only = false;       // no holder/spindle/structure in C(h)
  force::Coefficients k;
  const stock::ZMap* stock = nullptr;  // initial stock; copied per simulation
  // The same map when the caller no longer needs it: compensate() then runs
  // its mirror pass on it instead of on a copy (one Z-map less in memory),
  // simulate() its simulation, and leaves it moved from. Null: every
  // simulation copies `stock`.
  stock::ZMap* consumable_stock = nullptr;
  const part::PartModel* part = nullptr;  // the design surface (may be null)
  // The workpiece's compliance at the contact (workpiece.hpp); null: a rigid
  // workpiece, the tool's deflection alone.
  const WorkpieceCompliance* workpiece = nullptr;
  // The machine's spindle power and torque against speed (set: false, not
  // checked); with a feed limit the feeds keep within its S1 curve too.
  profile::SpindleRating spindle;
};

// The non-cutting parts of the tool assembly (collision.hpp).
enum class AssemblyPart : std::uint8_t { neck, shank, holder };

// One CL sample of one simulation.
struct Point {
  std::uint32_t line = 0;
  std::uint32_t motion = 0;     // index into the motion list
  std::int32_t tool = 0;        // T number of its motion
  interp::Fixed fixed = interp::Fixed::no;  // why its motion is never moved (no: it may be)
  int index = 0, count = 0;     // sample index within the motion (count: its end)
  V3 tip_mm = V3::Zero();       // commanded tool tip (with the offsets applied)
  double ap_mm = 0, ae_mm = 0;
  double cwe_area_mm2 = 0;      // engaged area of the tool envelope (engage::Metrics)
  double d_eff_mm = 0;          // effective cutting diameter (Bagci Eq. 2)
  double mrr_mm3_per_s = 0;     // material removal rate at the motion's feed (Bagci Eq. 1)
  double section_mm2 = 0;       // removed cross-section across the travel (mrr / feed; engage::Metrics)
  bool air = true, plunge = false;
  V3 force_N = V3::Zero();      // mean over a revolution, on the tool, machine axes
  double peak_N = 0;            // largest |F| over the revolution
  // The spindle's load: the mean torque over a revolution (sum of r dF_t) and
  // the cutting power P = M w at the motion's S (Altintas, Manufacturing
  // Automation, ch. 2); 0 in air and plunges.
  double torque_Nm = 0, power_kW = 0;
  double spindle_rpm = 0;       // the motion's S
  // With a feed limit: the largest share of the feed (0..1) at which this
  // point's peak force stays within Settings::feed_limit_N and its torque within
  // the spindle's S1 curve (Physics::spindle); 1 where they are met as written.
  double feed_share = 1;
  // The zero-order stability limit (chatter, stability/lobes.hpp) at this
  // point's immersion (force::immersion_hull) and speed, from the tool tip's
  // modes on the machine: a_p above it chatters. 0 where not checked (air,
  // plunges, nothing engaged in front); -1 where the tool has no dynamic
  // model (a material without density: stability/model.hpp).
  double ap_limit_mm = 0;
  double height_mm = 0;         // where along the flutes the force acts
  V3 delta_mm = V3::Zero();     // deflection of the tool at that height
  // With Physics::workpiece: the workpiece's displacement at the contact under
  // the force on it (-force_N); the surface lands off by delta - this.
  V3 workpiece_delta_mm = V3::Zero();
  V3 normal = V3::UnitZ();      // outward normal of the surface being generated
  NormalSource normal_source = NormalSource::travel;
  double part_gap_mm = 0;       // normal_source part: the programmed cutter's gap to the part
  // (delta - workpiece_delta) . normal; flank: (flank_min_mm + flank_max_mm) / 2
  double error_mm = 0;
  // simulate(): the highest stock over the leading half of the tool's disc
  // above the tip (the Z-map as committed so far: it may lag the last few
  // moves by a batch), 0 where none; the plausibility checks' depth of cut,
  // which a_p (at most the flute length) cannot show.
  double stock_depth_mm = 0;
  // The same stock's distance below the tip, 0 where it reaches the tip: how
  // far below the programmed surface an earlier operation left the stock
  // under a point in air.
  double stock_gap_mm = 0;
  // simulate(): how deep a non-cutting part of the assembly (neck, shank,
  // holder) stands in the stock at this point (the Z-map as committed when the
  // point is handed on, which may lag the last few moves by a batch), 0 where
  // it is clear (collision.hpp).
  double collision_mm = 0;
  AssemblyPart collision_part = AssemblyPart::shank;
  // Flank cuts: e(z) over the engaged flank at the commanded position (the
  // offset not included), its extremes and their heights above the tip.
  bool flank = false;
  double flank_min_mm = 0, flank_max_mm = 0;
  double flank_z_min_mm = 0, flank_z_max_mm = 0;
  // e(z) per engaged slice, only from simulate() with Settings::flank_profiles.
  std::vector<force::FlankPoint> flank_profile;
};

// The surface error against the design with the commanded point displaced by
// `offset` from it: offset . n + error_mm (the deflection moves with the tool;
// error_mm is delta . n, or a flank's mid-range of e(z) along n).
inline double landing_error(const Point& p, const V3& offset) { return offset.dot(p.normal) + p.error_mm; }

using Progress = std::function<void(const std::string& stage, double fraction)>;

// Runs the motions through the stock, each motion end displaced by offsets[i]
// (empty: none), and returns every CL sample of the cutting moves (rapids are
// cut into the stock but not reported). The motions are the design: surface
// normals follow their directions, not those of the displaced path.
// normals (may be null: built from `motions`): the design surface's normals.
std::vector<Point> simulate(const std::vector<interp::Motion>& motions, const std::vector<V3>& offsets,
                            const Physics& ph, const Settings& s, const Progress& progress = {},
                            const DesignNormals* normals = nullptr);
// The same, each point handed to `sink` as it is produced (program order)
// instead of kept: memory does not grow with the points.
using PointSink = std::function<void(const Point&)>;
void simulate(const std::vector<interp::Motion>& motions, const std::vector<V3>& offsets, const Physics& ph,
              const Settings& s, const PointSink& sink, const Progress& progress = {},
              const DesignNormals* normals = nullptr);

// The same over a program given in pieces, in program order (memory does not
// grow with the program): add() the motions of each piece, then finish(). The
// points go to `sink` as they are produced (a batch of samples late at most,
// all of them by finish()); Point::motion counts from the first motion added.
// `map` (may be null): the Z-map to cut, else a copy of the physics' stock.
// `total` (may be 0): the program's motions, for `progress`.
class Simulation {
 public:
  Simulation(const Physics& ph, const Settings& s, const DesignNormals& normals, PointSink sink,
             std::unique_ptr<stock::ZMap> map = nullptr, Progress progress = {}, std::size_t total = 0);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;
  // The next motions (the design), each end displaced by offsets[i] (empty:
  // none) and each start by the offset of the motion before.
  void add(const std::vector<interp::Motion>& motions, const std::vector<V3>& offsets = {});
  void finish();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The tool id a motion cuts with: Settings::tool_override, else "T<n>".
std::string tool_id(const interp::Motion& m, const Settings& s);
std::string tool_id(int t_number, const Settings& s);

// The normals of the design `motions` with the physics' part model or path.
std::unique_ptr<DesignNormals> design_normals(const std::vector<interp::Motion>& motions, const Physics& ph,
                                              const Settings& s);

struct Result {
  // The motions as written: the program's, with the blocks inserted where a
  // move was split (inserted[i]; such a motion ends on its parent move, the
  // next motion that is not inserted, before the offset), at their programmed
  // feeds (the feeds run are feeds_mm_per_min).
  std::vector<interp::Motion> motions;
  std::vector<bool> inserted;
  std::vector<V3> offsets;            // per motion of `motions`, mm (zero where not compensated)
  std::vector<Point> nominal;         // the program as written
  std::vector<Point> final;           // at the compensated points (last iteration)
  int iterations = 0;                 // most mirror updates any point needed
  std::size_t evaluations = 0;        // engagement evaluations of the mirror stream
  double last_change_mm = 0;          // largest change left where a point did not converge
  bool converged = false;
  std::size_t unconverged_points = 0; // where max_iterations ran out
  std::vector<std::uint32_t> capped_lines;    // lines where max_offset_mm bit
  std::vector<std::uint32_t> nonuniform_arcs; // arcs kept as translated arcs though their compensation varies
  std::size_t linearised_arcs = 0;   // arcs whose first part went into G1 chords
  std::size_t compensated_points = 0;
  std::size_t split_points = 0;       // blocks inserted to split moves
  // --feed-limit: feed per motion of `motions` (mm/min, as the program will run
  // it) and the lines where it was lowered.
  std::vector<double> feeds_mm_per_min;
  std::vector<std::uint32_t> feed_lowered_lines;
};

// `splittable` (may be null): per motion, whether its block may be split by
// inserting G1 blocks before it (compensate::splittable). A move is split where
// the error under the straight ramp of its end offsets would leave the
// tolerance (Settings::max_splits_per_move at most); an arc whose compensation
// varies by more than the tolerance is linearised: chords within chord_tol_mm
// as inserted G1 blocks, the arc block keeping the last chord's piece.
//
// `sinks` (may be null): the points go to them as they are produced and
// Result::nominal and Result::final stay empty; `nominal` is called on the
// thread of the as-written simulation, `final` on the caller's, with the
// offset the point lands with (its motion's offsets interpolated, as
// report::offset_at does).
struct PointSinks {
  PointSink nominal;
  // The offset commanded at the point, and the motion of the program as
  // written it lies on (a block inserted to split a move: the move's).
  std::function<void(const Point&, const V3& offset, std::size_t original)> final;
};
Result compensate(const std::vector<interp::Motion>& motions, const Physics& ph, const Settings& s,
                  const Progress& progress = {}, const std::vector<bool>* splittable = nullptr,
                  const PointSinks* sinks = nullptr);

// The same over a program given in pieces, in program order (memory does not
// grow with the program): add() each piece's motions, with movable() of them
// (it looks one motion ahead: the caller cuts pieces where that does not
// matter) and splittable() (may be null); add() returns the piece as written
// (motions, inserted, offsets, feeds and the lists and counts of the piece),
// finish() the totals (every list and count, iterations and evaluations; no
// motions). The points go to the sinks as produced; those of the as-written
// simulation may come a batch late (all of them by finish()), Point::motion
// counts from the first motion of the program (as written, for `final`).
// With a feed limit the program comes in one piece (the feeds need every
// peak force before the mirror pass), unless the caller simulated the program
// as written first (`as_written` false: no as-written simulation here, the
// sinks' nominal is not called) and plans the feeds: add()'s planned_feeds,
// one per motion (null: as programmed), with Settings::feed_limit_N 0.
class Compensation {
 public:
  Compensation(const Physics& ph, const Settings& s, const DesignNormals& normals, PointSinks sinks,
               Progress progress = {}, std::size_t total = 0, bool as_written = true);
  ~Compensation();
  Compensation(const Compensation&) = delete;
  Compensation& operator=(const Compensation&) = delete;
  Result add(const std::vector<interp::Motion>& motions, const std::vector<bool>& movable,
             const std::vector<bool>* splittable, const std::vector<double>* planned_feeds = nullptr);
  Result finish();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Which motions may be moved: compensable, and followed by a block the writer
// can re-target (a plain G90 G0-G3 block) or by nothing.
std::vector<bool> movable(const std::vector<interp::Motion>& motions);

}  // namespace deflex::compensate
