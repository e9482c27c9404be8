// `deflex fit` as a call: the machine profile that predicts what was
// measured on a cut of this machine (fit/solve.hpp), written as an ordinary
// machine profile with the fit's provenance in comments.
//
//   job::FitSettings s;
//   s.run.program = "testcut.nc"; s.run.read.machine = "mill3"; ...
//   s.run.measured = "probe_results.txt"; s.run.probe_program = "probe.nc";
//   s.output = "fitted.yaml";
//   job::FitReport r = job::fit(s, io);
#pragma once
#include <iosfwd>
#include <string>
#include <vector>

#include "deflex/fit/observe.hpp"
#include "deflex/fit/solve.hpp"
#include "deflex/job/io.hpp"
#include "deflex/job/settings.hpp"
#include "deflex/stiffness/machine.hpp"

namespace deflex::job {

class Observer;

struct FitSettings {
  // The program whose cut was measured, machine, tool, material, stock, part,
  // and the measurements (Settings::measured, probe_program, measured_reach_mm).
  Settings run;
  // More measured cuts of the same machine fitted together with `run`: each
  // its own program, tool, stock and measurements (its machine is run's).
  // Tools that stick out differently weigh tool, clamp, spindle and
  // structure differently: what one tool's walls cannot tell apart, several
  // can (docs/fit.md).
  std::vector<Settings> more;
  std::string output;         // the fitted machine profile ("" or "-": the output stream)
  fit::FitOptions options;
};

// Residuals of one feature (the test cut's plan; "" for points without one).
struct FeatureFit {
  std::string feature;
  std::size_t points = 0;
  double rms_before_mm = 0, max_before_mm = 0;  // |predicted - measured| at the starting profile
  double rms_after_mm = 0, max_after_mm = 0;    // with the fitted one
};

struct FitReport {
  fit::FitResult fit;
  std::size_t observations = 0, matched = 0;
  std::vector<std::string> unmatched;  // sources of the points without a prediction
  std::vector<FeatureFit> features;    // sorted by name
  FeatureFit all;                      // every matched point
  stiffness::MachineStiffness start, fitted;
  double start_force_scale = 1;        // the profile's force_scale before the fit
  std::string profile_text;            // the fitted profile as written
};

// Reads the measurements, simulates the program once per basis machine and
// fits; writes the fitted profile to `out` or atomically to
// FitSettings::output. Every check that can fail runs before the simulation.
FitReport fit(const FitSettings& s, std::ostream& out, Io& io, Observer* observer = nullptr);
// The same with the measurements given (the tests, a caller with its own reader).
FitReport fit(const FitSettings& s, const std::vector<fit::Observation>& measured, std::ostream& out, Io& io,
              Observer* observer = nullptr);

// The profile file `profile_file` with its stiffness numbers scaled by
// `scales` (model.hpp; the coefficients' entry is the force_scale written,
// not a factor of the file's), the fit's provenance in comments at its head
// and " (fitted)" after its name: every other line and comment as it was.
std::string fitted_profile_text(const std::string& profile_file, const fit::Scales& scales,
                                const std::vector<std::string>& provenance);

}  // namespace deflex::job
