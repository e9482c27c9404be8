// `deflex stability` as a call: the milling stability lobes (chatter) of a
// library tool for one radial immersion - the zero-order limit of Altintas &
// Budak 1995 (stability/lobes.hpp) from the tool tip's modes on the machine
// (stability/model.hpp) or from a measured FRF (stability/frf.hpp).
#pragma once
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "deflex/force/engagement.hpp"
#include "deflex/job/settings.hpp"
#include "deflex/stability/frf.hpp"
#include "deflex/stability/lobes.hpp"
#include "deflex/stiffness/modes.hpp"
#include "deflex/stiffness/tool.hpp"

namespace deflex::job {

struct StabilitySettings {
  std::string tool;             // the tool's id in the library
  std::string tool_file;        // the library ("": config tool_file, else the installed one)
  MaterialSettings material;    // by name, or the coefficients ("": config material)
  std::string machine;          // profile file or name: holder, joints, damping, spindle speed range
  std::string frf;              // a measured tool-tip FRF (CSV) instead of the modal model ("": the model)
  bool tool_only = false;       // the model without holder and spindle (the tool clamped at the holder face)
  double ae_mm = 0;             // radial depth of cut from the cutting side (>= D: a slot)
  // The axial depth whose engagement the limit is for (a ball or a corner
  // radius: the slices near the tip are engaged less). Unset: the flutes'
  // straight-wall immersion of a_e, Altintas & Budak's textbook cut.
  std::optional<double> ap_mm;
  bool up_milling = false;      // up-milling (cuts on +Y); else down-milling
  double rpm_min = 0, rpm_max = 0;  // 0, 0: the machine spindle's max_rpm / 50 to max_rpm
  int points = 1000;            // speeds of the printed limit (the envelope)
};

struct StabilityResult {
  stiffness::Tool tool;
  std::string machine_file;                 // "" with a measured FRF and no machine
  std::string material;                     // what the coefficients are
  std::string frf_source;
  std::vector<stiffness::Mode> modes;       // the model's (empty with a measured FRF)
  bool damping_given = false;               // the profile's dynamics: damping_ratio, else the default
  force::AngleInterval immersion;           // the textbook interval of a_e
  Eigen::Matrix2d alpha = Eigen::Matrix2d::Zero();  // the mean directional coefficients
  double Kt_N_per_mm2 = 0, Kr_ratio = 0;
  double rpm_min = 0, rpm_max = 0;
  stability::Lobes lobes;                   // every lobe's curve
  std::vector<std::pair<double, double>> limit;    // rpm, ap_limit_mm: the lower envelope, `points` + 1 speeds
  std::vector<std::pair<double, double>> pockets;  // rpm, ap_limit_mm: its local maxima, the stable speeds, best first
};

// Each setting checked (a settings Error) before anything is computed.
StabilityResult stability(const StabilitySettings& s);

}  // namespace deflex::job
