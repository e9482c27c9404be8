// The spindle's power and torque against speed: what the machine can give the
// cut (deflex::compensate compares every point's cutting power and torque with
// it, and --feed-limit keeps the feed under it).
//
// Machine profile section (optional; without it nothing is checked):
//
//   spindle:
//     max_rpm: 12000            # highest programmable S
//     source: "..."             # where the figures come from (shown in messages)
//     S1:                       # continuous duty: the curves read off the data sheet,
//       rpm:       [0, 1500, 12000]   # strictly increasing, from 0
//       power_kW:  [0,   11,    11]   # linear between the points
//       torque_Nm: [70,  70,  8.75]   # optional when power_kW is given, and the other way round
//     S6:                       # intermittent duty (S6-40 %, 30 min, ...): optional, same keys
//       ...
//
// A data sheet draws both curves of one rating; they are one limit (P = M w,
// w = 2 pi n / 60), so where both are given they must agree within 10 % at
// every point (a misread curve is an error, not a silent lower limit). The
// torque the spindle allows at n is the lower of the torque curve and the
// power curve over w.
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace deflex::profile {

// w = 2 pi n / 60, rad/s.
double angular_speed_rad_per_s(double rpm);
// P = M w, in kW from N m.
double power_from_torque_kW(double torque_Nm, double rpm);

struct SpindleCurve {
  std::vector<double> rpm;        // strictly increasing, rpm.front() == 0
  std::vector<double> power_kW;   // empty, or one per rpm
  std::vector<double> torque_Nm;  // empty, or one per rpm
  // The torque the curve allows at n rpm, N m (the last point's values past
  // the end; +inf at n = 0 on a power-only curve, which gives nothing there).
  double allowed_torque_Nm(double rpm) const;
  double allowed_power_kW(double rpm) const;
};

struct SpindleRating {
  bool set = false;     // the profile has a spindle: section
  double max_rpm = 0;
  std::string source;
  SpindleCurve s1;                  // continuous: the limit deflex checks and keeps
  std::optional<SpindleCurve> s6;   // intermittent: told beside it when given
};

}  // namespace deflex::profile
