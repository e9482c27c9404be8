// The machine's axis limits and the control's corner look-ahead: what the
// machining time (deflex::process) needs from the machine profile.
//
// Machine profile section (optional; every key optional, absent ones keep the
// defaults below). A per-axis value is {x: .., y: .., z: ..} or one number for
// all three axes; every value must be finite and > 0.
//
//   axis_limits:
//     max_feed_mm_per_min: {x: 15000, y: 15000, z: 10000}  # highest cutting feed per axis
//     rapid_mm_per_min: {x: 36000, y: 36000, z: 30000}     # G0 rate per axis
//     acceleration_mm_per_s2: {x: 2500, y: 2500, z: 2000}  # per axis
//     corner_tolerance_mm: 0.01  # how far the control may round a corner (G64 P, junction deviation)
#pragma once
#include <array>

namespace deflex::profile {

// Axes x, y, z. The defaults are round, deliberately modest figures for a
// 40-taper 3-axis VMC of the mill3 class, so a profile without the section
// still gives a believable time rather than none:
// - max feed 10 m/min: the common ceiling of cutting feed on such machines
//   (Fanuc parameter 1430 class), far above what finishing programs ask;
// - rapids 30 m/min in X/Y, 24 m/min in Z (the heavier spindle head axis is
//   usually the slowest);
// - 2000 mm/s^2 (0.2 g): what a box-way or older linear-guide VMC reaches with
//   acceleration before interpolation in cutting mode; faster machines give
//   their own figures;
// - corner tolerance 0.01 mm: Grbl's default junction deviation and a typical
//   LinuxCNC G64 P for finishing.
struct AxisLimits {
  std::array<double, 3> max_feed_mm_per_min{10000, 10000, 10000};
  std::array<double, 3> rapid_mm_per_min{30000, 30000, 24000};
  std::array<double, 3> acceleration_mm_per_s2{2000, 2000, 2000};
  double corner_tolerance_mm = 0.01;
  bool set = false;  // read from a profile (false: the defaults above)
};

}  // namespace deflex::profile
