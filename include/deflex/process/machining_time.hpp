// Machining time of a program from the machine's axis limits, as a control
// with look-ahead runs it.
//
// Model (each decision is one a real control makes one way or another; these
// are the ones stated here and tested in tests/process/test_machining_time.cpp):
// - Every motion has a trapezoidal speed profile along its path: constant
//   acceleration to its cruise speed, cruise, constant deceleration (no jerk
//   limit, so the time is a lower bound for a jerk-limited control).
// - Look-ahead over the whole program: the speed at each junction is the
//   smallest of (a) the corner speed the blend tolerance allows, (b) the cruise
//   speeds of both motions, (c) what the acceleration lets the tool reach from
//   the program start and still stop by the program end (backward pass, then
//   forward pass).
// - Axis limits are projected on the direction of travel: the path speed (or
//   acceleration) is the largest that keeps every axis within its own limit,
//   min over axes of limit_i / |u_i| (LinuxCNC's and Grbl's rule: the axes are
//   independent drives). So a 45-degree XY move with equal axis limits may run
//   at sqrt(2) times the axis limit.
// - Cutting motions (G1/G2/G3) cruise at min(F, projected max feed); arcs also
//   at their centripetal limit sqrt(a r), a the smallest acceleration of the
//   arc's plane axes (helices: the limits apply to the in-plane part).
// - Rapids (G0) are straight interpolated moves at the projected rapid rates
//   (not dog-leg moves), with exact stop at both ends: a Fanuc control does an
//   in-position check after every G0 block, so any junction with a rapid (G0 to
//   G1, G1 to G0, G0 to G0) and any tool change is at rest.
// - Corners between cutting motions are blended: the control may leave the
//   programmed corner by at most corner_tolerance_mm on a circular blend
//   tangent to both legs; its radius R = tol sin(t/2) / (1 - sin(t/2)), t the
//   angle between the legs, and the corner speed is sqrt(a R) (Grbl's
//   junction deviation; LinuxCNC G64 P tolerance), a the smallest acceleration
//   of the axes either leg moves. The blend's shorter path is not counted.
// - Dwells (G4), tool changes, spindle starts and any other time without motion
//   are not counted: interp::Motion does not carry them.
//
// Cost: O(n) time; memory one array of four doubles per motion plus the
// per-motion output; no allocation per motion (one map node per tool number).
#pragma once
#include <array>
#include <map>
#include <limits>
#include <vector>

#include "deflex/interp/motion.hpp"
#include "deflex/profile/axis_limits.hpp"

namespace deflex::process {

// Time and path length of a set of motions.
struct TimeTotals {
  double total_s = 0;
  double cutting_s = 0;   // G1, G2, G3
  double rapid_s = 0;     // G0
  double cutting_mm = 0;  // path length, helices by their true length
  double rapid_mm = 0;
};

struct MachiningTime {
  TimeTotals program;
  std::map<int, TimeTotals> per_tool;  // T number -> its motions (they sum to `program`)
  std::vector<double> motion_s;        // per motion, the same index as the input
};

// `feed_mm_per_min`: empty, or one feed per motion replacing the programmed F of
// each cutting motion (--feed-limit's feeds; rapids ignore theirs). Throws
// Error(ErrorKind::internal) when its size differs from the motions' or a cutting
// motion has no positive finite feed (the interpreter never emits one).
MachiningTime machining_time(const std::vector<interp::Motion>& motions, const profile::AxisLimits& limits,
                             const std::vector<double>& feed_mm_per_min = {});

// The same motion by motion (a program in pieces): memory is the look-ahead,
// the motions whose entry speed a later stop may still lower. The totals are
// those of machining_time() whatever pieces the motions come in.
class MachiningClock {
 public:
  // motion_s (may be null): receives each motion's time at its index.
  explicit MachiningClock(const profile::AxisLimits& limits, std::vector<double>* motion_s = nullptr);
  ~MachiningClock();
  // feed_mm_per_min: NaN for the motion's own (else --feed-limit's).
  void add(const interp::Motion& m, double feed_mm_per_min = std::numeric_limits<double>::quiet_NaN());
  MachiningTime finish();  // program and per-tool totals (motion_s stays empty)

 private:
  struct Entry;
  struct ShapeState {
    interp::Vec3 u_end{};
    double vmax_mm_per_s = 0;
  };
  void settle(bool end);
  static constexpr std::size_t kBatch = 4096;  // motions added between settlements
  profile::AxisLimits k_;
  std::vector<double>* motion_s_;
  std::vector<Entry> window_;
  std::size_t settled_size_ = 0, count_ = 0;
  double v_ = 0;  // exit speed of the last motion timed
  ShapeState prev_shape_;
  bool have_prev_ = false, prev_rapid_ = false;
  int prev_tool_ = 0, tool_ = 0;
  TimeTotals* per_tool_ = nullptr;
  MachiningTime r_;
};

// --- The pieces, for tests and plots ---

// Largest path rate along unit direction `u` that keeps each axis within its
// own limit: min over axes with u_i != 0 of limit[i] / |u_i|.
double along(const std::array<double, 3>& limit, const interp::Vec3& u);

// Time to cover `length_mm` entering at v0 and leaving at v1 (mm/s), never
// above vmax, accelerating and braking at `accel_mm_per_s2`. v0, v1 <= vmax and
// |v1^2 - v0^2| <= 2 a L are the caller's (the look-ahead guarantees them).
double segment_time_s(double length_mm, double v0_mm_per_s, double v1_mm_per_s, double vmax_mm_per_s,
                      double accel_mm_per_s2);

// Corner speed from unit direction `u_in` to `u_out` with a blend that stays
// within `tolerance_mm` of the corner at centripetal acceleration
// `accel_mm_per_s2`: infinite when the legs are collinear, 0 on a reversal.
double corner_speed_mm_per_s(const interp::Vec3& u_in, const interp::Vec3& u_out, double accel_mm_per_s2,
                             double tolerance_mm);

}  // namespace deflex::process
