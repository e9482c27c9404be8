// Identification of the six mechanistic coefficients from slot tests
// (Altintas 2012 ch. 2): the mean forces of a full-immersion cut with a flat
// end mill are linear in the feed per tooth,
//   F_mean / (N a_p) = slope * f_z + intercept      (per axis),
// and in the convention of deflex (forces on the tool, feed +X, M3, slot
// phi in [0, pi], dFz = -dFa on the cylinder):
//   Fx: slope = -K_rc / 4,  intercept = -K_re / pi
//   Fy: slope =  K_tc / 4,  intercept =  K_te / pi
//   Fz: slope = -K_ac / pi, intercept = -K_ae / 2
// The helix angle and diameter do not enter the means.
//
// CSV format (see samples/calibration/README.md):
//   # comment lines start with '#'; "# key: value" lines set defaults for every
//   # row: diameter_mm, flutes, ap_mm, helix_deg, material, tool,
//   # forces_on (tool | workpiece; workpiece forces are negated)
//   fz_mm,Fx_N,Fy_N,Fz_N[,ap_mm][,flutes][,diameter_mm]    <- header row, any order
//   0.05,-120.3,180.2,-30.1                                 <- mean forces of one test
#pragma once
#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "deflex/force/coefficients.hpp"

namespace deflex::force {

struct SlotTest {
  double fz_mm = 0;
  double ap_mm = 0;
  int flutes = 0;
  double diameter_mm = 0;  // 0: not given
  Eigen::Vector3d mean_N = Eigen::Vector3d::Zero();  // on the tool, machine axes
  int line = 0;            // in the CSV file
};

struct SlotTestData {
  std::string file;
  std::string material;  // from "# material:", may be empty
  std::string tool;      // from "# tool:", may be empty
  double helix_deg = 0;  // 0: not given
  std::vector<SlotTest> tests;
};

// Throws Error(ErrorKind::input, "file:line:col: error: ...") on a malformed file.
SlotTestData parse_slot_tests(const std::string& csv_text, const std::string& file);
SlotTestData load_slot_tests(const std::string& path);  // Error(ErrorKind::io) when unreadable

struct LineFit {
  double slope = 0, intercept = 0;
  double r2 = 0;  // coefficient of determination of the normalised means
};

struct SlotCalibration {
  Coefficients k;
  std::array<LineFit, 3> fit;                // Fx, Fy, Fz, of F / (N a_p) against f_z
  std::vector<Eigen::Vector3d> predicted_N;  // per test, from the fitted coefficients
  std::vector<Eigen::Vector3d> residual_N;   // measured - predicted
  Eigen::Vector3d rms_residual_N = Eigen::Vector3d::Zero();
};

// Least squares; needs at least two distinct feeds (Error(ErrorKind::input) otherwise).
SlotCalibration calibrate_slot_tests(const SlotTestData& data);

// Mean slot forces on the tool predicted by the closed form above.
Eigen::Vector3d slot_mean_force(const Coefficients& k, int flutes, double ap_mm, double fz_mm);

}  // namespace deflex::force
